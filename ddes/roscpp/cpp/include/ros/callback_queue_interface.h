// ddes roscpp: ros::CallbackInterface and ros::CallbackQueueInterface.
#ifndef ROSCPP_CALLBACK_QUEUE_INTERFACE_H
#define ROSCPP_CALLBACK_QUEUE_INTERFACE_H

#include <stdint.h>

#include <boost/shared_ptr.hpp>

#include <ros/common.h>

namespace ros
{

/// One callback waiting in a queue.
class CallbackInterface
{
public:
  enum CallResult
  {
    Success,   ///< it ran
    TryAgain,  ///< not ready: put it back at the end of the queue
    Invalid,   ///< no longer valid (its subscription or timer is gone)
  };

  virtual ~CallbackInterface() {}
  virtual CallResult call() = 0;
  /// False: skip it for now, it stays queued.
  virtual bool ready() { return true; }
};
typedef boost::shared_ptr<CallbackInterface> CallbackInterfacePtr;

/// Where callbacks wait until something calls them.
class CallbackQueueInterface
{
public:
  virtual ~CallbackQueueInterface() {}
  /// Queues `callback`; `owner_id` names its owner for removeByID.
  virtual void addCallback(const CallbackInterfacePtr& callback, uint64_t owner_id = 0) = 0;
  /// Drops every queued callback of `owner_id`.
  virtual void removeByID(uint64_t owner_id) = 0;
};

}  // namespace ros

#endif  // ROSCPP_CALLBACK_QUEUE_INTERFACE_H
