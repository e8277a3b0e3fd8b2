// ddes roscpp: the transport of the lockstep protocol (docs/external-nodes.md) and the
// dispatch of the world's callbacks.
//
// The process speaks only when it has the floor.  A request is one frame; an immediate one's
// REPLY comes at once, a blocking one's when the world is done (meanwhile the world may hand
// over callbacks: each runs here to its end and is closed with CB_DONE, nesting as the
// process's stack does).  An exception that leaves a callback leaves the blocking call it ran
// in, as in roscpp (where it leaves ros::spin()): the callback is closed with CB_DONE ok 2,
// the world answers the interrupted request at once, callbacks that still arrive meanwhile wait
// in their queues, and the exception is raised again when the REPLY is read.
#include "ddes_core.h"

#include <cctype>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <fstream>
#include <set>
#include <sstream>

#include <sys/uio.h>
#include <unistd.h>

#include <ros/console.h>
#include <ros/init.h>
#include <ros/names.h>
#include <ros/single_subscriber_publisher.h>

namespace ros
{
namespace ddes
{

namespace
{

constexpr uint32_t kMaxPayload = 256u * 1024u * 1024u;

struct Context
{
  CallbackQueueInterface* queue;
  bool just_one;
  size_t ran;
  std::exception_ptr thrown;  // a callback's exception, raised again after the REPLY
};

struct Transport
{
  int rfd = -1;
  int wfd = -1;
  uint32_t next_req = 1;
  std::vector<Context*> contexts;
  Context async_context = {0, false, 0, std::exception_ptr()};
  std::map<CallbackQueueInterface*, int> async_queues;
  int async_total = 0;
  bool world_down = false;  // SHUTDOWN_NOTICE, or our SHUTDOWN
  bool exiting = false;     // after main returned: send nothing more
  bool shutdown_requested = false;

  std::map<uint32_t, boost::weak_ptr<PublisherImpl> > pubs;
  std::map<uint32_t, boost::weak_ptr<SubscriberImpl> > subs;
  std::map<uint32_t, boost::weak_ptr<ServiceServerImpl> > services;
  std::map<uint32_t, boost::weak_ptr<TimerImpl> > timers;
};

Transport& transport()
{
  static Transport* t = new Transport;  // never destroyed: static destructors may still send
  return *t;
}

volatile std::sig_atomic_t g_sigint = 0;

/// DDES_ROSCPP_TRACE=1: every frame's kind and size on stderr (a debugging aid).
bool tracing()
{
  static const bool on = [] {
    const char* v = std::getenv("DDES_ROSCPP_TRACE");
    return v && *v && std::strcmp(v, "0") != 0;
  }();
  return on;
}

void onSigint(int)
{
  g_sigint = 1;
}

void onExit()
{
  transport().exiting = true;
}

[[noreturn]] void protocolError(const std::string& what)
{
  std::fflush(stdout);
  std::fprintf(stderr, "[ddes] protocol error: %s\n", what.c_str());
  std::fflush(stderr);
  std::_Exit(1);
}

/// The world closed the pipe: it has ended (or stopped this node); nothing is left to do.
[[noreturn]] void worldGone()
{
  std::fflush(stdout);
  std::fflush(stderr);
  std::_Exit(0);
}

void writeAll(struct iovec* iov, int count)
{
  // whatever the process printed goes out before the frame, so the world reads it first
  std::fflush(stdout);
  std::fflush(stderr);
  Transport& t = transport();
  while (count > 0)
  {
    ssize_t n = ::writev(t.wfd, iov, count);
    if (n < 0)
    {
      if (errno == EINTR)
        continue;
      worldGone();
    }
    size_t left = static_cast<size_t>(n);
    while (count > 0 && left >= iov->iov_len)
    {
      left -= iov->iov_len;
      ++iov;
      --count;
    }
    if (count > 0)
    {
      iov->iov_base = static_cast<char*>(iov->iov_base) + left;
      iov->iov_len -= left;
    }
  }
}

void writeFrame(uint8_t kind, const void* payload, size_t size, const void* extra = 0, size_t extra_size = 0)
{
  if (size + extra_size > kMaxPayload)
    protocolError("a frame of " + std::to_string(size + extra_size) + " bytes is over the protocol's 256 MiB");
  if (tracing())
    std::fprintf(stderr, "[ddes trace] -> 0x%02x %zu bytes\n", kind, size + extra_size);
  unsigned char head[7] = {'D', 'X', kind, 0, 0, 0, 0};
  uint32_t len = static_cast<uint32_t>(size + extra_size);
  std::memcpy(head + 3, &len, 4);
  struct iovec iov[3];
  iov[0].iov_base = head;
  iov[0].iov_len = 7;
  iov[1].iov_base = const_cast<void*>(payload);
  iov[1].iov_len = size;
  iov[2].iov_base = const_cast<void*>(extra);
  iov[2].iov_len = extra_size;
  writeAll(iov, extra_size ? 3 : 2);
}

void readExact(void* out, size_t n)
{
  char* p = static_cast<char*>(out);
  while (n > 0)
  {
    ssize_t got = ::read(transport().rfd, p, n);
    if (got < 0)
    {
      if (errno == EINTR)
        continue;
      worldGone();
    }
    if (got == 0)
      worldGone();
    p += got;
    n -= static_cast<size_t>(got);
  }
}

void readFrame(uint8_t& kind, std::vector<uint8_t>& payload)
{
  unsigned char head[7];
  readExact(head, 7);
  if (head[0] != 'D' || head[1] != 'X')
    protocolError("a frame from the world must start with DX");
  kind = head[2];
  uint32_t len;
  std::memcpy(&len, head + 3, 4);
  if (len > kMaxPayload)
    protocolError("a frame of " + std::to_string(len) + " bytes from the world");
  payload.resize(len);
  if (len)
    readExact(payload.data(), len);
  if (tracing())
    std::fprintf(stderr, "[ddes trace] <- 0x%02x %u bytes\n", kind, len);
}

void setTimes(int64_t now, int64_t wall)
{
  state().now_ns = now;
  state().wall_ns = wall;
}

void checkSigint()
{
  Transport& t = transport();
  if (g_sigint && !t.shutdown_requested && state().connected && !t.world_down)
  {
    t.shutdown_requested = true;
    Writer w;
    w.str("");
    writeFrame(REQUEST_SHUTDOWN, w.bytes().data(), w.bytes().size());
  }
}

/// CB_DONE's `ok`: 1 done, 0 a service that failed, 2 an exception leaves the callback.
enum Done : uint8_t
{
  DONE_FAILED = 0,
  DONE_OK = 1,
  DONE_THREW = 2,
};

void sendDone(uint32_t cb, uint8_t ok, const void* data, size_t n)
{
  Writer w;
  w.u32(cb).u8(ok).blob(data, n);
  writeFrame(CB_DONE, w.bytes().data(), w.bytes().size());
}

/// The context that serves `queue` now, or null (its callbacks wait in the queue).
Context* servingContext(CallbackQueueInterface* queue)
{
  Transport& t = transport();
  if (!t.contexts.empty() && t.contexts.back()->thrown)
    return 0;  // the request is being left by an exception: what comes now waits
  for (auto it = t.contexts.rbegin(); it != t.contexts.rend(); ++it)
  {
    if ((*it)->queue == queue)
    {
      if ((*it)->just_one && (*it)->ran >= 1)
        return 0;
      return *it;
    }
  }
  auto a = t.async_queues.find(queue);
  if (a != t.async_queues.end() && a->second > 0)
    return &t.async_context;
  return 0;
}

template <class T>
boost::shared_ptr<T> lookup(std::map<uint32_t, boost::weak_ptr<T> >& table, uint32_t id)
{
  auto it = table.find(id);
  return it == table.end() ? boost::shared_ptr<T>() : it->second.lock();
}

void onMessage(uint32_t entity, Reader& r)
{
  const std::string caller = r.str();
  const int64_t receipt = r.i64();
  uint32_t n = 0;
  const uint8_t* data = r.blob(n);
  boost::shared_ptr<SubscriberImpl> sub = lookup(transport().subs, entity);
  if (!sub || !sub->isValid())
    return;
  if (Context* c = servingContext(sub->callback_queue))
  {
    ++c->ran;
    sub->deliver(data, n, caller, receipt);
    return;
  }
  boost::shared_ptr<std::vector<uint8_t> > bytes(new std::vector<uint8_t>(data, data + n));
  boost::weak_ptr<SubscriberImpl> weak = sub;
  sub->deferred(boost::make_shared<DeferredCallback>([weak, bytes, caller, receipt]() {
    boost::shared_ptr<SubscriberImpl> s = weak.lock();
    if (!s || !s->isValid())
      return CallbackInterface::Invalid;
    s->deliver(bytes->data(), static_cast<uint32_t>(bytes->size()), caller, receipt);
    return CallbackInterface::Success;
  }));
}

void onTimer(uint32_t entity, Reader& r)
{
  TimerTimes times;
  times.last_expected = r.i64();
  times.last_real = r.i64();
  times.current_expected = r.i64();
  times.current_real = r.i64();
  times.last_duration = r.i64();
  boost::shared_ptr<TimerImpl> timer = lookup(transport().timers, entity);
  if (!timer || !timer->started)
    return;
  if (Context* c = servingContext(timer->callback_queue))
  {
    ++c->ran;
    timer->fire(times);
    return;
  }
  ++timer->waiting;
  boost::weak_ptr<TimerImpl> weak = timer;
  timer->callback_queue->addCallback(boost::make_shared<DeferredCallback>([weak, times]() {
    boost::shared_ptr<TimerImpl> tm = weak.lock();
    if (!tm)
      return CallbackInterface::Invalid;
    --tm->waiting;
    if (!tm->started)
      return CallbackInterface::Invalid;
    tm->fire(times);
    return CallbackInterface::Success;
  }), reinterpret_cast<uint64_t>(timer.get()));
}

void onPeer(bool connected, uint32_t entity, Reader& r)
{
  const std::string subscriber = r.str();
  boost::shared_ptr<PublisherImpl> pub = lookup(transport().pubs, entity);
  if (!pub || !pub->isValid())
    return;
  if (Context* c = servingContext(pub->callback_queue))
  {
    ++c->ran;
    pub->peer(connected, subscriber);
    return;
  }
  boost::weak_ptr<PublisherImpl> weak = pub;
  pub->callback_queue->addCallback(boost::make_shared<DeferredCallback>([weak, connected, subscriber]() {
    boost::shared_ptr<PublisherImpl> p = weak.lock();
    if (!p || !p->isValid())
      return CallbackInterface::Invalid;
    p->peer(connected, subscriber);
    return CallbackInterface::Success;
  }), reinterpret_cast<uint64_t>(pub.get()));
}

void dispatchCallback(Reader& r)
{
  const uint32_t cb = r.u32();
  const uint8_t what = r.u8();
  const uint32_t entity = r.u32();
  const int64_t now = r.i64();
  const int64_t wall = r.i64();
  setTimes(now, wall);
  try
  {
    switch (what)
    {
      case 1:
        onMessage(entity, r);
        break;
      case 2:
        onTimer(entity, r);
        break;
      case 3:
      {
        const std::string caller = r.str();
        uint32_t n = 0;
        const uint8_t* data = r.blob(n);
        boost::shared_ptr<ServiceServerImpl> srv = lookup(transport().services, entity);
        std::vector<uint8_t> response;
        std::string error;
        bool ok = false;
        if (srv && srv->isValid())
        {
          // a request runs whatever queue the server named: the world waits for the answer
          ok = srv->serve(data, n, caller, response, error);
        }
        if (ok)
          sendDone(cb, DONE_OK, response.data(), response.size());
        else
          sendDone(cb, DONE_FAILED, error.data(), error.size());
        return;
      }
      case 4:
      case 5:
        onPeer(what == 4, entity, r);
        break;
      default:
        protocolError("CALLBACK of unknown kind " + std::to_string(what));
    }
  }
  catch (...)
  {
    // roscpp lets it leave ros::spin() (a service's std::exception was caught in serve())
    const std::string text = exceptionText();
    Transport& t = transport();
    if (!t.contexts.empty() && !t.contexts.back()->thrown)
      t.contexts.back()->thrown = std::current_exception();
    sendDone(cb, DONE_THREW, text.data(), text.size());
    if (t.contexts.empty())
      throw;  // not inside a blocking request (cannot happen): on up the stack at once
    return;
  }
  sendDone(cb, DONE_OK, 0, 0);
}

/// Reads frames until the REPLY to `req`, running the callbacks the world hands over.
Reader waitReply(uint32_t req)
{
  Transport& t = transport();
  for (;;)
  {
    uint8_t kind = 0;
    std::vector<uint8_t> payload;
    readFrame(kind, payload);
    Reader r(std::move(payload));
    if (kind == REPLY)
    {
      const uint32_t got = r.u32();
      const int64_t now = r.i64();
      const int64_t wall = r.i64();
      setTimes(now, wall);
      const uint8_t status = r.u8();
      if (got != req)
        protocolError("REPLY to request " + std::to_string(got) + " while request " + std::to_string(req) +
                      " waits");
      if (status != 0)
        throw ReplyError(r.str());
      return r;
    }
    if (kind == CALLBACK)
    {
      dispatchCallback(r);
      continue;
    }
    if (kind == SHUTDOWN_NOTICE)
    {
      const int64_t now = r.i64();
      const int64_t wall = r.i64();
      setTimes(now, wall);
      t.world_down = true;
      markShutdown();
      continue;
    }
    protocolError("unexpected frame kind " + std::to_string(kind) + " from the world");
  }
}

void openTransport()
{
  const char* fds = std::getenv("DDES_NODE_FDS");
  if (!fds)
  {
    std::fflush(stdout);
    std::fprintf(stderr,
                 "[ddes] this node must be started by ddes (rosrun, roslaunch, ddes run): DDES_NODE_FDS is not set\n");
    std::fflush(stderr);
    std::exit(1);
  }
  int r = -1, w = -1;
  if (std::sscanf(fds, "%d,%d", &r, &w) != 2 || r < 0 || w < 0)
  {
    std::fprintf(stderr, "[ddes] DDES_NODE_FDS must be \"R,W\" (two descriptors), got \"%s\"\n", fds);
    std::exit(1);
  }
  Transport& t = transport();
  t.rfd = r;
  t.wfd = w;
  std::signal(SIGPIPE, SIG_IGN);
  std::atexit(onExit);
}

void hello(const std::string& name, uint32_t options, const std::vector<std::string>& argv)
{
  openTransport();
  Writer w;
  w.u32(kVersion).str(name).u32(options).u32(static_cast<uint32_t>(argv.size()));
  for (const std::string& a : argv)
    w.str(a);
  writeFrame(HELLO, w.bytes().data(), w.bytes().size());
  NodeState& s = state();
  try
  {
    Reader r = waitReply(0);
    s.name = r.str();
    s.ns = r.str();
    s.use_sim_time = r.u8() != 0;
    uint32_t argc = r.u32();
    for (uint32_t i = 0; i < argc; ++i)
      r.str();  // the command line without ROS's arguments: ros::init computes the same
  }
  catch (ReplyError& e)
  {
    std::fflush(stdout);
    std::fprintf(stderr, "[ddes] %s\n", e.what());
    std::fflush(stderr);
    std::exit(1);
  }
  s.connected = true;
}

std::string programName(const std::vector<std::string>& argv)
{
  std::string base = argv.empty() ? std::string("node") : argv[0];
  size_t slash = base.find_last_of('/');
  if (slash != std::string::npos)
    base = base.substr(slash + 1);
  std::string out;
  for (char c : base)
    out += (std::isalnum(static_cast<unsigned char>(c)) || c == '_') ? c : '_';
  if (out.empty() || !std::isalpha(static_cast<unsigned char>(out[0])))
    out = "n" + out;
  return out;
}

}  // namespace

const uint8_t* Reader::view(size_t n)
{
  if (n > data_.size() - pos_)
    protocolError("a frame from the world ends inside a field");
  const uint8_t* p = data_.data() + pos_;
  pos_ += n;
  return p;
}

NodeState& state()
{
  static NodeState* s = new NodeState;
  return *s;
}

std::recursive_mutex& floorMutex()
{
  static std::recursive_mutex* m = new std::recursive_mutex;
  return *m;
}

std::vector<std::string> processArgv()
{
  std::vector<std::string> out;
  std::ifstream in("/proc/self/cmdline", std::ios::binary);
  std::string arg;
  while (std::getline(in, arg, '\0'))
    out.push_back(arg);
  return out;
}

void connectNode(const std::string& name, uint32_t options, const std::vector<std::string>& argv)
{
  std::lock_guard<std::recursive_mutex> lock(floorMutex());
  NodeState& s = state();
  if (s.connected)
  {
    if (s.time_only)
      std::fprintf(stderr, "[ddes] ros::init after ros::Time was used without it: this process stays the "
                           "clock-only node it joined the world as\n");
    return;
  }
  uint32_t hello_options = 0;
  if (options & init_options::AnonymousName)
    hello_options |= HELLO_ANONYMOUS;
  if (options & init_options::NoSigintHandler)
    hello_options |= HELLO_NO_SIGINT_HANDLER;
  if (options & init_options::NoRosout)
    hello_options |= HELLO_NO_ROSOUT;
  hello(name, hello_options, argv);
  if (!(options & init_options::NoSigintHandler))
    std::signal(SIGINT, onSigint);
}

void ensureTimeSource()
{
  std::lock_guard<std::recursive_mutex> lock(floorMutex());
  NodeState& s = state();
  if (s.connected)
    return;
  std::vector<std::string> argv = processArgv();
  s.time_only = true;
  hello(programName(argv), HELLO_TIME_ONLY, argv);
}

Reader request(uint8_t kind, Writer& w)
{
  std::lock_guard<std::recursive_mutex> lock(floorMutex());
  Transport& t = transport();
  checkSigint();
  const uint32_t req = t.next_req++;
  w.setReq(req);
  writeFrame(kind, w.bytes().data(), w.bytes().size());
  return waitReply(req);
}

void post(uint8_t kind, const Writer& w)
{
  std::lock_guard<std::recursive_mutex> lock(floorMutex());
  checkSigint();
  writeFrame(kind, w.bytes().data(), w.bytes().size());
}

void postPublish(uint32_t id, const uint8_t* data, uint32_t len)
{
  std::lock_guard<std::recursive_mutex> lock(floorMutex());
  checkSigint();
  Writer w;
  w.u32(id).u32(len);
  writeFrame(PUBLISH, w.bytes().data(), w.bytes().size(), data, len);
}

void postPublishOne(uint32_t id, const std::string& subscriber, const uint8_t* data, uint32_t len)
{
  std::lock_guard<std::recursive_mutex> lock(floorMutex());
  checkSigint();
  Writer w;
  w.u32(id).str(subscriber).u32(len);
  writeFrame(PUBLISH_ONE, w.bytes().data(), w.bytes().size(), data, len);
}

Reader blocking(uint8_t kind, Writer& w, CallbackQueueInterface* serve, bool just_one, size_t* ran)
{
  std::lock_guard<std::recursive_mutex> lock(floorMutex());
  Transport& t = transport();
  // what a started spinner serves and already waits here runs first, as its threads would
  if (t.async_total > 0)
  {
    std::vector<CallbackQueueInterface*> served;
    for (auto& q : t.async_queues)
      if (q.second > 0)
        served.push_back(q.first);
    for (CallbackQueueInterface* q : served)
      QueueAccess::callLocal(q, false);
  }
  Context ctx = {serve, just_one, 0, std::exception_ptr()};
  t.contexts.push_back(&ctx);
  struct Pop
  {
    ~Pop() { transport().contexts.pop_back(); }
  } pop;
  Reader r;
  try
  {
    r = request(kind, w);
  }
  catch (ReplyError&)
  {
    if (!ctx.thrown)
      throw;  // (the world answers an interrupted request with an error: the exception wins)
  }
  if (ran)
    *ran = ctx.ran;
  if (ctx.thrown)
    std::rethrow_exception(ctx.thrown);
  return r;
}

bool live()
{
  const Transport& t = transport();
  return state().connected && !t.world_down && !t.exiting;
}

bool sleepUntil(uint8_t clock, int64_t t_ns, CallbackQueueInterface* serve, bool just_one, size_t* ran)
{
  std::lock_guard<std::recursive_mutex> lock(floorMutex());
  ensureTimeSource();
  if (transport().exiting)
    return false;
  Writer w = Writer::request();
  w.u8(clock).i64(t_ns);
  Reader r = blocking(SLEEP_UNTIL, w, serve, just_one, ran);
  return r.u8() != 0;
}

void spinnerStart(CallbackQueueInterface* queue, uint32_t threads)
{
  std::lock_guard<std::recursive_mutex> lock(floorMutex());
  Transport& t = transport();
  const bool first = t.async_total == 0;
  ++t.async_queues[queue];
  ++t.async_total;
  if ((first || queue != 0) && live())
  {
    Writer w = Writer::request();
    w.u8(0).u32(threads);
    request(SPINNER, w);
  }
}

void spinnerStop(CallbackQueueInterface* queue)
{
  std::lock_guard<std::recursive_mutex> lock(floorMutex());
  Transport& t = transport();
  auto it = t.async_queues.find(queue);
  if (it == t.async_queues.end() || it->second <= 0)
    return;
  if (--it->second == 0)
    t.async_queues.erase(it);
  if (--t.async_total == 0 && live())
  {
    Writer w = Writer::request();
    w.u8(1).u32(0);
    request(SPINNER, w);
  }
}

bool spinnerServes(CallbackQueueInterface* queue)
{
  std::lock_guard<std::recursive_mutex> lock(floorMutex());
  if (!queue)
    return false;
  Transport& t = transport();
  auto it = t.async_queues.find(queue);
  return it != t.async_queues.end() && it->second > 0;
}

void markShutdown()
{
  NodeState& s = state();
  s.ok = false;
  s.shutting_down = true;
  s.started = false;
  ros::console::shutdown();
  if (CallbackQueue* q = globalQueue())
  {
    q->disable();
    q->clear();
  }
}

void setWorldDown()
{
  transport().world_down = true;
}

bool worldDown()
{
  return transport().world_down;
}

void registerPublisher(const boost::shared_ptr<PublisherImpl>& p) { transport().pubs[p->id] = p; }
void registerSubscriber(const boost::shared_ptr<SubscriberImpl>& s) { transport().subs[s->id] = s; }
void registerService(const boost::shared_ptr<ServiceServerImpl>& s) { transport().services[s->id] = s; }
void registerTimer(const boost::shared_ptr<TimerImpl>& t) { transport().timers[t->id] = t; }
void unregisterPublisher(uint32_t id) { transport().pubs.erase(id); }
void unregisterSubscriber(uint32_t id) { transport().subs.erase(id); }
void unregisterService(uint32_t id) { transport().services.erase(id); }
void unregisterTimer(uint32_t id) { transport().timers.erase(id); }

void advertisedTopics(V_string& out)
{
  std::lock_guard<std::recursive_mutex> lock(floorMutex());
  std::set<std::string> seen;
  for (auto& p : transport().pubs)
    if (boost::shared_ptr<PublisherImpl> pub = p.second.lock())
      if (pub->isValid() && seen.insert(pub->topic).second)
        out.push_back(pub->topic);
}

void subscribedTopics(V_string& out)
{
  std::lock_guard<std::recursive_mutex> lock(floorMutex());
  std::set<std::string> seen;
  for (auto& p : transport().subs)
    if (boost::shared_ptr<SubscriberImpl> sub = p.second.lock())
      if (sub->isValid() && seen.insert(sub->topic).second)
        out.push_back(sub->topic);
}

std::string exceptionText()
{
  try
  {
    throw;
  }
  catch (std::exception& e)
  {
    return e.what();
  }
  catch (...)
  {
    return "unknown exception";
  }
}

void requireInit(const char* what)
{
  if (state().initialized)
    return;
  ROS_FATAL("You must call ros::init() before %s", what);
  ROS_BREAK();
  std::abort();
}

size_t QueueAccess::callLocal(CallbackQueueInterface* queue, bool just_one)
{
  CallbackQueue* q = dynamic_cast<CallbackQueue*>(queue);
  return q ? q->callLocal(just_one) : 0;
}

}  // namespace ddes
}  // namespace ros
