// ddes roscpp: roscpp's forward declarations, smart-pointer typedefs, callback types and the
// timer event structs.
#ifndef ROSCPP_FORWARDS_H
#define ROSCPP_FORWARDS_H

#include <list>
#include <map>
#include <set>
#include <string>
#include <vector>

#include <boost/function.hpp>
#include <boost/make_shared.hpp>
#include <boost/shared_ptr.hpp>
#include <boost/weak_ptr.hpp>

#include <ros/datatypes.h>
#include <ros/exceptions.h>
#include <ros/macros.h>
#include <ros/time.h>

namespace ros
{

typedef boost::shared_ptr<void> VoidPtr;
typedef boost::weak_ptr<void> VoidWPtr;
typedef boost::shared_ptr<void const> VoidConstPtr;
typedef boost::weak_ptr<void const> VoidConstWPtr;

class NodeHandle;
typedef boost::shared_ptr<NodeHandle> NodeHandlePtr;

class SingleSubscriberPublisher;
typedef boost::function<void(const SingleSubscriberPublisher&)> SubscriberStatusCallback;

class CallbackQueue;
class CallbackQueueInterface;
class CallbackInterface;
typedef boost::shared_ptr<CallbackInterface> CallbackInterfacePtr;

/// What a ros::Timer callback receives.
struct TimerEvent
{
  Time last_expected;     ///< when the last callback should have happened
  Time last_real;         ///< when the last callback did happen
  Time last_expired;      ///< when the last timer expired and its callback was queued

  Time current_expected;  ///< when this callback should be happening
  Time current_real;      ///< when this callback is happening (Time::now() as it starts)
  Time current_expired;   ///< when this timer expired and its callback was queued

  struct
  {
    WallDuration last_duration;  ///< how long the last callback ran for
  } profile;
};
typedef boost::function<void(const TimerEvent&)> TimerCallback;

/// What a ros::WallTimer callback receives.
struct WallTimerEvent
{
  WallTime last_expected;
  WallTime last_real;
  WallTime last_expired;

  WallTime current_expected;
  WallTime current_real;
  WallTime current_expired;

  struct
  {
    WallDuration last_duration;
  } profile;
};
typedef boost::function<void(const WallTimerEvent&)> WallTimerCallback;

/// What a ros::SteadyTimer callback receives.
struct SteadyTimerEvent
{
  SteadyTime last_expected;
  SteadyTime last_real;
  SteadyTime last_expired;

  SteadyTime current_expected;
  SteadyTime current_real;
  SteadyTime current_expired;

  struct
  {
    WallDuration last_duration;
  } profile;
};
typedef boost::function<void(const SteadyTimerEvent&)> SteadyTimerCallback;

}  // namespace ros

#endif  // ROSCPP_FORWARDS_H
