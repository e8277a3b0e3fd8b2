// ddes roscpp: ros::NodeHandle.
#include "ddes_core.h"
#include "param_impl.h"

#include <sstream>

#include <ros/callback_queue.h>
#include <ros/init.h>
#include <ros/names.h>
#include <ros/node_handle.h>
#include <ros/this_node.h>

namespace ros
{

namespace ddes
{

namespace
{
int g_nh_refcount = 0;
bool g_node_started_by_nh = false;
}  // namespace

NodeRef::NodeRef()
{
  std::lock_guard<std::recursive_mutex> lock(floorMutex());
  if (g_nh_refcount == 0 && !ros::isStarted())
  {
    g_node_started_by_nh = true;
    ros::start();
  }
  ++g_nh_refcount;
}

NodeRef::~NodeRef()
{
  std::lock_guard<std::recursive_mutex> lock(floorMutex());
  --g_nh_refcount;
  if (g_nh_refcount == 0 && g_node_started_by_nh && state().started)
  {
    // roscpp calls ros::shutdown() here.  ddes stops the node in this process only (ok()
    // false, logging off, as roscpp leaves them); the world keeps the node until the process
    // ends or a later NodeHandle starts it again, which roscpp allows.
    markShutdown();
  }
}

}  // namespace ddes

class NodeHandleBackingCollection
{
public:
  std::vector<boost::weak_ptr<ddes::PublisherImpl> > pubs;
  std::vector<boost::weak_ptr<ddes::SubscriberImpl> > subs;
  std::vector<boost::weak_ptr<ddes::ServiceServerImpl> > srvs;
  std::vector<boost::weak_ptr<ddes::ServiceClientImpl> > clients;
  ddes::NodeRefPtr node_ref;
};

namespace
{

std::string tildeError(const std::string& name)
{
  std::stringstream ss;
  ss << "Using ~ names with NodeHandle methods is not allowed.  If you want to use private names with the NodeHandle ";
  ss << "interface, construct a NodeHandle using a private name as its namespace.  e.g. ";
  ss << "ros::NodeHandle nh(\"~\");  ";
  ss << "nh.getParam(\"my_private_name\");";
  ss << " (name = [" << name << "])";
  return ss.str();
}

void validateName(const std::string& name)
{
  std::string error;
  if (!names::validate(name, error))
    throw InvalidNameException(error);
}

/// NodeHandle::resolveName without the validation: in `ns`, this handle's remappings first,
/// then the node's (the world's).
std::string resolveIn(const std::string& ns, const M_string& remappings, const std::string& name, bool remap)
{
  if (name.empty())
    return ns;
  if (name[0] == '~')
    throw InvalidNameException(tildeError(name));
  std::string final = name[0] == '/' ? name : names::append(ns, name);
  final = names::clean(final);
  if (final.empty() || final[0] != '/')
    final = "/" + final;
  if (remap)
  {
    M_string::const_iterator it = remappings.find(final);
    if (it != remappings.end())
      return it->second;
    final = ddes::resolveRemote("/", final);
  }
  return final;
}

}  // namespace

NodeHandle::NodeHandle(const std::string& ns, const M_string& remappings)
: namespace_(this_node::getNamespace()), callback_queue_(0), collection_(0), ok_(false)
{
  std::string tilde_resolved_ns;
  if (!ns.empty() && ns[0] == '~')
  {
    ddes::requireInit("creating the first NodeHandle");
    tilde_resolved_ns = names::resolve(ns);
  }
  else
  {
    tilde_resolved_ns = ns;
  }
  construct(tilde_resolved_ns, true);
  initRemappings(remappings);
}

NodeHandle::NodeHandle(const NodeHandle& parent, const std::string& ns)
: collection_(0), ok_(false)
{
  namespace_ = parent.getNamespace();
  callback_queue_ = parent.callback_queue_;
  remappings_ = parent.remappings_;
  unresolved_remappings_ = parent.unresolved_remappings_;
  construct(ns, false);
}

NodeHandle::NodeHandle(const NodeHandle& parent, const std::string& ns, const M_string& remappings)
: collection_(0), ok_(false)
{
  namespace_ = parent.getNamespace();
  callback_queue_ = parent.callback_queue_;
  remappings_ = parent.remappings_;
  unresolved_remappings_ = parent.unresolved_remappings_;
  construct(ns, false);
  initRemappings(remappings);
}

NodeHandle::NodeHandle(const NodeHandle& rhs)
: namespace_(rhs.namespace_), unresolved_namespace_(rhs.unresolved_namespace_), remappings_(rhs.remappings_),
  unresolved_remappings_(rhs.unresolved_remappings_), callback_queue_(rhs.callback_queue_), collection_(0),
  ok_(true)
{
  // the namespace is resolved already: a copy asks the world nothing
  ddes::requireInit("creating the first NodeHandle");
  collection_ = new NodeHandleBackingCollection;
  collection_->node_ref = boost::make_shared<ddes::NodeRef>();
}

NodeHandle::~NodeHandle()
{
  destruct();
}

NodeHandle& NodeHandle::operator=(const NodeHandle& rhs)
{
  namespace_ = rhs.namespace_;
  callback_queue_ = rhs.callback_queue_;
  remappings_ = rhs.remappings_;
  unresolved_remappings_ = rhs.unresolved_remappings_;
  return *this;
}

void NodeHandle::construct(const std::string& ns, bool validate_name)
{
  ddes::requireInit("creating the first NodeHandle");
  collection_ = new NodeHandleBackingCollection;
  unresolved_namespace_ = ns;
  if (validate_name)
    namespace_ = resolveName(ns, true);
  else
    namespace_ = resolveIn(namespace_, remappings_, ns, true);
  ok_ = true;
  collection_->node_ref = boost::make_shared<ddes::NodeRef>();
}

void NodeHandle::destruct()
{
  std::lock_guard<std::recursive_mutex> lock(ddes::floorMutex());
  delete collection_;
  collection_ = 0;
}

void NodeHandle::initRemappings(const M_string& remappings)
{
  for (M_string::const_iterator it = remappings.begin(); it != remappings.end(); ++it)
  {
    remappings_.insert(std::make_pair(resolveName(it->first, false), resolveName(it->second, false)));
    unresolved_remappings_.insert(*it);
  }
}

void NodeHandle::setCallbackQueue(CallbackQueueInterface* queue)
{
  callback_queue_ = queue;
}

CallbackQueueInterface* NodeHandle::getCallbackQueue() const
{
  return callback_queue_ ? callback_queue_ : static_cast<CallbackQueueInterface*>(getGlobalCallbackQueue());
}

std::string NodeHandle::resolveName(const std::string& name, bool remap) const
{
  validateName(name);
  return resolveIn(namespace_, remappings_, name, remap);
}

void NodeHandle::worldName(const std::string& name, std::string& ns_out, std::string& name_out) const
{
  validateName(name);
  if (!name.empty() && name[0] == '~')
    throw InvalidNameException(tildeError(name));
  if (!remappings_.empty())
  {
    std::string local = resolveIn(namespace_, remappings_, name, false);
    M_string::const_iterator it = remappings_.find(local);
    if (it != remappings_.end())
    {
      ns_out = "/";
      name_out = it->second;
      return;
    }
  }
  ns_out = namespace_;
  name_out = name;
}

// -- advertise / subscribe / services -----------------------------------------------------------

Publisher NodeHandle::advertise(AdvertiseOptions& ops)
{
  std::lock_guard<std::recursive_mutex> lock(ddes::floorMutex());
  std::string ns, name;
  worldName(ops.topic, ns, name);
  if (ops.callback_queue == 0)
    ops.callback_queue = getCallbackQueue();
  if (!ddes::live())
    return Publisher();
  ddes::Writer w = ddes::Writer::request();
  w.str(ns)
      .str(name)
      .str(ops.datatype)
      .str(ops.md5sum)
      .str(ops.message_definition)
      .u32(ops.queue_size)
      .u8(ops.latch ? 1 : 0)
      .u8((ops.connect_cb || ops.disconnect_cb) ? 1 : 0);
  boost::shared_ptr<ddes::PublisherImpl> impl = boost::make_shared<ddes::PublisherImpl>();
  try
  {
    ddes::Reader r = ddes::request(ddes::ADVERTISE, w);
    impl->id = r.u32();
    impl->topic = r.str();
  }
  catch (ddes::ReplyError& e)
  {
    impl->unadvertised = true;
    ROS_ERROR("%s", e.what());
    return Publisher();
  }
  impl->md5sum = ops.md5sum;
  impl->datatype = ops.datatype;
  impl->latch = ops.latch;
  impl->connect_cb = ops.connect_cb;
  impl->disconnect_cb = ops.disconnect_cb;
  impl->callback_queue = ops.callback_queue;
  impl->has_tracked_object = static_cast<bool>(ops.tracked_object);
  impl->tracked_object = ops.tracked_object;
  impl->node_ref = collection_->node_ref;
  ddes::registerPublisher(impl);
  collection_->pubs.push_back(impl);
  return Publisher(impl);
}

Subscriber NodeHandle::subscribe(SubscribeOptions& ops)
{
  std::lock_guard<std::recursive_mutex> lock(ddes::floorMutex());
  std::string ns, name;
  worldName(ops.topic, ns, name);
  if (ops.callback_queue == 0)
    ops.callback_queue = getCallbackQueue();
  if (!ddes::live() || !ops.helper)
    return Subscriber();
  ddes::Writer w = ddes::Writer::request();
  w.str(ns).str(name).str(ops.datatype).str(ops.md5sum).u32(ops.queue_size);
  boost::shared_ptr<ddes::SubscriberImpl> impl = boost::make_shared<ddes::SubscriberImpl>();
  try
  {
    ddes::Reader r = ddes::request(ddes::SUBSCRIBE, w);
    impl->id = r.u32();
    impl->topic = r.str();
  }
  catch (ddes::ReplyError& e)
  {
    impl->unsubscribed = true;
    ROS_ERROR("%s", e.what());
    return Subscriber();
  }
  impl->md5sum = ops.md5sum;
  impl->datatype = ops.datatype;
  impl->queue_size = ops.queue_size;
  impl->helper = ops.helper;
  impl->callback_queue = ops.callback_queue;
  impl->has_tracked_object = static_cast<bool>(ops.tracked_object);
  impl->tracked_object = ops.tracked_object;
  impl->node_ref = collection_->node_ref;
  ddes::registerSubscriber(impl);
  collection_->subs.push_back(impl);
  return Subscriber(impl);
}

ServiceServer NodeHandle::advertiseService(AdvertiseServiceOptions& ops)
{
  std::lock_guard<std::recursive_mutex> lock(ddes::floorMutex());
  std::string ns, name;
  worldName(ops.service, ns, name);
  if (ops.callback_queue == 0)
    ops.callback_queue = getCallbackQueue();
  if (!ddes::live() || !ops.helper)
    return ServiceServer();
  ddes::Writer w = ddes::Writer::request();
  w.str(ns).str(name).str(ops.datatype).str(ops.md5sum).str(ops.req_datatype).str(ops.res_datatype);
  boost::shared_ptr<ddes::ServiceServerImpl> impl = boost::make_shared<ddes::ServiceServerImpl>();
  try
  {
    ddes::Reader r = ddes::request(ddes::ADVERTISE_SERVICE, w);
    impl->id = r.u32();
    impl->service = r.str();
  }
  catch (ddes::ReplyError& e)
  {
    impl->unadvertised = true;
    ROS_ERROR("%s", e.what());
    return ServiceServer();
  }
  impl->helper = ops.helper;
  impl->has_tracked_object = static_cast<bool>(ops.tracked_object);
  impl->tracked_object = ops.tracked_object;
  impl->node_ref = collection_->node_ref;
  ddes::registerService(impl);
  collection_->srvs.push_back(impl);
  return ServiceServer(impl);
}

namespace service
{
bool existsIn(const std::string& ns, const std::string& name, bool print_failure_reason);
}

ServiceClient NodeHandle::serviceClient(ServiceClientOptions& ops)
{
  std::lock_guard<std::recursive_mutex> lock(ddes::floorMutex());
  ServiceClient client;
  client.impl_.reset(new ddes::ServiceClientImpl);
  ddes::ServiceClientImpl& impl = *client.impl_;
  worldName(ops.service, impl.ns, impl.name);
  impl.md5sum = ops.md5sum;
  impl.datatype = ops.datatype;
  impl.persistent = ops.persistent;
  impl.header_values = ops.header;
  impl.node_ref = collection_->node_ref;
  if (ops.persistent)
    impl.link_ok = service::existsIn(impl.ns, impl.name, false);
  collection_->clients.push_back(client.impl_);
  return client;
}

// -- timers -------------------------------------------------------------------------------------

namespace
{

template <class Ops>
boost::shared_ptr<ddes::TimerImpl> makeTimer(const Ops& ops, uint8_t clock, int64_t period_ns)
{
  std::lock_guard<std::recursive_mutex> lock(ddes::floorMutex());
  ddes::requireInit("creating a timer");
  boost::shared_ptr<ddes::TimerImpl> impl = boost::make_shared<ddes::TimerImpl>();
  impl->clock = clock;
  impl->period_ns = period_ns;
  impl->oneshot = ops.oneshot;
  impl->callback_queue = ops.callback_queue ? ops.callback_queue : getGlobalCallbackQueue();
  impl->has_tracked_object = static_cast<bool>(ops.tracked_object);
  impl->tracked_object = ops.tracked_object;
  if (ddes::live())
  {
    ddes::Writer w = ddes::Writer::request();
    w.u8(clock).i64(period_ns).u8(ops.oneshot ? 1 : 0).u8(ops.autostart ? 1 : 0);
    impl->id = ddes::request(ddes::TIMER_CREATE, w).u32();
    impl->created = true;
    impl->started = ops.autostart;
    impl->next_expected_ns = (clock == ddes::CLOCK_ROS ? ddes::state().now_ns : ddes::state().wall_ns) + period_ns;
    ddes::registerTimer(impl);
  }
  return impl;
}

}  // namespace

Timer::Timer(const TimerOptions& ops) : impl_(makeTimer(ops, ddes::CLOCK_ROS, ops.period.toNSec()))
{
  impl_->ros_cb = ops.callback;
}

WallTimer::WallTimer(const WallTimerOptions& ops) : impl_(makeTimer(ops, ddes::CLOCK_WALL, ops.period.toNSec()))
{
  impl_->wall_cb = ops.callback;
}

SteadyTimer::SteadyTimer(const SteadyTimerOptions& ops)
: impl_(makeTimer(ops, ddes::CLOCK_STEADY, ops.period.toNSec()))
{
  impl_->steady_cb = ops.callback;
}

Timer NodeHandle::createTimer(Duration period, const TimerCallback& callback, bool oneshot, bool autostart) const
{
  TimerOptions ops;
  ops.period = period;
  ops.callback = callback;
  ops.oneshot = oneshot;
  ops.autostart = autostart;
  return createTimer(ops);
}

Timer NodeHandle::createTimer(TimerOptions& ops) const
{
  if (ops.callback_queue == 0)
    ops.callback_queue = getCallbackQueue();
  return Timer(ops);
}

WallTimer NodeHandle::createWallTimer(WallDuration period, const WallTimerCallback& callback, bool oneshot,
                                      bool autostart) const
{
  WallTimerOptions ops;
  ops.period = period;
  ops.callback = callback;
  ops.oneshot = oneshot;
  ops.autostart = autostart;
  return createWallTimer(ops);
}

WallTimer NodeHandle::createWallTimer(WallTimerOptions& ops) const
{
  if (ops.callback_queue == 0)
    ops.callback_queue = getCallbackQueue();
  return WallTimer(ops);
}

SteadyTimer NodeHandle::createSteadyTimer(WallDuration period, const SteadyTimerCallback& callback, bool oneshot,
                                          bool autostart) const
{
  SteadyTimerOptions ops;
  ops.period = period;
  ops.callback = callback;
  ops.oneshot = oneshot;
  ops.autostart = autostart;
  return createSteadyTimer(ops);
}

SteadyTimer NodeHandle::createSteadyTimer(SteadyTimerOptions& ops) const
{
  if (ops.callback_queue == 0)
    ops.callback_queue = getCallbackQueue();
  return SteadyTimer(ops);
}

// -- parameters ---------------------------------------------------------------------------------

#define DDES_NH_SET(Type) \
  void NodeHandle::setParam(const std::string& key, Type v) const \
  { \
    std::string ns, k; \
    worldName(key, ns, k); \
    ddes::paramSet(ns, k, ddes::toXmlRpc(v)); \
  }

DDES_NH_SET(const XmlRpc::XmlRpcValue&)
DDES_NH_SET(const std::string&)
DDES_NH_SET(const char*)
DDES_NH_SET(double)
DDES_NH_SET(int)
DDES_NH_SET(bool)
DDES_NH_SET(const std::vector<std::string>&)
DDES_NH_SET(const std::vector<double>&)
DDES_NH_SET(const std::vector<float>&)
DDES_NH_SET(const std::vector<int>&)
DDES_NH_SET(const std::vector<bool>&)
DDES_NH_SET(const std::map<std::string DDES_COMMA std::string>&)
DDES_NH_SET(const std::map<std::string DDES_COMMA double>&)
DDES_NH_SET(const std::map<std::string DDES_COMMA float>&)
DDES_NH_SET(const std::map<std::string DDES_COMMA int>&)
DDES_NH_SET(const std::map<std::string DDES_COMMA bool>&)

#define DDES_NH_GET(Type) \
  bool NodeHandle::getParam(const std::string& key, Type& v) const \
  { \
    std::string ns, k; \
    worldName(key, ns, k); \
    return ddes::paramGetAs(ns, k, v, false); \
  } \
  bool NodeHandle::getParamCached(const std::string& key, Type& v) const \
  { \
    std::string ns, k; \
    worldName(key, ns, k); \
    return ddes::paramGetAs(ns, k, v, true); \
  }

DDES_NH_GET(std::string)
DDES_NH_GET(double)
DDES_NH_GET(float)
DDES_NH_GET(int)
DDES_NH_GET(bool)
DDES_NH_GET(XmlRpc::XmlRpcValue)
DDES_NH_GET(std::vector<std::string>)
DDES_NH_GET(std::vector<double>)
DDES_NH_GET(std::vector<float>)
DDES_NH_GET(std::vector<int>)
DDES_NH_GET(std::vector<bool>)
DDES_NH_GET(std::map<std::string DDES_COMMA std::string>)
DDES_NH_GET(std::map<std::string DDES_COMMA double>)
DDES_NH_GET(std::map<std::string DDES_COMMA float>)
DDES_NH_GET(std::map<std::string DDES_COMMA int>)
DDES_NH_GET(std::map<std::string DDES_COMMA bool>)

#undef DDES_NH_SET
#undef DDES_NH_GET

bool NodeHandle::hasParam(const std::string& key) const
{
  std::string ns, k;
  worldName(key, ns, k);
  return ddes::paramHas(ns, k);
}

bool NodeHandle::searchParam(const std::string& key, std::string& result) const
{
  // roscpp remaps the unresolved key with this handle's remappings, then searches up from
  // the handle's namespace
  std::string remapped = key;
  M_string::const_iterator it = unresolved_remappings_.find(key);
  if (it != unresolved_remappings_.end())
    remapped = it->second;
  return ddes::paramSearch(namespace_, remapped, result);
}

bool NodeHandle::deleteParam(const std::string& key) const
{
  std::string ns, k;
  worldName(key, ns, k);
  return ddes::paramDelete(ns, k);
}

bool NodeHandle::getParamNames(std::vector<std::string>& keys) const
{
  return ddes::paramNames(keys);
}

// -- life ---------------------------------------------------------------------------------------

void NodeHandle::shutdown()
{
  std::lock_guard<std::recursive_mutex> lock(ddes::floorMutex());
  if (collection_)
  {
    for (auto& w : collection_->subs)
      if (boost::shared_ptr<ddes::SubscriberImpl> s = w.lock())
        s->unsubscribe();
    for (auto& w : collection_->pubs)
      if (boost::shared_ptr<ddes::PublisherImpl> p = w.lock())
        p->unadvertise();
    for (auto& w : collection_->srvs)
      if (boost::shared_ptr<ddes::ServiceServerImpl> s = w.lock())
        s->unadvertise();
    for (auto& w : collection_->clients)
      if (boost::shared_ptr<ddes::ServiceClientImpl> c = w.lock())
        c->is_shutdown = true;
  }
  ok_ = false;
}

bool NodeHandle::ok() const
{
  return ros::ok() && ok_;
}

}  // namespace ros
