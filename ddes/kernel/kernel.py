"""The kernel: one simulation's SimPy environment on integer nanoseconds,
its random streams, ids, trace and extension slots.

The kernel knows nothing of ROS.  :class:`ddes.graph.World` builds the ROS
graph on top of it, and the services, actionlib, rosbag and tf2 rooms keep
their per-world state in :meth:`Kernel.extension` slots.

Time.  The SimPy environment's ``now`` is an integer number of
nanoseconds.  Every delay ddes schedules is an ``int``, so ``now`` never
becomes a float.  A bare number handed to a public method is **seconds**
(see :mod:`ddes.time.units`).

Same-time order: see :mod:`ddes.kernel.events` and docs/determinism.md.

``run(until=...)`` processes every event scheduled strictly before the
given instant, as SimPy does; so ``run(1 s)`` then ``run(2 s)`` is the same
as ``run(2 s)``.  A run to the current instant (``run_for(0)``) processes
the events due now: what a process just started or scheduled with no delay
(:meth:`Kernel.settle`).  :meth:`Kernel.run_through` includes the final
instant.
"""

from __future__ import annotations

import hashlib
import random
import sys
from collections.abc import Callable, Mapping
from types import MappingProxyType
from typing import TYPE_CHECKING, TypeVar

import simpy

from ddes.errors import DdesTypeError, DdesValueError, RunawayError, WorldError
from ddes.kernel.events import (
    DEFAULT_INSTANT_BUDGET,
    NsEnvironment,
    ZeroTimeLivelock,
    disarm_stops,
    post,
)
from ddes.kernel.runaway import (
    DEFAULT_WALL_BUDGET,
    WallBudgetExceeded,
    Watchdog,
    describe_livelock,
    describe_runaway,
)
from ddes.kernel.trace import Trace
from ddes.time.clock import KernelClock
from ddes.time.rostime import Duration, Time, WallTime
from ddes.time.units import DurationLike, TimeLike, to_ns

if TYPE_CHECKING:
    from simpy.events import ProcessGenerator

    from ddes.kernel.events import Posted

__all__ = ["Kernel"]

_E = TypeVar("_E")
_K = TypeVar("_K", bound="Kernel")
_V = TypeVar("_V")


class Kernel:
    """A deterministic discrete-event kernel: clock, randomness, trace.

    Parameters
    ----------
    seed:
        Seeds :attr:`rng` and every stream from :meth:`rng_for`.  Same
        scenario + same seed = same trace.
    """

    def __init__(self, seed: int = 0, *, wall_budget: float | None = DEFAULT_WALL_BUDGET,
                 instant_budget: int | None = DEFAULT_INSTANT_BUDGET) -> None:
        if isinstance(seed, bool) or not isinstance(seed, int):
            raise DdesTypeError(f"seed must be an int, got {seed!r}")
        self.seed = seed
        #: The SimPy environment; ``env.now`` is integer nanoseconds.
        self.env = NsEnvironment(initial_time=0)
        self.wall_budget = wall_budget
        self.instant_budget = instant_budget
        #: The world's random generator (all randomness comes from here).
        self.rng = random.Random(seed)
        #: Every observable event of this world.
        self.trace = Trace()
        #: The kernel clock, shared by every node not on simulated time.
        self.kernel_clock = KernelClock(self.env)
        self._ids: dict[str, int] = {}
        self._extensions: dict[str, object] = {}

    # -- budgets against runaway code ------------------------------------------------
    @property
    def wall_budget(self) -> float | None:
        """Wall-clock seconds one step (one callback) may take before :meth:`run` stops it.

        ``None`` switches the watchdog off.  It needs the main thread of a Unix
        process (it uses ``SIGALRM``); elsewhere it is off.
        """
        return self._wall_budget

    @wall_budget.setter
    def wall_budget(self, seconds: float | None) -> None:
        if seconds is not None and (isinstance(seconds, bool)
                                    or not isinstance(seconds, (int, float)) or not seconds > 0):
            raise DdesValueError(f"wall_budget must be None or seconds > 0, got {seconds!r}")
        self._wall_budget = None if seconds is None else float(seconds)

    @property
    def instant_budget(self) -> int | None:
        """Events one simulated instant may hold before :meth:`run` declares a livelock."""
        budget = self.env.instant_budget
        return None if budget == sys.maxsize else budget

    @instant_budget.setter
    def instant_budget(self, events: int | None) -> None:
        if events is not None and (isinstance(events, bool) or not isinstance(events, int)
                                   or events < 1):
            raise DdesValueError(f"instant_budget must be None or an int >= 1, got {events!r}")
        self.env.instant_budget = sys.maxsize if events is None else events

    # -- time -----------------------------------------------------------------
    @property
    def now(self) -> int:
        """Kernel time in integer nanoseconds."""
        return self.env.now_ns

    def time(self) -> Time:
        """Kernel time as a :class:`Time`."""
        return Time._from_ns(self.env.now)

    def wall_time(self) -> WallTime:
        """Kernel time as a :class:`WallTime` (ddes's "wall" clock)."""
        return WallTime._from_ns(self.env.now)

    # -- randomness -------------------------------------------------------------
    def rng_for(self, name: str) -> random.Random:
        """An independent generator for ``name``, derived from the world seed.

        Streams for different names do not disturb each other, so adding a
        lossy link does not change the draws of another.
        """
        digest = hashlib.sha256(f"{self.seed}\x00{name}".encode()).digest()
        return random.Random(int.from_bytes(digest[:16], "little"))

    def next_id(self, kind: str) -> int:
        """A per-world counter (ids of connections, goals, anonymous names...)."""
        n = self._ids.get(kind, 0) + 1
        self._ids[kind] = n
        return n

    # -- extension slots ----------------------------------------------------------
    def extension(self: _K, key: str, factory: Callable[[_K], _E]) -> _E:
        """The per-world object of a room (``"services"``, ``"tf2"``...), made on first use.

        ``factory(world)`` builds it once; later calls return the same object.
        Rooms above the kernel keep their per-world state here instead of in
        attributes of the world, so the kernel never imports them.
        """
        ext = self._extensions.get(key)
        if ext is None:
            ext = self._extensions[key] = factory(self)
        return ext  # type: ignore[return-value]  # made by this key's factory

    @property
    def extensions(self) -> Mapping[str, object]:
        """The extension objects made so far, by key (read-only)."""
        return MappingProxyType(self._extensions)

    # -- processes ----------------------------------------------------------
    def process(self, generator: ProcessGenerator) -> simpy.Process:
        """Start a process from a generator; it may ``yield`` ddes/SimPy events."""
        return self.env.process(generator)

    def timeout(self, delay: DurationLike, value: object = None) -> simpy.Timeout:
        """An event that fires after ``delay`` (Duration or seconds; >= 0)."""
        ns = to_ns(delay, "delay")
        if ns < 0:
            raise DdesValueError(f"negative delay {delay!r}; a timeout cannot go back in time")
        return self.env.timeout(ns, value)

    def timeout_ns(self, delay_ns: int, value: object = None) -> simpy.Timeout:
        """An event that fires after ``delay_ns`` nanoseconds (>= 0)."""
        if delay_ns < 0:
            raise DdesValueError(f"negative delay {delay_ns} ns; a timeout cannot go back in time")
        return self.env.timeout(delay_ns, value)

    def event(self) -> simpy.Event:
        """A fresh untriggered event of this world."""
        return self.env.event()

    def post_ns(self, delay_ns: int, value: _V,
                callback: Callable[[Posted[_V]], object]) -> Posted[_V]:
        """Call ``callback(event)`` after ``delay_ns`` (``event.value`` is ``value``)."""
        return post(self.env, delay_ns, value, callback)

    def call_at(self, t_ns: int, fn: Callable[[], object]) -> simpy.Event:
        """Call ``fn()`` at absolute kernel time ``t_ns`` (no process needed)."""
        delay = t_ns - self.env.now
        if delay < 0:
            raise WorldError(f"call_at({t_ns}) is in the past (now={self.env.now})")
        return post(self.env, delay, None, lambda _ev: fn())

    def run(self, until: TimeLike | Duration | simpy.Event | None = None) -> None:
        """Run the simulation (see :meth:`_run`), stopping runaway code.

        A step that takes longer than :attr:`wall_budget` wall-clock seconds
        (a callback in ``while True:``), or an instant that holds more than
        :attr:`instant_budget` events (a zero-time livelock), ends the run with
        :class:`~ddes.errors.RunawayError` naming the node, the callback and
        the simulated time.
        """
        with Watchdog(self.env, self._wall_budget):
            try:
                self._run(until)
            except ZeroTimeLivelock as live:
                raise RunawayError(describe_livelock(live, self.instant_budget)) from None
            except WallBudgetExceeded as stop:
                raise RunawayError(describe_runaway(stop, self.env.now_ns,
                                                    self._wall_budget)) from None

    def _run(self, until: TimeLike | Duration | simpy.Event | None = None) -> None:
        """Run the simulation.

        ``until`` is a :class:`Time` (an absolute instant), a
        :class:`Duration` (relative to now), a number of seconds (absolute,
        as in SimPy), or a SimPy event.  ``None`` runs until no event is left.
        """
        if until is None:
            self.env.run()
            return
        if isinstance(until, simpy.Event):
            try:
                self.env.run(until=until)
            except BaseException:
                disarm_stops(self.env, until)
                raise
            return
        if isinstance(until, Duration):
            target = self.env.now + until.to_nsec()
        else:
            target = to_ns(until, "until")
        if target < self.env.now:
            raise WorldError(
                f"cannot run until {target / 1e9:.9f}s: the world is already at "
                f"{self.env.now / 1e9:.9f}s (time never runs backwards)"
            )
        if target == self.env.now:
            self._settle()
            return
        try:
            self.env.run(until=target)
        except BaseException:
            disarm_stops(self.env)
            raise

    def settle(self) -> None:
        """Process every event due at the current instant (time does not move).

        A process started or an event scheduled with no delay runs now; the
        instant budget still stops a zero-time livelock.
        """
        with Watchdog(self.env, self._wall_budget):
            try:
                self._settle()
            except ZeroTimeLivelock as live:
                raise RunawayError(describe_livelock(live, self.instant_budget)) from None
            except WallBudgetExceeded as stop:
                raise RunawayError(describe_runaway(stop, self.env.now_ns,
                                                   self._wall_budget)) from None

    def _settle(self) -> None:
        env = self.env
        now = env.now
        while env.peek() == now:
            env.step()

    def run_through(self, t_ns: int, stop: simpy.Event | None = None) -> None:
        """Run until ``t_ns`` (kernel nanoseconds, absolute) *including* the events due then.

        ``run(until=t)`` stops before the events at ``t``; this processes them
        too (what a paced, real-time run needs when it reaches an instant).
        With ``stop``, the run ends as soon as that event has been processed,
        as ``run(until=stop)`` would end.
        """
        env = self.env
        if t_ns < env.now:
            raise WorldError(
                f"cannot run through {t_ns / 1e9:.9f}s: the world is already at "
                f"{env.now / 1e9:.9f}s (time never runs backwards)"
            )
        with Watchdog(env, self._wall_budget):
            try:
                while (stop is None or not stop.processed) and env.peek() <= t_ns:
                    env.step()
                if env.now < t_ns and (stop is None or not stop.processed):
                    env.run(until=t_ns)  # nothing is due before t_ns: only the clock moves
            except ZeroTimeLivelock as live:
                raise RunawayError(describe_livelock(live, self.instant_budget)) from None
            except WallBudgetExceeded as stop_run:
                raise RunawayError(describe_runaway(stop_run, env.now_ns,
                                                   self._wall_budget)) from None

    def run_for(self, duration: DurationLike) -> None:
        """Run for a span (Duration or seconds) from now."""
        ns = to_ns(duration, "duration")
        if ns < 0:
            raise WorldError(f"cannot run for a negative span {duration!r}")
        self.run(Duration._from_ns(ns))

    # -- trace ----------------------------------------------------------------
    def record(self, kind: str, source: str, **details: object) -> None:
        """Append an event to the trace at the current kernel time."""
        self.trace.record(self.env.now, kind, source, details)

    def digest(self) -> str:
        """sha256 of the trace: equal digests mean identical runs."""
        return self.trace.digest()

    def __repr__(self) -> str:
        return f"<{type(self).__name__} seed={self.seed} t={self.env.now / 1e9:.9f}s>"
