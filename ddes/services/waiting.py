"""``wait_for_service`` as an event on the node's ROS time.

rospy polls the master and probes the server every 0.3 s of *wall* time and
measures its timeout on the wall clock; roscpp polls every 20 ms.  ddes
needs no polling: the event fires at the very instant the service is
registered (or at once if it already is), and the timeout runs on the
node's ROS time, so it lands on an exact simulated instant.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from ddes.errors import DdesValueError, ROSException, ROSInterruptException
from ddes.services.network import network_of
from ddes.services.server import check_service_name
from ddes.time.rospy_calls import REQUIRED, is_node_like, node_first
from ddes.time.sleep import must_yield
from ddes.time.units import DurationLike, duration_to_ns

if TYPE_CHECKING:
    import simpy

    from ddes.graph.node import Node

__all__ = ["check_nonzero_timeout", "wait_for_service", "wait_for_service_ns"]


def check_nonzero_timeout(timeout_ns: int | None) -> int | None:
    """``timeout_ns`` unchanged, unless it is 0: rospy's ``ValueError("timeout must be
    non-zero")`` (None, no timeout, is fine)."""
    if timeout_ns == 0:
        raise DdesValueError("timeout must be non-zero")
    return timeout_ns


class _Waiter:
    """One pending wait; a node entity so that shutdown interrupts it."""

    __slots__ = ("node", "name", "event")

    def __init__(self, node: Node, name: str, event: simpy.Event) -> None:
        self.node = node
        self.name = name
        self.event = event

    def registered(self) -> None:
        if not self.event.triggered:
            self.node.remove_entity(self)
            self.event.succeed(None)

    def expire(self, _ev: simpy.Event | None = None) -> None:
        if not self.event.triggered:
            self._stop()
            self.event.fail(ROSException(f"timeout exceeded while waiting for service {self.name}"))

    def shutdown(self) -> None:
        if not self.event.triggered:
            self._stop()
            self.event.fail(ROSInterruptException("rospy shutdown"))

    def _stop(self) -> None:
        self.node.remove_entity(self)
        network_of(self.node.world).remove_waiter(self.name, self.registered)


def wait_for_service(node: Node, service: str = REQUIRED,
                     timeout: DurationLike | None = None) -> simpy.Event:
    """Event that fires once ``service`` is available (rospy.wait_for_service).

    ``service`` is resolved with ``node``'s namespace and remappings.
    ``timeout`` (seconds or Duration, ROS time of ``node``) makes the event
    fail with ``ROSException("timeout exceeded while waiting for service
    /name")``; ``timeout=0`` raises ValueError at once, as rospy; a negative
    timeout fails at once (rospy's loop never runs).  If the node shuts down
    first the event fails with ``ROSInterruptException("rospy shutdown")``.
    """
    if not is_node_like(node):  # rospy's wait_for_service(service, timeout): shifted
        node_first("wait_for_service", "yield ", node, [],
                   {"timeout": service} if service is not REQUIRED else
                   ({} if timeout is None else {"timeout": timeout}),
                   "(in the node's process)")
    check_service_name(service, "wait_for_service")
    timeout_ns = None if timeout is None else duration_to_ns(timeout, "timeout")
    check_nonzero_timeout(timeout_ns)
    node.check_alive("wait for a service")
    return must_yield(wait_for_service_ns(node, node.resolve_name(service), timeout_ns),
                      "wait_for_service(...)")


def wait_for_service_ns(node: Node, name: str, timeout_ns: int | None) -> simpy.Event:
    """:func:`wait_for_service` for a resolved ``name`` and a timeout in int ns (None: for
    ever)."""
    world = node.world
    event = world.env.event()
    waiter = _Waiter(node, name, event)
    if timeout_ns is not None and timeout_ns < 0:
        waiter.expire()
        return event
    if world.master.lookup_service(name) is not None:
        event.succeed(None)
        return event
    node.add_entity(waiter)
    network_of(world).add_waiter(name, waiter.registered)
    if timeout_ns is not None:
        clock = node.clock
        clock.wait_until(clock.now_ns() + timeout_ns).callbacks.append(waiter.expire)
    return event
