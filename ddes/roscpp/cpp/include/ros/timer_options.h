// ddes roscpp: ros::TimerOptions, everything NodeHandle::createTimer needs.
#ifndef ROSCPP_TIMER_OPTIONS_H
#define ROSCPP_TIMER_OPTIONS_H

#include <ros/forwards.h>

namespace ros
{

struct TimerOptions
{
  TimerOptions() : period(0.1), callback_queue(0), oneshot(false), autostart(true) {}

  TimerOptions(Duration _period, const TimerCallback& _callback, CallbackQueueInterface* _queue,
               bool _oneshot = false, bool _autostart = true)
  : period(_period), callback(_callback), callback_queue(_queue), oneshot(_oneshot), autostart(_autostart)
  {}

  Duration period;
  TimerCallback callback;
  CallbackQueueInterface* callback_queue;  ///< 0: the NodeHandle's queue (the global one)
  VoidConstPtr tracked_object;
  bool oneshot;
  bool autostart;
};

}  // namespace ros

#endif  // ROSCPP_TIMER_OPTIONS_H
