"""ROS time: Time, Duration, the unit rule, clocks, Rate and sleep, all on simulated time.

Timers live with the nodes that own them (:mod:`ddes.graph.timer`).
"""

from ddes.time.clock import Clock, KernelClock, SimClock
from ddes.time.rate import Rate, RoscppRate, WallRate
from ddes.time.rostime import (
    DAY,
    HOUR,
    MICROSECOND,
    MILLISECOND,
    MINUTE,
    NANOSECOND,
    SECOND,
    Duration,
    Time,
    TVal,
    WallDuration,
    WallTime,
)
from ddes.time.sleep import duration_sleep, sleep
from ddes.time.units import DurationLike, TimeLike, duration_to_ns, ns_to_sec, time_to_ns, to_ns

__all__ = [
    "DAY",
    "HOUR",
    "MICROSECOND",
    "MILLISECOND",
    "MINUTE",
    "NANOSECOND",
    "SECOND",
    "Clock",
    "Duration",
    "DurationLike",
    "KernelClock",
    "Rate",
    "RoscppRate",
    "SimClock",
    "TVal",
    "Time",
    "TimeLike",
    "WallDuration",
    "WallRate",
    "WallTime",
    "duration_sleep",
    "duration_to_ns",
    "ns_to_sec",
    "sleep",
    "time_to_ns",
    "to_ns",
]
