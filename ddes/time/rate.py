"""Rate loops: rospy's ``Rate`` (default), roscpp's as :class:`RoscppRate`, and ``WallRate``.

``yield rate.sleep()`` keeps a loop at a frequency on the node's clock.

rospy (``rospy/timer.py``): the period is ``Duration(0, int(1e9/hz))``;
``sleep`` sleeps the remaining time, advances ``last_time`` by one period,
and drops the backlog (``last_time = now``) when more than two periods
late.  A backwards time jump fails the sleep with
``ROSTimeMovedBackwardsException`` unless ``reset=True``.

roscpp (``rostime/src/rate.cpp``): the period is ``Duration(1.0/hz)``
(rounded to the nearest ns); ``sleep`` returns whether the cycle was met and
restarts the cycle when more than one period late.
"""

from __future__ import annotations

import math
import numbers
from collections.abc import Generator
from typing import Protocol

import simpy

from ddes.errors import DdesTypeError, DdesValueError, ROSTimeMovedBackwardsException
from ddes.time.clock import Clock, ClockOwner, KernelClock
from ddes.time.rospy_calls import REQUIRED, arg_text, call_text, missing_node
from ddes.time.rostime import Duration, WallDuration
from ddes.time.sleep import (
    FORGOTTEN_YIELD_CALLS,
    MUST_YIELD,
    _sim_sleep,
    duration_sleep,
    forgotten_yield,
    must_yield,
)

__all__ = ["Rate", "RoscppRate", "WallRate", "check_hz", "roscpp_period_ns"]


class KernelClockOwner(Protocol):
    """A world (or kernel): it has the :attr:`kernel_clock` a :class:`WallRate` runs on."""

    @property
    def kernel_clock(self) -> KernelClock: ...


class WorldOwner(Protocol):
    """A node, as :class:`WallRate` sees it: it belongs to a world."""

    @property
    def world(self) -> KernelClockOwner: ...


def check_hz(hz: object) -> float:
    """Validate a frequency: a finite number > 0."""
    if isinstance(hz, bool) or not isinstance(hz, numbers.Real):
        raise DdesTypeError(f"rate must be a number in Hz, got {hz!r} ({type(hz).__name__})")
    f = float(hz)
    if math.isnan(f) or math.isinf(f) or f <= 0:
        raise DdesValueError(f"rate must be a finite frequency > 0 Hz, got {hz!r}")
    return f


def roscpp_period_ns(hz: float) -> int:
    """roscpp ``Duration(1.0/hz)``: floor seconds, nanoseconds rounded half away from zero."""
    d = 1.0 / hz
    sec = math.floor(d)
    nsec = math.floor((d - sec) * 1e9 + 0.5)
    return sec * 1_000_000_000 + nsec


def _clock_of(owner: Clock | ClockOwner) -> Clock:
    clock = getattr(owner, "clock", owner)
    if not isinstance(clock, Clock):
        raise DdesTypeError(f"expected a node or a clock, got {owner!r}")
    return clock


def _check_rospy_shape(cls: str, method: str, node: object, hz: object,
                       kwargs: dict[str, object]) -> None:
    """``ddes.Rate(10)``, rospy's spelling, left ``hz`` out: say what to write instead."""
    if hz is not REQUIRED:
        return
    if isinstance(node, numbers.Real) and not isinstance(node, bool):
        extra = "".join(f", {k}={arg_text(v)}" for k, v in kwargs.items())
        raise missing_node(call_text(f"ddes.{cls}", [node], kwargs),
                           f"rate = ddes.{cls}(node, {arg_text(node)}{extra})"
                           f"    # or node.{method}({arg_text(node)}{extra})",
                           "yield rate.sleep()    # in the node's process")
    raise DdesTypeError(f"ddes.{cls} needs a frequency in Hz: ddes.{cls}(node, 10)")


class Rate:
    """rospy.Rate on a node's ROS clock: ``yield rate.sleep()``."""

    def __init__(self, node: Clock | ClockOwner, hz: float = REQUIRED, reset: bool = False) -> None:
        _check_rospy_shape(type(self).__name__, "create_rate", node, hz,
                           {"reset": reset} if reset else {})
        self._clock = _clock_of(node)
        hz = check_hz(hz)
        period = int(1e9 / hz)
        if period <= 0:
            raise DdesValueError(f"rate {hz!r} Hz has a period below one nanosecond")
        self._period = period
        self._reset = reset
        #: ``last_time`` of rospy, integer ns.
        self.last_time_ns = self._clock.now_ns()

    @property
    def sleep_dur(self) -> Duration:
        """The period (rospy attribute name)."""
        return Duration._from_ns(self._period)

    @property
    def last_time(self) -> Duration:
        return Duration._from_ns(self.last_time_ns)

    def _remaining(self, curr: int) -> int:
        if self.last_time_ns > curr:
            self.last_time_ns = curr
        return self._period - (curr - self.last_time_ns)

    def remaining(self) -> Duration:
        """Time left in the current cycle (negative if late)."""
        return Duration._from_ns(self._remaining(self._clock.now_ns()))

    def _advance(self, curr: int) -> None:
        self.last_time_ns += self._period
        if curr - self.last_time_ns > 2 * self._period:
            self.last_time_ns = curr

    def sleep(self) -> simpy.Event:
        """Event that fires at the end of the current cycle."""
        clock = self._clock
        ev: simpy.Event
        if type(clock) is KernelClock:
            # _remaining and _advance inlined on the kernel clock (a loop's hottest call)
            env = clock.env
            curr: int = env.now  # NsEnvironment: int ns
            period = self._period
            last = self.last_time_ns
            if last > curr:
                last = curr
            remaining = period - (curr - last)
            last += period
            self.last_time_ns = curr if curr - last > 2 * period else last
            ev = env.timeout(remaining if remaining > 0 else 0)
            setattr(ev, MUST_YIELD, "rate.sleep()")  # must_yield, inlined
            box = env.unyielded
            if box[0] == curr and box[1] == env._same_instant:
                box[2] += 1
                if box[2] >= FORGOTTEN_YIELD_CALLS:
                    box[2] = 0
                    forgotten_yield("rate.sleep()", curr)
            else:
                box[0], box[1], box[2] = curr, env._same_instant, 1
            return ev
        else:
            curr = clock.now_ns()
            remaining = self._remaining(curr)
            if not clock.is_sim:
                self._advance(curr)
                ev = clock.env.timeout(remaining if remaining > 0 else 0)
            else:
                ev = clock.env.process(self._sim_sleep(curr, remaining))
        return must_yield(ev, "rate.sleep()")

    def _sim_sleep(self, curr: int, remaining: int) -> Generator[simpy.Event, object, None]:
        try:
            yield from _sim_sleep(self._clock, remaining)
        except ROSTimeMovedBackwardsException:
            if not self._reset:
                raise
            self.last_time_ns = self._clock.now_ns()
            return
        self._advance(curr)


class WallRate(Rate):
    """roscpp ``ros::WallRate``: a Rate on the kernel ("wall") clock."""

    def __init__(self, node: KernelClockOwner | WorldOwner, hz: float = REQUIRED,
                 reset: bool = False) -> None:
        _check_rospy_shape("WallRate", "create_wall_rate", node, hz,
                           {"reset": reset} if reset else {})
        world = node.world if hasattr(node, "world") else node  # a node's world, or the world
        super().__init__(world.kernel_clock, hz, reset)

    @property
    def sleep_dur(self) -> WallDuration:  # type: ignore[override]
        return WallDuration._from_ns(self._period)


class RoscppRate:
    """roscpp ``ros::Rate``: ``ok = yield rate.sleep()`` tells if the cycle was met."""

    def __init__(self, node: Clock | ClockOwner, hz: float = REQUIRED) -> None:
        _check_rospy_shape("RoscppRate", "create_roscpp_rate", node, hz, {})
        self._clock = _clock_of(node)
        hz = check_hz(hz)
        self._period = roscpp_period_ns(hz)
        if self._period <= 0:
            raise DdesValueError(f"rate {hz!r} Hz has a period below one nanosecond")
        self._start = self._clock.now_ns()
        self._actual_cycle = 0

    def sleep(self) -> simpy.Event:
        """Event whose value is True if the loop met its rate, False if it missed."""
        expected_end = self._start + self._period
        actual_end = self._clock.now_ns()
        if actual_end < self._start:  # backwards jump
            expected_end = actual_end + self._period
        sleep_time = expected_end - actual_end
        self._actual_cycle = actual_end - self._start
        self._start = expected_end
        if sleep_time <= 0:
            if actual_end > expected_end + self._period:
                self._start = actual_end
            return must_yield(self._clock.env.timeout(0, False), "rate.sleep()")
        return must_yield(duration_sleep(self._clock, Duration._from_ns(sleep_time)),
                          "rate.sleep()")

    def reset(self) -> None:
        """Restart the cycle now."""
        self._start = self._clock.now_ns()

    def cycle_time(self) -> Duration:
        """How long the last cycle actually took."""
        return Duration._from_ns(self._actual_cycle)

    def expected_cycle_time(self) -> Duration:
        """The period."""
        return Duration._from_ns(self._period)
