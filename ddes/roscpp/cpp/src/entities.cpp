// ddes roscpp: publishers, subscribers, service servers and clients, timers: their handles
// and the entities behind them.
#include "ddes_core.h"

#include <boost/make_shared.hpp>

#include <ros/console.h>
#include <ros/publisher.h>
#include <ros/service_client.h>
#include <ros/service_server.h>
#include <ros/single_subscriber_publisher.h>
#include <ros/steady_timer.h>
#include <ros/subscriber.h>
#include <ros/timer.h>
#include <ros/wall_timer.h>

namespace ros
{
namespace ddes
{

uint8_t* scratchBuffer(uint32_t size)
{
  thread_local std::vector<uint8_t> buffer;
  if (buffer.size() < size)
    buffer.resize(size);
  return buffer.data();
}

namespace
{

Time toTime(int64_t ns)
{
  return ns < 0 ? Time() : Time().fromNSec(static_cast<uint64_t>(ns));
}

WallTime toWallTime(int64_t ns)
{
  return ns < 0 ? WallTime() : WallTime().fromNSec(static_cast<uint64_t>(ns));
}

SteadyTime toSteadyTime(int64_t ns)
{
  return ns < 0 ? SteadyTime() : SteadyTime().fromNSec(static_cast<uint64_t>(ns));
}

void postId(uint8_t kind, uint32_t id)
{
  if (!live())
    return;
  Writer w;
  w.u32(id);
  post(kind, w);
}

}  // namespace

// -- PublisherImpl ----------------------------------------------------------------------------

PublisherImpl::~PublisherImpl()
{
  unadvertise();
}

void PublisherImpl::unadvertise()
{
  std::lock_guard<std::recursive_mutex> lock(floorMutex());
  if (unadvertised)
    return;
  unadvertised = true;
  unregisterPublisher(id);
  if (callback_queue)
    callback_queue->removeByID(reinterpret_cast<uint64_t>(this));
  postId(UNADVERTISE, id);
}

void PublisherImpl::peer(bool connected, const std::string& subscriber)
{
  VoidConstPtr tracker;
  if (has_tracked_object)
  {
    tracker = tracked_object.lock();
    if (!tracker)
      return;
  }
  const SubscriberStatusCallback& cb = connected ? connect_cb : disconnect_cb;
  if (!cb)
    return;
  SingleSubscriberPublisher pub(shared_from_this(), subscriber);
  cb(pub);
}

// -- SubscriberImpl ---------------------------------------------------------------------------

SubscriberImpl::~SubscriberImpl()
{
  unsubscribe();
}

void SubscriberImpl::unsubscribe()
{
  std::lock_guard<std::recursive_mutex> lock(floorMutex());
  if (unsubscribed)
    return;
  unsubscribed = true;
  unregisterSubscriber(id);
  if (callback_queue)
    callback_queue->removeByID(reinterpret_cast<uint64_t>(this));
  postId(UNSUBSCRIBE, id);
}

void SubscriberImpl::deliver(const uint8_t* data, uint32_t len, const std::string& caller, int64_t receipt_ns)
{
  VoidConstPtr tracker;
  if (has_tracked_object)
  {
    tracker = tracked_object.lock();
    if (!tracker)
      return;
  }
  boost::shared_ptr<M_string> header = boost::make_shared<M_string>();
  (*header)["callerid"] = caller;
  (*header)["topic"] = topic;
  (*header)["type"] = datatype;
  (*header)["md5sum"] = md5sum;
  SubscriptionCallbackHelperDeserializeParams params;
  params.buffer = const_cast<uint8_t*>(data);
  params.length = len;
  params.connection_header = header;
  VoidConstPtr msg;
  try
  {
    msg = helper->deserialize(params);
  }
  catch (std::exception& e)
  {
    ROS_ERROR("Exception thrown when deserializing message of length [%d] from [%s]: %s", static_cast<int>(len),
              caller.c_str(), e.what());
    return;
  }
  if (!msg)
    return;
  SubscriptionCallbackHelperCallParams call;
  call.event = MessageEvent<void const>(msg, header, toTime(receipt_ns), false,
                                        MessageEvent<void const>::CreateFunction());
  helper->call(call);
}

void SubscriberImpl::deferred(const DeferredCallbackPtr& cb)
{
  while (!waiting.empty() && waiting.front().expired())
    waiting.pop_front();
  waiting.push_back(cb);
  if (queue_size > 0 && waiting.size() > queue_size)
  {
    if (DeferredCallbackPtr oldest = waiting.front().lock())
      oldest->drop();
    waiting.pop_front();
  }
  callback_queue->addCallback(cb, reinterpret_cast<uint64_t>(this));
}

// -- ServiceServerImpl ------------------------------------------------------------------------

ServiceServerImpl::~ServiceServerImpl()
{
  unadvertise();
}

void ServiceServerImpl::unadvertise()
{
  std::lock_guard<std::recursive_mutex> lock(floorMutex());
  if (unadvertised)
    return;
  unadvertised = true;
  unregisterService(id);
  postId(UNADVERTISE_SERVICE, id);
}

bool ServiceServerImpl::serve(const uint8_t* data, uint32_t len, const std::string& caller,
                              std::vector<uint8_t>& response, std::string& error)
{
  VoidConstPtr tracker;
  if (has_tracked_object)
  {
    tracker = tracked_object.lock();
    if (!tracker)
      return false;
  }
  ServiceCallbackHelperCallParams params;
  boost::shared_array<uint8_t> buf(new uint8_t[len > 0 ? len : 1]);
  if (len > 0)
    std::memcpy(buf.get(), data, len);
  params.request = SerializedMessage(buf, len);
  params.connection_header = boost::make_shared<M_string>();
  (*params.connection_header)["callerid"] = caller;
  (*params.connection_header)["service"] = service;
  bool ok = false;
  try
  {
    ok = helper->call(params);
  }
  catch (std::exception& e)
  {
    ROS_ERROR("Exception thrown while processing service call: %s", e.what());
    error = e.what();
    return false;
  }
  if (!ok)
    return false;
  // serializeServiceResponse wrote the ok byte and a u32 length before the message
  const SerializedMessage& m = params.response;
  if (m.num_bytes >= 5)
    response.assign(m.buf.get() + 5, m.buf.get() + m.num_bytes);
  return true;
}

// -- ServiceClientImpl ------------------------------------------------------------------------

const std::string& ServiceClientImpl::resolvedName()
{
  if (resolved.empty())
    resolved = resolveRemote(ns, name);
  return resolved;
}

// -- TimerImpl --------------------------------------------------------------------------------

namespace
{

int64_t clockNow(uint8_t clock)
{
  return clock == CLOCK_ROS ? state().now_ns : state().wall_ns;
}

void timerControl(uint32_t id, uint8_t op, int64_t period_ns, bool reset)
{
  if (!live())
    return;
  Writer w;
  w.u32(id).u8(op).i64(period_ns).u8(reset ? 1 : 0);
  post(TIMER_CONTROL, w);
}

}  // namespace

TimerImpl::~TimerImpl()
{
  std::lock_guard<std::recursive_mutex> lock(floorMutex());
  stop();
  unregisterTimer(id);
}

void TimerImpl::start()
{
  std::lock_guard<std::recursive_mutex> lock(floorMutex());
  if (started)
    return;
  started = true;
  next_expected_ns = clockNow(clock) + period_ns;
  timerControl(id, 1, period_ns, false);
}

void TimerImpl::stop()
{
  std::lock_guard<std::recursive_mutex> lock(floorMutex());
  if (!started)
    return;
  started = false;
  waiting = 0;
  if (callback_queue)
    callback_queue->removeByID(reinterpret_cast<uint64_t>(this));
  timerControl(id, 0, 0, false);
}

void TimerImpl::setPeriod(int64_t period, bool reset)
{
  std::lock_guard<std::recursive_mutex> lock(floorMutex());
  period_ns = period;
  if (reset)
    next_expected_ns = clockNow(clock) + period;
  timerControl(id, 2, period, reset);
}

bool TimerImpl::hasPending()
{
  if (period_ns == 0 || !started)
    return false;
  if (has_tracked_object && !tracked_object.lock())
    return false;
  return next_expected_ns <= clockNow(clock) || waiting > 0;
}

void TimerImpl::fire(const TimerTimes& t)
{
  VoidConstPtr tracker;
  if (has_tracked_object)
  {
    tracker = tracked_object.lock();
    if (!tracker)
      return;
  }
  next_expected_ns = (t.current_expected >= 0 ? t.current_expected : clockNow(clock)) + period_ns;
  const WallDuration last_duration = WallDuration().fromNSec(t.last_duration > 0 ? t.last_duration : 0);
  if (clock == CLOCK_ROS)
  {
    TimerEvent e;
    e.last_expected = e.last_expired = toTime(t.last_expected);
    e.last_real = toTime(t.last_real);
    e.current_expected = e.current_expired = toTime(t.current_expected);
    e.current_real = toTime(t.current_real);
    e.profile.last_duration = last_duration;
    if (ros_cb)
      ros_cb(e);
  }
  else if (clock == CLOCK_WALL)
  {
    WallTimerEvent e;
    e.last_expected = e.last_expired = toWallTime(t.last_expected);
    e.last_real = toWallTime(t.last_real);
    e.current_expected = e.current_expired = toWallTime(t.current_expected);
    e.current_real = toWallTime(t.current_real);
    e.profile.last_duration = last_duration;
    if (wall_cb)
      wall_cb(e);
  }
  else
  {
    SteadyTimerEvent e;
    e.last_expected = e.last_expired = toSteadyTime(t.last_expected);
    e.last_real = toSteadyTime(t.last_real);
    e.current_expected = e.current_expired = toSteadyTime(t.current_expected);
    e.current_real = toSteadyTime(t.current_real);
    e.profile.last_duration = last_duration;
    if (steady_cb)
      steady_cb(e);
  }
}

}  // namespace ddes

// -- Publisher --------------------------------------------------------------------------------

Publisher::Publisher(const Publisher& rhs) : impl_(rhs.impl_) {}
Publisher::Publisher(const boost::shared_ptr<ddes::PublisherImpl>& impl) : impl_(impl) {}
Publisher::~Publisher() {}

bool Publisher::isValidImpl() const
{
  return impl_ && impl_->isValid();
}

void Publisher::publishSerialized(const uint8_t* data, uint32_t len) const
{
  if (!ddes::live())
    return;  // after shutdown roscpp drops what is published
  ddes::postPublish(impl_->id, data, len);
}

void Publisher::shutdown()
{
  if (impl_)
    impl_->unadvertise();
}

std::string Publisher::getTopic() const
{
  return impl_ ? impl_->topic : std::string();
}

uint32_t Publisher::getNumSubscribers() const
{
  if (!isValidImpl() || !ddes::live())
    return 0;
  ddes::Writer w = ddes::Writer::request();
  w.u32(impl_->id);
  return ddes::request(ddes::NUM_SUBSCRIBERS, w).u32();
}

bool Publisher::isLatched() const
{
  return impl_ && impl_->latch;
}

// -- SingleSubscriberPublisher ----------------------------------------------------------------

SingleSubscriberPublisher::SingleSubscriberPublisher(const boost::shared_ptr<ddes::PublisherImpl>& publisher,
                                                     const std::string& subscriber)
: publisher_(publisher), subscriber_(subscriber)
{}

SingleSubscriberPublisher::~SingleSubscriberPublisher() {}

void SingleSubscriberPublisher::publishSerialized(const uint8_t* data, uint32_t len) const
{
  if (!publisher_ || !publisher_->isValid() || !ddes::live())
    return;
  ddes::postPublishOne(publisher_->id, subscriber_, data, len);
}

std::string SingleSubscriberPublisher::getTopic() const
{
  return publisher_ ? publisher_->topic : std::string();
}

std::string SingleSubscriberPublisher::getSubscriberName() const
{
  return subscriber_;
}

// -- Subscriber -------------------------------------------------------------------------------

Subscriber::Subscriber(const Subscriber& rhs) : impl_(rhs.impl_) {}
Subscriber::Subscriber(const boost::shared_ptr<ddes::SubscriberImpl>& impl) : impl_(impl) {}
Subscriber::~Subscriber() {}

bool Subscriber::isValidImpl() const
{
  return impl_ && impl_->isValid();
}

void Subscriber::shutdown()
{
  if (impl_)
    impl_->unsubscribe();
}

std::string Subscriber::getTopic() const
{
  return impl_ ? impl_->topic : std::string();
}

uint32_t Subscriber::getNumPublishers() const
{
  if (!isValidImpl() || !ddes::live())
    return 0;
  ddes::Writer w = ddes::Writer::request();
  w.u32(impl_->id);
  return ddes::request(ddes::NUM_PUBLISHERS, w).u32();
}

// -- ServiceServer ----------------------------------------------------------------------------

ServiceServer::ServiceServer(const ServiceServer& rhs) : impl_(rhs.impl_) {}
ServiceServer::ServiceServer(const boost::shared_ptr<ddes::ServiceServerImpl>& impl) : impl_(impl) {}
ServiceServer::~ServiceServer() {}

bool ServiceServer::isValidImpl() const
{
  return impl_ && impl_->isValid();
}

void ServiceServer::shutdown()
{
  if (impl_)
    impl_->unadvertise();
}

std::string ServiceServer::getService() const
{
  return impl_ ? impl_->service : std::string();
}

// -- ServiceClient ----------------------------------------------------------------------------

namespace service
{
bool existsIn(const std::string& ns, const std::string& name, bool print_failure_reason);
bool waitForServiceIn(const std::string& ns, const std::string& name, ros::Duration timeout);
}  // namespace service

ServiceClient::ServiceClient(const std::string& service_name, bool persistent, const M_string& header_values,
                             const std::string& service_md5sum)
: impl_(new ddes::ServiceClientImpl)
{
  ddes::requireInit("creating a ServiceClient");
  impl_->ns = ddes::state().ns;
  impl_->name = ddes::nodeRelative(service_name);
  impl_->persistent = persistent;
  impl_->header_values = header_values;
  impl_->md5sum = service_md5sum;
  if (persistent)
    impl_->link_ok = service::existsIn(impl_->ns, impl_->name, false);
}

ServiceClient::ServiceClient(const ServiceClient& rhs) : impl_(rhs.impl_) {}
ServiceClient::~ServiceClient() {}

bool ServiceClient::callBytes(const std::vector<uint8_t>& request, std::vector<uint8_t>& response,
                              const std::string& md5, const std::string& datatype)
{
  if (!impl_ || !ddes::live())
    return false;
  ddes::Writer w = ddes::Writer::request();
  w.str(impl_->ns)
      .str(impl_->name)
      .str(datatype.empty() ? impl_->datatype : datatype)
      .str(md5)
      .blob(request.data(), request.size())
      .u8(impl_->persistent ? 1 : 0);
  try
  {
    ddes::Reader r = ddes::blocking(ddes::CALL, w);
    if (r.u8() == 0)
    {
      r.str();  // roscpp's call() says nothing: the caller reports the failure
      if (impl_->persistent)
        impl_->link_ok = false;
      return false;
    }
    uint32_t n = 0;
    const uint8_t* data = r.blob(n);
    response.assign(data, data + n);
    return true;
  }
  catch (ddes::ReplyError& e)
  {
    ROS_ERROR("%s", e.what());
    if (impl_->persistent)
      impl_->link_ok = false;
    return false;
  }
}

bool ServiceClient::call(const SerializedMessage& req, SerializedMessage& resp, const std::string& service_md5sum)
{
  if (!isValid())
    return false;
  // serializeMessage put the message's u32 length first; message_start points past it
  const uint8_t* begin = req.buf.get();
  const uint8_t* end = begin + req.num_bytes;
  const uint8_t* start = req.message_start ? req.message_start : begin + 4;
  std::vector<uint8_t> request;
  if (start < end)
    request.assign(start, end);
  std::vector<uint8_t> response;
  if (!callBytes(request, response, service_md5sum, impl_->datatype))
    return false;
  boost::shared_array<uint8_t> buf(new uint8_t[response.size() + 1]);
  if (!response.empty())
    std::memcpy(buf.get(), response.data(), response.size());
  resp = SerializedMessage(buf, response.size());
  return true;
}

bool ServiceClient::isValid() const
{
  if (!impl_)
    return false;
  if (!impl_->persistent)
    return true;
  return !impl_->is_shutdown && impl_->link_ok;
}

bool ServiceClient::isPersistent() const
{
  return impl_ && impl_->persistent;
}

void ServiceClient::shutdown()
{
  if (impl_)
    impl_->is_shutdown = true;
}

bool ServiceClient::waitForExistence(ros::Duration timeout)
{
  if (!impl_)
    return false;
  return service::waitForServiceIn(impl_->ns, impl_->name, timeout);
}

bool ServiceClient::exists()
{
  if (!isValid())
    return false;
  return service::existsIn(impl_->ns, impl_->name, false);
}

std::string ServiceClient::getService()
{
  return impl_ ? impl_->resolvedName() : std::string();
}

// -- Timer, WallTimer, SteadyTimer ------------------------------------------------------------

#define DDES_TIMER_HANDLE(Class, PeriodType) \
  Class::Class(const Class& rhs) : impl_(rhs.impl_) {} \
  Class::~Class() {} \
  void Class::start() \
  { \
    if (impl_) \
      impl_->start(); \
  } \
  void Class::stop() \
  { \
    if (impl_) \
      impl_->stop(); \
  } \
  bool Class::hasPending() { return impl_ && impl_->hasPending(); } \
  void Class::setPeriod(const PeriodType& period, bool reset) \
  { \
    if (impl_) \
      impl_->setPeriod(period.toNSec(), reset); \
  } \
  bool Class::hasStarted() const { return impl_ && impl_->started; } \
  bool Class::isValidImpl() const { return impl_ && impl_->period_ns != 0; }

DDES_TIMER_HANDLE(Timer, Duration)
DDES_TIMER_HANDLE(WallTimer, WallDuration)
DDES_TIMER_HANDLE(SteadyTimer, WallDuration)

#undef DDES_TIMER_HANDLE

}  // namespace ros
