"""Timers: periodic and one-shot callbacks on a node's ROS clock.

The callback receives a :class:`TimerEvent` shaped like rospy's
(``last_expected``, ``last_real``, ``current_expected``, ``current_real``,
``last_duration``; the ``last_*`` fields are None on the first call).
``last_duration`` is the *simulated* time, in float seconds, that the
previous callback took: a callback may be a generator that yields events.

:class:`Timer` (``ddes.Timer``, ``node.create_timer``) is rospy's
``rospy.Timer.run`` loop, step for step (``rospy/timer.py``):

* at creation ``current_expected = now + period`` and a ``Rate`` of
  ``1.0 / period.to_sec()`` Hz starts, whose period is
  ``Duration(0, int(1e9 / hz))`` (so a 0.3 s timer sleeps 299,999,999 ns);
* each turn ``rate.sleep()`` sleeps what is left of the Rate's period,
  advances its ``last_time`` by one period, and drops the backlog
  (``last_time = now``) when it was more than two periods behind; then the
  callback runs with ``current_real = now``; afterwards ``last_expected,
  last_real = current_expected, current_real`` and ``current_expected +=
  period`` — never re-aligned to the clock.  A callback slower than the
  period, or a forward jump of ``/clock``, makes the next fires come at once
  until the Rate has dropped its backlog.
* Under simulated time a timer created before the first ``/clock`` reads
  time 0: ``current_expected`` counts from 0, and the first sleep starts at
  the first ``/clock`` (rospy.sleep waits for a non-zero time).
* A backwards jump below the start of a sleep ends the sleep and the
  callback runs at once (``reset=True``; see docs/time.md for ``reset=False``).

:class:`RoscppTimer` (``node.create_roscpp_timer``) is roscpp's
``TimerManager``.  Callbacks of both run through the node's callback runner
(:mod:`ddes.graph.callbacks`), like every other callback: on a
single-threaded node a generator timer callback holds the spinner.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import TYPE_CHECKING, NoReturn

from ddes.errors import DdesTypeError, DdesValueError
from ddes.kernel.events import post, repost
from ddes.time.rospy_calls import REQUIRED, arg_text, call_text, is_node_like, missing_node
from ddes.time.rostime import Duration, Time
from ddes.time.units import DurationLike, duration_to_ns

if TYPE_CHECKING:
    import simpy
    from simpy import Timeout

    from ddes.graph.node import Node
    from ddes.kernel.events import Posted

__all__ = ["RoscppTimer", "Timer", "TimerEvent", "rospy_timer_sleep_ns"]

_NS = 1_000_000_000
_FIRE_KEYS = ("expected", "real")


_new_event = object.__new__


def _new_time(ns: int) -> Time:
    t = Time.__new__(Time)
    t.secs, t.nsecs = divmod(ns, _NS)
    return t


def rospy_timer_sleep_ns(period_ns: int) -> int:
    """The period of the Rate inside a rospy Timer: ``int(1e9 / (1.0 / period.to_sec()))``.

    genpy's ``to_sec`` is ``float(secs) + float(nsecs) / 1e9``; the float
    round trip loses a nanosecond for periods like 0.3 s.  At least 1 ns.
    """
    secs, nsecs = divmod(period_ns, _NS)
    hz = 1.0 / (float(secs) + float(nsecs) / 1e9)
    return max(int(1e9 / hz), 1)


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



def _no_node(node: object, period: object, callback: object, oneshot: bool,
             reset: bool) -> NoReturn:
    """``ddes.Timer(rospy.Duration(1), cb)``, rospy's spelling: say what to write instead."""
    if callable(period) and not callable(callback):
        if callback is not REQUIRED:  # rospy.Timer(period, cb, oneshot, reset): all shifted
            oneshot, reset = bool(callback), bool(oneshot or reset)
        kwargs: dict[str, object] = {k: v for k, v in (("oneshot", oneshot), ("reset", reset)) if v}
        args = [node, period]
        extra = "".join(f", {k}={arg_text(v)}" for k, v in kwargs.items())
        raise missing_node(
            call_text("ddes.Timer", args, kwargs),
            f"timer = ddes.Timer(node, {arg_text(node)}, {arg_text(period)}{extra})"
            f"    # or node.create_timer({arg_text(node)}, {arg_text(period)}{extra})")
    raise DdesTypeError(f"ddes.Timer(node, period, callback) needs a node first, got {node!r}")


class Timer:
    """rospy's ``Timer``: ``ddes.Timer(node, period, callback, oneshot=False, reset=False)``.

    ``node.create_timer(...)`` is the same.  The schedule is rospy's (see the
    module docstring); ``reset`` is accepted for rospy compatibility: a ddes
    timer always survives a backwards jump as rospy's does with ``reset=True``.
    """

    __slots__ = ("_alive", "_kernel", "_cbq", "cb_active", "_callback", "_trace", "_source",
                 "_env", "_period", "_armed", "_fire_cb", "_done_cb", "_ce", "_le", "_lr", "_ld",
                 "_last_time", "_started", "fires", "_clock", "_sleep_dur", "_oneshot", "_reset",
                 "_node")

    def __init__(
        self,
        node: Node,
        period: DurationLike,
        callback: Callable[[TimerEvent], object] = REQUIRED,
        oneshot: bool = False,
        reset: bool = False,
    ) -> None:
        if not is_node_like(node):
            _no_node(node, period, callback, oneshot, reset)
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
        clock = self._clock = node.clock
        self._env = node.world.env
        self._period = period_ns
        #: The period of rospy's Rate inside the timer (see rospy_timer_sleep_ns).
        self._sleep_dur = rospy_timer_sleep_ns(period_ns)
        self._callback = callback
        self._oneshot = oneshot
        self._reset = reset
        self._alive = True
        self._kernel = not clock.is_sim
        self._fire_cb = self._fire
        self._done_cb = self._done
        self._armed: Posted[None] | None = None
        self._trace = node.world.trace
        self._source = node.name
        now = clock.now_ns()
        #: rospy's ``Rate.last_time`` (ns).
        self._last_time = now
        self._ce = now + period_ns
        self._le: int | None = None
        self._lr: int | None = None
        self._ld: float | None = None
        self._started = 0
        #: Number of times the callback was started.
        self.fires = 0
        node.add_entity(self)
        if self._kernel:
            self._sleep(now)
        else:
            self._sim_sleep()

    @property
    def period(self) -> Duration:
        return Duration._from_ns(self._period)

    # -- rate.sleep() on the kernel clock (the common, fast case) ---------------------------
    def _sleep(self, now: int) -> None:
        """rospy ``Rate.sleep`` from ``now``: arm the wake-up, advance ``last_time``.

        (The kernel clock never goes back, so ``last_time <= now`` here: rospy's
        "time moved backwards" clamp is left out.)
        """
        sd = self._sleep_dur
        lt = self._last_time
        remaining = sd - (now - lt)
        lt += sd
        if now - lt > 2 * sd:
            lt = now
        self._last_time = lt
        self._armed = post(self._env, remaining if remaining > 0 else 0, None, self._fire_cb)

    def _fire(self, ev: Posted[None]) -> None:
        """Kernel-clock wake-up: the callback's turn (built inline, run by the node's runner)."""
        if ev is not self._armed or not self._alive:
            return
        self._armed = None
        cbq = self._cbq
        if not (cbq.free and not self.cb_active):
            cbq.enqueue(self._run, (), self, self._done_cb)
            return
        now = ev.at_ns
        ce = self._ce
        self._started = now
        event = _new_event(TimerEvent)
        event._le = self._le
        event._lr = self._lr
        event._ce = ce
        event._cr = now
        event.last_duration = self._ld
        self.fires += 1
        self._trace.append_row((now, "timer.fire", self._source, _FIRE_KEYS, ce, now))
        if not cbq.run1(self._callback, event, self, self._done_cb):
            return  # it failed (on_done ran) or goes on as a generator (on_done at its end)
        # Finished at once: _done without the call.
        if self._oneshot or not self._alive:
            self._done()
            return
        self._ld = 0.0
        self._le = ce
        self._lr = now
        self._ce = ce + self._period
        sd = self._sleep_dur  # _sleep(now), inline
        lt = self._last_time
        remaining = sd - (now - lt)
        lt += sd
        if now - lt > 2 * sd:
            lt = now
        self._last_time = lt
        # the wake-up that ran this is processed: re-armed, as post() would arm a new one
        self._armed = repost(self._env, ev, remaining if remaining > 0 else 0, self._fire_cb)

    # -- rate.sleep() on a simulated clock ----------------------------------------------------
    def _sim_sleep(self) -> None:
        """rospy ``Rate.sleep`` → ``rospy.sleep(remaining)`` under simulated time."""
        clock = self._clock
        curr = clock.now_ns()
        if self._last_time > curr:
            self._last_time = curr
        remaining = self._sleep_dur - (curr - self._last_time)
        if curr == 0:  # rospy.sleep waits for a non-zero time first
            clock.wait_valid().callbacks.append(lambda _e: self._sim_wait(curr, remaining))
        else:
            self._sim_wait(curr, remaining)

    def _sim_wait(self, curr: int, remaining: int) -> None:
        if not self._alive:
            return
        clock = self._clock
        start = clock.now_ns()
        target = start + remaining
        if start >= target:  # nothing left to sleep: wake in this instant
            post(self._env, 0, None, lambda _e: self._sim_woke(curr, True))
            return
        ev = clock.wait_until(target, start)
        ev.callbacks.append(lambda e: self._sim_woke(curr, e))

    def _sim_woke(self, curr: int, ev: simpy.Event | bool) -> None:
        slept = True
        if ev is not True and not ev.ok:  # type: ignore[union-attr]
            ev.defused = True  # type: ignore[union-attr]  # time moved back below the start
            slept = False
        if not self._alive:
            return
        if slept:
            lt = self._last_time + self._sleep_dur
            self._last_time = curr if curr - lt > 2 * self._sleep_dur else lt
        else:  # rospy Rate(reset=True): restart from now, and the callback runs at once
            self._last_time = self._clock.now_ns()
        cbq = self._cbq
        if not (cbq.free and not self.cb_active):
            cbq.enqueue(self._run, (), self, self._done_cb)
            return
        now = self._clock.now_ns()
        ce = self._ce
        self._started = now
        event = TimerEvent.__new__(TimerEvent)
        event._le = self._le
        event._lr = self._lr
        event._ce = ce
        event._cr = now
        event.last_duration = self._ld
        self.fires += 1
        self._trace.append_row((self._env.now_ns, "timer.fire", self._source, _FIRE_KEYS, ce, now))
        if cbq.run1(self._callback, event, self, self._done_cb):
            self._done()

    # -- the callback -------------------------------------------------------------------------
    def _run(self) -> object:
        """The callback's turn: build the TimerEvent, record, call (through the node's runner)."""
        now = self._clock.now_ns()
        ce = self._ce
        self._started = now
        event = TimerEvent.__new__(TimerEvent)
        event._le = self._le
        event._lr = self._lr
        event._ce = ce
        event._cr = now
        event.last_duration = self._ld
        self.fires += 1
        self._trace.append_row((self._env.now_ns, "timer.fire", self._source, _FIRE_KEYS, ce, now))
        return self._callback(event)

    def _done(self) -> None:
        """After the callback: rospy's bookkeeping, then the next ``rate.sleep()``."""
        if self._oneshot:
            self.shutdown()
            return
        if not self._alive:
            return
        now = self._env.now_ns if self._kernel else self._clock.now_ns()
        started = self._started
        self._ld = (now - started) / 1e9
        self._le = self._ce
        self._lr = started
        self._ce += self._period
        if self._kernel:
            self._sleep(now)
        else:
            self._sim_sleep()

    def callback_failed(self) -> None:
        """The callback raised: the timer stops, as the exception ends rospy's timer thread."""
        self.shutdown()

    def shutdown(self) -> None:
        """Stop the timer; a callback already running finishes."""
        if self._alive:
            self._alive = False
            self._armed = None
            self._node.remove_entity(self)

    def is_alive(self) -> bool:
        """True until :meth:`shutdown` (or the one fire of a one-shot timer)."""
        return self._alive


class RoscppTimer:
    """roscpp's ``ros::Timer``: ``node.create_roscpp_timer(period, callback, oneshot=False)``.

    Scheduling follows roscpp's ``TimerManager::updateNext``: after each
    callback, ``next += period`` if it was due, and if ``next + period < now``
    (the callback was slow or time jumped forward) ``next = now``, skipping
    the missed fires.  A backwards jump of a simulated clock restarts the
    timer at ``now + period``.  ``reset`` is accepted and ignored.
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
