"""One service call on the wire: the connection and the pending call.

A call goes through these hops, each one kernel event after the link
latency ``L`` (drawn per message, see :mod:`ddes.services.network`):

1. **header** (new connections only: every call of a non-persistent proxy,
   the first call of a persistent one): client → server; the server checks
   that it still serves the name and that the md5sums match, and answers
   with its own header: server → client.  A failure here is
   ``"unable to connect to service: ..."``.
2. **request**: client → server, sent as soon as the client has the
   server's header; it is queued on the server node's callback queue.
3. **response** (ok byte + message, or ok byte 0 + error text): server →
   client, sent when the handler finishes.

So with the default 0.1 ms a call to an instant handler takes 0.4 ms on a
new connection and 0.2 ms on an open persistent one.  When the server goes
away its connections close: a client waiting for a response learns it one
latency later (``"transport error completing service call: ..."``).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from ddes.errors import DdesError, DdesTypeError, ROSSerializationException, ServiceException
from ddes.kernel.events import succeed
from ddes.kernel.trace_lines import wire_keys
from ddes.services.convert import args_kwds_to_request
from ddes.services.network import network_of

if TYPE_CHECKING:
    import simpy

    from ddes.msg.message import Message
    from ddes.services.client import ServiceProxy
    from ddes.services.network import ServiceLink, ServiceStats
    from ddes.services.server import Service

__all__ = ["PendingCall", "ServiceConnection", "open_call", "request_keys", "response_keys",
           "serialize"]

_CALL_KEYS = ("service", "call", "persistent", "request")
_RESPONSE_KEYS = ("service", "call", "latency", "response")
_ERROR_KEYS = ("service", "call", "latency", "reason", "error")


def serialize(msg: Message) -> bytes:
    """Wire bytes of ``msg``; a bad field raises ROSSerializationException naming it."""
    try:
        return msg._serialize_to_bytes()
    except Exception as exc:  # noqa: BLE001 - re-raised with the field that was wrong
        from ddes.msg.message import serialize_checked

        try:
            return serialize_checked(msg)
        except ROSSerializationException:
            raise
        except Exception:  # noqa: BLE001
            raise ROSSerializationException(f"cannot serialize {type(msg).__name__}: {exc}") from exc


class ServiceConnection:
    """A client's TCPROS connection to one server (one call, or many if persistent)."""

    __slots__ = ("id", "proxy", "server", "link", "persistent", "ready", "waiting", "server_gone",
                 "closed", "last_request", "last_response", "cb_active", "_client_header",
                 "_server_header")

    def __init__(self, proxy: ServiceProxy, server: Service, link: ServiceLink) -> None:
        self.id = proxy.world.next_id("service_connection")
        self.proxy = proxy
        self.server = server
        self.link = link
        self.persistent = proxy.persistent
        #: The header exchange is done: requests may be sent.
        self.ready = False
        #: Calls whose request waits for the header exchange to finish.
        self.waiting: list[PendingCall] = []
        #: The server shut down: nothing more crosses this connection.
        self.server_gone = False
        #: Either end closed it.
        self.closed = False
        #: Arrival times of the last request / response (TCP keeps them in order).
        self.last_request = 0
        self.last_response = 0
        #: A request of this connection is being served (one at a time per connection).
        self.cb_active = False
        self._client_header: dict[str, str] | None = None
        self._server_header: dict[str, str] | None = None

    @property
    def client_header(self) -> dict[str, str]:
        """The handshake header the client sent (rospy's TCPROSServiceClient fields, then the
        proxy's ``headers=``, which may override them): each request's ``_connection_header``."""
        header = self._client_header
        if header is None:
            proxy = self.proxy
            header = {"service": proxy.resolved_name, "md5sum": proxy.service_class._md5sum,
                      "callerid": proxy.node.name}
            header.update(proxy.headers)
            self._client_header = header
        return header

    @property
    def server_header(self) -> dict[str, str]:
        """The handshake header the server answered with (rospy's four fields; roscpp's also
        names the request and response types): each response's ``_connection_header``."""
        header = self._server_header
        if header is None:
            server = self.server
            cls = server.service_class
            if server.node.client_library == "roscpp":
                header = {"callerid": server.node.name, "md5sum": server.md5sum,
                          "request_type": cls._request_class._type,
                          "response_type": cls._response_class._type, "type": cls._type}
            else:
                header = {"callerid": server.node.name, "md5sum": server.md5sum,
                          "service": server.resolved_name, "type": cls._type}
            self._server_header = header
        return header

    def close(self) -> None:
        """Close from the client side (the server forgets it)."""
        self.closed = True
        self.server._conns.pop(self.id, None)


class PendingCall:
    """One call from the moment ``call()`` returns its event until it is answered."""

    __slots__ = ("id", "proxy", "event", "data", "t0", "conn", "done", "gave_up_at", "sent_at",
                 "responded", "server_text", "stats")

    def __init__(self, proxy: ServiceProxy, data: bytes, event: simpy.Event, stats: ServiceStats) -> None:
        world = proxy.world
        self.id = world.next_id("service_call")
        self.proxy = proxy
        self.event = event
        self.data = data
        self.t0: int = world.env.now_ns
        self.conn: ServiceConnection | None = None
        self.done = False
        #: Kernel time the client stopped waiting (timeout, shutdown), or -1.
        self.gave_up_at = -1
        #: Kernel time the request left the client, or -1 while unsent.
        self.sent_at = -1
        self.responded = False
        #: The error text the server sent (ok byte 0), if it did.
        self.server_text: str | None = None
        self.stats = stats

    def succeed(self, data: bytes) -> None:
        """The response arrived: deserialize the client's copy and wake the caller."""
        self.done = True
        proxy = self.proxy
        proxy._pending.pop(self.id, None)
        cls = proxy.response_class
        response = _new(cls)._deserialize_from(data)
        conn = self.conn
        if conn is not None:
            response._connection_header = conn.server_header  # as rospy sets it
        world = proxy.world
        now: int = world.env.now_ns
        latency = now - self.t0
        stats = self.stats  # ServiceStats.add_latency, inline
        stats.succeeded += 1
        stats.latency_total_ns += latency
        low = stats.latency_min_ns
        if low is None or latency < low:
            stats.latency_min_ns = latency
        high = stats.latency_max_ns
        if high is None or latency > high:
            stats.latency_max_ns = latency
        trace = world.trace
        if trace.enabled:
            trace.append_row((now, "service.response", proxy.node.name, proxy._response_keys,
                              proxy.resolved_name, self.id, latency, data))
        else:
            trace.append_row((now, "service.response", proxy.node.name, _RESPONSE_KEYS))
        succeed(self.event, response)

    def fail(self, reason: str, exc: Exception) -> None:
        """The call failed for ``reason`` (see ERROR_KINDS): trace it and raise ``exc`` in the caller."""
        self.done = True
        proxy = self.proxy
        proxy._pending.pop(self.id, None)
        self.stats.errors[reason] += 1
        world = proxy.world
        now: int = world.env.now_ns
        world.trace.append_row((now, "service.error", proxy.node.name, _ERROR_KEYS,
                                 proxy.resolved_name, self.id, now - self.t0, reason, str(exc)))
        self.event.fail(exc)


def open_call(proxy: ServiceProxy, args: tuple[object, ...], kwds: dict[str, object]) -> PendingCall:
    """The first steps of ``proxy(*args, **kwds)``, in one frame: check that the node is
    alive, build the request (:func:`~ddes.services.convert.args_kwds_to_request`'s rules),
    serialize it, count the call, trace it (``service.call``, with a snapshot of the request)
    and hold it in ``proxy._pending``."""
    node = proxy.node
    node.check_alive("call a service")
    request: Message
    cls = proxy.request_class
    if kwds or len(args) == 1:
        if len(args) == 1 and not kwds and type(args[0]) is cls:
            request = args[0]
        else:
            request = args_kwds_to_request(cls, args, kwds)
    else:  # positional field values (or none): args_kwds_to_request's last rule, inline
        try:
            request = cls(*args)
        except DdesError:
            raise
        except TypeError as exc:
            raise DdesTypeError(str(exc)) from None
    try:
        data = request._serialize_to_bytes()
    except Exception:  # noqa: BLE001 - serialize() raises the error that names the field
        try:
            data = serialize(request)
        except DdesError:
            refused = _refused_before_sending(proxy)
            if refused is not None:
                raise ServiceException(refused) from None
            raise
    world = proxy.world
    stats = proxy._stats
    if stats is None:
        stats = proxy._stats = network_of(world).stats_for(proxy.resolved_name)
    stats.calls += 1
    proxy.seq += 1
    call = PendingCall(proxy, data, world.env.event(), stats)
    trace = world.trace
    if trace.enabled:
        trace.append_row((call.t0, "service.call", node.name, proxy._call_keys,
                          proxy.resolved_name, call.id, proxy.persistent, data))
    else:
        trace.append_row((call.t0, "service.call", node.name, _CALL_KEYS))
    proxy._pending[call.id] = call
    return call


def _refused_before_sending(proxy: ServiceProxy) -> str | None:
    """What rospy's call raises before it serializes the request (it finds the service and
    connects first): the service unavailable, or the connection refused (md5sums that do
    not match, a server shutting down).  None on an open persistent connection, or when the
    connection would be accepted: then the serialization error stands.  ddes raises it at
    once, where rospy learns the refusal one round trip later."""
    conn = proxy._transport
    if conn is not None and not conn.server_gone:
        return None
    name = proxy.resolved_name
    entry = proxy.world.master.lookup_service(name)
    if entry is None:
        return f"service [{name}] unavailable"
    error = entry.server.refusal(proxy)
    return None if error is None else f"unable to connect to service: {error}"


def _wire_keys(keys: tuple[str, ...], field: str, cls: type[Message]) -> tuple[str, ...]:
    """``keys`` for a row that holds ``field`` as the wire bytes of a ``cls`` message.

    The trace reads the message from the bytes only when something looks at it (a digest,
    a query), each time as a new, independent copy of what went over the wire; until then
    the row holds bytes, strs and ints only, which the garbage collector stops tracking
    (:func:`ddes.kernel.trace_lines.wire_keys`).
    """
    cache = _WIRE_KEYS.get(keys)
    if cache is None:
        cache = _WIRE_KEYS[keys] = {}
    made = cache.get(cls)
    if made is None:
        fill = cls._deserialize_from

        def decode(data: bytes) -> Message:
            return fill(_new(cls), data)

        made = cache[cls] = wire_keys(keys, field, decode)
    return made


def request_keys(cls: type[Message]) -> tuple[str, ...]:
    """The key tuple of a ``service.call`` row whose request is a ``cls`` (its wire bytes)."""
    return _wire_keys(_CALL_KEYS, "request", cls)


def response_keys(cls: type[Message]) -> tuple[str, ...]:
    """The key tuple of a ``service.response`` row whose response is a ``cls`` (its wire bytes)."""
    return _wire_keys(_RESPONSE_KEYS, "response", cls)


#: Per key tuple, per message class: its wire_keys tuple (a cache of what the classes are).
_WIRE_KEYS: dict[tuple[str, ...], dict[type[Message], tuple[str, ...]]] = {}
_new = object.__new__
