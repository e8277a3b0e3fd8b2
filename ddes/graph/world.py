"""The ROS world: the kernel plus the graph — master, parameters, nodes, links.

A :class:`World` is one simulation.  It owns the :class:`~ddes.kernel.Kernel`
parts (integer-nanosecond SimPy environment, seeded random streams, trace)
and the ROS graph on top: the master with its parameter server, the nodes,
and the transport model of topic connections.  Services, actionlib, bags and
TF keep their per-world state in the kernel's extension slots; the
``ddes.World`` facade adds their conveniences (``world.set_service_link``...).
"""

from __future__ import annotations

import os
from collections.abc import Callable, Iterable
from typing import TYPE_CHECKING, ClassVar, TypedDict

import simpy

from ddes.errors import ROSTopicException
from ddes.graph.failures import NODE_OF_PROCESS, STRICT_DEFAULT, user_frames
from ddes.graph.master import Master
from ddes.graph.params import ParamServer
from ddes.graph.topics import (
    Connection,
    LinkLatency,
    LinkModel,
    Publisher,
    Subscriber,
    connect_later,
)
from ddes.kernel.events import DEFAULT_INSTANT_BUDGET
from ddes.kernel.kernel import Kernel
from ddes.kernel.runaway import DEFAULT_WALL_BUDGET
from ddes.msg.registry import MessageRegistry, default_registry
from ddes.rospack import RosPack
from ddes.time.rostime import Duration
from ddes.time.units import TimeLike

if TYPE_CHECKING:
    from typing_extensions import Unpack

    from ddes.graph.node import Node, NodeOptions
    from ddes.msg.message import MessageClass

__all__ = ["ConnectionStats", "LinkLatency", "TopicStats", "World"]


class ConnectionStats(TypedDict):
    """The counters of one connection in :meth:`World.topic_stats`."""

    id: int
    publisher: str
    subscriber: str
    sent: int
    lost: int
    received: int
    dropped: int
    delivered: int


class TopicStats(TypedDict):
    """What :meth:`World.topic_stats` returns: a topic's counters, summed over its connections."""

    topic: str
    type: str
    published: int
    sent: int
    lost: int
    received: int
    dropped: int
    delivered: int
    connections: list[ConnectionStats]


class World(Kernel):
    """A deterministic ROS world on a SimPy kernel.

    Parameters
    ----------
    seed:
        Seeds :attr:`rng` and every stream from :meth:`rng_for`.  Same
        scenario + same seed = same trace.
    package_path:
        Folders of the user's ROS packages (their ``msg/``, ``srv/``,
        ``action/``, node types and launch files), searched before ddes's
        bundled packages.  They belong to this world only: two worlds with
        different package paths never see each other's types.  Nothing reads
        ``DDES_PACKAGE_PATH`` behind your back; the ``ddes`` command passes it
        here when it starts.
    wall_budget:
        Wall-clock seconds one callback may run without returning or yielding
        before :meth:`run` stops it with RunawayError (default 10; None: off).
    instant_budget:
        Events one simulated instant may hold before :meth:`run` stops a
        zero-time livelock with RunawayError (default 10,000,000; None: off).
    strict:
        False (rospy's rule): a failing callback is logged ("bad callback")
        and a failing node main shuts that node down; the world runs on.
        True: :meth:`run` raises the first such exception, with the user's
        frames on top.  None takes the default of :func:`strict_worlds`
        (False unless inside one).
    """

    #: The class :meth:`create_node` makes (the ``ddes.World`` facade makes ``ddes.Node``).
    node_class: ClassVar[type[Node] | None] = None

    def __init__(self, seed: int = 0, *,
                 package_path: Iterable[str | os.PathLike[str]] = (),
                 wall_budget: float | None = DEFAULT_WALL_BUDGET,
                 instant_budget: int | None = DEFAULT_INSTANT_BUDGET,
                 strict: bool | None = None) -> None:
        super().__init__(seed, wall_budget=wall_budget, instant_budget=instant_budget)
        paths = [package_path] if isinstance(package_path, (str, os.PathLike)) else list(package_path)
        #: Message, service and action types of this world (the bundled
        #: registry, shared and immutable, unless a package path is given).
        self.messages: MessageRegistry = MessageRegistry(paths) if paths else default_registry()
        #: Packages of this world: the package path, then the bundled packages.
        self.rospack: RosPack = RosPack(paths)
        self._nodes: dict[str, Node] = {}
        #: (node, callback, exception, traceback) of every failed callback.
        self.callback_errors: list[tuple[str, str, BaseException, str]] = []
        #: Strict: :meth:`run` raises the first exception of user code (a callback, a
        #: node's main) instead of logging it as rospy does (see ddes.graph.failures).
        self.strict: bool = STRICT_DEFAULT.get() if strict is None else bool(strict)
        self._failure: BaseException | None = None
        self.env.on_failure = self._on_failure
        #: How long a new publisher→subscriber connection takes to set up (ns).
        #: Messages published before it exists are not delivered (as in ROS).
        self.connect_delay_ns: int = 1_000_000
        #: Where log lines are printed: ``fn(line, level)``, or None (trace only).
        self.log_output: Callable[[str, int], object] | bool | None = None
        #: Folders shown under another name in what nodes log (``{real: shown}``): the grader
        #: shows a submission's temporary folder as ``/submission``, so a log line naming a
        #: file in it (``rosbag play``'s ``Opening ...``) and a grade's digest do not depend on
        #: where the submission was unpacked.  Empty (every path as it is) by default.
        self.display_paths: dict[str, str] = {}
        #: Told of every parameter a node reads: ``fn(node, resolved key, found)`` after each
        #: ``get_param`` and ``has_param`` of a node, or None (nothing told: the default).  The
        #: grader's sandbox uses it to learn which names a student's node read.
        self.param_observer: Callable[[str, str, bool], object] | None = None
        #: Told of every node as it registers with the master: ``fn(node)``, the node's names,
        #: clock and callback queue made, its logger and private parameters not yet (empty by
        #: default).  The console gives roscpp-style nodes roscpp's ``~get_loggers`` and
        #: ``~set_logger_level`` services this way (:mod:`ddes.services.loggers`).
        self.node_observers: list[Callable[[Node], object]] = []
        self._links: list[tuple[tuple[str | None, str | None, str | None], LinkModel]] = []
        #: The world's master: registry of nodes, topics, services, and the parameters.
        self.master = Master(self)

    # -- failures of user code (ddes.graph.failures) ------------------------------------------
    @property
    def raise_callback_errors(self) -> bool:
        """The older name of :attr:`strict`."""
        return self.strict

    @raise_callback_errors.setter
    def raise_callback_errors(self, value: bool) -> None:
        self.strict = bool(value)

    def note_failure(self, exc: BaseException) -> None:
        """Strict mode: remember the first failure of user code; :meth:`run` raises it."""
        if self._failure is None:
            self._failure = exc

    def _on_failure(self, event: object, exc: BaseException) -> bool:
        """A failed event nobody waited on: a node's main process that raised."""
        node = getattr(event, NODE_OF_PROCESS, None)
        if node is None or not isinstance(exc, Exception):
            return False
        if self.strict:
            self.note_failure(exc)
            return False
        node.report_crash(exc)
        return True

    def run(self, until: TimeLike | Duration | simpy.Event | None = None) -> None:
        """Run the simulation (see :meth:`ddes.kernel.Kernel.run`).

        In strict mode the first exception of user code ends the run and is
        raised here, with the user's frames at the top of its traceback.
        """
        try:
            super().run(until)
        except BaseException:
            failure, self._failure = self._failure, None
            if failure is None:
                raise
            raise failure.with_traceback(user_frames(failure.__traceback__)) from None

    @property
    def connect_delay(self) -> int:
        """Deprecated spelling of :attr:`connect_delay_ns` (nanoseconds)."""
        return self.connect_delay_ns

    @connect_delay.setter
    def connect_delay(self, value_ns: int) -> None:
        self.connect_delay_ns = value_ns

    # -- the ROS graph -----------------------------------------------------------------------
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

    def get_use_sim_time(self) -> bool:
        """The ``/use_sim_time`` setting that new nodes read."""
        return self.use_sim_time

    def set_link(self, topic: str | None = None, *, publisher: str | None = None,
                 subscriber: str | None = None, latency: LinkLatency = 0,
                 loss: float = 0.0) -> None:
        """Set the transport model of matching connections (existing and future).

        ``topic``, ``publisher`` and ``subscriber`` (node names) narrow the
        match; None matches anything; the most specific rule wins, later rules
        win ties.  ``latency`` is seconds, a Duration, or ``f(rng)`` drawn per
        message from the connection's own seeded stream; ``loss`` is a
        probability.
        """
        link = LinkModel(latency, loss)
        self._links.append(((topic, publisher, subscriber), link))
        for entry in self.master.topics.values():
            for pub in entry.publishers:
                for conn in pub.connections:
                    conn.set_link(self.link_for(conn.pub, conn.sub))

    def link_for(self, pub: Publisher[MessageClass], sub: Subscriber[MessageClass]) -> LinkModel:
        """The transport model a connection from ``pub`` to ``sub`` uses."""
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

    def graph_connect(self, pub: Publisher[MessageClass], sub: Subscriber[MessageClass]) -> None:
        """Connect a publisher to a subscriber after :attr:`connect_delay_ns`."""
        connect_later(self, pub, sub, self.connect_delay_ns)

    def topic_stats(self, topic: str) -> TopicStats:
        """Published/sent/lost/received/dropped/delivered counts of a topic and its connections."""
        entry = self.master.topics.get(topic)
        if entry is None:
            raise ROSTopicException(f"unknown topic {topic}; known: {sorted(self.master.topics)}")
        conns: list[Connection] = [c for p in entry.publishers for c in p.connections]
        per: list[ConnectionStats] = [
            {"id": c.id, "publisher": c.pub.node.name, "subscriber": c.sub.node.name,
             "sent": c.sent, "lost": c.lost, "received": c.received, "dropped": c.dropped,
             "delivered": c.delivered} for c in conns]
        return {"topic": topic, "type": entry.type,
                "published": sum(p.published for p in entry.publishers),
                "sent": sum(c["sent"] for c in per), "lost": sum(c["lost"] for c in per),
                "received": sum(c["received"] for c in per),
                "dropped": sum(c["dropped"] for c in per),
                "delivered": sum(c["delivered"] for c in per), "connections": per}

    # -- nodes ------------------------------------------------------------------
    def create_node(self, name: str, **kwargs: Unpack[NodeOptions]) -> Node:
        """Create and start a node (see :class:`ddes.graph.node.Node`)."""
        cls = self.node_class
        if cls is None:
            from ddes.graph.node import Node

            cls = Node
        return cls(self, name, **kwargs)

    @property
    def nodes(self) -> dict[str, Node]:
        """Live nodes by fully-qualified name, in creation order."""
        return dict(self._nodes)

    def lookup_node(self, name: str) -> Node | None:
        """The live node of that fully-qualified name, or None."""
        return self._nodes.get(name)

    def register_node(self, node: Node) -> None:
        """Add a node to the world; a live node of the same name is shut down, as rosmaster does.

        rosmaster (``Registrations._register_node_api``) calls the old node's
        ``shutdown("/master", "[<name>] Reason: new node registered with same
        name")``: a rospy node prints ``shutdown request: [<name>] Reason: new
        node registered with same name`` and its shutdown hooks get ``external
        shutdown request from [/master]: [...]`` (see :meth:`Node.shutdown_request`).
        """
        old = self._nodes.get(node.name)
        if old is not None:
            old.shutdown_request("/master", f"[{node.name}] Reason: new node registered with same name")
        self._nodes[node.name] = node
        for observe in self.node_observers:
            observe(node)

    def unregister_node(self, node: Node) -> None:
        """Remove a node that shut down (no-op if another node took its name)."""
        if self._nodes.get(node.name) is node:
            del self._nodes[node.name]

    def __repr__(self) -> str:
        return f"<World seed={self.seed} t={self.env.now / 1e9:.9f}s nodes={len(self._nodes)}>"

    #: Trace length up to which the notebook view computes the digest (it reads every event).
    HTML_DIGEST_LIMIT: ClassVar[int] = 200_000

    def _repr_html_(self) -> str:
        """The world as HTML tables for notebooks: seed, time, nodes, topics, services,
        parameter count, trace length and digest prefix (every value escaped)."""
        from ddes.display.tables import MAX_ROWS, html_table, key_value_table
        from ddes.errors import DigestError

        trace = self.trace
        if len(trace) > self.HTML_DIGEST_LIMIT:
            digest = f"not computed for {len(trace)} events (world.digest())"
        else:
            try:
                digest = trace.digest()[:16] + "…"
            except DigestError:
                digest = "none: the trace does not hold every event"
        names = sorted(self._nodes)
        shown = ", ".join(names[:MAX_ROWS]) + (f", … {len(names) - MAX_ROWS} more"
                                                if len(names) > MAX_ROWS else "")
        counted = sum(trace.counted_only.values())
        topics = [e for e in self.master.topics.values() if e.publishers or e.subscribers]
        services = list(self.master.services.values())
        summary = key_value_table([
            ("seed", self.seed),
            ("time", f"{self.env.now / 1e9:.9f} s"),
            ("nodes", f"{len(names)}: {shown}" if names else "0"),
            ("topics", len(topics)),
            ("services", len(services)),
            ("parameters", len(self.params.get_param_names())),
            ("trace", f"{len(trace)} events" + (f" (+{counted} counted only)" if counted else "")),
            ("digest", digest),
        ], caption=type(self).__name__)
        out = [summary]
        if topics:
            out.append(html_table(
                ("topic", "type", "publishers", "subscribers"),
                ((e.name, e.type, ", ".join(e.publisher_nodes()), ", ".join(e.subscriber_nodes()))
                 for e in sorted(topics, key=lambda e: e.name)),
                caption="topics", mono=(0, 1)))
        if services:
            out.append(html_table(
                ("service", "type", "node"),
                ((e.name, e.type, e.node.name) for e in sorted(services, key=lambda e: e.name)),
                caption="services", mono=(0, 1)))
        return "".join(out)
