// ddes roscpp: ros::Time, ros::WallTime and ros::SteadyTime (rostime's API and arithmetic).
//
// Everything is header-only except what needs the world, which the ddes client library
// defines (src/time.cpp): Time::now() (the last ROS time the world sent: simulated /clock
// time under use_sim_time), isSimTime(), isSystemTime(), isValid(), waitForValid(), init(),
// sleepUntil(), WallTime::now() and SteadyTime::now() (the world's kernel clock, which ddes
// presents as the wall clock) and their sleepUntil().  Normalisation, range checks (throwing
// std::runtime_error with rostime's text) and printing ("sec.nsec", nine digits) are rostime's.
#ifndef ROS_TIME_H_INCLUDED
#define ROS_TIME_H_INCLUDED

#include <cmath>
#include <cstdint>
#include <iomanip>
#include <iostream>
#include <limits>
#include <stdexcept>

#include <ros/duration.h>
#include <ros/exception.h>

namespace ros
{

/// Thrown by ros::Time::now() before the node has joined the world.
class TimeNotInitializedException : public Exception
{
public:
  TimeNotInitializedException()
  : Exception("Cannot use ros::Time::now() before the first NodeHandle has been created or ros::start() has been called.  "
              "If this is a standalone app or test that just uses ros::Time and does not communicate over ROS, you may also call ros::Time::init()")
  {}
};

/// rostime's (Windows only); kept so code naming it compiles.
class NoHighPerformanceTimersException : public Exception
{
public:
  NoHighPerformanceTimersException()
  : Exception("This windows platform does not support the high-performance timing api.")
  {}
};

/// nsec carried into sec; throws if sec leaves uint32.
inline void normalizeSecNSec(uint64_t& sec, uint64_t& nsec)
{
  const uint64_t nsec_part = nsec % 1000000000ULL;
  const uint64_t sec_part = nsec / 1000000000ULL;
  if (sec + sec_part > std::numeric_limits<uint32_t>::max())
    detail::throwTimeOutOfRange();
  sec += sec_part;
  nsec = nsec_part;
}

inline void normalizeSecNSec(uint32_t& sec, uint32_t& nsec)
{
  uint64_t sec64 = sec;
  uint64_t nsec64 = nsec;
  normalizeSecNSec(sec64, nsec64);
  sec = static_cast<uint32_t>(sec64);
  nsec = static_cast<uint32_t>(nsec64);
}

/// nsec folded into [0, 1e9) (a negative one borrows a second); throws if sec leaves uint32.
inline void normalizeSecNSecUnsigned(int64_t& sec, int64_t& nsec)
{
  int64_t nsec_part = nsec % 1000000000LL;
  int64_t sec_part = sec + nsec / 1000000000LL;
  if (nsec_part < 0)
  {
    nsec_part += 1000000000LL;
    --sec_part;
  }
  if (sec_part < 0 || sec_part > static_cast<int64_t>(std::numeric_limits<uint32_t>::max()))
    detail::throwTimeOutOfRange();
  sec = sec_part;
  nsec = nsec_part;
}

/// Base of Time, WallTime and SteadyTime: T the time, D its duration.
template <class T, class D>
class TimeBase
{
public:
  uint32_t sec, nsec;

  TimeBase() : sec(0), nsec(0) {}
  TimeBase(uint32_t _sec, uint32_t _nsec) : sec(_sec), nsec(_nsec)
  {
    normalizeSecNSec(sec, nsec);
  }
  explicit TimeBase(double t) : sec(0), nsec(0) { fromSec(t); }

  D operator-(const T& rhs) const
  {
    D d;
    // the unsigned difference wraps; read as signed it is the (possibly negative) span
    return d.fromNSec(static_cast<int64_t>(toNSec() - rhs.toNSec()));
  }
  T operator+(const D& rhs) const
  {
    int64_t sec_sum = static_cast<int64_t>(sec) + static_cast<int64_t>(rhs.sec);
    int64_t nsec_sum = static_cast<int64_t>(nsec) + static_cast<int64_t>(rhs.nsec);
    normalizeSecNSecUnsigned(sec_sum, nsec_sum);
    return T(static_cast<uint32_t>(sec_sum), static_cast<uint32_t>(nsec_sum));
  }
  T operator-(const D& rhs) const { return *static_cast<const T*>(this) + (-rhs); }
  T& operator+=(const D& rhs)
  {
    *static_cast<T*>(this) = *static_cast<const T*>(this) + rhs;
    return *static_cast<T*>(this);
  }
  T& operator-=(const D& rhs)
  {
    *static_cast<T*>(this) += (-rhs);
    return *static_cast<T*>(this);
  }

  bool operator==(const T& rhs) const { return sec == rhs.sec && nsec == rhs.nsec; }
  bool operator!=(const T& rhs) const { return !(*this == rhs); }
  bool operator>(const T& rhs) const { return sec > rhs.sec || (sec == rhs.sec && nsec > rhs.nsec); }
  bool operator<(const T& rhs) const { return sec < rhs.sec || (sec == rhs.sec && nsec < rhs.nsec); }
  bool operator>=(const T& rhs) const { return sec > rhs.sec || (sec == rhs.sec && nsec >= rhs.nsec); }
  bool operator<=(const T& rhs) const { return sec < rhs.sec || (sec == rhs.sec && nsec <= rhs.nsec); }

  double toSec() const { return static_cast<double>(sec) + 1e-9 * static_cast<double>(nsec); }
  uint64_t toNSec() const { return static_cast<uint64_t>(sec) * 1000000000ULL + static_cast<uint64_t>(nsec); }

  /// Seconds as a double; the nanoseconds rounded half away from zero (as rostime).
  T& fromSec(double t)
  {
    const double whole = std::floor(t);
    // the negated test also refuses NaN
    if (!(whole >= 0.0 && whole <= static_cast<double>(std::numeric_limits<uint32_t>::max())))
      detail::throwTimeOutOfRange();
    uint64_t sec64 = static_cast<uint64_t>(whole);
    uint64_t nsec64 = static_cast<uint64_t>(std::round((t - static_cast<double>(sec64)) * 1e9));
    sec64 += nsec64 / 1000000000ULL;
    nsec64 %= 1000000000ULL;
    if (sec64 > std::numeric_limits<uint32_t>::max())
      detail::throwTimeOutOfRange();
    sec = static_cast<uint32_t>(sec64);
    nsec = static_cast<uint32_t>(nsec64);
    return *static_cast<T*>(this);
  }

  T& fromNSec(uint64_t t)
  {
    uint64_t sec64 = 0;
    uint64_t nsec64 = t;
    normalizeSecNSec(sec64, nsec64);
    sec = static_cast<uint32_t>(sec64);
    nsec = static_cast<uint32_t>(nsec64);
    return *static_cast<T*>(this);
  }

  bool isZero() const { return sec == 0 && nsec == 0; }
  bool is_zero() const { return isZero(); }
};

/// A point in ROS time (under ddes: the node's ROS clock, simulated /clock time with
/// use_sim_time, else the world's kernel time).
class Time : public TimeBase<Time, Duration>
{
public:
  Time() : TimeBase<Time, Duration>() {}
  Time(uint32_t _sec, uint32_t _nsec) : TimeBase<Time, Duration>(_sec, _nsec) {}
  explicit Time(double t) : TimeBase<Time, Duration>() { fromSec(t); }

  // Defined by the ddes client library (src/time.cpp): they need the world.
  /// The node's ROS time: the last time the world sent (time stands still while the node runs).
  static Time now();
  /// Sleeps until `end` on the ROS clock; false if the node shut down first.
  static bool sleepUntil(const Time& end);
  static void init();
  static bool isSimTime();
  static bool isSystemTime();
  /// False under use_sim_time until the first /clock message (ROS time is zero until then).
  static bool isValid();
  static bool waitForValid();
  static bool waitForValid(const WallDuration& timeout);
};

/// The latest and the earliest non-zero ROS time.
ROS_DDES_INLINE_VARIABLE const Time TIME_MAX(std::numeric_limits<uint32_t>::max(), 999999999);
ROS_DDES_INLINE_VARIABLE const Time TIME_MIN(0, 1);

/// A point in wall-clock time (under ddes: the world's kernel clock).
class WallTime : public TimeBase<WallTime, WallDuration>
{
public:
  WallTime() : TimeBase<WallTime, WallDuration>() {}
  WallTime(uint32_t _sec, uint32_t _nsec) : TimeBase<WallTime, WallDuration>(_sec, _nsec) {}
  explicit WallTime(double t) : TimeBase<WallTime, WallDuration>() { fromSec(t); }

  static WallTime now();
  static bool sleepUntil(const WallTime& end);
  static bool isSystemTime() { return true; }
};

/// A point on the steady clock (under ddes: the world's kernel clock).
class SteadyTime : public TimeBase<SteadyTime, WallDuration>
{
public:
  SteadyTime() : TimeBase<SteadyTime, WallDuration>() {}
  SteadyTime(uint32_t _sec, uint32_t _nsec) : TimeBase<SteadyTime, WallDuration>(_sec, _nsec) {}
  explicit SteadyTime(double t) : TimeBase<SteadyTime, WallDuration>() { fromSec(t); }

  static SteadyTime now();
  static bool sleepUntil(const SteadyTime& end);
  static bool isSystemTime() { return true; }
};

namespace detail
{
// "sec.nsec" with nine nanosecond digits; the stream's flags and fill are restored.
template <class T>
inline std::ostream& printTime(std::ostream& os, const T& rhs)
{
  const std::ios_base::fmtflags flags = os.flags();
  const char fill = os.fill();
  os << rhs.sec << "." << std::setw(9) << std::setfill('0') << rhs.nsec;
  os.flags(flags);
  os.fill(fill);
  return os;
}
}  // namespace detail

inline std::ostream& operator<<(std::ostream& os, const Time& rhs) { return detail::printTime(os, rhs); }
inline std::ostream& operator<<(std::ostream& os, const WallTime& rhs) { return detail::printTime(os, rhs); }
inline std::ostream& operator<<(std::ostream& os, const SteadyTime& rhs) { return detail::printTime(os, rhs); }

}  // namespace ros

#endif  // ROS_TIME_H_INCLUDED
