// ddes roscpp: what ros/time.h and ros/duration.h declare and the world defines: the clocks
// (the last times the world sent: time stands still while the process has the floor) and the
// sleeps (SLEEP_UNTIL, a blocking request).
#include "ddes_core.h"

#include <ros/duration.h>
#include <ros/time.h>

namespace ros
{

namespace
{

int64_t rosNow()
{
  return ddes::state().now_ns;
}

/// The world's kernel clock.  Before ros::init and ros::Time::init it reads zero (the process
/// has not joined the world yet).
int64_t wallNow()
{
  if (ddes::state().time_initialized)
    ddes::ensureTimeSource();
  return ddes::state().wall_ns;
}

}  // namespace

Time Time::now()
{
  ddes::NodeState& s = ddes::state();
  if (!s.time_initialized)
    throw TimeNotInitializedException();
  ddes::ensureTimeSource();
  return Time().fromNSec(static_cast<uint64_t>(rosNow() < 0 ? 0 : rosNow()));
}

void Time::init()
{
  // roscpp: ros::Time runs on the wall clock from here; under ddes the world's clock, which
  // the process joins (HELLO, time only) when it first needs it
  ddes::state().time_initialized = true;
}

bool Time::isSimTime()
{
  return ddes::state().use_sim_time;
}

bool Time::isSystemTime()
{
  return !isSimTime();
}

bool Time::isValid()
{
  return !ddes::state().use_sim_time || rosNow() != 0;
}

bool Time::waitForValid()
{
  return waitForValid(ros::WallDuration());
}

bool Time::waitForValid(const ros::WallDuration& timeout)
{
  // roscpp's poll, every 10 ms of wall time
  ros::WallTime start = ros::WallTime::now();
  while (!isValid() && !ddes::state().shutting_down)
  {
    ros::WallDuration(0.01).sleep();
    if (timeout > ros::WallDuration(0, 0) && (ros::WallTime::now() - start > timeout))
      return false;
  }
  return !ddes::state().shutting_down;
}

bool Time::sleepUntil(const Time& end)
{
  const Time now = Time::now();
  if (!isSimTime())
  {
    Duration d(end - now);
    if (d > Duration(0))
      return d.sleep();
    return true;
  }
  if (end <= now)
    return true;
  return ddes::sleepUntil(ddes::CLOCK_ROS, static_cast<int64_t>(end.toNSec()));
}

bool Duration::sleep() const
{
  ddes::ensureTimeSource();
  if (!Time::isSimTime())
  {
    if (toNSec() <= 0)
      return true;
    return ddes::sleepUntil(ddes::CLOCK_ROS, rosNow() + toNSec());
  }
  // simulated time: a sleep begun at time zero starts counting at the first clock message,
  // and a sleep that does not wait at all says false (roscpp's rules)
  if (toNSec() <= 0)
    return false;
  if (rosNow() == 0)
  {
    if (!ddes::sleepUntil(ddes::CLOCK_ROS, 1))
      return false;
  }
  return ddes::sleepUntil(ddes::CLOCK_ROS, rosNow() + toNSec());
}

WallTime WallTime::now()
{
  return WallTime().fromNSec(static_cast<uint64_t>(wallNow() < 0 ? 0 : wallNow()));
}

bool WallTime::sleepUntil(const WallTime& end)
{
  WallDuration d(end - WallTime::now());
  if (d > WallDuration(0))
    return d.sleep();
  return true;
}

bool WallDuration::sleep() const
{
  if (toNSec() <= 0)
    return true;
  const int64_t now = wallNow();
  return ddes::sleepUntil(ddes::CLOCK_WALL, now + toNSec());
}

SteadyTime SteadyTime::now()
{
  return SteadyTime().fromNSec(static_cast<uint64_t>(wallNow() < 0 ? 0 : wallNow()));
}

bool SteadyTime::sleepUntil(const SteadyTime& end)
{
  const int64_t now = wallNow();
  const int64_t t = static_cast<int64_t>(end.toNSec());
  if (t <= now)
    return true;
  return ddes::sleepUntil(ddes::CLOCK_STEADY, t);
}

}  // namespace ros
