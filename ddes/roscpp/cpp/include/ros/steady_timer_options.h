// ddes roscpp: ros::SteadyTimerOptions.
#ifndef ROSCPP_STEADY_TIMER_OPTIONS_H
#define ROSCPP_STEADY_TIMER_OPTIONS_H

#include <ros/forwards.h>

namespace ros
{

struct SteadyTimerOptions
{
  SteadyTimerOptions() : period(0.1), callback_queue(0), oneshot(false), autostart(true) {}

  SteadyTimerOptions(WallDuration _period, const SteadyTimerCallback& _callback, CallbackQueueInterface* _queue,
                     bool _oneshot = false, bool _autostart = true)
  : period(_period), callback(_callback), callback_queue(_queue), oneshot(_oneshot), autostart(_autostart)
  {}

  WallDuration period;
  SteadyTimerCallback callback;
  CallbackQueueInterface* callback_queue;
  VoidConstPtr tracked_object;
  bool oneshot;
  bool autostart;
};

}  // namespace ros

#endif  // ROSCPP_STEADY_TIMER_OPTIONS_H
