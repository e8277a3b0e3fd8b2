"""Service servers: ``Service(node, name, service_class, handler)`` (rospy.Service).

Serving model.  Requests are run through the server node's callback queue,
as roscpp does: with the default ``spinner="single"`` one request at a
time, in the order they arrive; a generator handler (``yield
node.sleep(0.5)``) takes simulated time and later requests wait behind it.
rospy instead runs one thread per incoming connection, so its handlers can
overlap; create the server node with ``spinner=N`` to serve up to N requests
at once.  ``spinner="manual"`` serves them from ``yield node.spin_once()``.

Handler styles:

* ``style="rospy"`` (default): ``handler(request)`` returns the response,
  converted by rospy's rules (:func:`~ddes.services.convert.convert_return_to_response`).
  ``raise ServiceException("x")`` gives the client
  ``"service cannot process request: x"``; any other exception gives
  ``"error processing request: x"`` and is logged (``Error processing request: x``)
  and traced (``service.exception``), or handed to ``error_handler(e,
  exc_type, exc_value, tb)`` if one is given.
* ``style="roscpp"``: ``handler(request, response) -> bool`` fills the
  response it is given.  ``False`` fails the call with an empty error text (a
  rospy client sees ``"service [X] responded with an error: "``, a roscpp
  :class:`~ddes.services.client.ServiceClient` gets False); an exception
  sends its text and logs ``Exception thrown while processing service call: x``.

A failing handler never takes the server down.  Advertising a name that is
already served raises ServiceException (``"service [X] already registered"``,
rospy's text); an illegal name raises ROSNameException.
"""

from __future__ import annotations

import sys
from collections.abc import Callable, Generator
from types import GeneratorType, TracebackType
from typing import TYPE_CHECKING, Any

from ddes.errors import DdesTypeError, DdesValueError, ServiceException
from ddes.graph.names import check_name
from ddes.services.convert import (
    ROSCPP_EXCEPTION_LOG,
    check_service_class,
    convert_return_to_response,
    roscpp_result,
    server_error_text,
)
from ddes.services.network import ServiceStats, network_of
from ddes.services.transport import PendingCall, ServiceConnection, serialize
from ddes.time.rospy_calls import REQUIRED, is_node_like, node_first

if TYPE_CHECKING:
    import simpy

    from ddes.graph.node import Node
    from ddes.kernel.events import Posted
    from ddes.msg.message import Message, ServiceDefinition
    from ddes.services.client import ServiceProxy

__all__ = ["ErrorHandler", "Handler", "LibraryService", "Service"]

#: A handler: ``handler(request)`` (rospy style) returns the response in any form
#: :func:`~ddes.services.convert.convert_return_to_response` takes;
#: ``handler(request, response) -> bool`` (roscpp style).  Either may be a generator.
Handler = Callable[..., object]
#: rospy's ``error_handler(e, exc_type, exc_value, tb)``.
ErrorHandler = Callable[[BaseException, type[BaseException], BaseException, TracebackType | None],
                        object]
#: The rest of a generator handler, run by the node's callback queue.
_Serving = Generator["simpy.Event", Any, None]

_REQUEST_KEYS = ("service", "call", "client")
_DISCARD_KEYS = ("service", "call", "client", "reason")
_EXCEPTION_KEYS = ("service", "call", "error")
_STYLES = ("rospy", "roscpp")


def check_service_name(name: object, what: str) -> str:
    """rospy's non-empty-string check, then ROS name legality (ROSNameException)."""
    if not isinstance(name, str) or not name:
        raise DdesValueError(f"{what}: service name is not a non-empty string, got {name!r}")
    return check_name(name, "service name")


class Service:
    """A service server on ``node`` (rospy.Service; roscpp ``advertiseService``).

    It registers with the world's master at once and serves until
    :meth:`shutdown` or until its node shuts down.
    """

    def __init__(
        self,
        node: Node,
        name: str,
        service_class: type[ServiceDefinition] = REQUIRED,
        handler: Handler = REQUIRED,
        buff_size: int = 65536,
        error_handler: ErrorHandler | None = None,
        *,
        style: str = "rospy",
    ) -> None:
        if not is_node_like(node):  # rospy's Service(name, service_class, handler): shifted
            node_first("Service", "srv = ", node, [name, service_class], {})
        node.check_alive("advertise a service")
        check_service_name(name, "Service")
        check_service_class(service_class, f"service {name!r}")
        if not callable(handler):
            raise DdesTypeError(f"service {name!r}: handler must be callable, got {handler!r}")
        if style not in _STYLES:
            raise DdesValueError(f"service {name!r}: style must be 'rospy' or 'roscpp', got {style!r}")
        self.node = node
        self.world = node.world
        self.resolved_name = node.resolve_name(name)
        self.service_class = service_class
        self.request_class: type[Message] = service_class._request_class
        self.response_class: type[Message] = service_class._response_class
        self.type: str = service_class._type
        self.md5sum: str = service_class._md5sum
        self.handler = handler
        self.error_handler = error_handler
        self.style = style
        self.buff_size = buff_size
        self._closed = False
        #: Open connections by id (closed with an error when the server goes away).
        self._conns: dict[int, ServiceConnection] = {}
        master = self.world.master
        existing = _claim(master, self.resolved_name, node)  # a library service gives way
        if existing is not None:
            by = "" if existing.node is node else f" by node [{existing.node.name}]"
            raise ServiceException(
                f"service [{self.resolved_name}] already registered{by}; shut the other server "
                "down first or choose another name"
            )
        net = network_of(self.world)
        #: The node's invented ROSRPC URI (``rosservice uri``).
        self.uri = net.uri_for(node)
        self._stats = net.stats_for(self.resolved_name)
        master.register_service(self.resolved_name, self.type, self.md5sum, node, self)
        node.add_entity(self)
        self.world.record("service.advertise", node.name, service=self.resolved_name,
                          type=self.type, style=style, uri=self.uri)
        net.notify_registered(self.resolved_name)

    # -- lifecycle ----------------------------------------------------------------------
    def shutdown(self, reason: str = "") -> None:
        """Stop serving: unregister, and close every connection (callers get an error)."""
        if self._closed:
            return
        self._closed = True
        self.world.master.unregister_service(self.resolved_name, self)
        self.node.remove_entity(self)
        # (a LibraryService's coming and going is no event of the world: it records nothing)
        self._record_unadvertise(reason)
        conns = list(self._conns.values())
        self._conns.clear()
        for conn in conns:
            conn.server_gone = True
            conn.closed = True
            for call in list(conn.proxy._pending.values()):
                if call.conn is conn and not call.responded and not call.done:
                    conn.proxy._transport_error(call)

    unregister = shutdown

    def spin(self) -> simpy.Event:
        """Event that fires when the node shuts down (rospy ``Service.spin``)."""
        return self.node.spin()

    # -- the connection handshake ---------------------------------------------------------
    def _accept(self, conn: ServiceConnection) -> str | None:
        """The error a new connection gets, or None when it is accepted."""
        error = self.refusal(conn.proxy)
        if error is None:
            self._conns[conn.id] = conn
        return error

    def refusal(self, proxy: ServiceProxy) -> str | None:
        """The error a new connection of ``proxy`` would get (rospy's texts), or None."""
        if self.node.is_shutdown():
            return "[Errno 111] Connection refused"
        if self._closed:
            return (f"remote error reported: [{self.node.name}] is not a provider of  "
                    f"[{proxy.resolved_name}]")
        md5 = proxy.service_class._md5sum
        if md5 != "*" and md5 != self.md5sum:
            return (f"remote error reported: request from [{proxy.node.name}]: md5sums do "
                    f"not match: [{md5}] vs. [{self.md5sum}]")
        return None

    # -- serving ---------------------------------------------------------------------------
    def _on_request(self, ev: Posted[tuple[ServiceConnection, PendingCall]]) -> None:
        """A request arrived (the client's hop): queue it on the node's callback queue."""
        conn, call = ev.payload
        if 0 <= call.gave_up_at < call.sent_at:
            return  # the client gave up before the request was sent
        if conn.server_gone:
            return
        world = self.world
        world.trace.append_row((world.env.now_ns, "service.request", self.node.name, _REQUEST_KEYS,
                                 self.resolved_name, call.id, conn.proxy.node.name))
        cls = self.request_class
        request = cls.__new__(cls)._deserialize_from(call.data)
        request._connection_header = conn.client_header  # as rospy sets it
        self.node.callbacks.invoke(self._serve, (conn, call, request), conn)

    def _serve(self, conn: ServiceConnection, call: PendingCall,
               request: Message) -> _Serving | None:
        """Run the handler on ``request`` and send back what it returns.

        A rospy-style handler returning at once to a client still listening takes
        the short way (its value converted by rospy's rules, serialized, sent: what
        :meth:`_finish` and :meth:`_send` do); a roscpp-style handler, a generator,
        and a client or server gone meanwhile go through :meth:`_finish`.
        """
        self._stats.served += 1
        response = None
        try:
            if self.style == "rospy":
                result = self.handler(request)
            else:
                response = self.response_class()
                result = self.handler(request, response)
        except Exception as exc:  # noqa: BLE001 - becomes the client's error
            self._handler_failed(conn, call, exc)
            return None
        if type(result) is GeneratorType:
            return self._serve_generator(conn, call, result, response)
        if response is not None or conn.server_gone or call.done:
            self._finish(conn, call, result, response)
            return None
        try:  # _finish for a rospy handler's value, inline
            msg = convert_return_to_response(result, self.response_class)
            try:
                data = msg._serialize_to_bytes()
            except Exception:  # noqa: BLE001 - serialize() raises the error that names the field
                data = serialize(msg)
        except ServiceException as exc:
            self._send(conn, call, False, server_error_text(exc, self.style))
            return None
        except Exception as exc:  # noqa: BLE001
            self._handler_failed(conn, call, exc)
            return None
        call.responded = True  # _send's steps, for a client still listening
        if not conn.persistent:
            conn.closed = True
            self._conns.pop(conn.id, None)
        conn.proxy._send_response(conn, call, True, data)
        return None

    def _serve_generator(self, conn: ServiceConnection, call: PendingCall,
                         gen: Generator[simpy.Event, Any, object], response: Message | None
                         ) -> _Serving:
        try:
            result = yield from gen
        except Exception as exc:  # noqa: BLE001 - becomes the client's error
            self._handler_failed(conn, call, exc)
            return
        self._finish(conn, call, result, response)

    def _handler_failed(self, conn: ServiceConnection, call: PendingCall, exc: Exception) -> None:
        if isinstance(exc, ServiceException) and self.style == "rospy":
            self._send(conn, call, False, server_error_text(exc, self.style))
            return
        world = self.world
        world.trace.append_row((world.env.now_ns, "service.exception", self.node.name,
                                 _EXCEPTION_KEYS, self.resolved_name, call.id,
                                 f"{type(exc).__name__}: {exc}"))
        if self.style == "roscpp":
            self.node.logerr(ROSCPP_EXCEPTION_LOG, str(exc))
        elif self.error_handler is not None:
            self.error_handler(exc, type(exc), exc, exc.__traceback__ or sys.exc_info()[2])
        else:
            self.node.logerr("Error processing request: %s", str(exc))
        self._send(conn, call, False, server_error_text(exc, self.style))

    def _send(self, conn: ServiceConnection, call: PendingCall, ok: bool,
              payload: bytes | str) -> None:
        """Send the response (bytes) or error text back, unless nobody is listening any more."""
        if conn.server_gone or call.done:
            reason = "server shut down" if conn.server_gone else "client gave up"
            call.stats.discarded += 1
            world = self.world
            world.trace.append_row((world.env.now_ns, "service.discard", self.node.name,
                                     _DISCARD_KEYS, self.resolved_name, call.id,
                                     conn.proxy.node.name, reason))
            return
        call.responded = True
        if not conn.persistent:
            conn.closed = True
            self._conns.pop(conn.id, None)
        conn.proxy._send_response(conn, call, ok, payload)

    def _finish(self, conn: ServiceConnection, call: PendingCall, result: object,
                response: Message | None) -> None:
        try:
            if response is None:
                msg = convert_return_to_response(result, self.response_class)
            else:
                if not roscpp_result(result):
                    self._send(conn, call, False, "")
                    return
                msg = response
            data = serialize(msg)
        except ServiceException as exc:
            if self.style == "roscpp":
                self._handler_failed(conn, call, exc)
            else:
                self._send(conn, call, False, server_error_text(exc, self.style))
            return
        except Exception as exc:  # noqa: BLE001
            self._handler_failed(conn, call, exc)
            return
        self._send(conn, call, True, data)

    def __repr__(self) -> str:
        state = "closed" if self._closed else "serving"
        return f"<Service {self.resolved_name} [{self.type}] on {self.node.name} {state}>"

    # Below the serving code on purpose: a log row names its source line, so lines added above
    # ``_handler_failed``'s logerr would change the digest of every world whose handler fails.
    def _record_unadvertise(self, reason: str) -> None:
        self.world.record("service.unadvertise", self.node.name, service=self.resolved_name,
                          reason=reason)


def _claim(master: Any, name: str, node: Node) -> Any:
    """The service registered under ``name``, after a :class:`LibraryService` of ``node`` there
    gave the name up (the node's own code advertises it: its server wins)."""
    existing = master.lookup_service(name)
    if existing is not None and existing.node is node and isinstance(existing.server,
                                                                      LibraryService):
        existing.server.shutdown("replaced by the node's own service")
        existing = master.lookup_service(name)
    return existing


class LibraryService(Service):
    """A service the client library itself offers on a node (roscpp's ``~get_loggers``,
    :mod:`ddes.services.loggers`): served as any :class:`Service` (``style`` as there), listed
    by the master, ``rosservice`` and ``rosnode info``, but not traced when it comes and goes,
    its URI and counters made when first asked for (so the URIs of the node's own services do
    not move), and a service the node's own code advertises under its name replaces it.
    """

    def __init__(self, node: Node, name: str, service_class: type[ServiceDefinition],
                 handler: Handler, *, style: str = "roscpp") -> None:
        node.check_alive("advertise a service")
        check_service_name(name, "Service")
        check_service_class(service_class, f"service {name!r}")
        if style not in _STYLES:
            raise DdesValueError(f"service {name!r}: style must be 'rospy' or 'roscpp', got {style!r}")
        self.node = node
        self.world = node.world
        self.resolved_name = node.resolve_name(name)
        self.service_class = service_class
        self.request_class = service_class._request_class
        self.response_class = service_class._response_class
        self.type = service_class._type
        self.md5sum = service_class._md5sum
        self.handler = handler
        self.error_handler = None
        self.style = style
        self.buff_size = 65536
        self._closed = False
        self._conns = {}
        self._lazy_uri: str | None = None
        self._lazy_stats: ServiceStats | None = None
        master = self.world.master
        existing = master.lookup_service(self.resolved_name)
        if existing is not None:
            raise ServiceException(f"service [{self.resolved_name}] already registered by node "
                                   f"[{existing.node.name}]")
        master.register_service(self.resolved_name, self.type, self.md5sum, node, self)
        node.add_entity(self)
        network_of(self.world).notify_registered(self.resolved_name)

    @property
    def uri(self) -> str:
        """The node's ROSRPC URI, handed out when first asked for (``rosservice uri``)."""
        if self._lazy_uri is None:
            self._lazy_uri = network_of(self.world).uri_for(self.node)
        return self._lazy_uri

    @uri.setter
    def uri(self, value: str) -> None:
        self._lazy_uri = value

    @property
    def _stats(self) -> ServiceStats:
        if self._lazy_stats is None:
            self._lazy_stats = network_of(self.world).stats_for(self.resolved_name)
        return self._lazy_stats

    @_stats.setter
    def _stats(self, value: ServiceStats) -> None:
        self._lazy_stats = value

    def _record_unadvertise(self, reason: str) -> None:
        pass  # a library service's coming and going is no event of the world
