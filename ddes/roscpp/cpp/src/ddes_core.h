// ddes roscpp, internal: the lockstep protocol's C++ side (docs/external-nodes.md) and the
// entities (publishers, subscriptions, services, timers) the world calls back.
//
// The process is one thread of execution in the world's eyes.  Every exchange with the world
// happens under one recursive mutex (floorMutex), held from a request's frame to its REPLY,
// the callbacks run meanwhile included; threads of the user's own that call ROS therefore take
// turns (docs/roscpp.md).
#ifndef DDES_ROSCPP_CORE_H
#define DDES_ROSCPP_CORE_H

#include <cstdint>
#include <cstring>
#include <deque>
#include <map>
#include <mutex>
#include <stdexcept>
#include <string>
#include <vector>

#include <boost/enable_shared_from_this.hpp>
#include <boost/shared_ptr.hpp>
#include <boost/weak_ptr.hpp>

#include <ros/advertise_options.h>
#include <ros/callback_queue.h>
#include <ros/callback_queue_interface.h>
#include <ros/forwards.h>
#include <ros/service_callback_helper.h>
#include <ros/subscription_callback_helper.h>

namespace ros
{
namespace ddes
{

/// The protocol version this library speaks.
constexpr uint32_t kVersion = 1;

enum Kind : uint8_t
{
  HELLO = 0x01,
  RESOLVE = 0x02,
  ADVERTISE = 0x03,
  PUBLISH = 0x04,
  UNADVERTISE = 0x05,
  SUBSCRIBE = 0x06,
  UNSUBSCRIBE = 0x07,
  ADVERTISE_SERVICE = 0x08,
  UNADVERTISE_SERVICE = 0x09,
  CALL = 0x0A,
  SERVICE_EXISTS = 0x0B,
  WAIT_FOR_SERVICE = 0x0C,
  NUM_SUBSCRIBERS = 0x0D,
  NUM_PUBLISHERS = 0x0E,
  PUBLISH_ONE = 0x0F,
  PARAM_GET = 0x10,
  PARAM_SET = 0x11,
  PARAM_HAS = 0x12,
  PARAM_DELETE = 0x13,
  PARAM_SEARCH = 0x14,
  PARAM_NAMES = 0x15,
  SLEEP_UNTIL = 0x20,
  SPIN = 0x21,
  SPIN_ONCE = 0x22,
  TIMER_CREATE = 0x23,
  TIMER_CONTROL = 0x24,
  SPINNER = 0x25,
  WAIT_FOR_MESSAGE = 0x26,
  LOG = 0x30,
  LOGGER_LEVEL = 0x31,
  SHUTDOWN = 0x40,
  REQUEST_SHUTDOWN = 0x41,
  CB_DONE = 0x42,
  REPLY = 0x81,
  CALLBACK = 0x90,
  SHUTDOWN_NOTICE = 0x91,
};

/// HELLO's option bits.
enum HelloOption : uint32_t
{
  HELLO_ANONYMOUS = 1,
  HELLO_NO_SIGINT_HANDLER = 2,
  HELLO_NO_ROSOUT = 4,
  HELLO_TIME_ONLY = 8,
};

/// SLEEP_UNTIL's and TIMER_CREATE's clocks.
enum Clock : uint8_t
{
  CLOCK_ROS = 0,
  CLOCK_WALL = 1,
  CLOCK_STEADY = 2,
};

/// A payload, field by field (little-endian).
class Writer
{
public:
  /// A payload that starts with a request id (filled in when it is sent).
  static Writer request()
  {
    Writer w;
    w.u32(0);
    return w;
  }

  Writer& u8(uint8_t v)
  {
    buf_.push_back(static_cast<char>(v));
    return *this;
  }
  Writer& u32(uint32_t v) { return raw(&v, 4); }
  Writer& i32(int32_t v) { return raw(&v, 4); }
  Writer& i64(int64_t v) { return raw(&v, 8); }
  Writer& f64(double v) { return raw(&v, 8); }
  Writer& str(const std::string& s)
  {
    u32(static_cast<uint32_t>(s.size()));
    buf_.append(s);
    return *this;
  }
  Writer& blob(const void* data, size_t n)
  {
    u32(static_cast<uint32_t>(n));
    return raw(data, n);
  }
  Writer& raw(const void* data, size_t n)
  {
    buf_.append(static_cast<const char*>(data), n);
    return *this;
  }

  void setReq(uint32_t req) { std::memcpy(&buf_[0], &req, 4); }
  const std::string& bytes() const { return buf_; }

private:
  std::string buf_;
};

/// A payload the world sent, read field by field; a field past its end is a protocol error.
class Reader
{
public:
  Reader() : pos_(0) {}
  explicit Reader(std::vector<uint8_t> data) : data_(std::move(data)), pos_(0) {}

  uint8_t u8()
  {
    uint8_t v;
    take(&v, 1);
    return v;
  }
  uint32_t u32()
  {
    uint32_t v;
    take(&v, 4);
    return v;
  }
  int32_t i32()
  {
    int32_t v;
    take(&v, 4);
    return v;
  }
  int64_t i64()
  {
    int64_t v;
    take(&v, 8);
    return v;
  }
  double f64()
  {
    double v;
    take(&v, 8);
    return v;
  }
  std::string str()
  {
    uint32_t n = u32();
    const uint8_t* p = view(n);
    return std::string(reinterpret_cast<const char*>(p), n);
  }
  /// A blob's bytes, in place (valid while the Reader lives).
  const uint8_t* blob(uint32_t& n)
  {
    n = u32();
    return view(n);
  }
  std::vector<uint8_t> blobCopy()
  {
    uint32_t n = 0;
    const uint8_t* p = blob(n);
    return std::vector<uint8_t>(p, p + n);
  }
  size_t left() const { return data_.size() - pos_; }

private:
  void take(void* out, size_t n) { std::memcpy(out, view(n), n); }
  const uint8_t* view(size_t n);

  std::vector<uint8_t> data_;
  size_t pos_;
};

/// A status-1 REPLY: the world refused the request; what() is its text.
class ReplyError : public std::runtime_error
{
public:
  explicit ReplyError(const std::string& text) : std::runtime_error(text) {}
};

/// Everything the process knows about its node.
struct NodeState
{
  bool connected = false;     // HELLO answered
  bool time_only = false;     // connected for ros::Time only (no ros::init)
  bool initialized = false;   // ros::init called
  bool started = false;       // ros::start (the first NodeHandle)
  bool ok = false;
  bool shutting_down = false;  // ros::shutdown() or the world's SHUTDOWN_NOTICE
  bool time_initialized = false;  // ros::Time::now() may be used
  bool use_sim_time = false;
  int64_t now_ns = 0;   // the node's ROS time, as the world last said
  int64_t wall_ns = 0;  // the world's kernel time
  uint32_t init_options = 0;
  std::string init_name;
  std::string name = "";
  std::string ns = "/";
  std::vector<std::string> argv;  // the full command line, for HELLO
  M_string remappings;            // this process's command-line remappings, resolved
  M_string unresolved_remappings;
};

NodeState& state();
std::recursive_mutex& floorMutex();

/// Sends HELLO for ros::init (name, roscpp's init options, the whole command line).
void connectNode(const std::string& name, uint32_t options, const std::vector<std::string>& argv);
/// For ros::Time without ros::init: HELLO with the time-only option, once, on first need.
void ensureTimeSource();
/// The command line of this process (/proc/self/cmdline).
std::vector<std::string> processArgv();

/// An immediate request (its first field a request id); returns the REPLY's payload.
/// Throws ReplyError for a status-1 reply.
Reader request(uint8_t kind, Writer& w);
/// An immediate frame without a reply.
void post(uint8_t kind, const Writer& w);
/// PUBLISH without copying the message twice.
void postPublish(uint32_t id, const uint8_t* data, uint32_t len);
/// PUBLISH_ONE (to one subscriber).
void postPublishOne(uint32_t id, const std::string& subscriber, const uint8_t* data, uint32_t len);

/// A blocking request.  While it waits, callbacks of `serve` (and of the queues a started
/// spinner serves) run as the world hands them over; others wait in their queues.  With
/// `just_one`, only the first of `serve`'s callbacks runs (CallbackQueue::callOne).  `ran`:
/// how many of `serve`'s callbacks ran.
Reader blocking(uint8_t kind, Writer& w, CallbackQueueInterface* serve = 0, bool just_one = false,
                size_t* ran = 0);

/// Whether frames to the world still make sense (connected, not shut down).
bool live();
/// Sleeps until `t_ns` on `clock` (SLEEP_UNTIL); false if the node shut down first.
bool sleepUntil(uint8_t clock, int64_t t_ns, CallbackQueueInterface* serve = 0, bool just_one = false,
                size_t* ran = 0);

/// A started spinner serves `queue` (SPINNER start/stop, counted); a null queue only keeps
/// the world's spinner running (a timed wait of CallbackQueue).
void spinnerStart(CallbackQueueInterface* queue, uint32_t threads);
void spinnerStop(CallbackQueueInterface* queue);
/// Whether a started spinner serves `queue`.
bool spinnerServes(CallbackQueueInterface* queue);

/// The node is down: ros::ok() false, the global queue disabled, logging off (roscpp's
/// ros::shutdown(), also when the last NodeHandle goes).
void markShutdown();
/// The world's node is down for good (SHUTDOWN sent, or SHUTDOWN_NOTICE received).
void setWorldDown();
bool worldDown();

/// A name as the world should read it from the node's own namespace: "~x" made absolute
/// (the node's private namespace), others as they are.  Throws InvalidNameException.
std::string nodeRelative(const std::string& name);
/// RESOLVE: `name` in `ns`, remapped by the world (cached).
std::string resolveRemote(const std::string& ns, const std::string& name);

/// "You must call ros::init() before ..." and a breakpoint, as roscpp.
void requireInit(const char* what);

/// The queue object behind ros::getGlobalCallbackQueue().
CallbackQueue* globalQueue();

/// Runs the callbacks waiting in `queue` (if it is a ros::CallbackQueue); how many ran.
struct QueueAccess
{
  static size_t callLocal(CallbackQueueInterface* queue, bool just_one);
};

/// Counts NodeHandles (and the handles that keep a node alive): the first starts the node,
/// the last stops it when a NodeHandle started it (roscpp's rule).
class NodeRef
{
public:
  NodeRef();
  ~NodeRef();
  NodeRef(const NodeRef&) = delete;
  NodeRef& operator=(const NodeRef&) = delete;
};
typedef boost::shared_ptr<NodeRef> NodeRefPtr;

// -- entities -----------------------------------------------------------------------------

/// A callback waiting in a queue until the queue is called.
class DeferredCallback : public CallbackInterface
{
public:
  explicit DeferredCallback(boost::function<CallResult()> fn) : fn_(fn), dropped_(false) {}
  virtual CallResult call() { return dropped_ ? Invalid : fn_(); }
  void drop() { dropped_ = true; }

private:
  boost::function<CallResult()> fn_;
  bool dropped_;
};
typedef boost::shared_ptr<DeferredCallback> DeferredCallbackPtr;

class PublisherImpl : public boost::enable_shared_from_this<PublisherImpl>
{
public:
  ~PublisherImpl();
  void unadvertise();
  bool isValid() const { return !unadvertised; }
  /// A peer callback (`connected`: 4, else 5).
  void peer(bool connected, const std::string& subscriber);

  uint32_t id = 0;
  std::string topic, md5sum, datatype;
  bool latch = false;
  SubscriberStatusCallback connect_cb, disconnect_cb;
  CallbackQueueInterface* callback_queue = 0;
  bool has_tracked_object = false;
  VoidConstWPtr tracked_object;
  bool unadvertised = false;
  NodeRefPtr node_ref;
};

class SubscriberImpl : public boost::enable_shared_from_this<SubscriberImpl>
{
public:
  ~SubscriberImpl();
  void unsubscribe();
  bool isValid() const { return !unsubscribed; }
  /// Deserializes and calls the user's callback.
  void deliver(const uint8_t* data, uint32_t len, const std::string& caller, int64_t receipt_ns);
  /// Keeps a callback waiting in the queue, dropping the oldest beyond queue_size.
  void deferred(const DeferredCallbackPtr& cb);

  uint32_t id = 0;
  std::string topic, md5sum, datatype;
  uint32_t queue_size = 0;
  SubscriptionCallbackHelperPtr helper;
  CallbackQueueInterface* callback_queue = 0;
  bool has_tracked_object = false;
  VoidConstWPtr tracked_object;
  bool unsubscribed = false;
  NodeRefPtr node_ref;
  std::deque<boost::weak_ptr<DeferredCallback> > waiting;
};

class ServiceServerImpl
{
public:
  ~ServiceServerImpl();
  void unadvertise();
  bool isValid() const { return !unadvertised; }
  /// Runs the handler: ok and the response's bytes, or not ok and a text (empty: it
  /// returned false).
  bool serve(const uint8_t* data, uint32_t len, const std::string& caller, std::vector<uint8_t>& response,
             std::string& error);

  uint32_t id = 0;
  std::string service;
  ServiceCallbackHelperPtr helper;
  bool has_tracked_object = false;
  VoidConstWPtr tracked_object;
  bool unadvertised = false;
  NodeRefPtr node_ref;
};

class ServiceClientImpl
{
public:
  std::string ns;       // the namespace the name is read in
  std::string name;     // as given (validated)
  std::string resolved;  // cached RESOLVE answer
  std::string md5sum, datatype;
  bool persistent = false;
  bool link_ok = true;   // a persistent client's connection
  bool is_shutdown = false;
  M_string header_values;
  NodeRefPtr node_ref;

  const std::string& resolvedName();
};

/// The times of a timer callback, as the world sends them (-1: none).
struct TimerTimes
{
  int64_t last_expected, last_real, current_expected, current_real, last_duration;
};

class TimerImpl : public boost::enable_shared_from_this<TimerImpl>
{
public:
  ~TimerImpl();
  void start();
  void stop();
  void setPeriod(int64_t period_ns, bool reset);
  bool hasPending();
  void fire(const TimerTimes& t);

  uint8_t clock = CLOCK_ROS;
  uint32_t id = 0;
  bool created = false;
  int64_t period_ns = 0;
  bool oneshot = false;
  bool started = false;
  int64_t next_expected_ns = 0;
  int waiting = 0;  // callbacks waiting in a queue
  TimerCallback ros_cb;
  WallTimerCallback wall_cb;
  SteadyTimerCallback steady_cb;
  CallbackQueueInterface* callback_queue = 0;
  bool has_tracked_object = false;
  VoidConstWPtr tracked_object;
  NodeRefPtr node_ref;
};

void registerPublisher(const boost::shared_ptr<PublisherImpl>& p);
void registerSubscriber(const boost::shared_ptr<SubscriberImpl>& s);
void registerService(const boost::shared_ptr<ServiceServerImpl>& s);
void registerTimer(const boost::shared_ptr<TimerImpl>& t);
void unregisterPublisher(uint32_t id);
void unregisterSubscriber(uint32_t id);
void unregisterService(uint32_t id);
void unregisterTimer(uint32_t id);
/// The resolved topics of the live publishers / subscriptions.
void advertisedTopics(V_string& out);
void subscribedTopics(V_string& out);

/// The text of a caught exception, for CB_DONE.
std::string exceptionText();

}  // namespace ddes
}  // namespace ros

#endif  // DDES_ROSCPP_CORE_H
