// ddes roscpp: rosconsole.  A message is formatted here and goes to the world as a LOG frame;
// the world prints it in roscpp's format and publishes it on /rosout.
#include "ddes_core.h"

#include <algorithm>
#include <cstdarg>
#include <cstdio>
#include <cstdlib>

#include <ros/console.h>
#include <ros/time.h>

namespace ros
{
namespace console
{

bool g_initialized = false;
std::string g_last_error_message = "Unknown Error";

namespace
{

struct Logger
{
  std::string name;
};

struct Registry
{
  std::map<std::string, Logger*> loggers;     // every logger used, by name (never freed)
  std::map<std::string, levels::Level> levels;  // the levels set (set_logger_level)
  std::vector<LogLocation*> locations;
  std::vector<LogAppender*> appenders;
  M_string fixed_tokens;
  bool shutting_down = false;
};

Registry& registry()
{
  static Registry* r = new Registry;
  return *r;
}

Logger* intern(const std::string& name)
{
  Registry& r = registry();
  std::map<std::string, Logger*>::iterator it = r.loggers.find(name);
  if (it != r.loggers.end())
    return it->second;
  Logger* l = new Logger;
  l->name = name;
  r.loggers[name] = l;
  return l;
}

/// A logger's own level, else its nearest ancestor's (dot-separated), else Info.
levels::Level effectiveLevel(const std::string& name)
{
  const Registry& r = registry();
  std::string n = name;
  for (;;)
  {
    std::map<std::string, levels::Level>::const_iterator it = r.levels.find(n);
    if (it != r.levels.end())
      return it->second;
    size_t dot = n.rfind('.');
    if (dot == std::string::npos)
      break;
    n.erase(dot);
  }
  return levels::Info;
}

const char* severityText(Level level)
{
  switch (level)
  {
    case levels::Debug:
      return "DEBUG";
    case levels::Info:
      return " INFO";
    case levels::Warn:
      return " WARN";
    case levels::Error:
      return "ERROR";
    default:
      return "FATAL";
  }
}

std::string vformat(const char* fmt, va_list args)
{
  va_list copy;
  va_copy(copy, args);
  char small[1024];
  int n = std::vsnprintf(small, sizeof(small), fmt, copy);
  va_end(copy);
  if (n < 0)
    return std::string();
  if (static_cast<size_t>(n) < sizeof(small))
    return std::string(small, static_cast<size_t>(n));
  std::string out(static_cast<size_t>(n) + 1, '\0');
  std::vsnprintf(&out[0], out.size(), fmt, args);
  out.resize(static_cast<size_t>(n));
  return out;
}

void emit(void* logger, Level level, const std::string& text, const char* file, const char* function, int line)
{
  Registry& r = registry();
  if (level == levels::Error)
    g_last_error_message = text;
  for (LogAppender* a : r.appenders)
    a->log(level, text.c_str(), file, function, line);
  ros::ddes::NodeState& s = ros::ddes::state();
  if (s.connected)
  {
    if (!ros::ddes::live())
      return;
    ros::ddes::Writer w;
    w.u8(static_cast<uint8_t>(std::min<int>(level, levels::Fatal)))
        .str(logger ? static_cast<Logger*>(logger)->name : std::string(ROSCONSOLE_DEFAULT_NAME))
        .str(text)
        .str(file ? file : "")
        .str(function ? function : "")
        .u32(static_cast<uint32_t>(line < 0 ? 0 : line));
    ros::ddes::post(ros::ddes::LOG, w);
    return;
  }
  // not joined to a world yet (before ros::init): roscpp's console line, with the world's
  // last time (zero)
  FILE* out = level >= levels::Warn ? stderr : stdout;
  std::fprintf(out, "[%s] [%d.%09d]: %s\n", severityText(level), static_cast<int>(s.wall_ns / 1000000000LL),
               static_cast<int>(s.wall_ns % 1000000000LL), text.c_str());
  std::fflush(out);
}

void filtered(FilterBase* filter, void* logger, Level level, std::string text, const char* file, int line,
              const char* function)
{
  if (filter)
  {
    FilterParams params;
    params.file = file;
    params.line = line;
    params.function = function;
    params.message = text.c_str();
    params.logger = logger;
    params.level = level;
    bool enabled = filter->isEnabled(params);
    level = params.level;
    logger = params.logger;
    if (!params.out_message.empty())
      text = params.out_message;
    if (!enabled)
      return;
  }
  emit(logger, level, text, file, function, line);
}

}  // namespace

void initialize()
{
  g_initialized = true;
}

void shutdown()
{
  registry().shutting_down = true;
}

bool get_loggers(std::map<std::string, levels::Level>& loggers)
{
  std::lock_guard<std::recursive_mutex> lock(ros::ddes::floorMutex());
  Registry& r = registry();
  for (const auto& l : r.loggers)
    loggers[l.first] = effectiveLevel(l.first);
  for (const auto& l : r.levels)
    loggers[l.first] = l.second;
  return true;
}

bool set_logger_level(const std::string& name, levels::Level level)
{
  if (level < levels::Debug || level >= levels::Count)
    return false;
  std::lock_guard<std::recursive_mutex> lock(ros::ddes::floorMutex());
  registry().levels[name] = level;
  intern(name);
  notifyLoggerLevelsChanged();
  if (ros::ddes::live())
  {
    ros::ddes::Writer w = ros::ddes::Writer::request();
    w.str(name).u8(static_cast<uint8_t>(level));
    try
    {
      ros::ddes::request(ros::ddes::LOGGER_LEVEL, w);
    }
    catch (ros::ddes::ReplyError&)
    {
    }
  }
  return true;
}

void notifyLoggerLevelsChanged()
{
  std::lock_guard<std::recursive_mutex> lock(ros::ddes::floorMutex());
  for (LogLocation* loc : registry().locations)
    checkLogLocationEnabled(loc);
}

void setFixedFilterToken(const std::string& key, const std::string& val)
{
  registry().fixed_tokens[key] = val;
}

void register_appender(LogAppender* appender)
{
  std::lock_guard<std::recursive_mutex> lock(ros::ddes::floorMutex());
  registry().appenders.push_back(appender);
}

void deregister_appender(LogAppender* appender)
{
  std::lock_guard<std::recursive_mutex> lock(ros::ddes::floorMutex());
  std::vector<LogAppender*>& a = registry().appenders;
  a.erase(std::remove(a.begin(), a.end(), appender), a.end());
}

void initializeLogLocation(LogLocation* loc, const std::string& name, Level level)
{
  std::lock_guard<std::recursive_mutex> lock(ros::ddes::floorMutex());
  if (loc->initialized_)
    return;
  loc->logger_ = intern(name);
  loc->level_ = level;
  registry().locations.push_back(loc);
  checkLogLocationEnabled(loc);
  loc->initialized_ = true;
}

void setLogLocationLevel(LogLocation* loc, Level level)
{
  loc->level_ = level;
}

void checkLogLocationEnabled(LogLocation* loc)
{
  const Logger* l = static_cast<const Logger*>(loc->logger_);
  loc->logger_enabled_ = l && loc->level_ >= effectiveLevel(l->name);
}

void print(FilterBase* filter, void* logger, Level level, const char* file, int line, const char* function,
           const char* fmt, ...)
{
  std::lock_guard<std::recursive_mutex> lock(ros::ddes::floorMutex());
  if (registry().shutting_down)
    return;
  va_list args;
  va_start(args, fmt);
  std::string text = vformat(fmt, args);
  va_end(args);
  filtered(filter, logger, level, text, file, line, function);
}

void print(FilterBase* filter, void* logger, Level level, const std::stringstream& ss, const char* file, int line,
           const char* function)
{
  std::lock_guard<std::recursive_mutex> lock(ros::ddes::floorMutex());
  if (registry().shutting_down)
    return;
  filtered(filter, logger, level, ss.str(), file, line, function);
}

double throttleStart()
{
  return ros::Time::isSimTime() ? 0.0 : -1e300;
}

std::string formatToString(const char* fmt, ...)
{
  va_list args;
  va_start(args, fmt);
  std::string out = vformat(fmt, args);
  va_end(args);
  return out;
}

}  // namespace console
}  // namespace ros
