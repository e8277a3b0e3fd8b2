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

from collections.abc import Callable
from typing import TYPE_CHECKING, Any

from ddes.errors import DdesError, DdesTypeError, ROSSerializationException
from ddes.services.convert import args_kwds_to_request
from ddes.services.network import network_of

if TYPE_CHECKING:
    import simpy

    from ddes.msg.message import Message
    from ddes.services.client import ServiceProxy
    from ddes.services.network import ServiceLink, ServiceStats
    from ddes.services.server import Service

__all__ = ["PendingCall", "ServiceConnection", "open_call", "serialize"]

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
                 "closed", "last_request", "last_response", "cb_active")

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
            trace.append_row((now, "service.response", proxy.node.name, _RESPONSE_KEYS,
                               proxy.resolved_name, self.id, latency, _snapshot(response, data)))
        else:
            trace.append_row((now, "service.response", proxy.node.name, _RESPONSE_KEYS))
        self.event.succeed(response)

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
        data = serialize(request)
    world = proxy.world
    stats = proxy._stats
    if stats is None:
        stats = proxy._stats = network_of(world).stats_for(proxy.resolved_name)
    stats.calls += 1
    proxy.seq += 1
    call = PendingCall(proxy, data, world.env.event(), stats)
    trace = world.trace
    if trace.enabled:
        trace.append_row((call.t0, "service.call", node.name, _CALL_KEYS, proxy.resolved_name,
                          call.id, proxy.persistent, _snapshot(request, data)))
    else:
        trace.append_row((call.t0, "service.call", node.name, _CALL_KEYS))
    proxy._pending[call.id] = call
    return call


def _snapshot(msg: Message, data: bytes) -> Message:
    """An independent copy of ``msg`` for the trace (what went over the wire).

    It is read from ``data`` only when something looks at it (a digest, a
    query of the trace): until then it holds the wire bytes.
    """
    cls = type(msg)
    made = _SNAPSHOT_CLASSES.get(cls)
    if made is None:
        made = _SNAPSHOT_CLASSES[cls] = _snapshot_class(cls)
    snap = _new(made[0])
    made[1](snap, data)
    return snap


#: Per message class: its snapshot class and the setter of the snapshot's wire bytes.
_SNAPSHOT_CLASSES: dict[type[Message], tuple[type[Message], Callable[[Message, bytes], None]]] = {}
_new = object.__new__
_WIRE = "_ddes_wire"


def _snapshot_class(cls: type[Message]) -> tuple[type[Message], Callable[[Message, bytes], None]]:
    """A subclass of ``cls`` whose instances hold wire bytes until a field is read or set.

    The first read or write of any attribute fills every field from the bytes
    (``cls._deserialize_from``), so it behaves as the message itself: equal to
    it, the same fields, ``__slots__``, ``_type``, name and canonical trace form.
    """
    meta: Any = type(cls)
    snap: type[Message] = meta(cls.__name__, (cls,), {
        "__slots__": (_WIRE,), "__module__": cls.__module__, "__qualname__": cls.__qualname__,
        "__doc__": cls.__doc__})
    wire = snap.__dict__[_WIRE]
    get_wire, drop_wire = wire.__get__, wire.__delete__
    fill = cls._deserialize_from
    set_attr, get_attr = object.__setattr__, object.__getattribute__

    def read(self: Message) -> None:
        try:
            data = get_wire(self, snap)
        except AttributeError:
            return  # read already (or a copy, which never held bytes)
        drop_wire(self)
        fill(self, data)

    def __getattr__(self: Message, name: str) -> object:
        read(self)
        return get_attr(self, name)

    def __setattr__(self: Message, name: str, value: object) -> None:
        read(self)
        set_attr(self, name, value)

    setattr(snap, "__getattr__", __getattr__)  # noqa: B010 - set on the class
    setattr(snap, "__setattr__", __setattr__)  # noqa: B010
    snap.__slots__ = cls.__slots__  # what equality, copies and the trace's encoder walk
    return snap, wire.__set__
