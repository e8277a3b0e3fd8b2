// ddes roscpp: ros::Duration and ros::WallDuration (rostime's API and arithmetic).
//
// Header-only except what needs the world: Duration::sleep() and WallDuration::sleep()
// (defined by the ddes client library, src/time.cpp) and the constructors from a Rate
// (defined with ros::Rate).  Every normalisation and range check is rostime's: a value
// outside the dual 32-bit range throws std::runtime_error with rostime's text.
#ifndef ROS_DURATION_H
#define ROS_DURATION_H

#include <climits>
#include <cmath>
#include <cstdint>
#include <iomanip>
#include <iostream>
#include <limits>
#include <stdexcept>

// C++17: one object in the program; before it, one per translation unit.
#ifndef ROS_DDES_INLINE_VARIABLE
#if __cplusplus >= 201703L
#define ROS_DDES_INLINE_VARIABLE inline
#else
#define ROS_DDES_INLINE_VARIABLE
#endif
#endif

namespace ros
{

namespace detail
{
[[noreturn]] inline void throwDurationOutOfRange()
{
  throw std::runtime_error("Duration is out of dual 32-bit range");
}

[[noreturn]] inline void throwTimeOutOfRange()
{
  throw std::runtime_error("Time is out of dual 32-bit range");
}
}  // namespace detail

/// nsec folded into [0, 1e9) and carried into sec; throws if sec leaves int32.
inline void normalizeSecNSecSigned(int64_t& sec, int64_t& nsec)
{
  int64_t nsec_part = nsec % 1000000000LL;
  int64_t sec_part = sec + nsec / 1000000000LL;
  if (nsec_part < 0)
  {
    nsec_part += 1000000000LL;
    --sec_part;
  }
  if (sec_part < std::numeric_limits<int32_t>::min() || sec_part > std::numeric_limits<int32_t>::max())
    detail::throwDurationOutOfRange();
  sec = sec_part;
  nsec = nsec_part;
}

inline void normalizeSecNSecSigned(int32_t& sec, int32_t& nsec)
{
  int64_t sec64 = sec;
  int64_t nsec64 = nsec;
  normalizeSecNSecSigned(sec64, nsec64);
  sec = static_cast<int32_t>(sec64);
  nsec = static_cast<int32_t>(nsec64);
}

/// Base of Duration and WallDuration: a signed second count and nanoseconds in [0, 1e9).
template <class T>
class DurationBase
{
public:
  int32_t sec, nsec;

  DurationBase() : sec(0), nsec(0) {}
  DurationBase(int32_t _sec, int32_t _nsec) : sec(_sec), nsec(_nsec)
  {
    normalizeSecNSecSigned(sec, nsec);
  }
  explicit DurationBase(double t) : sec(0), nsec(0) { fromSec(t); }

  T operator+(const T& rhs) const
  {
    T t;
    return t.fromNSec(toNSec() + rhs.toNSec());
  }
  T operator-(const T& rhs) const
  {
    T t;
    return t.fromNSec(toNSec() - rhs.toNSec());
  }
  T operator-() const
  {
    T t;
    return t.fromNSec(-toNSec());
  }
  T operator*(double scale) const { return T(toSec() * scale); }
  T& operator+=(const T& rhs)
  {
    *static_cast<T*>(this) = *static_cast<const T*>(this) + rhs;
    return *static_cast<T*>(this);
  }
  T& operator-=(const T& rhs)
  {
    *static_cast<T*>(this) += (-rhs);
    return *static_cast<T*>(this);
  }
  T& operator*=(double scale)
  {
    fromSec(toSec() * scale);
    return *static_cast<T*>(this);
  }

  bool operator==(const T& rhs) const { return sec == rhs.sec && nsec == rhs.nsec; }
  bool operator!=(const T& rhs) const { return !(*this == rhs); }
  bool operator>(const T& rhs) const { return sec > rhs.sec || (sec == rhs.sec && nsec > rhs.nsec); }
  bool operator<(const T& rhs) const { return sec < rhs.sec || (sec == rhs.sec && nsec < rhs.nsec); }
  bool operator>=(const T& rhs) const { return sec > rhs.sec || (sec == rhs.sec && nsec >= rhs.nsec); }
  bool operator<=(const T& rhs) const { return sec < rhs.sec || (sec == rhs.sec && nsec <= rhs.nsec); }

  double toSec() const { return static_cast<double>(sec) + 1e-9 * static_cast<double>(nsec); }
  int64_t toNSec() const { return static_cast<int64_t>(sec) * 1000000000LL + static_cast<int64_t>(nsec); }

  /// Seconds as a double; the nanoseconds rounded half away from zero (as rostime).
  T& fromSec(double d)
  {
    const double whole = std::floor(d);
    // the negated test also refuses NaN
    if (!(whole >= static_cast<double>(std::numeric_limits<int32_t>::min()) &&
          whole <= static_cast<double>(std::numeric_limits<int32_t>::max())))
      detail::throwDurationOutOfRange();
    int64_t sec64 = static_cast<int64_t>(whole);
    int64_t nsec64 = static_cast<int64_t>(std::round((d - static_cast<double>(sec64)) * 1e9));
    sec64 += nsec64 / 1000000000LL;
    nsec64 %= 1000000000LL;
    if (sec64 > std::numeric_limits<int32_t>::max())
      detail::throwDurationOutOfRange();
    sec = static_cast<int32_t>(sec64);
    nsec = static_cast<int32_t>(nsec64);
    return *static_cast<T*>(this);
  }

  T& fromNSec(int64_t t)
  {
    const int64_t sec64 = t / 1000000000LL;
    if (sec64 < std::numeric_limits<int32_t>::min() || sec64 > std::numeric_limits<int32_t>::max())
      detail::throwDurationOutOfRange();
    sec = static_cast<int32_t>(sec64);
    nsec = static_cast<int32_t>(t % 1000000000LL);
    normalizeSecNSecSigned(sec, nsec);
    return *static_cast<T*>(this);
  }

  bool isZero() const { return sec == 0 && nsec == 0; }
};

class Rate;

/// A span of ROS time (simulated time under ddes).
class Duration : public DurationBase<Duration>
{
public:
  Duration() : DurationBase<Duration>() {}
  Duration(int32_t _sec, int32_t _nsec) : DurationBase<Duration>(_sec, _nsec) {}
  explicit Duration(double t) : DurationBase<Duration>() { fromSec(t); }
  /// The rate's expected cycle time (defined with ros::Rate).
  explicit Duration(const Rate&);
  /// Sleeps this long on the node's ROS clock; false if the node shut down first.
  /// Defined by the ddes client library (it asks the world).
  bool sleep() const;
};

/// A span of wall-clock time (under ddes: the kernel's clock, never the host's).
class WallDuration : public DurationBase<WallDuration>
{
public:
  WallDuration() : DurationBase<WallDuration>() {}
  WallDuration(int32_t _sec, int32_t _nsec) : DurationBase<WallDuration>(_sec, _nsec) {}
  explicit WallDuration(double t) : DurationBase<WallDuration>() { fromSec(t); }
  explicit WallDuration(const Rate&);
  /// Sleeps this long on the wall clock (the world's); defined by the ddes client library.
  bool sleep() const;
};

namespace detail
{
// "sec.nsec" with nine nanosecond digits; a negative duration as a signed decimal
// (-0.5 s is "-0.500000000"), as rostime prints it.  The stream's flags and fill
// are restored afterwards.
template <class D>
inline std::ostream& printDuration(std::ostream& os, const D& rhs)
{
  const std::ios_base::fmtflags flags = os.flags();
  const char fill = os.fill();
  if (rhs.sec >= 0 || rhs.nsec == 0)
  {
    os << rhs.sec << "." << std::setw(9) << std::setfill('0') << rhs.nsec;
  }
  else
  {
    os << (rhs.sec == -1 ? "-" : "") << (rhs.sec + 1) << "." << std::setw(9) << std::setfill('0')
       << (1000000000 - rhs.nsec);
  }
  os.flags(flags);
  os.fill(fill);
  return os;
}
}  // namespace detail

inline std::ostream& operator<<(std::ostream& os, const Duration& rhs) { return detail::printDuration(os, rhs); }
inline std::ostream& operator<<(std::ostream& os, const WallDuration& rhs) { return detail::printDuration(os, rhs); }

/// The longest and the most negative Duration.
ROS_DDES_INLINE_VARIABLE const Duration DURATION_MAX(std::numeric_limits<int32_t>::max(), 999999999);
ROS_DDES_INLINE_VARIABLE const Duration DURATION_MIN(std::numeric_limits<int32_t>::min(), 0);

}  // namespace ros

#endif  // ROS_DURATION_H
