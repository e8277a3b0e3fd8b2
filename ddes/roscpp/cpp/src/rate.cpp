// ddes roscpp: ros::Rate and ros::WallRate (rostime's rules), and the Duration constructors
// from a Rate that duration.h declares.
#include <ros/rate.h>

namespace ros
{

Duration::Duration(const Rate& rate)
: DurationBase<Duration>(rate.expectedCycleTime().sec, rate.expectedCycleTime().nsec)
{}

WallDuration::WallDuration(const Rate& rate)
: DurationBase<WallDuration>(rate.expectedCycleTime().sec, rate.expectedCycleTime().nsec)
{}

Rate::Rate(double frequency)
: start_(Time::now()), expected_cycle_time_(1.0 / frequency), actual_cycle_time_(0.0)
{}

Rate::Rate(const Duration& d) : start_(Time::now()), expected_cycle_time_(d.sec, d.nsec), actual_cycle_time_(0.0) {}

bool Rate::sleep()
{
  Time expected_end = start_ + expected_cycle_time_;
  Time actual_end = Time::now();
  // time went backwards (a /clock reset): start over from now
  if (actual_end < start_)
    expected_end = actual_end + expected_cycle_time_;
  Duration sleep_time = expected_end - actual_end;
  actual_cycle_time_ = actual_end - start_;
  start_ = expected_end;
  if (sleep_time <= Duration(0.0))
  {
    // overran: more than a whole cycle late (or a jump forward) restarts the schedule
    if (actual_end > expected_end + expected_cycle_time_)
      start_ = actual_end;
    return false;
  }
  return sleep_time.sleep();
}

void Rate::reset()
{
  start_ = Time::now();
}

Duration Rate::cycleTime() const
{
  return actual_cycle_time_;
}

WallRate::WallRate(double frequency)
: start_(WallTime::now()), expected_cycle_time_(1.0 / frequency), actual_cycle_time_(0.0)
{}

WallRate::WallRate(const Duration& d)
: start_(WallTime::now()), expected_cycle_time_(d.sec, d.nsec), actual_cycle_time_(0.0)
{}

bool WallRate::sleep()
{
  WallTime expected_end = start_ + expected_cycle_time_;
  WallTime actual_end = WallTime::now();
  if (actual_end < start_)
    expected_end = actual_end + expected_cycle_time_;
  WallDuration sleep_time = expected_end - actual_end;
  actual_cycle_time_ = actual_end - start_;
  start_ = expected_end;
  if (sleep_time <= WallDuration(0.0))
  {
    if (actual_end > expected_end + expected_cycle_time_)
      start_ = actual_end;
    return false;
  }
  return sleep_time.sleep();
}

void WallRate::reset()
{
  start_ = WallTime::now();
}

WallDuration WallRate::cycleTime() const
{
  return actual_cycle_time_;
}

}  // namespace ros
