"""The facade: ``ddes.World``, ``ddes.Node`` and ``ddes.Console`` with every room attached.

The graph's :class:`~ddes.graph.world.World` and :class:`~ddes.graph.node.Node`
know topics, timers, parameters and logging only; services, actionlib, bags
and TF live in rooms above the graph and keep their per-world state in the
kernel's extension slots.  The facade classes here add the conveniences that
span rooms — ``world.set_service_link``, ``world.service_stats``,
``node.advertise_service`` — so a notebook cell needs one ``import ddes``.
Everything below the facade takes a graph ``World``/``Node``, so a facade
object can go anywhere.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import TYPE_CHECKING, Any, TypedDict

from ddes.console.shell import Console as _Console
from ddes.graph.node import Node as _Node
from ddes.graph.world import World as _World
from ddes.msg.message import ServiceDefinition
from ddes.services.network import DEFAULT_SERVICE_LATENCY, ServiceNetwork, network_of
from ddes.services.server import Service

if TYPE_CHECKING:
    from typing_extensions import Unpack

    from ddes.graph.topics import LinkLatency

__all__ = ["Console", "Node", "ServiceOptions", "World"]


class ServiceOptions(TypedDict, total=False):
    """The keyword arguments ``node.advertise_service(...)`` passes on to :class:`ddes.Service`."""

    buff_size: int
    error_handler: Callable[..., object] | None
    style: str


class Node(_Node):
    """A ROS node (:class:`ddes.graph.node.Node`) with the roscpp-style service aliases."""

    def advertise_service(self, name: str, service_class: type[ServiceDefinition],
                          handler: Callable[..., object],
                          **kwargs: Unpack[ServiceOptions]) -> Service:
        """roscpp's ``advertiseService``: the same as ``ddes.Service(node, name, ...)``.

        ``style="roscpp"`` for ``handler(req, resp) -> bool`` callbacks.
        """
        return Service(self, name, service_class, handler, **kwargs)

    create_service = advertise_service


class World(_World):
    """A deterministic ROS world (:class:`ddes.graph.world.World`) with every room attached."""

    node_class = Node

    # -- services (ddes.services) -------------------------------------------------------------
    @property
    def service_network(self) -> ServiceNetwork:
        """Service links, statistics and waiters (:class:`ddes.services.ServiceNetwork`)."""
        return network_of(self)

    def set_service_link(self, service: str | None = None, *, client: str | None = None,
                         latency: LinkLatency = DEFAULT_SERVICE_LATENCY) -> None:
        """Set the one-way latency of service messages (default 0.1 ms; see ddes.services.network)."""
        network_of(self).set_link(service, client=client, latency=latency)

    def service_stats(self, service: str) -> dict[str, Any]:
        """Calls, successes, failures by reason, discards and latency of ``service``."""
        return network_of(self).stats(service)


class Console(_Console):
    """A console session (:class:`ddes.console.Console`) on a ``ddes.World``."""

    world_class = World
