// ddes roscpp: ros::Rate and ros::WallRate (rostime's catch-up rule).
//
// sleep() sleeps until one cycle after the previous cycle's end; a cycle that overran by more
// than a full period restarts the schedule from now; it returns false when the rate was not
// met (no sleep) or the node shut down during the sleep.
#ifndef ROSLIB_RATE_H
#define ROSLIB_RATE_H

#include <ros/duration.h>
#include <ros/time.h>

namespace ros
{

class Rate
{
public:
  Rate(double frequency);
  explicit Rate(const Duration&);

  bool sleep();
  /// The next cycle starts now.
  void reset();
  /// How long the last cycle's work took.
  Duration cycleTime() const;
  Duration expectedCycleTime() const { return expected_cycle_time_; }

private:
  Time start_;
  Duration expected_cycle_time_, actual_cycle_time_;
};

class WallRate
{
public:
  WallRate(double frequency);
  explicit WallRate(const Duration&);

  bool sleep();
  void reset();
  WallDuration cycleTime() const;
  WallDuration expectedCycleTime() const { return expected_cycle_time_; }

private:
  WallTime start_;
  WallDuration expected_cycle_time_, actual_cycle_time_;
};

}  // namespace ros

#endif  // ROSLIB_RATE_H
