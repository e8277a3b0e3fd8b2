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
    from ddes.graph.master import Master
    from ddes.graph.node import Node
    from ddes.graph.params import ParamServer
    from ddes.services.network import ServiceNetwork

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
        #: How long a new publisher→subscriber connection takes to set up (ns).
        #: Messages published before it exists are not delivered (as in ROS).
        self.connect_delay: int = 1_000_000
        #: Where log lines are printed: ``fn(line, level)``, or None (trace only).
        self.log_output: Callable[[str, int], Any] | None = None
        self._links: list[tuple[tuple[str | None, str | None, str | None], Any]] = []
        self._master: Any = None
        self._service_network: Any = None

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

    # -- the ROS graph -----------------------------------------------------------------------
    @property
    def master(self) -> Master:
        """The world's master: registry of nodes, topics, services, and the parameters."""
        if self._master is None:
            from ddes.graph.master import Master

            self._master = Master(self)
        return self._master  # type: ignore[no-any-return]

    @property
    def params(self) -> ParamServer:
        """The parameter server (``world.master.params``)."""
        return self.master.params

    @property
    def use_sim_time(self) -> bool:
        """The ``/use_sim_time`` parameter that nodes read when they start."""
        return bool(self.master.params.get_param("/use_sim_time", False))

    @use_sim_time.setter
    def use_sim_time(self, value: bool) -> None:
        self.master.params.set_param("/use_sim_time", bool(value))

    def set_link(self, topic: str | None = None, *, publisher: str | None = None,
                 subscriber: str | None = None, latency: Any = 0, loss: float = 0.0) -> None:
        """Set the transport model of matching connections (existing and future).

        ``topic``, ``publisher`` and ``subscriber`` (node names) narrow the
        match; None matches anything; the most specific rule wins, later rules
        win ties.  ``latency`` is seconds, a Duration, or ``f(rng)`` drawn per
        message from the connection's own seeded stream; ``loss`` is a
        probability.
        """
        from ddes.graph.topics import LinkModel

        link = LinkModel(latency, loss)
        self._links.append(((topic, publisher, subscriber), link))
        for entry in self.master.topics.values():
            for pub in entry.publishers:
                for conn in pub.connections:
                    conn.set_link(self._link_for(conn.pub, conn.sub))

    def _link_for(self, pub: Any, sub: Any) -> Any:
        from ddes.graph.topics import LinkModel

        best, best_score = LinkModel(), -1
        for (topic, pnode, snode), link in self._links:
            if topic is not None and topic != pub.resolved_name:
                continue
            if pnode is not None and pnode != pub.node.name:
                continue
            if snode is not None and snode != sub.node.name:
                continue
            score = (topic is not None) * 4 + (pnode is not None) * 2 + (snode is not None)
            if score >= best_score:
                best, best_score = link, score
        return best

    def graph_connect(self, pub: Any, sub: Any) -> None:
        """Connect a publisher to a subscriber after :attr:`connect_delay`."""
        def connect(_ev: Any) -> None:
            if pub._closed or sub._closed:
                return
            from ddes.graph.topics import Connection

            conn = Connection(self, pub, sub, self._link_for(pub, sub))
            pub.connections.append(conn)
            sub.connections.append(conn)
            pub._rebuild_fanout()
            self.record("topic.connect", sub.node.name, topic=pub.resolved_name,
                        publisher=pub.node.name, connection=conn.id)
            if pub.latch and pub._latched is not None:
                conn.send(pub._latched, pub.seq)

        ev = self.env.timeout(self.connect_delay)
        ev.callbacks.append(connect)

    def graph_disconnect(self, conn: Any) -> None:
        """Close a connection (either end went away)."""
        if conn.closed:
            return
        if conn.batchable:
            conn._sent += conn.pub.seq - conn._seq0
            conn.batchable = False
        conn.closed = True
        if conn in conn.pub.connections:
            conn.pub.connections.remove(conn)
            conn.pub._rebuild_fanout()
        if conn in conn.sub.connections:
            conn.sub.connections.remove(conn)
        self.record("topic.disconnect", conn.sub.node.name, topic=conn.pub.resolved_name,
                    publisher=conn.pub.node.name, connection=conn.id)

    def topic_stats(self, topic: str) -> dict[str, Any]:
        """Published/sent/lost/received/dropped/delivered counts of a topic and its connections."""
        entry = self.master.topics.get(topic)
        if entry is None:
            from ddes.errors import ROSTopicException

            raise ROSTopicException(f"unknown topic {topic}; known: {sorted(self.master.topics)}")
        conns = [c for p in entry.publishers for c in p.connections]
        per = [{"id": c.id, "publisher": c.pub.node.name, "subscriber": c.sub.node.name,
                "sent": c.sent, "lost": c.lost, "received": c.received, "dropped": c.dropped,
                "delivered": c.delivered} for c in conns]
        total = {k: sum(int(c[k]) for c in per)  # type: ignore[call-overload]
                 for k in ("sent", "lost", "received", "dropped", "delivered")}
        return {"topic": topic, "type": entry.type,
                "published": sum(p.seq for p in entry.publishers), **total, "connections": per}

    # -- services (ddes.services) -------------------------------------------------------------
    @property
    def service_network(self) -> ServiceNetwork:
        """Service links, statistics and waiters (:class:`ddes.services.ServiceNetwork`)."""
        if self._service_network is None:
            from ddes.services.network import ServiceNetwork

            self._service_network = ServiceNetwork(self)
        return self._service_network  # type: ignore[no-any-return]

    def set_service_link(self, service: str | None = None, *, client: str | None = None,
                         latency: Any = 0.0001) -> None:
        """Set the one-way latency of service messages (default 0.1 ms; see ddes.services.network)."""
        self.service_network.set_link(service, client=client, latency=latency)

    def service_stats(self, service: str) -> dict[str, Any]:
        """Calls, successes, failures by reason, discards and latency of ``service``."""
        return self.service_network.stats(service)

    def get_use_sim_time(self) -> bool:
        """The ``/use_sim_time`` setting that new nodes read."""
        return self.use_sim_time

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
