// ddes roscpp: rosconsole (ROS_INFO and friends).
//
// A message whose logger is enabled is formatted here (printf or stream) and sent to the world
// as one LOG frame (level, logger, text, file, function, line); the world prints it in
// roscpp's console format and publishes it on /rosout (docs/external-nodes.md).  Loggers are
// rosconsole's hierarchy: "ros", "ros.<package>" (ROSCONSOLE_DEFAULT_NAME, the package from
// the ROS_PACKAGE_NAME compile definition catkin sets), "ros.<package>.<name>" for the _NAMED
// macros; a logger's level is its own (set_logger_level) or its nearest ancestor's, Info by
// default.  Every call site keeps its logger and whether it is enabled, and is revisited when
// a level changes, as rosconsole does.
#ifndef ROSCONSOLE_ROSCONSOLE_H
#define ROSCONSOLE_ROSCONSOLE_H

#include <cstdarg>
#include <cstdio>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <ros/console_backend.h>
#include <ros/macros.h>
#include <ros/time.h>

#ifdef __GNUC__
#define ROSCONSOLE_PRINTF_ATTRIBUTE(a, b) __attribute__((__format__(__printf__, a, b)))
#else
#define ROSCONSOLE_PRINTF_ATTRIBUTE(a, b)
#endif

#define ROSCONSOLE_DECL

namespace ros
{
namespace console
{

ROSCONSOLE_DECL void initialize();
ROSCONSOLE_DECL void shutdown();
extern ROSCONSOLE_DECL bool g_initialized;
extern ROSCONSOLE_DECL std::string g_last_error_message;

/// Every logger that has a level of its own or has been used, with its effective level.
ROSCONSOLE_DECL bool get_loggers(std::map<std::string, levels::Level>& loggers);
/// Sets a logger's level (its descendants without a level of their own follow); also tells
/// the world (LOGGER_LEVEL).  Returns false for levels::Count.
ROSCONSOLE_DECL bool set_logger_level(const std::string& name, levels::Level level);
/// Revisits every call site after levels changed.
ROSCONSOLE_DECL void notifyLoggerLevelsChanged();
/// rosconsole's ${key} tokens for the format; ddes's world formats, so this only stores.
ROSCONSOLE_DECL void setFixedFilterToken(const std::string& key, const std::string& val);

/// Receives every message that is printed (after the filter).
class LogAppender
{
public:
  virtual ~LogAppender() {}
  virtual void log(::ros::console::Level level, const char* str, const char* file, const char* function,
                   int line) = 0;
};
ROSCONSOLE_DECL void register_appender(LogAppender* appender);
ROSCONSOLE_DECL void deregister_appender(LogAppender* appender);

/// What a filter of ROS_*_FILTER sees, and may change (logger, level, out_message).
struct FilterParams
{
  const char* file;
  int line;
  const char* function;
  const char* message;
  void* logger;
  Level level;
  std::string out_message;
};

/// The filter of the ROS_*_FILTER macros: isEnabled() before formatting, isEnabled(params)
/// after.
class FilterBase
{
public:
  virtual ~FilterBase() {}
  inline virtual bool isEnabled() { return true; }
  inline virtual bool isEnabled(FilterParams&) { return true; }
};

/// One call site: its logger (an opaque handle), its level and whether the logger is enabled
/// for it.
struct LogLocation
{
  bool initialized_;
  bool logger_enabled_;
  ::ros::console::Level level_;
  void* logger_;
};

ROSCONSOLE_DECL void initializeLogLocation(LogLocation* loc, const std::string& name, Level level);
ROSCONSOLE_DECL void setLogLocationLevel(LogLocation* loc, Level level);
ROSCONSOLE_DECL void checkLogLocationEnabled(LogLocation* loc);

ROSCONSOLE_DECL void print(FilterBase* filter, void* logger, Level level, const char* file, int line,
                           const char* function, const char* fmt, ...) ROSCONSOLE_PRINTF_ATTRIBUTE(7, 8);
ROSCONSOLE_DECL void print(FilterBase* filter, void* logger, Level level, const std::stringstream& str,
                           const char* file, int line, const char* function);

ROSCONSOLE_DECL std::string formatToString(const char* fmt, ...) ROSCONSOLE_PRINTF_ATTRIBUTE(1, 2);

/// Where a ROS_*_THROTTLE site's "last printed" starts.  rosconsole starts it at 0.0, which
/// on ROS's wall clock (seconds since 1970) lets the first message through at once; ddes's
/// wall clock starts at zero, so without simulated time it starts far in the past instead
/// (the first message prints, as on a real robot).  Under use_sim_time it is rosconsole's 0.0.
ROSCONSOLE_DECL double throttleStart();

}  // namespace console
}  // namespace ros

#define ROS_LIKELY(x) __builtin_expect((x), 1)
#define ROS_UNLIKELY(x) __builtin_expect((x), 0)

#if defined(__GNUC__)
#define __ROSCONSOLE_FUNCTION__ __PRETTY_FUNCTION__
#else
#define __ROSCONSOLE_FUNCTION__ ""
#endif

#ifdef ROS_PACKAGE_NAME
#define ROSCONSOLE_PACKAGE_NAME ROS_PACKAGE_NAME
#else
#define ROSCONSOLE_PACKAGE_NAME "unknown_package"
#endif

#define ROSCONSOLE_ROOT_LOGGER_NAME "ros"
#define ROSCONSOLE_NAME_PREFIX ROSCONSOLE_ROOT_LOGGER_NAME "." ROSCONSOLE_PACKAGE_NAME
#define ROSCONSOLE_DEFAULT_NAME ROSCONSOLE_NAME_PREFIX

#define ROSCONSOLE_SEVERITY_DEBUG 0
#define ROSCONSOLE_SEVERITY_INFO 1
#define ROSCONSOLE_SEVERITY_WARN 2
#define ROSCONSOLE_SEVERITY_ERROR 3
#define ROSCONSOLE_SEVERITY_FATAL 4
#define ROSCONSOLE_SEVERITY_NONE 5

/// Messages below this severity are compiled out.
#ifndef ROSCONSOLE_MIN_SEVERITY
#define ROSCONSOLE_MIN_SEVERITY ROSCONSOLE_SEVERITY_DEBUG
#endif

#define ROSCONSOLE_AUTOINIT \
  do \
  { \
    if (ROS_UNLIKELY(!::ros::console::g_initialized)) \
    { \
      ::ros::console::initialize(); \
    } \
  } while (false)

// The call site's static location; `name` is evaluated only the first time through.
#define ROSCONSOLE_DEFINE_LOCATION(cond, level, name) \
  ROSCONSOLE_AUTOINIT; \
  static ::ros::console::LogLocation ddes_log_loc_ = {false, false, ::ros::console::levels::Count, 0}; \
  if (ROS_UNLIKELY(!ddes_log_loc_.initialized_)) \
  { \
    ::ros::console::initializeLogLocation(&ddes_log_loc_, name, level); \
  } \
  if (ROS_UNLIKELY(ddes_log_loc_.level_ != level)) \
  { \
    ::ros::console::setLogLocationLevel(&ddes_log_loc_, level); \
    ::ros::console::checkLogLocationEnabled(&ddes_log_loc_); \
  } \
  bool ddes_log_enabled_ = ddes_log_loc_.logger_enabled_ && (cond);

#define ROSCONSOLE_PRINT_AT_LOCATION_WITH_FILTER(filter, ...) \
  ::ros::console::print(filter, ddes_log_loc_.logger_, ddes_log_loc_.level_, __FILE__, __LINE__, \
                        __ROSCONSOLE_FUNCTION__, __VA_ARGS__)

#define ROSCONSOLE_PRINT_AT_LOCATION(...) ROSCONSOLE_PRINT_AT_LOCATION_WITH_FILTER(0, __VA_ARGS__)

#define ROSCONSOLE_PRINT_STREAM_AT_LOCATION_WITH_FILTER(filter, args) \
  do \
  { \
    std::stringstream ddes_log_ss_; \
    ddes_log_ss_ << args; \
    ::ros::console::print(filter, ddes_log_loc_.logger_, ddes_log_loc_.level_, ddes_log_ss_, __FILE__, \
                          __LINE__, __ROSCONSOLE_FUNCTION__); \
  } while (0)

#define ROSCONSOLE_PRINT_STREAM_AT_LOCATION(args) ROSCONSOLE_PRINT_STREAM_AT_LOCATION_WITH_FILTER(0, args)

#define ROSCONSOLE_THROTTLE_CHECK(now, last, period) (ROS_UNLIKELY(last + period <= now) || ROS_UNLIKELY(now < last))

#define ROS_LOG_COND(cond, level, name, ...) \
  do \
  { \
    ROSCONSOLE_DEFINE_LOCATION(cond, level, name); \
    if (ROS_UNLIKELY(ddes_log_enabled_)) \
    { \
      ROSCONSOLE_PRINT_AT_LOCATION(__VA_ARGS__); \
    } \
  } while (false)

#define ROS_LOG_STREAM_COND(cond, level, name, args) \
  do \
  { \
    ROSCONSOLE_DEFINE_LOCATION(cond, level, name); \
    if (ROS_UNLIKELY(ddes_log_enabled_)) \
    { \
      ROSCONSOLE_PRINT_STREAM_AT_LOCATION(args); \
    } \
  } while (false)

#define ROS_LOG_ONCE(level, name, ...) \
  do \
  { \
    ROSCONSOLE_DEFINE_LOCATION(true, level, name); \
    static bool ddes_log_hit_ = false; \
    if (ROS_UNLIKELY(ddes_log_enabled_) && ROS_UNLIKELY(!ddes_log_hit_)) \
    { \
      ddes_log_hit_ = true; \
      ROSCONSOLE_PRINT_AT_LOCATION(__VA_ARGS__); \
    } \
  } while (false)

#define ROS_LOG_STREAM_ONCE(level, name, args) \
  do \
  { \
    ROSCONSOLE_DEFINE_LOCATION(true, level, name); \
    static bool ddes_log_hit_ = false; \
    if (ROS_UNLIKELY(ddes_log_enabled_) && ROS_UNLIKELY(!ddes_log_hit_)) \
    { \
      ddes_log_hit_ = true; \
      ROSCONSOLE_PRINT_STREAM_AT_LOCATION(args); \
    } \
  } while (false)

// Throttled: at most once per `period` seconds of ROS time (a jump back in time lets one through).
#define ROS_LOG_THROTTLE(period, level, name, ...) \
  do \
  { \
    ROSCONSOLE_DEFINE_LOCATION(true, level, name); \
    static double ddes_log_last_ = ::ros::console::throttleStart(); \
    double ddes_log_now_ = ::ros::Time::now().toSec(); \
    if (ROS_UNLIKELY(ddes_log_enabled_) && ROSCONSOLE_THROTTLE_CHECK(ddes_log_now_, ddes_log_last_, period)) \
    { \
      ddes_log_last_ = ddes_log_now_; \
      ROSCONSOLE_PRINT_AT_LOCATION(__VA_ARGS__); \
    } \
  } while (false)

#define ROS_LOG_STREAM_THROTTLE(period, level, name, args) \
  do \
  { \
    ROSCONSOLE_DEFINE_LOCATION(true, level, name); \
    static double ddes_log_last_ = ::ros::console::throttleStart(); \
    double ddes_log_now_ = ::ros::Time::now().toSec(); \
    if (ROS_UNLIKELY(ddes_log_enabled_) && ROSCONSOLE_THROTTLE_CHECK(ddes_log_now_, ddes_log_last_, period)) \
    { \
      ddes_log_last_ = ddes_log_now_; \
      ROSCONSOLE_PRINT_STREAM_AT_LOCATION(args); \
    } \
  } while (false)

// Delayed: the first message is let through only `period` after the site was first reached.
#define ROS_LOG_DELAYED_THROTTLE(period, level, name, ...) \
  do \
  { \
    ROSCONSOLE_DEFINE_LOCATION(true, level, name); \
    double ddes_log_now_ = ::ros::Time::now().toSec(); \
    static double ddes_log_last_ = ddes_log_now_; \
    if (ROS_UNLIKELY(ddes_log_enabled_) && ROSCONSOLE_THROTTLE_CHECK(ddes_log_now_, ddes_log_last_, period)) \
    { \
      ddes_log_last_ = ddes_log_now_; \
      ROSCONSOLE_PRINT_AT_LOCATION(__VA_ARGS__); \
    } \
  } while (false)

#define ROS_LOG_STREAM_DELAYED_THROTTLE(period, level, name, args) \
  do \
  { \
    ROSCONSOLE_DEFINE_LOCATION(true, level, name); \
    double ddes_log_now_ = ::ros::Time::now().toSec(); \
    static double ddes_log_last_ = ddes_log_now_; \
    if (ROS_UNLIKELY(ddes_log_enabled_) && ROSCONSOLE_THROTTLE_CHECK(ddes_log_now_, ddes_log_last_, period)) \
    { \
      ddes_log_last_ = ddes_log_now_; \
      ROSCONSOLE_PRINT_STREAM_AT_LOCATION(args); \
    } \
  } while (false)

#define ROS_LOG_FILTER(filter, level, name, ...) \
  do \
  { \
    ROSCONSOLE_DEFINE_LOCATION(true, level, name); \
    if (ROS_UNLIKELY(ddes_log_enabled_) && (filter)->isEnabled()) \
    { \
      ROSCONSOLE_PRINT_AT_LOCATION_WITH_FILTER(filter, __VA_ARGS__); \
    } \
  } while (false)

#define ROS_LOG_STREAM_FILTER(filter, level, name, args) \
  do \
  { \
    ROSCONSOLE_DEFINE_LOCATION(true, level, name); \
    if (ROS_UNLIKELY(ddes_log_enabled_) && (filter)->isEnabled()) \
    { \
      ROSCONSOLE_PRINT_STREAM_AT_LOCATION_WITH_FILTER(filter, args); \
    } \
  } while (false)

#define ROS_LOG(level, name, ...) ROS_LOG_COND(true, level, name, __VA_ARGS__)
#define ROS_LOG_STREAM(level, name, args) ROS_LOG_STREAM_COND(true, level, name, args)

#include <rosconsole/macros_generated.h>

#endif  // ROSCONSOLE_ROSCONSOLE_H
