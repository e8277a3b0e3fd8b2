"""The trusted world and the sandboxed child in lockstep: proxies, validation, the sync rule.

:class:`Lockstep` runs the grader's authoritative :class:`~ddes.graph.world.World` together with a
:class:`~ddes.grading.sandbox.Sandbox` holding the student's nodes.

**Sync rule** (conservative, exact).  The child's next event changes only when it receives
input, and it reports that time after every step.  The grader takes the next instant
``t = min(its own next event, the child's next event)``, moves its clock there, and runs
*delta rounds*: it processes every event due at ``t`` (collecting what the student's
subscriptions receive), sends those messages with ``STEP t`` when there are any or when the
child has an event due at ``t``, and publishes the child's answer (messages its nodes published
at ``t``) through proxies, at ``t``; then again, until an instant passes with nothing crossing.
Deliveries that cross are FIFO after the receiver's events already scheduled at that instant.
Both kernels are deterministic and the rounds are taken in one fixed order, so a submission's
trace is the same on every run.

**Timing compared with an in-process run.**  With the default zero link latency a message
crosses at the instant it is published, so no simulated time is added.  What differs: (1) within
one instant the student's reaction comes after the grader's other events of that instant (an
in-process run may interleave them by event id); (2) a link latency or loss set on the grader's
world applies once, on the proxy's connections, and the child's links are ideal; (3) the
proxy publisher counts ``header.seq`` itself (rospy's rule, the same count unless the student
publishes before a subscriber is connected).

**Proxies.**  Every student node gets a proxy node of the same name in the grader's world, with a
publisher per advertised topic (latched as the student's) and a subscriber per subscription
(same type and queue size), so the grader's master, ``rosnode info`` and the trace show the
student's graph.  A name already taken by a grader node is refused (no student node can replace
a trusted one), as are types the grader does not know, md5 sums that differ from the grader's,
stamps other than the step's, and bytes that do not decode to exactly themselves with the
grader's own message class.  A refused item is recorded in :attr:`Lockstep.problems` and
dropped (fail closed); a frame that breaks the protocol ends the child.

**Services.**  A service a student node advertises (``SRV``) gets a proxy server of the same
name and type on the node's proxy, once the grader's own service class of that type has the same
md5 sum (a name a grader node serves is refused).  A grader-side call of it is not served in the
grader: its request bytes cross as ``CALL id`` before the next ``STEP``, the child calls the
student's server through a ServiceProxy of its bridge node, and the answer comes back as ``RESP
id``, at the instant it arrives in the child (a handler that yields simulated time answers
later).  Response bytes must decode to exactly themselves with the grader's response class; error
texts are UTF-8 of at most ``MAX_ERROR`` bytes.  A RESP that is malformed, unknown or answered
twice is refused; the caller of a refused answer receives an error, and the callers of a child
that ends receive rospy's transport error (the proxy server shuts down with the node).

**A child per node.**  The grader runs each student node in a child of its own (as ROS runs
each node in a process of its own): each has its own budgets (wall time per step, CPU, memory)
and its own outcome, so a node that hangs or dies leaves the others running.  What one child's
nodes publish reaches another child's subscribers through their proxies in the grader's world
(the proxy's forwarder skips only its own child's messages).  A service served outside a child
(by another child, or by the grader's world) is offered to it (``OFFER``): the child serves a
stand-in whose calls cross as ``ASK``, are made in the grader's world from the calling node's
proxy, and answered with ``ANSWER`` when the response arrives.  Every delta round sends each due
child its step before it reads the first reply (the children compute in parallel) and applies
the replies in the children's order; what a reply publishes reaches the others only at the next
round, so the result is the one of stepping them one after the other.

**Left out** (documented in docs/grading.md): parameters do not cross yet (the child's nodes
see only the parameters of their command line and the grader's ``/use_sim_time``), nor do
subscriptions on ``AnyMsg``.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from ddes.errors import DdesError
from ddes.grading import protocol
from ddes.grading.sandbox import Sandbox, SandboxOutcome
from ddes.graph.names import is_legal_name
from ddes.graph.topics import Publisher, Subscriber
from ddes.kernel.trace import scrub_addresses
from ddes.services.server import Service
from ddes.time import Time

if TYPE_CHECKING:
    from collections.abc import Callable, Sequence

    from ddes.graph.node import Node
    from ddes.graph.world import World

__all__ = ["MAX_ENDPOINTS", "MAX_NODES", "MAX_ROUNDS", "ForwardingService", "Lockstep",
           "combined"]

#: Delta rounds at one instant before the exchange counts as a livelock.
MAX_ROUNDS = 1000
#: Most student nodes, and publishers plus subscribers, the grader mirrors (more are refused).
MAX_NODES = 64
MAX_ENDPOINTS = 1024
_INF = float("inf")


def _global_name(name: str) -> bool:
    return (isinstance(name, str) and name.startswith("/") and len(name) <= 256
            and is_legal_name(name) and "~" not in name)


class _Child:
    """One sandboxed child of a lockstep: its process and what waits to cross into it."""

    def __init__(self, index: int, sandbox: Sandbox) -> None:
        self.index = index
        self.sandbox = sandbox
        #: The child's next event (ns); 0 until its first step.
        self.next: float = 0
        self.inputs: list[tuple[str, str, str, bytes]] = []
        #: Calls of its services waiting for the next STEP: ``(id, service, request bytes)``.
        self.calls: list[tuple[int, str, bytes]] = []
        #: Services of elsewhere to offer it: ``(service, type, md5)``.
        self.offers: list[tuple[str, str, str]] = []
        self.offered: set[str] = set()
        #: Answers to its ASK frames waiting for the next STEP: ``(id, ok, bytes or text)``.
        self.answers: list[tuple[int, bool, bytes | str]] = []
        self.gone = False

    def due(self, t: int) -> bool:
        return bool(self.inputs or self.calls or self.offers or self.answers or self.next == t)


class Lockstep:
    """The grader's ``world`` and the student's sandboxes, stepped together.

    ``sandboxes`` is one :class:`~ddes.grading.sandbox.Sandbox` or several (a child per
    student node, as ROS runs each node in a process of its own): each child has its own
    budgets and its own outcome (:attr:`outcomes`); what one child's nodes publish reaches
    another's through their proxies in the grader's world, and a service one child serves is
    offered to the others (``OFFER``/``ASK``/``ANSWER``).  Children are stepped in the order
    given, every delta round.
    """

    def __init__(self, world: World, sandboxes: Sandbox | Sequence[Sandbox]) -> None:
        self.world = world
        boxes = [sandboxes] if isinstance(sandboxes, Sandbox) else list(sandboxes)
        self._children = [_Child(i, box) for i, box in enumerate(boxes)]
        self.proxies: dict[str, Node] = {}
        #: Which child a proxy node mirrors (its index).
        self._owner: dict[str, int] = {}
        self._pubs: dict[tuple[str, str], Publisher[Any]] = {}
        self._subs: dict[tuple[str, str], Subscriber[Any]] = {}
        self._forwarding: dict[tuple[int, str], tuple[str, str]] = {}
        #: Calls sent to a child and not answered yet, by id.
        self._pending: dict[int, tuple[_ProxyService, Any, Any]] = {}
        self._services: dict[str, _ProxyService] = {}
        self._service_owner: dict[str, int] = {}
        self._clients: dict[tuple[str, str], Any] = {}
        self._next_call = 0
        #: The service names offered so far (the master's, at the last offer).
        self._known_services: set[str] = set()
        #: What the grader refused from the children, in order: ``(t_ns, text)``.
        self.problems: list[tuple[int, str]] = []
        #: Student nodes whose main ended with an exception, in order: ``(t_ns, node, the
        #: traceback with the student's frames)`` (the child's word: shown, never scored).
        self.deaths: list[tuple[int, str, str]] = []
        #: The first failure of each student callback (the node went on): ``(t_ns, node,
        #: "in the callback NAME:" and the traceback)``.
        self.callback_failures: list[tuple[int, str, str]] = []
        #: Parameters the student's nodes read, in order: ``(t_ns, node, resolved key, found)``,
        #: once each (the child's word: a criterion may trust it only as far as the student
        #: could have made their node read that name anyway).
        self.param_reads: list[tuple[int, str, str, bool]] = []
        #: Exchanges made (STEP frames sent).
        self.steps = 0

    @property
    def sandbox(self) -> Sandbox:
        """The first child's sandbox (the only one of a one-child lockstep)."""
        return self._children[0].sandbox

    @property
    def sandboxes(self) -> list[Sandbox]:
        return [c.sandbox for c in self._children]

    @property
    def outcomes(self) -> list[SandboxOutcome]:
        """How each child ended, in the order given."""
        return [c.sandbox.outcome for c in self._children]

    # -- the loop -----------------------------------------------------------------------------
    def run(self, until_ns: int, done: Callable[[], bool] | None = None) -> SandboxOutcome:
        """Run both until ``until_ns`` (exclusive, as ``World.run(until)``), or until ``done()``
        is true after an instant, then end the children; returns how they ended (the one
        child's outcome, or :func:`combined` of several).  The proxies of a child still
        running at the end stay registered (criteria read the graph); those of a child that
        ended earlier were shut down then."""
        world = self.world
        env = world.env
        for c in self._children:
            if not c.sandbox.alive and c.sandbox.outcome.state == "running":
                c.sandbox.start()
        ended = False
        while not ended:
            tc = min((c.next for c in self._children if c.sandbox.alive), default=_INF)
            t = min(env.peek(), tc)
            if t >= until_ns:
                break
            t = int(t)
            if world.now < t:
                world.run(until=Time._from_ns(t))
            self._instant(t)
            ended = done is not None and done()
        if world.now < until_ns and not ended:
            world.run(until=Time._from_ns(until_ns))
        for c in self._children:
            outcome = c.sandbox.close()
            if outcome.state != "finished":
                self._child_gone(c)
        return combined(self.outcomes, [s.scripts for s in self.sandboxes])

    def _instant(self, t: int) -> None:
        self._offer_new_services()
        for _ in range(MAX_ROUNDS):
            self.world.run_through(t)
            due = []
            for c in self._children:
                if not c.sandbox.alive:
                    if not c.gone:
                        self._child_gone(c)
                elif c.due(t):
                    due.append(c)
            if not due:
                return
            # every due child gets its step before the first reply is read, so they compute in
            # parallel; the replies are applied in the children's order.  What one child's
            # reply publishes reaches the others only through the grader's world, at the next
            # round, so the result is the one of stepping them one after the other.
            sent = [c for c in due if self._begin(c, t)]
            for c in sent:
                self._finish(c, t)
            self._offer_new_services()
        for c in self._children:
            c.sandbox.kill("killed", f"more than {MAX_ROUNDS} exchanges at t={t / 1e9:.9f} s "
                                     "(a zero-time loop between the student's nodes and the world)")
            self._child_gone(c)

    def _begin(self, c: _Child, t: int) -> bool:
        inputs, c.inputs = c.inputs, []
        calls, c.calls = c.calls, []
        offers, c.offers = c.offers, []
        answers, c.answers = c.answers, []
        self.steps += 1
        if c.sandbox.begin(t, inputs, calls, offers, answers):
            return True
        for call_id, _name, _data in calls:
            self._answer(call_id, False, "the student's process has ended")
        self._child_gone(c)
        return False

    def _finish(self, c: _Child, t: int) -> None:
        reply = c.sandbox.finish(t)
        if reply is None:
            self._child_gone(c)
            return
        if reply.next_ns != -1 and reply.next_ns <= t:
            c.sandbox.kill("killed", f"reported its next event at {reply.next_ns} ns, not "
                                     f"after the step at {t} ns")
            self._child_gone(c)
            return
        c.next = _INF if reply.next_ns == -1 else reply.next_ns
        self._apply(reply.frames, t, c)

    # -- validation of the child's frames ------------------------------------------------------
    def _refuse(self, t: int, text: str) -> None:
        if len(self.problems) < 1000:
            self.problems.append((t, text))

    def _class(self, type_: str, md5: str, t: int, what: str) -> Any:
        try:
            cls = self.world.messages.get_message_class(type_)
        except (DdesError, ValueError, KeyError):
            self._refuse(t, f"{what}: unknown message type {type_[:80]!r}")
            return None
        if cls._md5sum != md5:
            self._refuse(t, f"{what}: md5 {md5[:40]!r} of {type_[:80]} differs from the grader's "
                            f"{cls._md5sum}")
            return None
        return cls

    def _proxy(self, name: str, t: int, c: _Child) -> Node | None:
        node = self.proxies.get(name)
        if node is not None:
            if self._owner[name] != c.index:
                self._refuse(t, f"node name {name[:80]} is taken by another of your nodes: "
                                "refused (as ROS ends the older node of a name)")
                return None
            return None if node.is_shutdown() else node
        if not _global_name(name) or name.startswith("/ddes_grading"):
            self._refuse(t, f"illegal node name {name[:80]!r}")
            return None
        if len(self.proxies) >= MAX_NODES:
            self._refuse(t, f"node {name[:80]}: more than {MAX_NODES} student nodes")
            return None
        if self.world.lookup_node(name) is not None:
            self._refuse(t, f"node name {name} is taken by the grader's world: refused")
            return None
        # a proxy only mirrors: it keeps no clock of its own (no /clock subscription under sim time)
        node = self.world.create_node(name, disable_rosout=True, use_sim_time=False)
        self.proxies[name] = node
        self._owner[name] = c.index
        return node

    def _apply(self, frames: list[Any], t: int, c: _Child | None = None) -> None:
        """Validate and apply one child's frames (the first child's when ``c`` is None)."""
        if c is None:
            c = self._children[0]
        for fr in frames:
            if isinstance(fr, protocol.Msg):
                self._msg(fr, t, c)
            elif isinstance(fr, protocol.Adv):
                self._adv(fr, t, c)
            elif isinstance(fr, protocol.Sub):
                self._sub(fr, t, c)
            elif isinstance(fr, protocol.Srv):
                self._srv(fr, t, c)
            elif isinstance(fr, protocol.Resp):
                self._resp(fr, t, c)
            elif isinstance(fr, protocol.Ask):
                self._ask(fr, t, c)
            elif isinstance(fr, protocol.Died):
                self._died(fr, t)
            elif isinstance(fr, protocol.Read):
                self._read(fr, t)
            elif isinstance(fr, protocol.Gone):
                node = self.proxies.get(fr.node)
                if node is not None and self._owner[fr.node] == c.index \
                        and not node.is_shutdown():
                    node.shutdown("the student's node ended")

    def _died(self, fr: protocol.Died, t: int) -> None:
        if fr.t_ns != t:
            self._refuse(t, f"a death of {fr.node[:80]!r} stamped {fr.t_ns} ns in the step at "
                            f"{t} ns")
            return
        into = self.deaths if fr.fatal else self.callback_failures
        if len(into) < MAX_NODES:
            # an address in the text (a repr's 0x7f…) differs on every grade: shown as 0x…
            into.append((t, fr.node[:256], scrub_addresses(fr.text)))

    def _read(self, fr: protocol.Read, t: int) -> None:
        if not _global_name(fr.key) and fr.key != "/":
            self._refuse(t, f"a parameter read of an illegal name {fr.key[:80]!r}")
            return
        if len(self.param_reads) < 4096:
            self.param_reads.append((t, fr.node[:256], fr.key, fr.found))

    def _adv(self, fr: protocol.Adv, t: int, c: _Child) -> None:
        if not _global_name(fr.topic):
            self._refuse(t, f"illegal topic name {fr.topic[:80]!r}")
            return
        key = (fr.node, fr.topic)
        if key in self._pubs:
            return
        if len(self._pubs) + len(self._subs) >= MAX_ENDPOINTS:
            self._refuse(t, f"{fr.node[:80]} advertising {fr.topic[:80]}: more than "
                            f"{MAX_ENDPOINTS} publishers and subscribers")
            return
        cls = self._class(fr.type, fr.md5, t, f"{fr.node} advertising {fr.topic}")
        node = self._proxy(fr.node, t, c) if cls is not None else None
        if node is None:
            return
        try:
            self._pubs[key] = node.advertise(fr.topic, cls, queue_size=10, latch=fr.latch)
        except DdesError as exc:
            self._refuse(t, f"{fr.node} advertising {fr.topic}: {exc}")

    def _sub(self, fr: protocol.Sub, t: int, c: _Child) -> None:
        if not _global_name(fr.topic):
            self._refuse(t, f"illegal topic name {fr.topic[:80]!r}")
            return
        key = (fr.node, fr.topic)
        if key in self._subs:
            return
        if len(self._pubs) + len(self._subs) >= MAX_ENDPOINTS:
            self._refuse(t, f"{fr.node[:80]} subscribing {fr.topic[:80]}: more than "
                            f"{MAX_ENDPOINTS} publishers and subscribers")
            return
        cls = self._class(fr.type, fr.md5, t, f"{fr.node} subscribing {fr.topic}")
        node = self._proxy(fr.node, t, c) if cls is not None else None
        if node is None:
            return
        qs = None if fr.queue_size < 1 else min(fr.queue_size, 100_000)
        forward = (c.index, fr.topic) not in self._forwarding
        callback = self._forwarder(fr.topic, cls, c) if forward else None
        try:
            self._subs[key] = Subscriber(node, fr.topic, cls, callback, queue_size=qs,
                                         internal=True)
        except DdesError as exc:
            self._refuse(t, f"{fr.node} subscribing {fr.topic}: {exc}")
            return
        if forward:
            self._forwarding[(c.index, fr.topic)] = (cls._type, cls._md5sum)

    def _forwarder(self, topic: str, cls: Any, c: _Child) -> Any:
        owner = self._owner
        index = c.index

        def forward(msg: Any) -> None:
            caller = msg._connection_header.get("callerid", "")
            if owner.get(caller) == index:
                return  # the child's own message: delivered inside it already
            c.inputs.append((topic, cls._type, cls._md5sum, msg._serialize_to_bytes()))

        return forward

    def _msg(self, fr: protocol.Msg, t: int, c: _Child) -> bool:
        pub = self._pubs.get((fr.node, fr.topic))
        if pub is None or self._owner.get(fr.node) != c.index:
            self._refuse(t, f"message from {fr.node[:80]} on {fr.topic[:80]} it never advertised")
            return False
        if fr.t_ns != t:
            self._refuse(t, f"message from {fr.node} on {fr.topic} stamped {fr.t_ns} ns in the "
                            f"step at {t} ns")
            return False
        cls = pub.data_class
        try:
            msg = cls.__new__(cls)._deserialize_from(fr.data)
            same = msg._serialize_to_bytes() == fr.data
        except Exception:  # noqa: BLE001 - bytes from the student: any decoding failure refuses them
            same = False
        if not same:
            self._refuse(t, f"message from {fr.node} on {fr.topic}: {len(fr.data)} bytes that are "
                            f"not one {pub.type}")
            return False
        if pub.node.is_shutdown():
            return False
        pub.publish(msg)
        return True

    # -- services ------------------------------------------------------------------------------
    def _srv(self, fr: protocol.Srv, t: int, c: _Child) -> None:
        if not _global_name(fr.service):
            self._refuse(t, f"illegal service name {fr.service[:80]!r}")
            return
        if fr.service in self._services:
            return
        if len(self._pubs) + len(self._subs) + len(self._services) >= MAX_ENDPOINTS:
            self._refuse(t, f"{fr.node[:80]} advertising service {fr.service[:80]}: more than "
                            f"{MAX_ENDPOINTS} endpoints")
            return
        what = f"{fr.node[:80]} advertising service {fr.service[:80]}"
        try:
            cls = self.world.messages.get_service_class(fr.type)
        except (DdesError, ValueError, KeyError):
            self._refuse(t, f"{what}: unknown service type {fr.type[:80]!r}")
            return
        if cls._md5sum != fr.md5:
            self._refuse(t, f"{what}: md5 {fr.md5[:40]!r} of {fr.type[:80]} differs from the "
                            f"grader's {cls._md5sum}")
            return
        if self.world.master.lookup_service(fr.service) is not None:
            self._refuse(t, f"{what}: the name is served by the grader's world: refused")
            return
        node = self._proxy(fr.node, t, c)
        if node is None:
            return
        try:
            self._services[fr.service] = _ProxyService(node, fr.service, cls, self)
            self._service_owner[fr.service] = c.index
        except DdesError as exc:
            self._refuse(t, f"{what}: {exc}")
            return
        c.offered.add(fr.service)  # its own: never offered back

    def _offer_new_services(self) -> None:
        """Offer every child the services served outside it: the other children's (their
        proxies) and the grader world's own, once each, as they appear."""
        services = self.world.master.services
        if services.keys() == self._known_services:
            return
        self._known_services = set(services)
        for name, entry in sorted(services.items()):
            for c in self._children:
                if name in c.offered:  # offered already, or its own (see _srv)
                    continue
                c.offered.add(name)
                c.offers.append((name, entry.type, entry.md5sum))

    def _forward_call(self, server: _ProxyService, conn: Any, call: Any) -> None:
        """A grader-side client's request reached a proxy server: it crosses at the next STEP of
        the child that serves it."""
        self._next_call += 1
        self._pending[self._next_call] = (server, conn, call)
        owner = self._children[self._service_owner[server.resolved_name]]
        if not owner.gone:
            owner.calls.append((self._next_call, server.resolved_name, call.data))
        else:
            self._answer(self._next_call, False, "the student's process has ended")

    def _answer(self, call_id: int, ok: bool, payload: bytes | str) -> bool:
        found = self._pending.pop(call_id, None)
        if found is None:
            return False
        server, conn, call = found
        server._send(conn, call, ok, payload)
        return True

    def _resp(self, fr: protocol.Resp, t: int, c: _Child) -> bool:
        found = self._pending.get(fr.id)
        if found is None or self._service_owner.get(found[0].resolved_name) != c.index:
            self._refuse(t, f"answer to service call {fr.id}, which is not waiting for one")
            return False
        server = found[0]
        if not fr.ok:
            try:
                text = fr.data.decode("utf-8")
            except UnicodeDecodeError:
                self._refuse(t, f"error text of the call of {server.resolved_name} is not UTF-8")
                return self._answer(fr.id, False, "the student's server sent an unreadable error")
            return self._answer(fr.id, False, text)
        cls = server.response_class
        try:
            same = cls.__new__(cls)._deserialize_from(fr.data)._serialize_to_bytes() == fr.data
        except Exception:  # noqa: BLE001 - bytes from the student: any decoding failure refuses them
            same = False
        if not same:
            self._refuse(t, f"answer of {server.resolved_name}: {len(fr.data)} bytes that are not "
                            f"one {server.type} response")
            return self._answer(fr.id, False, f"the student's server answered bytes that are not "
                                              f"one {server.type} response")
        return self._answer(fr.id, True, fr.data)

    def _ask(self, fr: protocol.Ask, t: int, c: _Child) -> None:
        """A student node called a service served outside its child: call it in the grader's
        world from the node's proxy; the answer crosses back as ANSWER when it arrives."""
        from ddes.services.client import ServiceProxy

        def refuse(text: str) -> None:
            c.answers.append((fr.id, False, text))

        entry = self.world.master.lookup_service(fr.service)
        if entry is None or self._service_owner.get(fr.service) == c.index:
            refuse(f"service [{fr.service[:200]}] unavailable")
            return
        node = self._proxy(fr.node, t, c)
        if node is None:
            refuse(f"service [{fr.service[:200]}] unavailable to {fr.node[:80]}")
            return
        try:
            key = (fr.node, fr.service)
            proxy = self._clients.get(key)
            if proxy is None or proxy.service_class is not entry.server.service_class:
                proxy = self._clients[key] = ServiceProxy(node, fr.service,
                                                          entry.server.service_class)
            cls = proxy.request_class
            request = cls.__new__(cls)._deserialize_from(fr.data)
            if request._serialize_to_bytes() != fr.data:
                raise ValueError(f"{len(fr.data)} bytes that are not one {entry.type} request")
            pending = proxy._start((request,), {}, None)
        except Exception as exc:  # noqa: BLE001 - bytes from the student: refused, never raised
            self._refuse(t, f"{fr.node[:80]} calling {fr.service[:80]}: {exc}")
            refuse(f"{type(exc).__name__}: {exc}")
            return

        def answered(ev: Any, pc: Any = pending) -> None:
            ev.defused = True
            if c.gone:
                return
            if ev.ok:
                c.answers.append((fr.id, True, ev.value._serialize_to_bytes()))
            else:
                c.answers.append((fr.id, False, pc.server_text if pc.server_text is not None
                                  else str(ev.value)))

        pending.event.callbacks.append(answered)

    def _child_gone(self, c: _Child) -> None:
        c.gone = True
        for name, node in self.proxies.items():
            if self._owner[name] == c.index and not node.is_shutdown():
                node.shutdown("the student's process ended")
        for call_id, _name, _data in c.calls:
            self._answer(call_id, False, "the student's process has ended")
        c.calls = []


def combined(outcomes: Sequence[SandboxOutcome],
             scripts: Sequence[Sequence[tuple[str, Sequence[str]]]] = ()) -> SandboxOutcome:
    """One outcome of several children (a child per student node): the only one's when there
    is one; else ``finished`` when all finished, or the first other state with every child's
    reason that is not ``finished`` (named by its script), the output tails joined and what was
    enforced (the same for every child)."""
    if len(outcomes) == 1:
        return outcomes[0]
    out = SandboxOutcome(state="finished")
    reasons, tails = [], []
    for i, o in enumerate(outcomes):
        name = scripts[i][0][0] if i < len(scripts) and scripts[i] else f"child {i}"
        if o.state != "finished" and out.state == "finished":
            out.state, out.returncode = o.state, o.returncode
        if o.reason:
            reasons.append(f"{name}: {o.reason}")
        if o.output_tail:
            tails.append(f"[{name}]\n{o.output_tail}")
        out.enforced = out.enforced or list(o.enforced)
    out.reason = "; ".join(reasons)
    out.output_tail = "\n".join(tails)
    return out


class ForwardingService(Service):
    """A service served elsewhere: each request goes to ``forward(self, conn, call)``, whose
    caller answers it later with ``self._send(conn, call, ok, bytes or error text)``; nothing
    is handled here.  The grader's face of a student's service (:class:`_ProxyService`), and a
    child's stand-in for a service of another child or of the grader (``OFFER``)."""

    def __init__(self, node: Node, name: str, service_class: Any,
                 forward: Callable[[ForwardingService, Any, Any], None]) -> None:
        self._forward = forward
        super().__init__(node, name, service_class, self._never)

    @staticmethod
    def _never(_request: Any) -> None:
        raise AssertionError("a proxy service is never served in the grader")

    def _on_request(self, ev: Any) -> None:
        conn, call = ev.payload
        if 0 <= call.gave_up_at < call.sent_at:
            return  # the client gave up before the request was sent
        if conn.server_gone:
            return
        world = self.world
        world.trace.append_row((world.env.now_ns, "service.request", self.node.name,
                                 ("service", "call", "client"), self.resolved_name, call.id,
                                 conn.proxy.node.name))
        self._stats.served += 1
        self._forward(self, conn, call)


class _ProxyService(ForwardingService):
    """The grader-side face of a student's service: requests are forwarded to the child by the
    :class:`Lockstep`, never served here (no handler of the student runs in the grader)."""

    def __init__(self, node: Node, name: str, service_class: Any, lock: Lockstep) -> None:
        super().__init__(node, name, service_class, lock._forward_call)  # type: ignore[arg-type]
