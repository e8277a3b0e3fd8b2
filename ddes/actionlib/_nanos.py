"""Conversion of the time arguments of the actionlib core to integer nanoseconds.

The pure actionlib core keeps every time as an ``int`` of nanoseconds, as the
kernel does.  Callers may pass an ``int`` or a :class:`ddes.Time`; durations
may be an ``int`` or a :class:`ddes.Duration`.
"""

from __future__ import annotations

from ddes.errors import DdesTypeError, DdesValueError
from ddes.time.rostime import Duration, Time

__all__ = ["duration_ns", "time_ns"]


def time_ns(value: int | Time, what: str) -> int:
    """``value`` (int nanoseconds >= 0 or a ``Time``) as int nanoseconds."""
    if isinstance(value, Time):
        return value.to_nsec()
    if isinstance(value, bool) or not isinstance(value, int):
        raise DdesTypeError(
            f"{what} must be int nanoseconds or a ddes.Time, got {value!r} "
            f"({type(value).__name__}); convert seconds with Time.from_sec(s)"
        )
    if value < 0:
        raise DdesValueError(f"{what} must be >= 0 nanoseconds (a ROS time), got {value}")
    return value


def duration_ns(value: int | Duration, what: str) -> int:
    """``value`` (int nanoseconds or a ``Duration``) as int nanoseconds."""
    if isinstance(value, Duration):
        return value.to_nsec()
    if isinstance(value, bool) or not isinstance(value, int):
        raise DdesTypeError(
            f"{what} must be int nanoseconds or a ddes.Duration, got {value!r} "
            f"({type(value).__name__}); convert seconds with Duration.from_sec(s)"
        )
    return value
