"""The one unit rule, and the one place that converts.

At every public edge of ddes a bare number is **seconds** (``rate.sleep``,
``node.sleep(0.5)``, ``world.run(until=2)``, ``latency=0.001``), as in rospy.
Inside, time is an ``int`` of **nanoseconds**, and every parameter, attribute
or function that holds nanoseconds says so in its name (``*_ns``).  A
:class:`~ddes.time.rostime.Time` or :class:`~ddes.time.rostime.Duration` is
accepted wherever seconds are.

This module is the only converter between the two:

* :func:`to_ns` — seconds (``int``/``float``), a Duration/WallDuration, or a
  Time/WallTime → int nanoseconds.
* :func:`duration_to_ns` — the same, but a point in time is refused (a sleep
  or a period must be a span).
* :func:`time_to_ns` — an instant: a Time/WallTime or seconds, never negative.
* :func:`ns_to_sec` — nanoseconds → float seconds, for display.

Seconds become nanoseconds as genpy's ``Duration.from_sec`` does (truncated
to whole nanoseconds), so ``to_ns(0.1) == Duration.from_sec(0.1).to_nsec()``.
"""

from __future__ import annotations

from typing import Protocol, runtime_checkable

from ddes.errors import DdesTypeError, DdesValueError
from ddes.time.rostime import Duration, Time, TVal, WallDuration, WallTime

__all__ = [
    "DurationLike",
    "HasNsec",
    "TimeLike",
    "duration_to_ns",
    "ns_to_sec",
    "time_to_ns",
    "to_ns",
]

_NS = 1_000_000_000


@runtime_checkable
class HasNsec(Protocol):
    """Anything with ``to_nsec()`` (genpy/rospy time values too)."""

    def to_nsec(self) -> int: ...


#: A span: seconds, or a Duration/WallDuration.
DurationLike = float | int | Duration | WallDuration
#: An instant: seconds since the epoch of the clock, or a Time/WallTime.
TimeLike = float | int | Time | WallTime


def to_ns(value: DurationLike | TimeLike | HasNsec, what: str = "time") -> int:
    """Seconds, or any value with ``to_nsec()``, as integer nanoseconds."""
    to_nsec = getattr(value, "to_nsec", None)
    if to_nsec is not None:
        return int(to_nsec())
    if isinstance(value, bool):
        raise DdesTypeError(f"{what} must be a Time, Duration or seconds, got {value!r}")
    if isinstance(value, int):
        return value * _NS
    if isinstance(value, float):
        return Duration.from_sec(value).to_nsec()
    raise DdesTypeError(
        f"{what} must be a Time, Duration or a number of seconds, got {value!r} "
        f"({type(value).__name__})"
    )


def duration_to_ns(value: DurationLike, what: str = "duration") -> int:
    """A span (seconds, Duration or WallDuration) as integer nanoseconds."""
    if isinstance(value, (Duration, WallDuration)):
        return value.to_nsec()
    if isinstance(value, TVal):
        raise DdesTypeError(f"{what} must be a Duration or seconds, got the point in time {value!r}")
    return Duration.from_sec(value).to_nsec()


def time_to_ns(value: TimeLike, what: str = "time") -> int:
    """An instant (seconds, Time or WallTime) as integer nanoseconds >= 0."""
    if isinstance(value, (Duration, WallDuration)):
        raise DdesTypeError(f"{what} must be a Time or seconds, got the span {value!r}")
    ns = to_ns(value, what)
    if ns < 0:
        raise DdesValueError(f"{what} must not be negative, got {value!r}")
    return ns


def ns_to_sec(ns: int) -> float:
    """Integer nanoseconds as float seconds (for display and rospy's float APIs)."""
    return ns / 1e9
