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
``rosbag play --loop --clock``.  Callbacks run through the node's callback
runner (:mod:`ddes.graph.callbacks`), like every other callback: on a
single-threaded node a generator timer callback holds the spinner.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import TYPE_CHECKING

from ddes.errors import DdesValueError
from ddes.kernel.events import post
from ddes.time.rostime import Duration, Time
from ddes.time.units import DurationLike, duration_to_ns

if TYPE_CHECKING:
    from simpy import Timeout

    from ddes.graph.node import Node
    from ddes.kernel.events import Posted

__all__ = ["Timer", "TimerEvent"]

_NS = 1_000_000_000
_FIRE_KEYS = ("expected", "real")


def _new_time(ns: int) -> Time:
    t = Time.__new__(Time)
    t.secs, t.nsecs = divmod(ns, _NS)
    return t


class TimerEvent:
    """What a timer callback is told (rospy.timer.TimerEvent).

    The Time fields are built on first access (most callbacks never read
    them), from integer nanoseconds kept by the timer.
    """

    __slots__ = ("_le", "_lr", "_ce", "_cr", "last_duration")

    def __init__(
        self,
        last_expected: Time | int | None,
        last_real: Time | int | None,
        current_expected: Time | int,
        current_real: Time | int,
        last_duration: float | None,
    ) -> None:
        self._le = _ns_or_none(last_expected)
        self._lr = _ns_or_none(last_real)
        self._ce = _ns_or_none(current_expected)
        self._cr = _ns_or_none(current_real)
        #: Simulated seconds the previous callback took (None on the first call).
        self.last_duration = last_duration

    @property
    def last_expected(self) -> Time | None:
        """When the previous callback should have run (None on the first call)."""
        return None if self._le is None else _new_time(self._le)

    @property
    def last_real(self) -> Time | None:
        """When the previous callback actually ran (None on the first call)."""
        return None if self._lr is None else _new_time(self._lr)

    @property
    def current_expected(self) -> Time:
        """When this callback should have run."""
        return _new_time(self._ce)  # type: ignore[arg-type]

    @property
    def current_real(self) -> Time:
        """When this callback actually runs."""
        return _new_time(self._cr)  # type: ignore[arg-type]

    def __repr__(self) -> str:
        return (f"TimerEvent(last_expected={self.last_expected!r}, last_real={self.last_real!r}, "
                f"current_expected={self.current_expected!r}, current_real={self.current_real!r}, "
                f"last_duration={self.last_duration!r})")


def _ns_or_none(t: Time | int | None) -> int | None:
    if t is None or isinstance(t, int):
        return t
    return t.to_nsec()


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
        period: DurationLike,
        callback: Callable[[TimerEvent], object],
        oneshot: bool = False,
        reset: bool = False,
    ) -> None:
        period_ns = duration_to_ns(period, "timer period")
        if period_ns <= 0:
            raise DdesValueError(f"timer period must be > 0, got {period!r}")
        if not callable(callback):
            raise DdesValueError(f"timer callback must be callable, got {callback!r}")
        node.check_alive("create a timer")
        self._node = node
        self._cbq = node.callbacks
        #: True while the callback runs (the node's runner sets it).
        self.cb_active = False
        self._clock = node.clock
        self._env = node.world.env
        self._period = period_ns
        self._callback = callback
        self._oneshot = oneshot
        self._reset = reset
        self._alive = True
        self._gen = 0
        self._last_expected_ns: int | None = None
        self._last_real_ns: int | None = None
        self._last_duration: float | None = None
        self._started = 0
        self._next = 0
        self._kernel = not self._clock.is_sim
        self._fire_cb = self._fire
        self._armed: Timeout | None = None
        self._trace = node.world.trace
        self._source = node.name
        #: Number of times the callback was started.
        self.fires = 0
        node.add_entity(self)
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
        if self._kernel:
            delay = self._next - self._env.now_ns
            self._armed = post(self._env, delay if delay > 0 else 0, gen, self._fire_cb)
        else:
            ev = self._clock.wait_until(self._next)
            ev.callbacks.append(lambda _e: self._fire_gen(gen))

    def _on_jump(self, old_ns: int, new_ns: int) -> None:
        if self._alive and new_ns < old_ns:
            self._next = new_ns + self._period
            self._arm()

    def _fire(self, ev: Posted[int]) -> None:
        """Kernel-clock wake-up (the common case: built inline, run by the node's runner)."""
        if ev is not self._armed or not self._alive:
            return
        self._armed = None  # nothing else may fire until this callback finished
        self._gen += 1
        cbq = self._cbq
        if not (cbq.free and not self.cb_active):
            cbq.enqueue(self._run, (), self, self._done)
            return
        now = ev.at_ns
        nxt = self._next
        self._started = now
        event = TimerEvent.__new__(TimerEvent)
        event._le = self._last_expected_ns
        event._lr = self._last_real_ns
        event._ce = nxt
        event._cr = now
        event.last_duration = self._last_duration
        self.fires += 1
        self._trace.append_row((now, "timer.fire", self._source, _FIRE_KEYS, nxt, now))
        if not cbq.run1(self._callback, event, self, self._done):
            return  # it failed (on_done ran) or goes on as a generator (on_done at its end)
        # Finished at once: roscpp's TimerManager::updateNext, as in _done, without the call.
        self._last_duration = 0.0
        self._last_real_ns = now
        if self._oneshot or not self._alive:
            self._done()
            return
        period = self._period
        if nxt <= now:
            self._last_expected_ns = nxt
            nxt += period
            if nxt + period < now:
                nxt = now
            self._next = nxt
        self._gen += 1
        self._armed = post(self._env, nxt - now if nxt > now else 0, self._gen, self._fire_cb)

    def _fire_gen(self, gen: int) -> None:
        if gen != self._gen or not self._alive:
            return
        self._gen += 1  # nothing else may fire until this callback finished
        self._cbq.invoke(self._run, (), self, self._done)

    def _run(self) -> object:
        """The callback's turn: build the TimerEvent, record, call (through the node's runner)."""
        now = self._clock.now_ns()
        nxt = self._next
        self._started = now
        event = TimerEvent.__new__(TimerEvent)
        event._le = self._last_expected_ns
        event._lr = self._last_real_ns
        event._ce = nxt
        event._cr = now
        event.last_duration = self._last_duration
        self.fires += 1
        self._trace.append_row((self._env.now_ns, "timer.fire", self._source, _FIRE_KEYS, nxt, now))
        return self._callback(event)

    def _done(self) -> None:
        env = self._env
        now: int = env.now_ns if self._kernel else self._clock.now_ns()
        started = self._started
        self._last_duration = (now - started) / 1e9
        self._last_real_ns = started
        if self._oneshot:
            self._last_expected_ns = self._next
            self.shutdown()
            return
        if not self._alive:
            return
        nxt = self._next
        period = self._period
        if nxt <= now:
            self._last_expected_ns = nxt
            nxt += period
        if nxt + period < now:
            nxt = now
        self._next = nxt
        if self._kernel:
            self._gen += 1
            delay = nxt - now
            self._armed = post(env, delay if delay > 0 else 0, self._gen, self._fire_cb)
        else:
            self._arm()

    def shutdown(self) -> None:
        """Stop the timer; a callback already running finishes."""
        if self._alive:
            self._alive = False
            self._gen += 1
            self._clock.remove_jump_listener(self._on_jump)
            self._node.remove_entity(self)

    def is_alive(self) -> bool:
        """True until :meth:`shutdown` (or the one fire of a one-shot timer)."""
        return self._alive
