"""The World: one simulation, owning clock, RNG, trace, master and parameters.

Time.  The SimPy environment's ``now`` is an integer number of
nanoseconds.  Every delay ddes schedules is an ``int``, so ``now`` never
becomes a float.

Same-time order.  SimPy keeps one heap keyed ``(time, priority, sequence)``:
events due at the same instant fire urgent-first (process starts and
interrupts), then in the order they were *scheduled* (FIFO by a global
sequence number).  ddes schedules everything through this one heap, so the
order of same-time events is a pure function of the program and the seed,
never of hashing, sets or the wall clock.  See docs/determinism.md.

``run(until=...)`` processes every event scheduled strictly before the
given instant, as SimPy does; so ``run(1 s)`` then ``run(2 s)`` is the same
as ``run(2 s)``.
"""

from __future__ import annotations

import hashlib
import random
from collections.abc import Callable, Generator
from typing import TYPE_CHECKING, Any

import simpy

from ddes.errors import DdesTypeError, DdesValueError, WorldError
from ddes.kernel.trace import Trace
from ddes.time.clock import KernelClock
from ddes.time.rostime import Duration, Time, WallTime

if TYPE_CHECKING:
    from ddes.graph.node import Node

__all__ = ["NsEnvironment", "World", "to_ns"]


def to_ns(value: Any, what: str = "time") -> int:
    """Convert a Time, Duration, WallTime/WallDuration or seconds to integer ns."""
    to_nsec = getattr(value, "to_nsec", None)
    if to_nsec is not None:
        return int(to_nsec())
    if isinstance(value, bool):
        raise DdesTypeError(f"{what} must be a Time, Duration or seconds, got {value!r}")
    if isinstance(value, int):
        return value * 1_000_000_000
    if isinstance(value, float):
        return Duration.from_sec(value).to_nsec()
    raise DdesTypeError(
        f"{what} must be a Time, Duration or a number of seconds, got {value!r} "
        f"({type(value).__name__})"
    )


class NsEnvironment(simpy.Environment):
    """A SimPy environment whose clock holds integer nanoseconds."""

    @property
    def now(self) -> int:
        """Current kernel time, integer nanoseconds."""
        return self._now  # type: ignore[return-value]


class World:
    """A deterministic ROS world on a SimPy kernel.

    Parameters
    ----------
    seed:
        Seeds :attr:`rng` and every stream from :meth:`rng_for`.  Same
        scenario + same seed = same trace.
    """

    def __init__(self, seed: int = 0) -> None:
        if isinstance(seed, bool) or not isinstance(seed, int):
            raise DdesTypeError(f"seed must be an int, got {seed!r}")
        self.seed = seed
        #: The SimPy environment; ``env.now`` is integer nanoseconds.
        self.env = NsEnvironment(initial_time=0)
        #: The world's random generator (all randomness comes from here).
        self.rng = random.Random(seed)
        #: Every observable event of this world.
        self.trace = Trace()
        self._ids: dict[str, int] = {}
        self._nodes: dict[str, Node] = {}
        self._graph: Any = None  # the master, created lazily by ddes.graph
        #: The kernel clock, shared by every node not on simulated time.
        self.kernel_clock = KernelClock(self)
        #: (node, callback, exception, traceback) of every failed callback.
        self.callback_errors: list[tuple[str, str, BaseException, str]] = []
        #: Re-raise callback exceptions out of :meth:`run` (default) or only
        #: record them in the trace and :attr:`callback_errors`.
        self.raise_callback_errors = True
        #: ``/use_sim_time`` until the parameter server exists.
        self.use_sim_time = False

    # -- time -----------------------------------------------------------------
    @property
    def now(self) -> int:
        """Kernel time in integer nanoseconds."""
        return self.env.now

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

    # -- processes ----------------------------------------------------------
    def process(self, generator: Generator[Any, Any, Any]) -> simpy.Process:
        """Start a process from a generator; it may ``yield`` ddes/SimPy events."""
        return self.env.process(generator)

    def timeout(self, delay: Any, value: Any = None) -> simpy.Timeout:
        """An event that fires after ``delay`` (Duration or seconds; >= 0)."""
        ns = to_ns(delay, "delay")
        if ns < 0:
            raise DdesValueError(f"negative delay {delay!r}; a timeout cannot go back in time")
        return self.env.timeout(ns, value)

    def event(self) -> simpy.Event:
        """A fresh untriggered event of this world."""
        return self.env.event()

    def call_at(self, t_ns: int, fn: Callable[[], Any]) -> simpy.Event:
        """Call ``fn()`` at absolute kernel time ``t_ns`` (no process needed)."""
        delay = t_ns - self.env.now
        if delay < 0:
            raise WorldError(f"call_at({t_ns}) is in the past (now={self.env.now})")
        ev = self.env.timeout(delay)
        ev.callbacks.append(lambda _ev: fn())  # type: ignore[union-attr]
        return ev

    def run(self, until: Any = None) -> None:
        """Run the simulation.

        ``until`` is a :class:`Time` (an absolute instant), a
        :class:`Duration` (relative to now), a number of seconds (absolute,
        as in SimPy), or a SimPy event.  ``None`` runs until no event is left.
        """
        if until is None:
            self.env.run()
            return
        if isinstance(until, simpy.Event):
            self.env.run(until=until)
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
            return
        self.env.run(until=target)

    def run_for(self, duration: Any) -> None:
        """Run for a span (Duration or seconds) from now."""
        ns = to_ns(duration, "duration")
        if ns < 0:
            raise WorldError(f"cannot run for a negative span {duration!r}")
        self.run(Duration._from_ns(ns))

    # -- trace ----------------------------------------------------------------
    def record(self, kind: str, source: str, **details: Any) -> None:
        """Append an event to the trace at the current kernel time."""
        self.trace.record(self.env.now, kind, source, details)

    def digest(self) -> str:
        """sha256 of the trace: equal digests mean identical runs."""
        return self.trace.digest()

    def get_use_sim_time(self) -> bool:
        """The ``/use_sim_time`` setting that new nodes read."""
        return bool(self.use_sim_time)

    # -- nodes ------------------------------------------------------------------
    def create_node(self, name: str, **kwargs: Any) -> Node:
        """Create and start a node (see :class:`ddes.graph.node.Node`)."""
        from ddes.graph.node import Node

        return Node(self, name, **kwargs)

    @property
    def nodes(self) -> dict[str, Node]:
        """Live nodes by fully-qualified name, in creation order."""
        return dict(self._nodes)

    def __repr__(self) -> str:
        return f"<World seed={self.seed} t={self.env.now / 1e9:.9f}s nodes={len(self._nodes)}>"
