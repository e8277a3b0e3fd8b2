"""Service clients: ``ServiceProxy`` (rospy) and ``ServiceClient`` (roscpp).

``resp = yield proxy.call(req)`` (or ``proxy(req)``, ``proxy(1, 2)``,
``proxy(a=1, b=2)``): the event's value is the response; a failure raises
:class:`~ddes.errors.ServiceException` in the caller with rospy's text:

* ``service [X] unavailable``: nothing is registered under the name;
* ``unable to connect to service: ...``: the server went away before the
  connection was made, or the md5sums differ;
* ``service [X] responded with an error: <text>``: the server answered
  with ok byte 0 (handler error, roscpp callback returned false);
* ``transport error completing service call: ...``: the server shut down
  while the call was in progress;
* a persistent proxy whose server went away fails every later call and says
  so (create a new proxy, as in ROS).

A request of the wrong type raises TypeError and a bad field
ROSSerializationException, at once, from ``call()`` itself.  If the
calling node shuts down during a call, the event fails with
``ROSInterruptException("node shutdown interrupted service call")``.

**Call timeout (a ddes extension).**  ROS 1 service calls have no timeout
(ros/ros_comm#152; PR #1282 was closed).  ``proxy.call(req, timeout=0.5)``
or ``ServiceProxy(..., timeout=0.5)`` makes the call fail with
:class:`~ddes.errors.ServiceTimeout` (a ServiceException) after that much
ROS time of the calling node.  As the ros_comm#152 discussion points out, the
server is not told: it finishes its work, and its late response is
discarded and traced (``service.discard``).  The connection is closed; a
persistent proxy opens a new one on its next call.  If the request type has
a field called ``timeout``, ``timeout=`` fills that field instead; use the
proxy-level default then.
"""

from __future__ import annotations

from enum import Enum
from typing import TYPE_CHECKING, Final, cast

from ddes.errors import ROSInterruptException, ServiceException, ServiceTimeout
from ddes.kernel.events import Posted, post
from ddes.services.convert import check_service_class
from ddes.services.network import network_of
from ddes.services.server import check_service_name
from ddes.services.transport import (
    PendingCall,
    ServiceConnection,
    open_call,
    request_keys,
    response_keys,
)
from ddes.services.waiting import check_nonzero_timeout, wait_for_service, wait_for_service_ns
from ddes.time.rospy_calls import REQUIRED, is_node_like, node_first
from ddes.time.sleep import must_yield
from ddes.time.units import DurationLike, duration_to_ns, ns_to_sec

if TYPE_CHECKING:
    import simpy

    from ddes.graph.node import Node
    from ddes.msg.message import Message, ServiceDefinition
    from ddes.services.network import ServiceNetwork, ServiceStats
    from ddes.services.server import Service

__all__ = ["ServiceClient", "ServiceProxy"]


class _Unset(Enum):
    """No ``timeout=`` given: the proxy's default applies."""

    UNSET = 0


_UNSET: Final = _Unset.UNSET
_DISCARD_KEYS = ("service", "call", "client", "reason")
_TRANSPORT_ERROR = ("transport error completing service call: unable to receive data from sender, "
                    "check sender's logs for details")


class ServiceProxy:
    """A handle to call a ROS service (rospy.ServiceProxy), owned by ``node``.

    ``persistent=True`` keeps one connection open across calls (no header
    exchange after the first call) until :meth:`close`.  ``timeout`` is the
    default call timeout (seconds or Duration of ROS time; a ddes extension).
    """

    def __init__(self, node: Node, name: str, service_class: type[ServiceDefinition] = REQUIRED,
                 persistent: bool = False, headers: dict[str, str] | None = None, *,
                 timeout: DurationLike | None = None) -> None:
        if not is_node_like(node):  # rospy's ServiceProxy(name, service_class): shifted
            node_first("ServiceProxy", "proxy = ", node, [name], {},
                       "resp = yield proxy(req)    # in the node's process")
        node.check_alive("create a service proxy")
        check_service_name(name, "ServiceProxy")
        check_service_class(service_class, f"ServiceProxy {name!r}")
        self.node = node
        self.world = node.world
        self.resolved_name = node.resolve_name(name)
        self.service_class = service_class
        self.request_class: type[Message] = service_class._request_class
        self.response_class: type[Message] = service_class._response_class
        self.persistent = bool(persistent)
        self.headers = dict(headers or {})
        if self.persistent:
            self.headers["persistent"] = "1"
        #: The default call timeout (int ns), None for none.
        self.timeout_ns = check_nonzero_timeout(
            None if timeout is None else duration_to_ns(timeout, "timeout"))
        self.seq = 0
        self._transport: ServiceConnection | None = None
        #: Why every call of this persistent proxy now fails (closed, or its server went away).
        self._broken: str | None = None
        self._pending: dict[int, PendingCall] = {}
        self._field_timeout = "timeout" in self.request_class.__slots__
        self._stats: ServiceStats | None = None
        self._net: ServiceNetwork | None = None
        #: This proxy's key in its network's link cache: (service, client node).
        self._link_key = (self.resolved_name, node.name)
        #: Key tuples of this proxy's service.call and service.response rows (wire bytes).
        self._call_keys = request_keys(self.request_class)
        self._response_keys = response_keys(self.response_class)
        node.add_entity(self)

    # -- calling --------------------------------------------------------------------------
    def call(self, *args: object, timeout: DurationLike | None | _Unset = _UNSET,
             **kwds: object) -> simpy.Event:
        """Call the service; ``yield`` the event for the response (see module docstring)."""
        if timeout is not _UNSET and self._field_timeout:
            kwds["timeout"] = timeout
            timeout = _UNSET
        timeout_ns = self.timeout_ns if timeout is _UNSET else self._call_timeout_ns(timeout)
        return must_yield(self._start(args, kwds, timeout_ns).event, "proxy(request)")

    __call__ = call

    def _call_timeout_ns(self, timeout: DurationLike | None | _Unset) -> int | None:
        """The timeout of one call: the proxy's default unless ``timeout=`` was given."""
        if timeout is _UNSET:
            return self.timeout_ns
        return check_nonzero_timeout(None if timeout is None
                                     else duration_to_ns(timeout, "timeout"))

    def _start(self, args: tuple[object, ...], kwds: dict[str, object],
               timeout_ns: int | None) -> PendingCall:
        """Start one call: its request leaves now, or once its connection is made.

        :func:`~ddes.services.transport.open_call` checks the node, builds the
        request by rospy's rules, serializes it, counts and traces the call
        (``service.call``) and holds it as pending.  Then, by the proxy's state:
        a broken persistent proxy fails it; an open connection sends it at once
        (or queues it behind the header exchange in progress); otherwise the
        master is asked for the server and a new connection starts (header hop).
        """
        call = open_call(self, args, kwds)
        node = self.node
        world = self.world
        name = self.resolved_name
        if timeout_ns is not None:
            self._arm_timeout(call, timeout_ns)
        conn = self._transport
        if conn is not None and conn.server_gone:
            self._transport = conn = None
            self._broken = (f"persistent connection to service [{name}] was closed: the server "
                            "went away; create a new ServiceProxy")
        if self._broken is not None:
            call.fail("closed", ServiceException(self._broken))
            return call
        if conn is not None:
            call.conn = conn
            if not conn.ready:
                conn.waiting.append(call)  # the request leaves once the header exchange is done
            else:  # _send_request(conn, call, now), inline (the hot path of a persistent proxy)
                call.sent_at = now = call.t0
                at = now + conn.link.sample_ns()
                if at < conn.last_request:
                    at = conn.last_request
                conn.last_request = at
                post(world.env, at - now, (conn, call), conn.server._on_request)
            return call
        entry = world.master.lookup_service(name)
        if entry is None:
            call.fail("unavailable", ServiceException(f"service [{name}] unavailable"))
            return call
        net = self._net
        if net is None:
            net = self._net = network_of(world)
        link = net._links.get(self._link_key)  # ServiceNetwork.link, its cache read inline
        if link is None:
            link = net.link(name, node.name)
        conn = ServiceConnection(self, entry.server, link)
        call.conn = conn
        conn.waiting.append(call)
        if self.persistent:
            self._transport = conn
        post(world.env, conn.link.sample_ns(), (conn, entry.server), self._on_header)
        return call

    def _arm_timeout(self, call: PendingCall, timeout_ns: int) -> None:
        clock = self.node.clock
        ev = clock.wait_until(clock.now_ns() + timeout_ns)
        ev.callbacks.append(lambda _ev: self._expire(call, timeout_ns))

    # -- hops (see ddes.services.transport) ---------------------------------------------------
    def _calls_on(self, conn: ServiceConnection) -> list[PendingCall]:
        return [c for c in self._pending.values() if c.conn is conn and not c.done]

    def _on_header(self, ev: Posted[tuple[ServiceConnection, Service]]) -> None:
        """The connection header reached the server: accepted or refused."""
        conn, server = ev.payload
        if conn.closed:
            return  # the client gave up before connecting
        waiting = conn.waiting
        if len(waiting) != 1 or waiting[0].done:  # one call waiting: every call of a plain proxy
            waiting = [call for call in waiting if not call.done]
        conn.waiting = []
        error = server._accept(conn)
        back = conn.link.sample_ns()
        now: int = self.world.env.now_ns
        if error is not None:
            conn.closed = True
            if self._transport is conn:
                self._transport = None
            post(self.world.env, back, (waiting, error), self._on_refused)
            return
        conn.ready = True
        for call in waiting:
            self._send_request(conn, call, now + back)

    def _on_refused(self, ev: Posted[tuple[list[PendingCall], str]]) -> None:
        waiting, error = ev.payload
        for call in waiting:
            if not call.done:
                call.fail("connect", ServiceException(f"unable to connect to service: {error}"))

    def _send_request(self, conn: ServiceConnection, call: PendingCall, sent_at: int) -> None:
        """The request leaves the client at ``sent_at`` (FIFO per connection)."""
        call.sent_at = sent_at
        now: int = self.world.env.now_ns
        at = sent_at + conn.link.sample_ns()
        if at < conn.last_request:
            at = conn.last_request
        conn.last_request = at
        post(self.world.env, at - now, (conn, call), conn.server._on_request)

    def _send_response(self, conn: ServiceConnection, call: PendingCall, ok: bool,
                       payload: bytes | str) -> None:
        """Called by the server: the response (bytes, ``ok``) or the error text travels back."""
        now: int = self.world.env.now_ns
        at = now + conn.link.sample_ns()
        if at < conn.last_response:
            at = conn.last_response
        conn.last_response = at
        post(self.world.env, at - now, (call, ok, payload), self._on_response)

    def _on_response(self, ev: Posted[tuple[PendingCall, bool, bytes | str]]) -> None:
        call, ok, payload = ev.payload
        if call.done:
            call.stats.discarded += 1
            world = self.world
            world.trace.append_row((world.env.now_ns, "service.discard", self.node.name,
                                     _DISCARD_KEYS, self.resolved_name, call.id, self.node.name,
                                     "client gave up"))
            return
        if ok:
            call.succeed(cast(bytes, payload))
        else:
            text = call.server_text = cast(str, payload)
            call.fail("server", ServiceException(
                f"service [{self.resolved_name}] responded with an error: {text}"))

    def _transport_error(self, call: PendingCall) -> None:
        """The server went away during ``call``: the client learns it one latency later."""
        conn = call.conn
        assert conn is not None
        post(self.world.env, conn.link.sample_ns(), call, self._on_transport_error)

    def _on_transport_error(self, ev: Posted[PendingCall]) -> None:
        call = ev.payload
        if not call.done:
            call.fail("transport", ServiceException(_TRANSPORT_ERROR))

    def _expire(self, call: PendingCall, timeout_ns: int) -> None:
        if call.done:
            return
        call.gave_up_at = self.world.env.now_ns
        conn = call.conn
        call.fail("timeout", ServiceTimeout(
            f"service [{self.resolved_name}] call timed out after {ns_to_sec(timeout_ns):g} s of "
            "ROS time "
            "(a ddes extension: ROS 1 calls have no timeout); the server was not told and "
            "its late response will be discarded"))
        if conn is not None and not conn.closed:
            if self._transport is conn:
                self._transport = None
            conn.close()
            for other in self._calls_on(conn):
                other.gave_up_at = call.gave_up_at
                other.fail("transport", ServiceException(_TRANSPORT_ERROR))

    # -- waiting, closing --------------------------------------------------------------------
    def wait_for_service(self, timeout: DurationLike | None = None) -> simpy.Event:
        """:func:`~ddes.services.waiting.wait_for_service` for this proxy's service."""
        return wait_for_service(self.node, self.resolved_name, timeout)

    def close(self) -> None:
        """Close a persistent proxy's connection (no effect on non-persistent ones, as rospy).

        Calls still waiting on it fail with a transport error; later calls
        fail too: create a new proxy.
        """
        if not self.persistent:
            return
        if self._broken is None:
            self._broken = (f"persistent ServiceProxy for service [{self.resolved_name}] was "
                            "closed; create a new one")
        conn = self._transport
        self._transport = None
        if conn is not None and not conn.closed:
            conn.close()
            for call in self._calls_on(conn):
                call.gave_up_at = self.world.env.now_ns
                call.fail("transport", ServiceException(_TRANSPORT_ERROR))

    def shutdown(self) -> None:
        """The node shut down: pending calls fail with ROSInterruptException."""
        now: int = self.world.env.now_ns
        for call in list(self._pending.values()):
            if not call.done:
                call.gave_up_at = now
                if call.conn is not None:
                    call.conn.close()
                call.fail("interrupted", ROSInterruptException("node shutdown interrupted service call"))
        if self._transport is not None:
            self._transport.close()
            self._transport = None
        self._broken = f"the node of this ServiceProxy for [{self.resolved_name}] is shut down"
        self.node.remove_entity(self)

    def __repr__(self) -> str:
        kind = "persistent " if self.persistent else ""
        return f"<ServiceProxy {kind}{self.resolved_name} [{self.service_class._type}] of {self.node.name}>"


class ServiceClient:
    """roscpp's ``ros::ServiceClient``: ``ok = yield client.call(req, resp)``.

    The event's value is True with ``resp`` filled in place, or False for
    any failure (an error the server sent is also logged, as roscpp:
    ``Service call failed: service [X] responded with an error: <text>``).
    A roscpp server whose callback returned false sends an empty error, so
    the call is False and nothing is logged.
    """

    def __init__(self, node: Node, name: str, service_class: type[ServiceDefinition],
                 persistent: bool = False, *, timeout: DurationLike | None = None) -> None:
        self._proxy = ServiceProxy(node, name, service_class, persistent, timeout=timeout)
        self.node = node

    @property
    def resolved_name(self) -> str:
        return self._proxy.resolved_name

    def get_service(self) -> str:
        """The resolved service name (``getService()``)."""
        return self._proxy.resolved_name

    def is_persistent(self) -> bool:
        return self._proxy.persistent

    def is_valid(self) -> bool:
        """False once a persistent client's connection was lost or shut down (``isValid()``)."""
        proxy = self._proxy
        conn = proxy._transport
        return proxy._broken is None and (conn is None or not conn.server_gone)

    def exists(self) -> bool:
        """Is the service registered now (``exists()``)."""
        return self.node.world.master.lookup_service(self._proxy.resolved_name) is not None

    def call(self, request: Message, response: Message, *,
             timeout: DurationLike | None | _Unset = _UNSET) -> simpy.Event:
        """Call; the event's value is True (``response`` filled) or False."""
        proxy = self._proxy
        pending = proxy._start((request,), {}, proxy._call_timeout_ns(timeout))
        result = self.node.world.env.event()

        def done(ev: simpy.Event) -> None:
            if ev.ok:
                for slot in response.__slots__:
                    setattr(response, slot, getattr(ev.value, slot))
                result.succeed(True)
                return
            ev.defused = True
            if pending.server_text:
                self.node.logerr("Service call failed: service [%s] responded with an error: %s",
                                 proxy.resolved_name, pending.server_text)
            result.succeed(False)

        pending.event.callbacks.append(done)
        return result

    def wait_for_existence(self, timeout: DurationLike | None = None) -> simpy.Event:
        """roscpp ``waitForExistence``: event with value True, or False after ``timeout``.

        ``timeout`` (seconds or Duration of ROS time) None or negative waits
        for ever; 0 checks once.  Logs roscpp's ``waitForService: Service [X]
        has not been advertised, waiting...`` and ``... is now available.``
        """
        node = self.node
        name = self._proxy.resolved_name
        result = node.world.env.event()
        if self.exists():
            result.succeed(True)
            return result
        node.loginfo("waitForService: Service [%s] has not been advertised, waiting...", name)
        timeout_ns = None if timeout is None else duration_to_ns(timeout, "timeout")
        if timeout_ns == 0:
            result.succeed(False)
            return result
        wait = wait_for_service_ns(node, name, timeout_ns if timeout_ns is not None
                                   and timeout_ns > 0 else None)

        def done(ev: simpy.Event) -> None:
            if ev.ok:
                node.loginfo("waitForService: Service [%s] is now available.", name)
            else:
                ev.defused = True
            result.succeed(bool(ev.ok))

        wait.callbacks.append(done)
        return result

    def shutdown(self) -> None:
        """Stop using this client (``shutdown()``)."""
        self._proxy.shutdown()
