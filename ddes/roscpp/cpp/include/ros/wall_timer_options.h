// ddes roscpp: ros::WallTimerOptions.
#ifndef ROSCPP_WALL_TIMER_OPTIONS_H
#define ROSCPP_WALL_TIMER_OPTIONS_H

#include <ros/forwards.h>

namespace ros
{

struct WallTimerOptions
{
  WallTimerOptions() : period(0.1), callback_queue(0), oneshot(false), autostart(true) {}

  WallTimerOptions(WallDuration _period, const WallTimerCallback& _callback, CallbackQueueInterface* _queue,
                   bool _oneshot = false, bool _autostart = true)
  : period(_period), callback(_callback), callback_queue(_queue), oneshot(_oneshot), autostart(_autostart)
  {}

  WallDuration period;
  WallTimerCallback callback;
  CallbackQueueInterface* callback_queue;
  VoidConstPtr tracked_object;
  bool oneshot;
  bool autostart;
};

}  // namespace ros

#endif  // ROSCPP_WALL_TIMER_OPTIONS_H
