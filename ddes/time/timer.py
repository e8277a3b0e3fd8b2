"""Timers: periodic and one-shot callbacks on a node's ROS clock.

The callback receives a :class:`TimerEvent` shaped like rospy's
(``last_expected``, ``last_real``, ``current_expected``, ``current_real``,
``last_duration``; the ``last_*`` fields are None on the first call).
``last_duration`` is the *simulated* time, in float seconds, that the
previous callback took: a callback may be a generator that yields events.

Scheduling follows roscpp's ``TimerManager::updateNext``: after each
callback, ``next += period`` if it was due, and if ``next + period < now``
(the callback was slow or time jumped forward) ``next = now``, skipping the
missed fires.  A backwards jump of a simulated clock restarts the timer at
``now + period`` (roscpp, and rospy since ros_comm#2257), so timers survive
``rosbag play --loop --clock``.  Callbacks run through the node (see
:meth:`ddes.graph.node.Node._invoke`).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import TYPE_CHECKING, Any, NamedTuple

from ddes.errors import DdesValueError
from ddes.time.rostime import Duration, Time
from ddes.time.sleep import duration_ns

if TYPE_CHECKING:
    from ddes.graph.node import Node

__all__ = ["Timer", "TimerEvent"]


class TimerEvent(NamedTuple):
    """What a timer callback is told (rospy.timer.TimerEvent)."""

    last_expected: Time | None
    last_real: Time | None
    current_expected: Time
    current_real: Time
    last_duration: float | None


class Timer:
    """A periodic (or one-shot) timer owned by a node.

    ``Timer(node, period, callback, oneshot=False, reset=False)`` mirrors
    ``rospy.Timer``; ``node.create_timer(...)`` is the same.  ``reset`` is
    accepted for rospy compatibility: ddes timers always survive backwards
    jumps.
    """

    def __init__(
        self,
        node: Node,
        period: Any,
        callback: Callable[[TimerEvent], Any],
        oneshot: bool = False,
        reset: bool = False,
    ) -> None:
        period_ns = duration_ns(period, "timer period")
        if period_ns <= 0:
            raise DdesValueError(f"timer period must be > 0, got {period!r}")
        if not callable(callback):
            raise DdesValueError(f"timer callback must be callable, got {callback!r}")
        node._check_alive("create a timer")
        self._node = node
        self._clock = node.clock
        self._env = node.world.env
        self._period = period_ns
        self._callback = callback
        self._oneshot = oneshot
        self._reset = reset
        self._alive = True
        self._gen = 0
        self._last_expected: int | None = None
        self._last_real: int | None = None
        self._last_duration: float | None = None
        self._started = 0
        self._next = 0
        self._source = node.name
        #: Number of times the callback was started.
        self.fires = 0
        node._add_entity(self)
        self._clock.add_jump_listener(self._on_jump)
        if self._clock.is_valid():
            self._start(self._clock.now_ns())
        else:  # rospy: a sim-time timer starts at the first /clock
            ev = self._clock.wait_valid()
            ev.callbacks.append(lambda _e: self._start(self._clock.now_ns()))

    @property
    def period(self) -> Duration:
        return Duration._from_ns(self._period)

    def _start(self, now: int) -> None:
        if not self._alive:
            return
        self._next = now + self._period
        self._arm()

    def _arm(self) -> None:
        self._gen += 1
        gen = self._gen
        ev = self._clock.wait_until(self._next)
        ev.callbacks.append(lambda _e: self._due(gen))

    def _on_jump(self, old_ns: int, new_ns: int) -> None:
        if self._alive and new_ns < old_ns:
            self._next = new_ns + self._period
            self._arm()

    def _due(self, gen: int) -> None:
        if gen != self._gen or not self._alive:
            return
        self._gen += 1  # nothing else may fire until this callback finished
        self._node._invoke(self._run, (), self._done)

    def _run(self) -> Any:
        now = self._clock.now_ns()
        self._started = now
        le, lr = self._last_expected, self._last_real
        event = TimerEvent(
            None if le is None else Time._from_ns(le),
            None if lr is None else Time._from_ns(lr),
            Time._from_ns(self._next),
            Time._from_ns(now),
            self._last_duration,
        )
        self.fires += 1
        self._node.world.trace.record(
            self._env.now, "timer.fire", self._source, {"expected": self._next, "real": now}
        )
        return self._callback(event)

    def _done(self) -> None:
        now = self._clock.now_ns()
        started_ns = self._started
        self._last_duration = (now - started_ns) / 1e9
        self._last_real = started_ns
        if self._oneshot:
            self._last_expected = self._next
            self.shutdown()
            return
        if not self._alive:
            return
        if self._next <= now:
            self._last_expected = self._next
            self._next += self._period
        if self._next + self._period < now:
            self._next = now
        self._arm()

    def shutdown(self) -> None:
        """Stop the timer; a callback already running finishes."""
        if self._alive:
            self._alive = False
            self._gen += 1
            self._clock.remove_jump_listener(self._on_jump)
            self._node._remove_entity(self)

    def is_alive(self) -> bool:
        """True until :meth:`shutdown` (or the one fire of a one-shot timer)."""
        return self._alive
