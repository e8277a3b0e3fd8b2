"""SimPy on integer nanoseconds: the one module that touches SimPy's internals.

Everything else in ddes uses SimPy's public API (``env.now``, ``env.event()``,
``env.timeout()``, ``env.process()``, ``event.callbacks``, ``event.value``)
or the functions here.  SimPy is pinned to ``>=4.1,<5``; ``tests/kernel``
checks the assumptions below against the installed version.

Same-time order.  SimPy keeps one heap keyed ``(time, priority, sequence)``:
events due at the same instant fire urgent-first (process starts and
interrupts), then in the order they were *scheduled* (FIFO by a global
sequence number).  ddes schedules everything through this one heap, so the
order of same-time events is a pure function of the program and the seed.

:func:`post` is the kernel's hottest operation — schedule a value with one
callback.  It is exactly ``env.timeout(delay, value).callbacks.append(cb)``:
the same event type, the same ``(time, NORMAL, sequence)`` heap key, so the
same same-time order, without two Python calls per message.
"""

from __future__ import annotations

import warnings
from collections.abc import Callable
from heapq import heappop, heappush
from typing import Generic, TypeVar

import simpy
from simpy.core import EmptySchedule, SimTime, StopSimulation
from simpy.events import NORMAL, PENDING, URGENT, Event, ProcessGenerator, Timeout

from ddes.errors import BadYieldError
from ddes.time.sleep import MUST_YIELD

__all__ = [
    "DEFAULT_INSTANT_BUDGET",
    "NeverYieldedWarning",
    "NsEnvironment",
    "Posted",
    "ZeroTimeLivelock",
    "disarm_stops",
    "is_pending",
    "never_yielded",
    "post",
    "queued_events",
    "repost",
    "succeed",
]

_V = TypeVar("_V")
_V_co = TypeVar("_V_co", covariant=True)


class NsEnvironment(simpy.Environment):
    """A SimPy environment whose clock holds integer nanoseconds.

    Besides SimPy's ``now`` property it keeps the time in a plain attribute,
    :attr:`now_ns`, which the hot paths read (a property costs a Python call,
    about 100 ns, per read).  :meth:`step` is SimPy 4's, plus that one store.
    """

    def __init__(self, initial_time: int = 0) -> None:
        super().__init__(initial_time)
        #: Current kernel time, integer nanoseconds (a plain attribute; read-only by contract).
        self.now_ns: int = initial_time
        #: Called as ``on_failure(event, exception)`` for a failed event nobody waited on;
        #: returning True means it was handled (SimPy would crash the run).
        self.on_failure: Callable[[Event, BaseException], bool] | None = None
        #: Most events one instant may hold before the run stops as a zero-time livelock.
        self.instant_budget: int = DEFAULT_INSTANT_BUDGET
        #: Events processed at the current instant after its first: the livelock count, and
        #: with ``now_ns`` the kernel's progress (see :meth:`progress`).
        self._same_instant = 0
        #: ``[now_ns, events at now_ns, calls]``: blocking calls made since the kernel's last
        #: step (:func:`ddes.time.sleep.must_yield` stops a loop whose ``yield`` is missing).
        self.unyielded: list[int] = [-1, -1, 0]

    def progress(self) -> tuple[int, int]:
        """A mark that grows with every event processed: ``(now_ns, events at now_ns after the
        first)``, increasing lexicographically per step (the wall-clock watchdog watches it)."""
        return (self.now_ns, self._same_instant)

    @property
    def now(self) -> int:
        """Current kernel time, integer nanoseconds."""
        return self.now_ns

    # SimPy binds ``timeout``/``event``/``process`` to an Environment instance early, but only
    # for attributes of the instance's own class, so a subclass pays a descriptor call per use.
    # ddes's are plain methods; ``timeout`` builds the Timeout as SimPy's ``__init__`` does (the
    # same fields, the same ``(time, NORMAL, sequence)`` heap key: the same order).
    def timeout(self, delay: SimTime = 0, value: object = None) -> Timeout:
        """``simpy.Timeout(env, delay, value)``; integer delays take the inlined path."""
        if type(delay) is not int or delay < 0:
            return Timeout(self, delay, value)
        ev: Timeout = _new_posted(Posted)  # one class for timeouts and posts: see Posted
        ev.env = self
        ev.callbacks = []
        ev._value = value
        ev._delay = delay
        ev._ok = True
        heappush(self._queue, (self._now + delay, NORMAL, next(self._eid), ev))
        return ev

    def event(self) -> Event:
        """``simpy.Event(env)``, built as SimPy 4.1's ``__init__`` builds it, without calling
        it: ``env`` and ``callbacks``, in that order (``_value`` stays the class's PENDING), so
        its attribute layout is that of every other Event."""
        ev: Event = _new_event(Event)
        ev.env = self
        ev.callbacks = []
        return ev

    def process(self, generator: ProcessGenerator) -> simpy.Process:
        """``simpy.Process(env, generator)``."""
        return simpy.Process(self, generator)

    def run(self, until: SimTime | Event | None = None) -> object:
        """SimPy 4.1's ``Environment.run`` on integer ns (``self.step()`` per event, so an
        instance's own ``step``, as ``ddes.testing``'s tie explorer sets, is the one called).
        Inlining step's body into this loop was measured slower on CPython 3.11 (timers −20 %)."""
        if until is not None:
            if not isinstance(until, Event):
                at = until if isinstance(until, int) else float(until)
                if at <= self.now_ns:
                    raise ValueError(
                        f"until ({at}) must be greater than the current simulation time")
                until = Event(self)
                until._ok = True
                until._value = None
                self.schedule(until, URGENT, at - self.now_ns)
            elif until.callbacks is None:
                return until.value
            until.callbacks.append(StopSimulation.callback)
        try:
            while True:
                self.step()
        except StopSimulation as exc:
            return exc.args[0]
        except EmptySchedule:
            if until is not None:
                raise RuntimeError(
                    f'No scheduled events left but "until" event was not triggered: {until}'
                ) from None
        return None

    def step(self) -> None:
        """Process the next event (SimPy 4.1's ``Environment.step``, also setting ``now_ns``)."""
        try:
            t, _, _, event = heappop(self._queue)
        except IndexError:
            raise EmptySchedule from None
        now: int = t  # type: ignore[assignment]  # ddes schedules int delays only
        if now == self.now_ns:
            n = self._same_instant = self._same_instant + 1
            if n > self.instant_budget:
                raise ZeroTimeLivelock(now, n, event)
        else:
            self._now = self.now_ns = now
            self._same_instant = 0
        callbacks, event.callbacks = event.callbacks, None  # type: ignore[assignment]
        if not callbacks:
            label = getattr(event, MUST_YIELD, None)
            if label is not None:
                never_yielded(label, now)
        try:
            for callback in callbacks:
                callback(event)
        except StopSimulation:
            # Reattach the remaining callbacks and reschedule, as SimPy does.
            event.callbacks = callbacks[callbacks.index(callback) + 1:]
            self.schedule(event, URGENT)
            raise
        except RuntimeError as error:
            # SimPy's "Invalid yield value" (a process yielded a non-event) becomes a typed
            # error naming the value and the fix; a node's process crashes its node.
            process = getattr(callback, "__self__", None)
            if not isinstance(process, simpy.Process) or "Invalid yield value" not in str(error):
                raise
            bad = bad_yield(process, str(error))
            hook = self.on_failure
            if hook is not None and hook(process, bad):
                return
            raise bad from None
        if not event._ok and not hasattr(event, "_defused"):
            # The event failed and nobody defused it: crash the run (SimPy's rule),
            # unless the world's failure policy takes it (a node's main process).
            hook = self.on_failure
            if hook is not None and hook(event, event._value):
                event._defused = True
                return
            exc = type(event._value)(*event._value.args)
            exc.__cause__ = event._value
            raise exc


#: Default of :attr:`NsEnvironment.instant_budget`: events at one instant before a livelock is
#: declared (``rosbag play --immediate`` of a million-message bag stays well under it).
DEFAULT_INSTANT_BUDGET = 10_000_000


class ZeroTimeLivelock(Exception):  # noqa: N818 - an internal signal, turned into RunawayError
    """Raised by :meth:`NsEnvironment.step` when one instant holds too many events."""

    def __init__(self, t_ns: int, count: int, event: Event) -> None:
        super().__init__(t_ns, count)
        self.t_ns, self.count, self.event = t_ns, count, event


def bad_yield(process: simpy.Process, simpy_text: str) -> BadYieldError:
    """The typed error for a process that yielded something that is not an event."""
    start = simpy_text.find('Invalid yield value "')
    value = simpy_text[start + len('Invalid yield value "'):].rsplit('"', 1)[0] if start >= 0 else "?"
    return BadYieldError(
        f"the process {process.name} yielded {value}, which is not an event: yield only events, "
        "such as node.sleep(0.5), rate.sleep(), proxy(request) or world.timeout(1.0) "
        "(a plain value cannot be waited for)")


class NeverYieldedWarning(RuntimeWarning):
    """An event a blocking call returned fired with nobody waiting: a forgotten ``yield``."""


def never_yielded(label: str, t_ns: int) -> None:
    """Warn, as asyncio does for a coroutine never awaited, that ``label`` was not yielded."""
    warnings.warn(
        f"{label} was never yielded: the event it returned fired at t={t_ns / 1e9:.9f} s with "
        f"nobody waiting, so nothing waited for it; write 'yield {label}'",
        NeverYieldedWarning, stacklevel=1)


class Posted(Timeout, Generic[_V_co]):
    """The event :func:`post` schedules: a Timeout that also carries, as plain slots,
    ``payload`` (the posted value, also its ``value``) and ``at_ns`` (when it fires).

    Its callbacks read ``ev.payload`` and ``ev.at_ns`` — attribute loads, no
    property call — on the hot paths (deliveries, timer fires, service hops).

    :meth:`NsEnvironment.timeout` makes its timeouts of this class too (without
    ``payload`` and ``at_ns``): the kernel's hottest lines (``event.callbacks``
    in :meth:`~NsEnvironment.step`, ``event._value`` in a process's resume) then
    see one class, which CPython 3.11 specializes, where a mix of two classes
    takes the generic attribute lookup on every event.  Its ``repr`` is a
    Timeout's.
    """

    __slots__ = ("payload", "at_ns")
    payload: _V_co  # written once, by post()
    at_ns: int

    def _desc(self) -> str:
        """``Timeout(delay[, value=value])``, as SimPy writes a Timeout (which this is)."""
        value = "" if self._value is None else f", value={self.value}"
        return f"Timeout({self._delay}{value})"


_new_posted = Posted.__new__
_new_event = Event.__new__


def post(env: simpy.Environment, delay: int, value: _V,
         callback: Callable[[Posted[_V]], object]) -> Posted[_V]:
    """Schedule ``callback(event)`` after ``delay`` ns (>= 0); ``event.payload == value``."""
    ev: Posted[_V] = _new_posted(Posted)
    ev.env = env
    ev.callbacks = [callback]  # type: ignore[list-item]  # SimPy ignores what callbacks return
    ev._value = ev.payload = value
    ev._delay = delay
    ev._ok = True
    at: int = env._now + delay  # type: ignore[assignment]  # every delay ddes schedules is an int
    ev.at_ns = at
    heappush(env._queue, (at, NORMAL, next(env._eid), ev))
    return ev


def succeed(ev: Event, value: object = None) -> None:
    """``ev.succeed(value)``: the same checks and the same ``(now, NORMAL, next id)`` queue
    entry as SimPy's ``Event.succeed``, in one Python call instead of two."""
    if ev._value is not PENDING:
        raise RuntimeError(f"{ev} has already been triggered")
    ev._ok = True
    ev._value = value
    env = ev.env
    heappush(env._queue, (env._now, NORMAL, next(env._eid), ev))


def repost(env: simpy.Environment, ev: Posted[_V], delay: int,
           callback: Callable[[Posted[_V]], object]) -> Posted[_V]:
    """Schedule ``ev`` again: ``callback(ev)`` after ``delay`` ns (>= 0), its payload kept.

    For an event of :func:`post` that the kernel has *processed* (its callbacks
    ran; it is in the queue no more), from one of its own callbacks: a periodic
    wake-up re-arms the event it was woken by instead of allocating a new one.
    The queue entry is the one :func:`post` would push (same time, priority and
    next id), so the schedule, and every trace, are what ``post`` gives.
    """
    ev.callbacks = [callback]  # type: ignore[list-item]  # SimPy ignores what callbacks return
    ev._delay = delay
    at: int = env._now + delay  # type: ignore[assignment]  # every delay ddes schedules is an int
    ev.at_ns = at
    heappush(env._queue, (at, NORMAL, next(env._eid), ev))
    return ev


def is_pending(event: Event) -> bool:
    """True while ``event`` has neither succeeded nor failed (no value yet)."""
    return event._value is PENDING


def queued_events(env: simpy.Environment) -> int:
    """How many events wait in the kernel's queue (for diagnostics and budgets)."""
    return len(env._queue)


def disarm_stops(env: simpy.Environment, until: Event | None = None) -> None:
    """Remove the stop that an interrupted ``env.run(until=...)`` left behind.

    ``run`` hangs SimPy's ``StopSimulation.callback`` on its ``until`` event
    (or on an event it schedules at a numeric ``until``) and takes it off
    only by reaching it.  A run left by an exception (Ctrl+C, a failing
    callback) would otherwise stop some *later* run at that stale instant, or
    raise ``StopSimulation`` out of a plain :meth:`NsEnvironment.step`.
    """
    stop = StopSimulation.callback
    events = [entry[3] for entry in env._queue]
    if until is not None:
        events.append(until)
    for event in events:
        callbacks = event.callbacks
        if callbacks is not None:
            while stop in callbacks:
                callbacks.remove(stop)
