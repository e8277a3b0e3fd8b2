"""A hypothesis state machine that checks a service handler (or a node serving one) under
concurrent calls, handler errors, timeouts, and a server that goes away and comes back.

Give it the service type and either a ``handler`` (``handler(request)``,
rospy's style; a generator handler takes simulated time) or a node factory
``make_server(world, node)`` that advertises the service on ``node``, and a
``contract``: ``contract(request)`` returns what the call must give —

* ``None``: anything (only the built-in checks apply);
* a response, in any form a handler may return (a message, a dict, a tuple,
  a value): the response must equal it;
* a predicate ``f(response) -> bool``;
* an exception class or instance (``ServiceException``): the call must fail
  with a server error.

The machine builds a world with the server node (``spinner="rospy"`` by
default: rospy runs a thread per connection, so calls overlap in the
handler) and ``clients`` client nodes, then runs random schedules of:

* ``call``: a client calls, through a **one-shot** proxy (a new
  ``ServiceProxy``, a new connection) or its **persistent** proxy, with or
  without a call timeout; the call runs in the client's process while the
  schedule goes on, so several calls are in flight at once;
* ``fail_next``: the handler's next run raises (``RuntimeError`` or
  ``ServiceException``) instead of running the user's handler;
* ``stop_server`` (the node shuts down, or only the service is
  unadvertised) and ``start_server`` (a new node, the same name);
* ``new_persistent_proxy``: a client closes its persistent proxy and makes
  a new one (rospy's advice once its server went away);
* ``wait_for_service`` with a timeout; ``set_latency`` of one client's
  calls; ``advance``: simulated time passes.

After every step it checks, as rospy defines them (docs/services.md):

1. **the contract** for every answered call;
2. **every call is answered exactly once, or fails with the right error**:
   one ``service.response`` or ``service.error`` per call; ``service [X]
   unavailable`` only when nothing was registered at the call, at once; a
   handler that raised gives ``service [X] responded with an error: error
   processing request: <e>`` (``service cannot process request: <e>`` for a
   ServiceException), and the server serves on; a transport or connect error
   only when the server went away (or the connection closed) during the
   call; a call timeout exactly ``timeout`` after the call, never after its
   response;
3. **responses go to the right caller**: each response is the one the
   handler produced for that very request;
4. **persistent proxies as rospy's**: once the server of a persistent
   proxy's connection went away, every later call on it fails with
   ``persistent connection to service [X] was closed: the server went away;
   create a new ServiceProxy``, even after the server is back; after a call
   timeout the proxy reconnects;
5. ``wait_for_service(timeout)`` returns at once when the service is there,
   at the instant it registers when it comes within the timeout, else fails
   exactly at the timeout with ``timeout exceeded while waiting for service X``.

At the end every call must have ended within ``settle`` seconds.  A failure
shrinks (hypothesis, then step deletion) to a minimal schedule, printed with
a one-line :func:`replay_service_schedule` call; the replay's
:meth:`ServiceReplay.plot` draws the calls and marks the violating step.
See docs/testing.md.
"""

from __future__ import annotations

import re
import unittest
from collections.abc import Callable, Generator, Mapping
from dataclasses import dataclass, field
from types import GeneratorType
from typing import TYPE_CHECKING, Any, ClassVar

from hypothesis import HealthCheck, settings
from hypothesis import strategies as st
from hypothesis.stateful import (
    RuleBasedStateMachine,
    initialize,
    invariant,
    precondition,
    rule,
    run_state_machine_as_test,
)

from ddes.errors import (
    DdesTypeError,
    DdesValueError,
    ROSException,
    ServiceException,
    ServiceTimeout,
)
from ddes.msg import dict_to_message, message_to_dict
from ddes.msg.message import Message
from ddes.services import Service, ServiceProxy, wait_for_service
from ddes.services.convert import (
    ERROR_PROCESSING,
    SERVICE_CANNOT_PROCESS,
    convert_return_to_response,
)
from ddes.services.transport import serialize
from ddes.testing._draws import same_draws_everywhere
from ddes.testing._replay import Source, call_text, factory_name, mark_violation
from ddes.testing.strategies import messages
from ddes.time.units import duration_to_ns, ns_to_sec
from ddes.world import World

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

    from ddes.graph.node import Node
    from ddes.msg.message import ServiceDefinition

__all__ = [
    "ServiceProtocolMachine",
    "ServiceReplay",
    "ServiceViolation",
    "replay_service_schedule",
    "run_service_machine",
]

#: ``make_server(world, node)``: advertises the service under test on ``node``.
ServerFactory = Callable[[World, "Node"], object]
#: ``contract(request)``: None, the expected response, a predicate, or an exception.
Contract = Callable[[Message], object]
#: One step, as the replay call writes it (``('call', 0, {'a': 1, 'b': 2}, 'one-shot', None)``).
Step = tuple[object, ...]

#: Call timeouts (seconds) the machine draws; None (no timeout) is drawn most.
TIMEOUTS: tuple[float | None, ...] = (None, 0.0005, 0.005, 0.05)
#: Spans of simulated time (seconds) one ``advance`` step lets pass.
STEPS: tuple[float, ...] = (0.0001, 0.0005, 0.002, 0.01, 0.1, 1.0)
#: One-way latencies (seconds) of a client's calls (the default is 0.1 ms).
LATENCIES: tuple[float, ...] = (0.0001, 0.0, 0.0003, 0.002, 0.02)
_TRANSPORT = ("transport error completing service call: unable to receive data from sender, "
              "check sender's logs for details")
_RULES = ("call", "fail_next", "stop_server", "start_server", "new_persistent_proxy",
          "wait_for_service", "set_latency", "advance")


class ServiceViolation(AssertionError):
    """The service (or its handler) broke its contract or rospy's rules; the message says how.

    Attributes as :class:`ddes.testing.actions.ProtocolViolation`: ``problem``,
    ``seed``, ``steps``, ``step`` (``len(steps)``: the final check), ``t_ns``,
    ``replay``.
    """

    problem: str = ""
    seed: int = 0
    steps: list[Step]
    step: int = 0
    t_ns: int = 0
    replay: str = ""


@dataclass
class _Served:
    """One run of the handler, as the wrapper saw it."""

    request: bytes
    response: bytes | None = None  # the converted response, when it returned one
    error: str | None = None  # the text the client must get (ok byte 0)
    raised: BaseException | None = None  # what the user's handler raised (not a fault)
    fault: bool = False
    matched: bool = False


@dataclass
class _Call:
    """One call of the schedule and what became of it."""

    index: int
    client: int
    kind: str  # "one-shot" | "persistent"
    request: Message
    data: bytes
    timeout_ns: int | None
    start: int
    up: bool  # the service was registered when the call was made
    gen: int  # the persistent proxy's generation (0 for one-shot calls)
    end: int | None = None
    response: Message | None = None
    error: BaseException | None = None


@dataclass
class _Wait:
    client: int
    timeout_ns: int
    start: int
    up: bool
    ups_before: int  # registrations before the wait began
    end: int | None = None
    error: BaseException | None = None


def _norm(text: str) -> str:
    return re.sub(r"\S*\d\S*", "#", text)


class ServiceProtocolMachine(RuleBasedStateMachine):
    """The service machine; make one with :meth:`machine_for` or :meth:`for_service`."""

    service_class: ClassVar[type[ServiceDefinition] | None] = None
    name: ClassVar[str] = "/service"
    handler: ClassVar[Callable[..., object] | None] = None
    make_server: ClassVar[ServerFactory | None] = None
    contract: ClassVar[Contract | None] = None
    spinner: ClassVar[str | int] = "rospy"
    clients: ClassVar[int] = 3
    settle: ClassVar[float] = 10.0

    def __init__(self) -> None:
        super().__init__()
        self.world: World | None = None
        self.seed = 0
        self.steps: list[Step] = []
        self.spans: list[tuple[int, int]] = []
        self.schedule: list[str] = []
        self.calls: list[_Call] = []
        self.waits: list[_Wait] = []
        self.served: list[_Served] = []
        self.violations: list[str] = []
        self.up = False
        self.ups: list[int] = []  # instants the service registered
        self.downs: list[int] = []  # instants it went away
        self.closes: list[tuple[int, int, int]] = []  # (client, gen, t): a persistent conn closed
        self._faults: list[str] = []
        self._persistent: dict[int, tuple[ServiceProxy, int]] = {}
        self._gen = 0
        self._broken: set[tuple[int, int]] = set()  # persistent (client, gen) whose server left
        self._connected: set[tuple[int, int]] = set()  # persistent (client, gen) with a connection
        #: persistent (client, gen) whose connection answered (so the server accepted it), and
        #: those whose server then went away: every later call on them fails, as rospy's.
        self._answered: set[tuple[int, int]] = set()
        self._must_fail: dict[tuple[int, int], int] = {}
        self._failed = False
        self._in_teardown = False
        self._step_start = 0

    # -- set-up ---------------------------------------------------------------------------
    @classmethod
    def machine_for(
        cls,
        service_class: type[ServiceDefinition] | str,
        handler: Callable[..., object] | None = None,
        *,
        make_server: ServerFactory | None = None,
        name: str = "/service",
        contract: Contract | None = None,
        requests: st.SearchStrategy[Any] | None = None,
        spinner: str | int = "rospy",
        clients: int = 3,
        settle: float = 10.0,
    ) -> type[ServiceProtocolMachine]:
        """A machine class for one service (see the module docstring).

        ``requests`` draws the requests (messages or dicts of their fields;
        default: any request from :func:`ddes.testing.messages`); ``spinner``
        is the server node's (``"rospy"``: a thread per connection;
        ``"single"``: one request at a time, as roscpp's spin).
        """
        if isinstance(service_class, str):
            from ddes.msg import get_service_class

            service_class = get_service_class(service_class)
        if (handler is None) == (make_server is None):
            raise DdesValueError("give the service's handler or a make_server(world, node) "
                                 "factory that advertises it (one of the two)")
        for what, fn in (("handler", handler), ("make_server", make_server),
                         ("contract", contract)):
            if fn is not None and not callable(fn):
                raise DdesTypeError(f"{what} must be callable, got {fn!r}")
        if not isinstance(name, str) or not name.startswith("/"):
            raise DdesValueError(f"name must be the service's resolved name ('/add'), got {name!r}")
        if isinstance(clients, bool) or not isinstance(clients, int) or not 1 <= clients <= 8:
            raise DdesValueError(f"clients must be an int in 1..8, got {clients!r}")
        req_cls = service_class._request_class
        strategy = requests if requests is not None else messages(req_cls, max_size=3)
        dicts = strategy.map(lambda r: r if isinstance(r, Mapping) else message_to_dict(r))

        class Machine(cls):  # type: ignore[valid-type,misc]
            @rule(client=st.integers(0, clients - 1), request=dicts,
                  kind=st.sampled_from(["one-shot", "persistent"]),
                  timeout=st.sampled_from(TIMEOUTS))
            def call(self, client: int, request: Mapping[str, object], kind: str,
                     timeout: float | None) -> None:
                """A client calls the service (the call goes on while the schedule does)."""
                self._call(client, dict(request), kind, timeout)

            @rule(client=st.integers(0, clients - 1), latency=st.sampled_from(LATENCIES[1:]))
            def set_latency(self, client: int, latency: float) -> None:
                """Change the one-way latency of one client's calls."""
                self._set_latency(client, latency)

            @rule(client=st.integers(0, clients - 1), timeout=st.sampled_from((0.001, 0.1, 1.0)))
            def wait_for_service(self, client: int, timeout: float) -> None:
                """A client waits for the service, with a timeout."""
                self._wait(client, timeout)

            @precondition(lambda self: bool(self._persistent))
            @rule(client=st.integers(0, clients - 1))
            def new_persistent_proxy(self, client: int) -> None:
                """A client closes its persistent proxy; its next persistent call makes a new one."""
                self._new_persistent(client)

        Machine.service_class = service_class
        Machine.name = name
        Machine.handler = None if handler is None else staticmethod(handler)
        Machine.make_server = None if make_server is None else staticmethod(make_server)
        Machine.contract = None if contract is None else staticmethod(contract)
        Machine.spinner = spinner
        Machine.clients = clients
        Machine.settle = float(settle)
        Machine.__name__ = Machine.__qualname__ = "ServiceMachine_" + (
            getattr(make_server or handler, "__name__", "service"))
        return Machine

    @classmethod
    def for_service(cls, service_class: type[ServiceDefinition] | str,
                    handler: Callable[..., object] | None = None, *,
                    max_examples: int = 50, stateful_step_count: int = 20,
                    **kw: Any) -> type[unittest.TestCase]:
        """A ``unittest.TestCase`` class (pytest collects it) running the machine."""
        settings_kw = {k: kw.pop(k) for k in list(kw) if k not in _MACHINE_KW}
        machine = cls.machine_for(service_class, handler, **kw)

        class Case(machine.TestCase):  # type: ignore[name-defined,misc]
            def runTest(self) -> None:  # noqa: N802 - unittest's name
                try:
                    super().runTest()
                except ServiceViolation as exc:
                    raise _shrink_further(machine, exc) from None

        Case.settings = _settings(max_examples, stateful_step_count, **settings_kw)
        Case.__name__ = Case.__qualname__ = machine.TestCase.__name__
        return Case

    @initialize(seed=st.integers(0, 2**16))
    def start(self, seed: int) -> None:
        """Build the world: the server and the client nodes."""
        if type(self).service_class is None:
            raise DdesValueError("use ServiceProtocolMachine.machine_for(service_class, handler) "
                                 "or for_service(...): the base class has no service")
        self.seed = seed
        world = self.world = World(seed, strict=False)
        self.client_nodes = [world.create_node(f"client_{i}") for i in range(type(self).clients)]
        self.schedule.append(f"world seed {seed}")
        self._start_server()

    def _start_server(self) -> None:
        assert self.world is not None
        cls = type(self)
        world = self.world
        old = getattr(self, "server_node", None)
        if old is not None and not old.is_shutdown():
            node = old  # only the service went away: advertise it again on the same node
        else:
            node = world.create_node("service_server", spinner=cls.spinner)
        self.server_node = node
        if cls.make_server is not None:
            cls.make_server(world, node)
        else:
            assert cls.handler is not None and cls.service_class is not None
            Service(node, cls.name, cls.service_class, cls.handler)
        entry = world.master.lookup_service(cls.name)
        if entry is None:
            raise DdesValueError(f"make_server did not advertise {cls.name} on its node; "
                                 f"advertised: {sorted(world.master.services)}")
        self.server = server = entry.server
        server.handler = self._wrap(server.handler, server.style)
        self.up = True
        self.ups.append(world.now)

    # -- the handler, watched -------------------------------------------------------------------
    def _wrap(self, handler: Callable[..., object], style: str) -> Callable[..., object]:
        resp_cls = type(self).service_class._response_class  # type: ignore[union-attr]

        def finish(rec: _Served, result: object, response: Message | None) -> None:
            if style == "roscpp":
                rec.response = serialize(response) if result is True else None  # type: ignore[arg-type]
                if result is False:
                    rec.error = ""
                return
            try:
                rec.response = serialize(convert_return_to_response(result, resp_cls))
            except ServiceException as exc:
                rec.error = SERVICE_CANNOT_PROCESS + str(exc)

        def failed(rec: _Served, exc: BaseException) -> None:
            rec.raised = exc
            rec.error = str(exc) if style == "roscpp" else (
                SERVICE_CANNOT_PROCESS + str(exc) if isinstance(exc, ServiceException)
                else ERROR_PROCESSING + str(exc))

        def rest(rec: _Served, gen: Generator[Any, Any, object],
                 response: Message | None) -> Generator[Any, Any, object]:
            try:
                result = yield from gen
            except Exception as exc:
                failed(rec, exc)
                raise
            finish(rec, result, response)
            return result

        def watched(request: Message, *args: Any) -> object:
            rec = _Served(serialize(request))
            self.served.append(rec)
            if self._faults:
                kind = self._faults.pop(0)
                rec.fault = True
                exc: Exception = ServiceException(f"injected fault {len(self.served)}") \
                    if kind == "ServiceException" else RuntimeError(f"injected fault {len(self.served)}")
                failed(rec, exc)
                rec.raised = None
                raise exc
            try:
                result = handler(request, *args)
            except Exception as exc:
                failed(rec, exc)
                raise
            response = args[0] if args else None
            if type(result) is GeneratorType:
                return rest(rec, result, response)
            finish(rec, result, response)
            return result

        return watched

    # -- rules ------------------------------------------------------------------------------
    def _begin(self, *step: object) -> None:
        assert self.world is not None
        self.steps.append(tuple(step))
        self._step_start = self.world.now
        self.schedule.append(f"{len(self.steps):3d}. {ns_to_sec(self.world.now):10.6f}s  "
                             + " ".join(str(s) for s in step))

    def _end(self) -> None:
        assert self.world is not None
        self.spans.append((self._step_start, self.world.now))

    def _call(self, client: int, request: dict[str, object], kind: str,
              timeout: float | None) -> None:
        assert self.world is not None
        cls = type(self)
        svc = cls.service_class
        assert svc is not None
        self._begin("call", client, request, kind, timeout)
        node = self.client_nodes[client]
        msg = dict_to_message(svc._request_class, request)
        timeout_ns = None if timeout is None else duration_to_ns(timeout, "timeout")
        field_timeout = "timeout" in svc._request_class.__slots__
        gen = 0
        if kind == "persistent":
            if client not in self._persistent:
                self._gen += 1
                self._persistent[client] = (ServiceProxy(node, cls.name, svc, persistent=True),
                                            self._gen)
            proxy, gen = self._persistent[client]
            if self.up:
                self._connected.add((client, gen))
        else:
            proxy = ServiceProxy(node, cls.name, svc, timeout=timeout)
        rec = _Call(len(self.calls), client, kind, msg, serialize(msg), timeout_ns,
                    self.world.now, self.up, gen)
        self.calls.append(rec)
        self.schedule[-1] += f"  (call #{rec.index})"
        if kind == "persistent" and timeout is not None and not field_timeout:
            event = proxy.call(msg, timeout=timeout)
        else:
            event = proxy.call(msg)
        if kind == "persistent" and timeout is not None and field_timeout:
            rec.timeout_ns = None  # the request's own field took the timeout= argument

        def waiter() -> Generator[Any, Any, None]:
            try:
                rec.response = yield event
            except Exception as exc:  # noqa: BLE001 - every failure is checked below
                rec.error = exc
            assert self.world is not None
            rec.end = self.world.now
            self._check_call(rec)

        node.process(waiter())
        self.world.run_for(0)  # a call that fails at once ends in this step
        self._end()

    @precondition(lambda self: self.up)
    @rule(kind=st.sampled_from(["RuntimeError", "ServiceException"]))
    def fail_next(self, kind: str) -> None:
        """The handler's next run raises instead of running the user's handler."""
        self._begin("fail_next", kind)
        self._faults.append(kind)
        self._end()

    @precondition(lambda self: self.up)
    @rule(how=st.sampled_from(["node", "service"]))
    def stop_server(self, how: str) -> None:
        """The server goes away: its node shuts down, or it unadvertises the service."""
        assert self.world is not None
        self._begin("stop_server", how)
        if how == "node":
            self.server_node.shutdown("stopped by the protocol machine")
        else:
            self.server.shutdown("stopped by the protocol machine")
        self.up = False
        self._faults.clear()
        self.downs.append(self.world.now)
        self._broken |= self._connected
        for key in self._answered:
            self._must_fail.setdefault(key, self.world.now)
        self._connected = set()
        self.world.run_for(0)
        self._end()

    @precondition(lambda self: not self.up)
    @rule()
    def start_server(self) -> None:
        """The server comes back (a new node of the same name)."""
        assert self.world is not None
        self._begin("start_server")
        self._start_server()
        self.world.run_for(0)
        self._end()

    def _new_persistent(self, client: int) -> None:
        assert self.world is not None
        self._begin("new_persistent_proxy", client)
        old = self._persistent.pop(client, None)
        if old is not None:
            old[0].close()
            self.closes.append((client, old[1], self.world.now))
        self.world.run_for(0)
        self._end()

    def _wait(self, client: int, timeout: float) -> None:
        assert self.world is not None
        self._begin("wait_for_service", client, timeout)
        rec = _Wait(client, duration_to_ns(timeout, "timeout"), self.world.now, self.up,
                    len(self.ups))
        self.waits.append(rec)
        event = wait_for_service(self.client_nodes[client], type(self).name, timeout)

        def waiter() -> Generator[Any, Any, None]:
            try:
                yield event
            except Exception as exc:  # noqa: BLE001 - checked below
                rec.error = exc
            assert self.world is not None
            rec.end = self.world.now
            self._check_wait(rec)

        self.client_nodes[client].process(waiter())
        self.world.run_for(0)
        self._end()

    def _set_latency(self, client: int, latency: float) -> None:
        assert self.world is not None
        self._begin("set_latency", client, latency)
        self.world.set_service_link(type(self).name, client=f"/client_{client}", latency=latency)
        self._end()

    @rule(seconds=st.sampled_from(STEPS))
    def advance(self, seconds: float) -> None:
        """Let simulated time pass."""
        assert self.world is not None
        self._begin("advance", seconds)
        self.world.run_for(seconds)
        self._end()

    # -- checks -----------------------------------------------------------------------------
    def _bad(self, text: str) -> None:
        assert self.world is not None
        self.violations.append(f"at {ns_to_sec(self.world.now):.6f}s: {text}")

    def _what(self, rec: _Call) -> str:
        t = "" if rec.timeout_ns is None else f", timeout {ns_to_sec(rec.timeout_ns):g}s"
        return (f"call #{rec.index} ({rec.kind} proxy of /client_{rec.client}{t}, "
                f"request {message_to_dict(rec.request)}, at {ns_to_sec(rec.start):.6f}s)")

    def _went_away(self, start: int, end: int) -> bool:
        return any(start <= t <= end for t in self.downs)

    def _check_call(self, rec: _Call) -> None:
        """Check 1-4 for a call that just ended."""
        name = type(self).name
        assert rec.end is not None
        took = rec.end - rec.start
        err = rec.error
        key = (rec.client, rec.gen)
        if err is None:
            gone = self._must_fail.get(key)
            if rec.kind == "persistent" and gone is not None and gone <= rec.start:
                self._bad(f"{self._what(rec)} was answered, but the server of its persistent "
                          f"connection went away at {ns_to_sec(gone):.6f}s: a persistent proxy "
                          "fails every call after that, as rospy's (create a new ServiceProxy)")
            if rec.kind == "persistent":
                self._answered.add(key)
            self._check_response(rec)
            if rec.timeout_ns is not None and took > rec.timeout_ns:
                self._bad(f"{self._what(rec)} was answered {ns_to_sec(took):.6f}s later, after "
                          "its timeout")
            return
        text = str(err)
        if isinstance(err, ServiceTimeout):
            self._answered.discard(key)  # the proxy dropped that connection: it reconnects
            if rec.timeout_ns is None or took != rec.timeout_ns:
                self._bad(f"{self._what(rec)} timed out after {ns_to_sec(took):.6f}s")
            return
        if not isinstance(err, ServiceException):
            self._bad(f"{self._what(rec)} failed with {type(err).__name__}: {text} (a failing "
                      "call raises ServiceException in the caller, as rospy)")
            return
        if text == f"service [{name}] unavailable":
            if rec.up:
                self._bad(f"{self._what(rec)} failed with '{text}' although the service was "
                          "registered")
            elif took:
                self._bad(f"{self._what(rec)}: '{text}' came {ns_to_sec(took):.6f}s after the "
                          "call, not at once")
            return
        prefix = f"service [{name}] responded with an error: "
        if text.startswith(prefix):
            sent = text[len(prefix):]
            served = [s for s in self.served if s.request == rec.data and not s.matched
                      and s.error is not None]
            match = next((s for s in served if s.error == sent), None)
            if match is None:
                self._bad(f"{self._what(rec)} got the error '{text}', but the handler gave no "
                          "such error for its request" + (
                              f" (its error was {served[0].error!r})" if served else ""))
                return
            match.matched = True
            if rec.kind == "persistent":
                self._answered.add(key)
            self._check_contract_error(rec, match)
            return
        if rec.kind == "persistent" and text == (
                f"persistent connection to service [{name}] was closed: the server went away; "
                "create a new ServiceProxy"):
            if key not in self._broken and key not in self._must_fail:
                self._bad(f"{self._what(rec)} says its server went away, but the server of its "
                          "connection never did")
            return
        if text == _TRANSPORT or text.startswith("unable to connect to service: "):
            closed = any(c == rec.client and g == rec.gen and rec.start <= t <= rec.end
                         for c, g, t in self.closes)
            timed_out = rec.kind == "persistent" and any(
                o.kind == "persistent" and o.client == rec.client and o.gen == rec.gen
                and isinstance(o.error, ServiceTimeout) and o.end == rec.end
                for o in self.calls)
            if not (self._went_away(rec.start, rec.end) or closed or timed_out):
                self._bad(f"{self._what(rec)} failed with '{text}' although the server stayed "
                          "up and the connection open")
            return
        self._bad(f"{self._what(rec)} failed with an unexpected error: {text}")

    def _check_response(self, rec: _Call) -> None:
        assert rec.response is not None
        data = serialize(rec.response)
        match = next((s for s in self.served if s.request == rec.data and s.response == data
                      and not s.matched), None)
        if match is None:
            made = [s for s in self.served if s.response == data and not s.matched]
            self._bad(f"{self._what(rec)} got {message_to_dict(rec.response)}, which the handler "
                      "did not return for that request" + (
                          " (it returned it for another caller's request)" if made else ""))
            return
        match.matched = True
        contract = type(self).contract
        if contract is None:
            return
        expected = contract(rec.request)
        if expected is None:
            return
        if isinstance(expected, type) and issubclass(expected, BaseException) or \
                isinstance(expected, BaseException):
            self._bad(f"{self._what(rec)} was answered {message_to_dict(rec.response)}, but the "
                      f"contract expects it to fail ({expected!r})")
            return
        if callable(expected) and not isinstance(expected, Message):
            if not expected(rec.response):
                self._bad(f"{self._what(rec)}: the response {message_to_dict(rec.response)} "
                          "breaks the contract")
            return
        try:
            want = convert_return_to_response(
                expected, type(self).service_class._response_class)  # type: ignore[union-attr]
        except ServiceException as exc:
            raise DdesValueError(f"the contract returned {expected!r} for "
                                 f"{message_to_dict(rec.request)}, which is no response: {exc}") from None
        if serialize(want) != data:
            self._bad(f"{self._what(rec)}: the contract expects {message_to_dict(want)}, the "
                      f"response is {message_to_dict(rec.response)}")

    def _check_contract_error(self, rec: _Call, served: _Served) -> None:
        contract = type(self).contract
        if contract is None or served.fault or served.raised is None:
            return
        expected = contract(rec.request)
        if expected is None or isinstance(expected, BaseException) or (
                isinstance(expected, type) and issubclass(expected, BaseException)):
            return
        self._bad(f"{self._what(rec)}: the handler raised {type(served.raised).__name__}: "
                  f"{served.raised} where the contract expects a response")

    def _check_wait(self, rec: _Wait) -> None:
        assert rec.end is not None
        deadline = rec.start + rec.timeout_ns
        came = [t for t in self.ups[rec.ups_before:] if t <= deadline]
        up_at_start = rec.up
        if rec.error is None:
            want = rec.start if up_at_start else (came[0] if came else None)
            if want is None or rec.end != want:
                self._bad(f"wait_for_service of /client_{rec.client} at {ns_to_sec(rec.start):.6f}s "
                          f"returned at {ns_to_sec(rec.end):.6f}s" + (
                              "" if want is None else f", not at {ns_to_sec(want):.6f}s"))
            return
        text = f"timeout exceeded while waiting for service {type(self).name}"
        if not isinstance(rec.error, ROSException) or str(rec.error) != text or \
                rec.end != deadline or up_at_start or any(t < deadline for t in came):
            self._bad(f"wait_for_service of /client_{rec.client} at {ns_to_sec(rec.start):.6f}s "
                      f"failed at {ns_to_sec(rec.end):.6f}s with {type(rec.error).__name__}: "
                      f"{rec.error}")

    @invariant()
    def service_holds(self) -> None:
        """Checks 1-5 (see the module docstring) on what ended since the last step."""
        if self.world is None:
            return
        if self.violations:
            self._fail(self.violations[0])

    def teardown(self) -> None:
        """Let ``settle`` seconds pass; every call must have ended, each answered once."""
        if self.world is None or self._failed:
            return
        world = self.world
        self._in_teardown = True
        deadline = world.now + duration_to_ns(type(self).settle, "settle")
        while world.now < deadline and any(c.end is None for c in self.calls + self.waits):
            world.run_for(0.01)
            self.service_holds()
        self.service_holds()
        for rec in self.calls:
            if rec.end is None:
                self._fail(f"{self._what(rec)} was never answered ({type(self).settle}s later)")
        ended = world.trace.filter(kind="service.response") + world.trace.filter(
            kind="service.error")
        calls = world.trace.filter(kind="service.call")
        per: dict[object, int] = {}
        for ev in ended:
            per[ev.details.get("call")] = per.get(ev.details.get("call"), 0) + 1
        for ev in calls:
            n = per.get(ev.details.get("call"), 0)
            if n != 1:
                self._fail(f"service call {ev.details.get('call')} of {ev.source} ended {n} "
                           "times: every call is answered exactly once")

    def replay_call(self) -> str:
        """The one-line call that replays the schedule run so far."""
        cls = type(self)
        kwargs: dict[str, object] = {"seed": self.seed}
        if cls.handler is not None:
            kwargs["handler"] = Source(factory_name(cls.handler, "handler"))
        if cls.make_server is not None:
            kwargs["make_server"] = Source(factory_name(cls.make_server, "make_server"))
        if cls.contract is not None:
            kwargs["contract"] = Source(factory_name(cls.contract, "contract"))
        if cls.name != "/service":
            kwargs["name"] = cls.name
        if cls.spinner != "rospy":
            kwargs["spinner"] = cls.spinner
        if cls.clients != 3:
            kwargs["clients"] = cls.clients
        svc = cls.service_class
        assert svc is not None
        return call_text("replay_service_schedule", [svc._type, self.steps], kwargs)

    def _fail(self, problem: str) -> None:
        self._failed = True
        assert self.world is not None
        lines = [f"service {type(self).name} broke its contract or rospy's rules:", f"  {problem}",
                 "", f"replay: world seed {self.seed}; schedule (step, simulated time, what):"]
        lines += [f"  {s}" for s in self.schedule]
        replay = self.replay_call()
        lines += ["", "replay it (ddes.testing.services):", f"  {replay}"]
        exc = ServiceViolation("\n".join(lines))
        exc.problem, exc.seed, exc.steps = problem, self.seed, list(self.steps)
        exc.step = len(self.steps) if self._in_teardown else len(self.steps) - 1
        exc.t_ns, exc.replay = self.world.now, replay
        raise exc


_MACHINE_KW = ("make_server", "name", "contract", "requests", "spinner", "clients", "settle")


def _settings(max_examples: int, stateful_step_count: int, **kw: Any) -> settings:
    kw.setdefault("deadline", None)
    kw.setdefault("suppress_health_check", [HealthCheck.too_slow, HealthCheck.filter_too_much,
                                            HealthCheck.data_too_large])
    return settings(max_examples=max_examples, stateful_step_count=stateful_step_count, **kw)


def run_service_machine(service_class: type[ServiceDefinition] | str,
                        handler: Callable[..., object] | None = None, *,
                        max_examples: int = 50, stateful_step_count: int = 20,
                        **kw: Any) -> None:
    """Run the machine now; raises :class:`ServiceViolation` (shrunk) on a failure.

    Keywords: those of :meth:`ServiceProtocolMachine.machine_for`, then
    hypothesis settings (``derandomize=True``, ``database=None`` ...).
    """
    settings_kw = {k: kw.pop(k) for k in list(kw) if k not in _MACHINE_KW}
    machine = ServiceProtocolMachine.machine_for(service_class, handler, **kw)
    try:
        with same_draws_everywhere():
            run_state_machine_as_test(machine, settings=_settings(max_examples, stateful_step_count,
                                                                  **settings_kw))
    except ServiceViolation as exc:
        raise _shrink_further(machine, exc) from None


def _shrink_further(machine: type[ServiceProtocolMachine],
                    exc: ServiceViolation) -> ServiceViolation:
    """Delete the steps the failure does not need (see ddes.testing.actions)."""
    steps, best = list(exc.steps), exc
    for i in reversed(range(len(steps))):
        trial = steps[:i] + steps[i + 1:]
        try:
            v = _replay(machine, trial, best.seed).violation
        except DdesValueError:
            continue
        if v is not None and _norm(v.problem) == _norm(exc.problem):
            steps, best = trial, v
    return best


# -- replay ---------------------------------------------------------------------------------------

_OUTCOME_COLORS = {"ok": "#2e9d4f", "server": "#d62728", "timeout": "#f2a541",
                   "transport": "#9467bd", "other": "#8c564b", "open": "#bdbdbd"}


@dataclass
class ServiceReplay:
    """One schedule run again by :func:`replay_service_schedule` (see ActionReplay)."""

    world: World
    name: str
    steps: list[Step]
    violation: ServiceViolation | None
    spans: list[tuple[int, int]] = field(default_factory=list)
    calls: list[_Call] = field(default_factory=list)
    downs: list[tuple[int, int | None]] = field(default_factory=list)

    @property
    def step(self) -> int | None:
        """Index of the violating step (``len(steps)``: the final check), or None."""
        return None if self.violation is None else self.violation.step

    def raise_violation(self) -> None:
        if self.violation is not None:
            raise self.violation

    def plot(self, ax: Axes | None = None) -> Figure:
        """One row per call (a bar from call to answer, coloured by outcome), the spans with
        the server away shaded grey, and the violating step marked."""
        from matplotlib.figure import Figure

        if ax is None:
            fig = Figure(figsize=(9.0, 1.2 + 0.35 * max(1, len(self.calls))))
            ax = fig.add_subplot(1, 1, 1)
        else:
            fig = ax.figure  # type: ignore[assignment]
        end = self.world.now
        n = len(self.calls)
        for rec in self.calls:
            y = n - 1 - rec.index
            stop = rec.end if rec.end is not None else end
            err = rec.error
            outcome = "open" if rec.end is None else "ok" if err is None else \
                "timeout" if isinstance(err, ServiceTimeout) else \
                "server" if "responded with an error" in str(err) else \
                "transport" if "transport" in str(err) or "connect" in str(err) else "other"
            ax.broken_barh([(ns_to_sec(rec.start), max(ns_to_sec(stop - rec.start), 1e-5))],
                           (y - 0.3, 0.6), facecolors=_OUTCOME_COLORS[outcome])
            ax.annotate(outcome, (ns_to_sec(stop), y), xytext=(4, -3),
                        textcoords="offset points", fontsize=7)
        for down, up in self.downs:
            ax.axvspan(ns_to_sec(down), ns_to_sec(end if up is None else up), color="#000000",
                       alpha=0.07, linewidth=0)
        ax.set_yticks(list(range(n)))
        ax.set_yticklabels([f"#{c.index} {c.kind} /client_{c.client}"
                            for c in reversed(self.calls)], fontsize=7)
        ax.set_xlabel("simulated time [s]")
        ax.set_title(f"calls of {self.name} (grey: server away)")
        v = self.violation
        if v is not None:
            spans = self.spans
            start = spans[v.step][0] if 0 <= v.step < len(spans) else (
                spans[-1][1] if spans else 0)
            what = "final check" if v.step >= len(self.steps) else \
                " ".join(str(s) for s in self.steps[v.step])
            mark_violation(ax, ns_to_sec(start), ns_to_sec(v.t_ns),
                           f"step {v.step}: {what}\n{v.problem[:80]}")
        fig.tight_layout()
        return fig


def replay_service_schedule(service_class: type[ServiceDefinition] | str, steps: list[Step],
                            seed: int = 0, *, handler: Callable[..., object] | None = None,
                            make_server: ServerFactory | None = None,
                            contract: Contract | None = None, name: str = "/service",
                            spinner: str | int = "rospy", clients: int = 3,
                            settle: float = 10.0) -> ServiceReplay:
    """Run a schedule (as a :class:`ServiceViolation` prints it) again, with every check."""
    machine = ServiceProtocolMachine.machine_for(
        service_class, handler, make_server=make_server, contract=contract, name=name,
        spinner=spinner, clients=clients, settle=settle)
    return _replay(machine, steps, seed)


def _replay(machine_cls: type[ServiceProtocolMachine], steps: list[Step],
            seed: int) -> ServiceReplay:
    m = machine_cls()
    violation: ServiceViolation | None = None
    try:
        m.start(seed)
        for step in steps:
            kind, args = str(step[0]), step[1:]
            if kind not in _RULES:
                raise DdesValueError(f"unknown step {step!r}: a step is one of {_RULES}")
            if kind in ("fail_next", "stop_server") and not m.up or \
                    kind == "start_server" and m.up:
                raise DdesValueError(f"step {len(m.steps)} {step!r} cannot run here (the server "
                                     f"is {'up' if m.up else 'down'})")
            if kind == "call":
                m._call(*args)  # type: ignore[arg-type]
            elif kind == "set_latency":
                m._set_latency(*args)  # type: ignore[arg-type]
            elif kind == "wait_for_service":
                m._wait(*args)  # type: ignore[arg-type]
            elif kind == "new_persistent_proxy":
                m._new_persistent(*args)  # type: ignore[arg-type]
            else:
                getattr(m, kind)(*args)
            m.service_holds()
        m.teardown()
    except ServiceViolation as exc:
        violation = exc
    assert m.world is not None
    downs: list[tuple[int, int | None]] = []
    for d in m.downs:
        later = [u for u in m.ups if u >= d]
        downs.append((d, later[0] if later else None))
    return ServiceReplay(m.world, machine_cls.name, list(steps), violation, list(m.spans),
                         list(m.calls), downs)
