"""Service transport of one world: links, connections, waiters, URIs and statistics.

ROS services run over TCPROS.  ddes models each one-way message (a
connection header, a request, a response, a closing connection) as one
kernel event delayed by the link latency, drawn per message:

* the default latency is :data:`DEFAULT_SERVICE_LATENCY` (0.1 ms, the order
  of a loopback TCP message);
* ``world.set_service_link("/add_two_ints", client="/client", latency=...)``
  changes it for matching calls (seconds, a Duration, or ``f(rng)`` drawn per
  message from a stream seeded by the world seed, the service and the client
  node); the most specific rule wins, later rules win ties.

The :class:`ServiceNetwork` hangs off the world (``world.service_network``)
and holds everything services share: no module-level state.
"""

from __future__ import annotations

import functools
import itertools
import random
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, TypedDict

from ddes.errors import DdesTypeError, DdesValueError, ROSServiceException
from ddes.graph.topics import LinkLatency, LinkModel, link_latency_ns
from ddes.time.units import DurationLike

if TYPE_CHECKING:
    from ddes.graph.node import Node
    from ddes.graph.world import World

__all__ = [
    "DEFAULT_SERVICE_LATENCY",
    "ERROR_KINDS",
    "ServiceLink",
    "ServiceNetwork",
    "ServiceStats",
    "ServiceStatsDict",
    "network_of",
]

#: One-way latency of every service message unless a link rule says otherwise (seconds).
DEFAULT_SERVICE_LATENCY = 0.0001
#: First port of the invented ``rosrpc://`` URIs (one port per node that serves).
_FIRST_PORT = 40000

#: Why a call failed, as counted in :meth:`ServiceNetwork.stats` and traced as ``reason``.
ERROR_KINDS = ("unavailable", "connect", "server", "transport", "closed", "timeout", "interrupted")


class ServiceLink:
    """The latency of one (service, client) pair; ``sample_ns()`` gives the next one.

    A drawn latency (``f(rng)``) needs ``rng``, the pair's own seeded stream.
    """

    __slots__ = ("_fixed_ns", "_draw", "sample_ns")

    def __init__(self, latency: LinkLatency, rng: random.Random | None) -> None:
        self._draw: Callable[[], DurationLike] | None = None
        self._fixed_ns = 0
        #: ``sample_ns()``: the latency of the next one-way message (integer ns).  A fixed
        #: latency is ``itertools.repeat(ns).__next__``, which calls no Python code.
        self.sample_ns: Callable[[], int]
        if callable(latency):
            if rng is None:
                raise DdesValueError("a drawn latency f(rng) needs the link's random stream")
            self._draw = functools.partial(latency, rng)
            self.sample_ns = self._sample_drawn
        else:
            self._fixed_ns = link_latency_ns(latency)
            self.sample_ns = itertools.repeat(self._fixed_ns).__next__

    def _sample_drawn(self) -> int:
        assert self._draw is not None
        return link_latency_ns(self._draw())


class ServiceStatsDict(TypedDict):
    """What :meth:`ServiceNetwork.stats` (``world.service_stats``) returns.

    The round-trip latencies of the successful calls are in nanoseconds
    (None before the first success).
    """

    service: str
    calls: int
    succeeded: int
    failed: int
    in_flight: int
    errors: dict[str, int]
    served: int
    discarded: int
    latency_min_ns: int | None
    latency_max_ns: int | None
    latency_mean_ns: float | None


@dataclass
class ServiceStats:
    """Counters of one service name (calls to it, whoever serves it)."""

    name: str
    calls: int = 0
    succeeded: int = 0
    served: int = 0
    discarded: int = 0
    errors: dict[str, int] = field(default_factory=lambda: dict.fromkeys(ERROR_KINDS, 0))
    latency_min_ns: int | None = None
    latency_max_ns: int | None = None
    latency_total_ns: int = 0

    def add_latency(self, latency_ns: int) -> None:
        """A call succeeded after ``latency_ns`` (round trip)."""
        self.succeeded += 1
        self.latency_total_ns += latency_ns
        if self.latency_min_ns is None or latency_ns < self.latency_min_ns:
            self.latency_min_ns = latency_ns
        if self.latency_max_ns is None or latency_ns > self.latency_max_ns:
            self.latency_max_ns = latency_ns

    def as_dict(self) -> ServiceStatsDict:
        failed = sum(self.errors.values())
        return {
            "service": self.name,
            "calls": self.calls,
            "succeeded": self.succeeded,
            "failed": failed,
            "in_flight": self.calls - self.succeeded - failed,
            "errors": dict(self.errors),
            "served": self.served,
            "discarded": self.discarded,
            "latency_min_ns": self.latency_min_ns,
            "latency_max_ns": self.latency_max_ns,
            "latency_mean_ns": (self.latency_total_ns / self.succeeded if self.succeeded
                                else None),
        }


def network_of(world: World) -> ServiceNetwork:
    """The :class:`ServiceNetwork` of ``world`` (kept in its ``"services"`` extension slot)."""
    return world.extension("services", ServiceNetwork)


class ServiceNetwork:
    """Links, statistics, waiters and URIs of the services of one world."""

    def __init__(self, world: World) -> None:
        self.world = world
        self._rules: list[tuple[tuple[str | None, str | None], LinkLatency]] = []
        self._links: dict[tuple[str, str], ServiceLink] = {}
        self._stats: dict[str, ServiceStats] = {}
        self._waiters: dict[str, list[Callable[[], object]]] = {}
        self._uris: dict[str, tuple[Node, str]] = {}

    # -- links ------------------------------------------------------------------------------
    def set_link(self, service: str | None = None, *, client: str | None = None,
                 latency: LinkLatency = DEFAULT_SERVICE_LATENCY) -> None:
        """Set the one-way latency of calls to ``service`` from node ``client``.

        None matches any service / any client.  Applies to messages sent from
        now on; the most specific rule wins (service counts more than
        client), later rules win ties.
        """
        for value, what in ((service, "service"), (client, "client")):
            if value is not None and not isinstance(value, str):
                raise DdesTypeError(f"set_service_link: {what} must be a name or None, got {value!r}")
        LinkModel(latency)  # validates a fixed latency now
        self._rules.append(((service, client), latency))
        self._links.clear()

    def link(self, service: str, client: str) -> ServiceLink:
        """The link of calls to ``service`` from node ``client``."""
        key = (service, client)
        link = self._links.get(key)
        if link is None:
            latency: LinkLatency = DEFAULT_SERVICE_LATENCY
            best = -1
            for (srv, cli), lat in self._rules:
                if (srv is not None and srv != service) or (cli is not None and cli != client):
                    continue
                score = (srv is not None) * 2 + (cli is not None)
                if score >= best:
                    latency, best = lat, score
            rng = self.world.rng_for(f"service-link:{service}:{client}") if callable(latency) else None
            link = ServiceLink(latency, rng)
            self._links[key] = link
        return link

    # -- statistics -----------------------------------------------------------------------
    def stats_for(self, service: str) -> ServiceStats:
        """The (live) counters of ``service``, created on first use."""
        st = self._stats.get(service)
        if st is None:
            st = self._stats[service] = ServiceStats(service)
        return st

    def stats(self, service: str) -> dict[str, object]:
        """Counters of ``service``: calls, succeeded, failed (by reason), served, discarded,
        in flight, and the round-trip latency of successful calls (min/max/mean, ns): a
        :class:`ServiceStatsDict` (typed as a plain dict, as ``ddes.World.service_stats``)."""
        st = self._stats.get(service)
        if st is None:
            raise ROSServiceException(
                f"no statistics for service [{service}]: it was never advertised or called "
                f"(known: {', '.join(self._stats) or 'none'}); use the resolved name, e.g. "
                "'/add_two_ints'"
            )
        return dict(st.as_dict())

    def service_names(self) -> list[str]:
        """Every service name advertised or called so far, in first-seen order."""
        return list(self._stats)

    # -- waiting for a registration ---------------------------------------------------------
    def add_waiter(self, service: str, fn: Callable[[], object]) -> None:
        """Call ``fn()`` once, when ``service`` is next registered."""
        self._waiters.setdefault(service, []).append(fn)

    def remove_waiter(self, service: str, fn: Callable[[], object]) -> None:
        waiters = self._waiters.get(service)
        if waiters and fn in waiters:
            waiters.remove(fn)
            if not waiters:
                del self._waiters[service]

    def notify_registered(self, service: str) -> None:
        """Wake every waiter of ``service`` (in the order they started waiting)."""
        for fn in self._waiters.pop(service, []):
            fn()

    # -- URIs -------------------------------------------------------------------------------
    def uri_for(self, node: Node) -> str:
        """The node's invented ROSRPC URI: ``rosrpc://localhost:<port>``.

        Ports are handed out from 40000 in the order nodes first serve, so a
        scenario always shows the same URIs; a restarted node gets a new one.
        """
        known = self._uris.get(node.name)
        if known is not None and known[0] is node:
            return known[1]
        uri = f"rosrpc://localhost:{_FIRST_PORT + self.world.next_id('rosrpc') - 1}"
        self._uris[node.name] = (node, uri)
        return uri
