// ddes roscpp: ros::Timer, a periodic (or one-shot) callback on the node's ROS clock (simulated /clock time under use_sim_time).  The world keeps the
// timer (TIMER_CREATE/TIMER_CONTROL) and hands each expiry to the process as a callback.
// Copies share one timer; it stops when the last copy is destroyed, as in roscpp.
#ifndef ROSCPP_TIMER_H
#define ROSCPP_TIMER_H

#include <boost/shared_ptr.hpp>

#include <ros/common.h>
#include <ros/forwards.h>
#include <ros/timer_options.h>

namespace ros
{

namespace ddes
{
class TimerImpl;
}

class Timer
{
public:
  Timer() {}
  Timer(const Timer& rhs);
  ~Timer();
  Timer& operator=(const Timer& other) = default;

  /// Starts the timer (a no-op if it runs); the first expiry is one period from now.
  void start();
  /// Stops the timer; no callback of it runs until start().
  void stop();
  /// Whether an expiry is due or waiting to be called.
  bool hasPending();
  /// Changes the period; with `reset` the next expiry is one new period from now.
  void setPeriod(const Duration& period, bool reset = true);

  bool hasStarted() const;
  bool isValid() { return isValidImpl(); }
  bool isValid() const { return isValidImpl(); }
  operator void*() { return isValid() ? reinterpret_cast<void*>(1) : static_cast<void*>(0); }

  bool operator<(const Timer& rhs) { return impl_ < rhs.impl_; }
  bool operator==(const Timer& rhs) { return impl_ == rhs.impl_; }
  bool operator!=(const Timer& rhs) { return impl_ != rhs.impl_; }

private:
  Timer(const TimerOptions& ops);
  bool isValidImpl() const;

  boost::shared_ptr<ddes::TimerImpl> impl_;

  friend class NodeHandle;
};

}  // namespace ros

#endif  // ROSCPP_TIMER_H
