// ddes roscpp: ros::CallbackQueue.
//
// Under ddes the world holds the node's callbacks and hands them to the process while it waits
// in a blocking call (docs/external-nodes.md).  A callback whose queue is being served at that
// moment (the global queue in ros::spin/spinOnce, a custom queue in its callAvailable/callOne,
// a queue an AsyncSpinner or MultiThreadedSpinner serves) runs at once; any other waits in its
// CallbackQueue object here until that queue is called (a service request always runs at once:
// the world waits for its response).  callAvailable()/callOne() first run what waits here,
// then ask the world for what is ready now; with a timeout and nothing to run they wait that
// long on the wall clock, running the queue's callbacks as they come.  See docs/roscpp.md.
#ifndef ROSCPP_CALLBACK_QUEUE_H
#define ROSCPP_CALLBACK_QUEUE_H

#include <deque>

#include <ros/callback_queue_interface.h>
#include <ros/time.h>

namespace ros
{

namespace ddes
{
struct QueueAccess;
}

class CallbackQueue : public CallbackQueueInterface
{
public:
  CallbackQueue(bool enabled = true);
  virtual ~CallbackQueue();

  virtual void addCallback(const CallbackInterfacePtr& callback, uint64_t removal_id = 0);
  virtual void removeByID(uint64_t removal_id);

  enum CallOneResult
  {
    Called,
    TryAgain,
    Disabled,
    Empty,
  };

  /// Runs the oldest callback, if any is ready.
  CallOneResult callOne() { return callOne(ros::WallDuration()); }
  /// Runs the oldest callback, waiting up to `timeout` (wall time) for one.
  CallOneResult callOne(ros::WallDuration timeout);

  /// Runs every callback ready now.
  void callAvailable() { callAvailable(ros::WallDuration()); }
  /// Runs every callback ready now, waiting up to `timeout` (wall time) when there is none.
  void callAvailable(ros::WallDuration timeout);

  /// Whether nothing waits here (callbacks the world still holds are not counted).
  bool empty() { return isEmpty(); }
  bool isEmpty();
  /// Drops every waiting callback.
  void clear();
  void enable();
  void disable();
  bool isEnabled();

protected:
  struct CallbackInfo
  {
    CallbackInfo() : removal_id(0), marked_for_removal(false) {}
    CallbackInterfacePtr callback;
    uint64_t removal_id;
    bool marked_for_removal;
  };
  typedef std::deque<CallbackInfo> D_CallbackInfo;

  /// Runs the callbacks waiting here now (all of them, or one); how many ran.
  size_t callLocal(bool just_one, bool* tried_again = 0);

  D_CallbackInfo callbacks_;
  bool enabled_;

  friend struct ddes::QueueAccess;
};
typedef boost::shared_ptr<CallbackQueue> CallbackQueuePtr;

}  // namespace ros

#endif  // ROSCPP_CALLBACK_QUEUE_H
