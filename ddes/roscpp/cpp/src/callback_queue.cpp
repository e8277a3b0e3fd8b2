// ddes roscpp: ros::CallbackQueue and the spinners (see callback_queue.h and spinner.h).
#include "ddes_core.h"

#include <stdexcept>
#include <thread>

#include <ros/callback_queue.h>
#include <ros/console.h>
#include <ros/init.h>
#include <ros/node_handle.h>
#include <ros/spinner.h>

namespace ros
{

namespace
{

/// Waits up to `timeout` of wall time, running `queue`'s callbacks as the world hands them
/// over (the world's spinner serves the node meanwhile); how many of them ran.
size_t timedWait(CallbackQueueInterface* queue, const WallDuration& timeout, bool just_one)
{
  std::lock_guard<std::recursive_mutex> lock(ddes::floorMutex());
  ddes::spinnerStart(0, 1);
  size_t ran = 0;
  try
  {
    ddes::sleepUntil(ddes::CLOCK_WALL, ddes::state().wall_ns + timeout.toNSec(), queue, just_one, &ran);
  }
  catch (...)
  {
    ddes::spinnerStop(0);
    throw;
  }
  ddes::spinnerStop(0);
  return ran;
}

}  // namespace

CallbackQueue::CallbackQueue(bool enabled) : enabled_(enabled) {}

CallbackQueue::~CallbackQueue()
{
  disable();
}

void CallbackQueue::addCallback(const CallbackInterfacePtr& callback, uint64_t removal_id)
{
  std::lock_guard<std::recursive_mutex> lock(ddes::floorMutex());
  if (!enabled_)
    return;
  CallbackInfo info;
  info.callback = callback;
  info.removal_id = removal_id;
  callbacks_.push_back(info);
}

void CallbackQueue::removeByID(uint64_t removal_id)
{
  std::lock_guard<std::recursive_mutex> lock(ddes::floorMutex());
  for (D_CallbackInfo::iterator it = callbacks_.begin(); it != callbacks_.end();)
  {
    if (it->removal_id == removal_id)
      it = callbacks_.erase(it);
    else
      ++it;
  }
}

size_t CallbackQueue::callLocal(bool just_one, bool* tried_again)
{
  std::lock_guard<std::recursive_mutex> lock(ddes::floorMutex());
  size_t ran = 0;
  // only what waits now: callbacks queued by these callbacks wait for the next call
  size_t n = callbacks_.size();
  for (size_t i = 0; i < n && !callbacks_.empty() && enabled_; ++i)
  {
    CallbackInfo info = callbacks_.front();
    callbacks_.pop_front();
    if (info.marked_for_removal)
      continue;
    if (!info.callback->ready())
    {
      callbacks_.push_back(info);
      if (tried_again)
        *tried_again = true;
      continue;
    }
    CallbackInterface::CallResult result = info.callback->call();
    if (result == CallbackInterface::TryAgain)
    {
      callbacks_.push_back(info);
      if (tried_again)
        *tried_again = true;
      continue;
    }
    if (result == CallbackInterface::Success)
    {
      ++ran;
      if (just_one)
        break;
    }
  }
  return ran;
}

CallbackQueue::CallOneResult CallbackQueue::callOne(ros::WallDuration timeout)
{
  std::lock_guard<std::recursive_mutex> lock(ddes::floorMutex());
  if (!enabled_)
    return Disabled;
  bool tried_again = false;
  if (callLocal(true, &tried_again) > 0)
    return Called;
  if (ddes::state().connected && ros::ok())
  {
    size_t got = 0;
    ddes::Writer w = ddes::Writer::request();
    ddes::blocking(ddes::SPIN_ONCE, w, this, true, &got);
    if (got > 0)
      return Called;
    if (timeout > WallDuration(0) && ros::ok() && timedWait(this, timeout, true) > 0)
      return Called;
  }
  return tried_again ? TryAgain : Empty;
}

void CallbackQueue::callAvailable(ros::WallDuration timeout)
{
  std::lock_guard<std::recursive_mutex> lock(ddes::floorMutex());
  if (!enabled_)
    return;
  size_t ran = callLocal(false);
  if (!ddes::state().connected || !ros::ok() || !enabled_)
    return;
  size_t got = 0;
  ddes::Writer w = ddes::Writer::request();
  ddes::blocking(ddes::SPIN_ONCE, w, this, false, &got);
  ran += got;
  if (ran == 0 && timeout > WallDuration(0) && ros::ok())
    timedWait(this, timeout, false);
}

bool CallbackQueue::isEmpty()
{
  std::lock_guard<std::recursive_mutex> lock(ddes::floorMutex());
  return callbacks_.empty();
}

void CallbackQueue::clear()
{
  std::lock_guard<std::recursive_mutex> lock(ddes::floorMutex());
  callbacks_.clear();
}

void CallbackQueue::enable()
{
  std::lock_guard<std::recursive_mutex> lock(ddes::floorMutex());
  enabled_ = true;
}

void CallbackQueue::disable()
{
  std::lock_guard<std::recursive_mutex> lock(ddes::floorMutex());
  enabled_ = false;
}

bool CallbackQueue::isEnabled()
{
  std::lock_guard<std::recursive_mutex> lock(ddes::floorMutex());
  return enabled_;
}

// -- spinners -----------------------------------------------------------------------------------

namespace
{

/// roscpp's SpinnerMonitor: a queue is spun by one single-threaded spinner (on one thread) or
/// by any number of multi-threaded ones, never both.
struct SpinnerMonitor
{
  struct Entry
  {
    std::thread::id tid;  // a single-threaded spinner's thread; default for multi-threaded
    unsigned num = 0;
  };
  std::map<CallbackQueue*, Entry> queues;

  bool add(CallbackQueue* queue, bool single_threaded)
  {
    std::thread::id tid;
    if (single_threaded)
      tid = std::this_thread::get_id();
    std::map<CallbackQueue*, Entry>::iterator it = queues.find(queue);
    if (it != queues.end() && it->second.tid != tid)
      return false;
    if (it == queues.end())
    {
      Entry e;
      e.tid = tid;
      it = queues.insert(std::make_pair(queue, e)).first;
    }
    ++it->second.num;
    return true;
  }

  void remove(CallbackQueue* queue)
  {
    std::map<CallbackQueue*, Entry>::iterator it = queues.find(queue);
    if (it == queues.end())
      return;
    if (--it->second.num == 0)
      queues.erase(it);
  }
};

SpinnerMonitor& monitor()
{
  static SpinnerMonitor* m = new SpinnerMonitor;
  return *m;
}

const char* const kDefaultError = "Attempt to spin a callback queue from two spinners, one of them being single-threaded.";

}  // namespace

void SingleThreadedSpinner::spin(CallbackQueue* queue)
{
  if (!queue)
    queue = getGlobalCallbackQueue();
  {
    std::lock_guard<std::recursive_mutex> lock(ddes::floorMutex());
    if (!monitor().add(queue, true))
    {
      std::string error = std::string("SingleThreadedSpinner: ") + kDefaultError +
                          " You might want to use a MultiThreadedSpinner instead.";
      ROS_FATAL_STREAM(error);
      throw std::runtime_error(error);
    }
  }
  struct Remove
  {
    CallbackQueue* q;
    ~Remove()
    {
      std::lock_guard<std::recursive_mutex> lock(ddes::floorMutex());
      monitor().remove(q);
    }
  } remove = {queue};
  ros::NodeHandle n;
  if (queue == getGlobalCallbackQueue())
  {
    // SPIN: the world runs the node's callbacks until it shuts down
    while (n.ok())
    {
      ddes::QueueAccess::callLocal(queue, false);
      if (!n.ok())
        break;
      ddes::Writer w = ddes::Writer::request();
      ddes::blocking(ddes::SPIN, w, queue);
    }
  }
  else
  {
    ros::WallDuration timeout(0.1f);
    while (n.ok())
      queue->callAvailable(timeout);
  }
}

MultiThreadedSpinner::MultiThreadedSpinner(uint32_t thread_count) : thread_count_(thread_count) {}

void MultiThreadedSpinner::spin(CallbackQueue* queue)
{
  AsyncSpinner s(thread_count_, queue);
  s.start();
  ros::waitForShutdown();
}

class AsyncSpinnerImpl
{
public:
  AsyncSpinnerImpl(uint32_t thread_count, CallbackQueue* queue)
  : thread_count_(thread_count), callback_queue_(queue ? queue : getGlobalCallbackQueue()), running_(false)
  {}

  ~AsyncSpinnerImpl() { stop(); }

  bool canStart() { return true; }

  void start()
  {
    std::lock_guard<std::recursive_mutex> lock(ddes::floorMutex());
    if (running_)
      return;
    if (!monitor().add(callback_queue_, false))
    {
      std::string error = std::string("AsyncSpinnerImpl: ") + kDefaultError;
      ROS_FATAL_STREAM(error);
      throw std::runtime_error(error);
    }
    running_ = true;
    ddes::spinnerStart(callback_queue_, thread_count_);
  }

  void stop()
  {
    std::lock_guard<std::recursive_mutex> lock(ddes::floorMutex());
    if (!running_)
      return;
    running_ = false;
    ddes::spinnerStop(callback_queue_);
    monitor().remove(callback_queue_);
  }

private:
  uint32_t thread_count_;
  CallbackQueue* callback_queue_;
  bool running_;
  ros::NodeHandle nh_;  // as roscpp's: the spinner keeps the node started
};

AsyncSpinner::AsyncSpinner(uint32_t thread_count) : impl_(new AsyncSpinnerImpl(thread_count, 0)) {}

AsyncSpinner::AsyncSpinner(uint32_t thread_count, CallbackQueue* queue)
: impl_(new AsyncSpinnerImpl(thread_count, queue))
{}

bool AsyncSpinner::canStart()
{
  return impl_->canStart();
}

void AsyncSpinner::start()
{
  impl_->start();
}

void AsyncSpinner::stop()
{
  impl_->stop();
}

}  // namespace ros
