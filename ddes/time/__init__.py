"""ROS time: Time, Duration, clocks, Rate, Timer and sleep, all on simulated time."""

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
from ddes.time.timer import Timer, TimerEvent

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
    "KernelClock",
    "Rate",
    "RoscppRate",
    "SimClock",
    "TVal",
    "Time",
    "Timer",
    "TimerEvent",
    "WallDuration",
    "WallRate",
    "WallTime",
    "duration_sleep",
    "sleep",
]
