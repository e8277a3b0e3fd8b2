// ddes roscpp: ros::init and the node's life; ros::this_node, ros::names, ros::master.
#include "ddes_core.h"

#include <cstdlib>
#include <sstream>

#include <ros/callback_queue.h>
#include <ros/common.h>
#include <ros/console.h>
#include <ros/init.h>
#include <ros/master.h>
#include <ros/names.h>
#include <ros/node_handle.h>
#include <ros/spinner.h>
#include <ros/this_node.h>

namespace ros
{

namespace ddes
{

CallbackQueue* globalQueue()
{
  static CallbackQueue* q = new CallbackQueue(true);  // never destroyed: callbacks may outlive main
  return q;
}

std::string nodeRelative(const std::string& name)
{
  if (!name.empty() && name[0] == '~')
  {
    std::string error;
    if (!names::validate(name, error))
      throw InvalidNameException(error);
    return names::append(state().name, name.substr(1));
  }
  return name;
}

std::string resolveRemote(const std::string& ns, const std::string& name)
{
  static std::map<std::pair<std::string, std::string>, std::string>* cache =
      new std::map<std::pair<std::string, std::string>, std::string>;
  std::lock_guard<std::recursive_mutex> lock(floorMutex());
  if (!state().connected || state().time_only)
  {
    // no world to ask (before ros::init): roscpp's resolution without remappings
    return names::resolve(ns, name, false);
  }
  std::pair<std::string, std::string> key(ns, name);
  std::map<std::pair<std::string, std::string>, std::string>::iterator it = cache->find(key);
  if (it != cache->end())
    return it->second;
  Writer w = Writer::request();
  w.str(ns).str(name).u8(1);
  std::string resolved;
  try
  {
    resolved = request(RESOLVE, w).str();
  }
  catch (ReplyError& e)
  {
    throw InvalidNameException(e.what());
  }
  (*cache)[key] = resolved;
  return resolved;
}

}  // namespace ddes

void disableAllSignalsInThisThread() {}

// -- init ---------------------------------------------------------------------------------------

namespace
{

void initImpl(const M_string& remappings, const std::string& name, uint32_t options,
              const std::vector<std::string>& argv)
{
  ddes::NodeState& s = ddes::state();
  if (s.initialized)
    return;
  if (name.empty())
    throw InvalidNameException("The node name must not be empty");
  std::string effective = name;
  M_string::const_iterator it = remappings.find("__name");
  if (it != remappings.end())
    effective = it->second;
  if (effective.find('/') != std::string::npos)
    throw InvalidNodeNameException(effective, "node names cannot contain /");
  if (effective.find('~') != std::string::npos)
    throw InvalidNodeNameException(effective, "node names cannot contain ~");
  ROSCONSOLE_AUTOINIT;
  s.init_options = options;
  s.init_name = name;
  s.argv = argv;
  ddes::connectNode(name, options, argv);
  s.initialized = true;
  s.ok = true;
  // the command line's remappings, as roscpp's names::init keeps them
  for (it = remappings.begin(); it != remappings.end(); ++it)
  {
    const std::string& left = it->first;
    if (left.empty() || left[0] == '_' || left == s.name)
      continue;
    try
    {
      s.remappings[names::resolve(left, false)] = names::resolve(it->second, false);
      s.unresolved_remappings[left] = it->second;
    }
    catch (InvalidNameException&)
    {
    }
  }
}

}  // namespace

void init(int& argc, char** argv, const std::string& name, uint32_t options)
{
  std::vector<std::string> full;
  for (int i = 0; i < argc; ++i)
    full.push_back(argv[i]);
  M_string remappings;
  // roscpp's rule: every "a:=b" goes to the end of argv, and argc stops counting it
  const int full_argc = argc;
  for (int i = 0; i < argc;)
  {
    std::string arg = argv[i];
    size_t pos = arg.find(":=");
    if (pos != std::string::npos)
    {
      remappings[arg.substr(0, pos)] = arg.substr(pos + 2);
      char* tmp = argv[i];
      for (int j = i; j < full_argc - 1; ++j)
        argv[j] = argv[j + 1];
      argv[argc - 1] = tmp;
      --argc;
    }
    else
    {
      ++i;
    }
  }
  initImpl(remappings, name, options, full);
}

void init(const M_string& remappings, const std::string& name, uint32_t options)
{
  std::vector<std::string> argv;
  std::vector<std::string> proc = ddes::processArgv();
  argv.push_back(proc.empty() ? name : proc[0]);
  for (M_string::const_iterator it = remappings.begin(); it != remappings.end(); ++it)
    argv.push_back(it->first + ":=" + it->second);
  initImpl(remappings, name, options, argv);
}

void init(const VP_string& remapping_args, const std::string& name, uint32_t options)
{
  M_string remappings;
  for (VP_string::const_iterator it = remapping_args.begin(); it != remapping_args.end(); ++it)
    remappings[it->first] = it->second;
  init(remappings, name, options);
}

bool isInitialized()
{
  return ddes::state().initialized;
}

bool isShuttingDown()
{
  return ddes::state().shutting_down;
}

bool ok()
{
  return ddes::state().ok;
}

bool isStarted()
{
  return ddes::state().started;
}

void start()
{
  std::lock_guard<std::recursive_mutex> lock(ddes::floorMutex());
  ddes::NodeState& s = ddes::state();
  if (s.started)
    return;
  ddes::requireInit("starting the node");
  s.started = true;
  s.shutting_down = false;
  s.ok = !ddes::worldDown();
  s.time_initialized = true;
  if (!ddes::worldDown())
    ddes::globalQueue()->enable();
}

void shutdown()
{
  std::lock_guard<std::recursive_mutex> lock(ddes::floorMutex());
  ddes::NodeState& s = ddes::state();
  if (s.shutting_down)
    return;
  if (ddes::live())
  {
    ddes::Writer w = ddes::Writer::request();
    ddes::request(ddes::SHUTDOWN, w);
  }
  ddes::setWorldDown();
  ddes::markShutdown();
}

void requestShutdown()
{
  std::lock_guard<std::recursive_mutex> lock(ddes::floorMutex());
  if (!ddes::live())
    return;
  ddes::Writer w;
  w.str("");
  ddes::post(ddes::REQUEST_SHUTDOWN, w);
}

void spin()
{
  SingleThreadedSpinner s;
  spin(s);
}

void spin(Spinner& s)
{
  s.spin();
}

void spinOnce()
{
  ddes::globalQueue()->callAvailable(ros::WallDuration());
}

void waitForShutdown()
{
  while (ok())
    WallDuration(0.05).sleep();
}

CallbackQueue* getGlobalCallbackQueue()
{
  return ddes::globalQueue();
}

std::string getROSArg(int argc, const char* const* argv, const std::string& arg)
{
  for (int i = 0; i < argc; ++i)
  {
    std::string str_arg = argv[i];
    size_t pos = str_arg.find(":=");
    if (str_arg.substr(0, pos) == arg)
      return str_arg.substr(pos + 2);
  }
  return "";
}

void removeROSArgs(int argc, const char* const* argv, V_string& args_out)
{
  for (int i = 0; i < argc; ++i)
  {
    std::string arg = argv[i];
    if (arg.find(":=") == std::string::npos)
      args_out.push_back(arg);
  }
}

const std::string& getDefaultMasterURI()
{
  static const std::string uri = "http://localhost:11311";
  return uri;
}

// -- this_node ----------------------------------------------------------------------------------

namespace this_node
{

const std::string& getName()
{
  return ddes::state().name;
}

const std::string& getNamespace()
{
  return ddes::state().ns;
}

void getAdvertisedTopics(V_string& topics)
{
  ddes::advertisedTopics(topics);
}

void getSubscribedTopics(V_string& topics)
{
  ddes::subscribedTopics(topics);
}

}  // namespace this_node

// -- names --------------------------------------------------------------------------------------

namespace names
{

const M_string& getRemappings()
{
  return ddes::state().remappings;
}

const M_string& getUnresolvedRemappings()
{
  return ddes::state().unresolved_remappings;
}

namespace
{
bool isValidCharInName(char c)
{
  return std::isalnum(static_cast<unsigned char>(c)) || c == '/' || c == '_';
}
}  // namespace

bool validate(const std::string& name, std::string& error)
{
  if (name.empty())
    return true;
  char c = name[0];
  if (!std::isalpha(static_cast<unsigned char>(c)) && c != '/' && c != '~')
  {
    std::stringstream ss;
    ss << "Character [" << c << "] is not valid as the first character in Graph Resource Name [" << name
       << "].  Valid characters are a-z, A-Z, / and in some cases ~.";
    error = ss.str();
    return false;
  }
  for (size_t i = 1; i < name.size(); ++i)
  {
    c = name[i];
    if (!isValidCharInName(c))
    {
      std::stringstream ss;
      ss << "Character [" << c << "] at element [" << i << "] is not valid in Graph Resource Name [" << name
         << "].  Valid characters are a-z, A-Z, 0-9, / and _.";
      error = ss.str();
      return false;
    }
  }
  return true;
}

std::string clean(const std::string& name)
{
  std::string out = name;
  size_t pos = out.find("//");
  while (pos != std::string::npos)
  {
    out.erase(pos, 1);
    pos = out.find("//", pos);
  }
  if (!name.empty() && *out.rbegin() == '/')
    out.erase(out.size() - 1, 1);
  return out;
}

std::string append(const std::string& left, const std::string& right)
{
  return clean(left + "/" + right);
}

std::string remap(const std::string& name)
{
  std::string resolved = resolve(name, false);
  std::string mapped = ddes::resolveRemote("/", resolved);
  return mapped != resolved ? mapped : name;
}

std::string resolve(const std::string& name, bool remap)
{
  return resolve(this_node::getNamespace(), name, remap);
}

std::string resolve(const std::string& ns, const std::string& name, bool remap)
{
  std::string error;
  if (!validate(name, error))
    throw InvalidNameException(error);
  if (name.empty())
  {
    if (ns.empty())
      return "/";
    if (ns[0] == '/')
      return ns;
    return append("/", ns);
  }
  std::string copy = name;
  if (copy[0] == '~')
    copy = append(this_node::getName(), copy.substr(1));
  if (copy[0] != '/')
    copy = append("/", append(ns, copy));
  copy = clean(copy);
  if (copy.empty())
    copy = "/";
  if (remap)
    copy = ddes::resolveRemote("/", copy);
  return copy;
}

std::string parentNamespace(const std::string& name)
{
  std::string error;
  if (!validate(name, error))
    throw InvalidNameException(error);
  if (name.empty())
    return "";
  if (name == "/")
    return "/";
  std::string stripped = name;
  if (stripped.find_last_of('/') == stripped.size() - 1)
    stripped = stripped.substr(0, stripped.size() - 2);
  size_t last = stripped.find_last_of('/');
  if (last == std::string::npos)
    return "";
  if (last == 0)
    return "/";
  return stripped.substr(0, last);
}

}  // namespace names

// -- master -------------------------------------------------------------------------------------

namespace master
{

namespace
{
struct MasterUri
{
  std::string uri, host;
  uint32_t port;
  MasterUri()
  {
    const char* env = std::getenv("ROS_MASTER_URI");
    uri = env ? env : getDefaultMasterURI();
    host = "localhost";
    port = 11311;
    std::string rest = uri;
    size_t scheme = rest.find("://");
    if (scheme != std::string::npos)
      rest = rest.substr(scheme + 3);
    size_t colon = rest.find(':');
    if (colon != std::string::npos)
    {
      host = rest.substr(0, colon);
      port = static_cast<uint32_t>(std::atoi(rest.c_str() + colon + 1));
    }
    else
    {
      host = rest.substr(0, rest.find('/'));
    }
  }
};
const MasterUri& masterUri()
{
  static MasterUri m;
  return m;
}
}  // namespace

const std::string& getHost()
{
  return masterUri().host;
}

uint32_t getPort()
{
  return masterUri().port;
}

const std::string& getURI()
{
  return masterUri().uri;
}

bool check()
{
  return ddes::live();
}

bool getTopics(V_TopicInfo& topics)
{
  (void)topics;
  return false;
}

bool getNodes(V_string& nodes)
{
  (void)nodes;
  return false;
}

void setRetryTimeout(ros::WallDuration timeout)
{
  (void)timeout;
}

}  // namespace master

}  // namespace ros
