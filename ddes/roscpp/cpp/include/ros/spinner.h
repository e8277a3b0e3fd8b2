// ddes roscpp: ros::Spinner, SingleThreadedSpinner, MultiThreadedSpinner and AsyncSpinner.
//
// ddes's node is one thread of execution (docs/roscpp.md): a MultiThreadedSpinner or a
// started AsyncSpinner tells the world (SPINNER) that callbacks may run whenever the process
// waits in a blocking call, up to `thread_count` at once (a callback that blocks lets the next
// one in); they run on the thread that is blocked, not on threads of their own.
#ifndef ROSCPP_SPINNER_H
#define ROSCPP_SPINNER_H

#include <boost/shared_ptr.hpp>

#include <ros/types.h>

namespace ros
{

class NodeHandle;
class CallbackQueue;

class Spinner
{
public:
  virtual ~Spinner() {}
  /// Runs `queue`'s callbacks (0: the global queue) until the node shuts down.
  virtual void spin(CallbackQueue* queue = 0) = 0;
};

class SingleThreadedSpinner : public Spinner
{
public:
  virtual void spin(CallbackQueue* queue = 0);
};

class MultiThreadedSpinner : public Spinner
{
public:
  /// `thread_count` 0: as many as the machine has cores (the world decides what that means).
  MultiThreadedSpinner(uint32_t thread_count = 0);
  virtual void spin(CallbackQueue* queue = 0);

private:
  uint32_t thread_count_;
};

class AsyncSpinnerImpl;
typedef boost::shared_ptr<AsyncSpinnerImpl> AsyncSpinnerImplPtr;

class AsyncSpinner
{
public:
  AsyncSpinner(uint32_t thread_count);
  AsyncSpinner(uint32_t thread_count, CallbackQueue* queue);

  /// False when the queue is spun by a single-threaded spinner.
  bool canStart();
  void start();
  void stop();

private:
  AsyncSpinnerImplPtr impl_;
};

}  // namespace ros

#endif  // ROSCPP_SPINNER_H
