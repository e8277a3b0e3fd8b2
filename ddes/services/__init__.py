"""ROS services on simulated time: servers, clients, waits, and their error rules.

Quick start::

    AddTwoInts = get_service_class("rospy_tutorials/AddTwoInts")
    server = world.create_node("add_two_ints_server")
    Service(server, "add_two_ints", AddTwoInts, lambda req: req.a + req.b)

    client = world.create_node("client")

    def main():
        yield wait_for_service(client, "add_two_ints")
        add = ServiceProxy(client, "add_two_ints", AddTwoInts)
        resp = yield add(1, 2)          # resp.sum == 3, 0.4 ms later

    client.process(main())

* :mod:`ddes.services.convert`: rospy's handler-return rules and error texts;
* :mod:`ddes.services.server`: :class:`Service` and the serving model;
* :mod:`ddes.services.client`: :class:`ServiceProxy`, :class:`ServiceClient`,
  the call timeout extension;
* :mod:`ddes.services.transport`: the hops of a call and their latency;
* :mod:`ddes.services.network`: links and statistics, one
  :class:`ServiceNetwork` per world (:func:`network_of`; the ``ddes.World``
  facade's ``world.set_service_link`` and ``world.service_stats``);
* :mod:`ddes.services.waiting`: :func:`wait_for_service` as an event.

See docs/services.md.
"""

from ddes.errors import ServiceException, ServiceTimeout
from ddes.services.client import ServiceClient, ServiceProxy
from ddes.services.convert import convert_return_to_response
from ddes.services.network import (
    DEFAULT_SERVICE_LATENCY,
    ServiceNetwork,
    ServiceStats,
    ServiceStatsDict,
    network_of,
)
from ddes.services.server import Service
from ddes.services.waiting import wait_for_service

__all__ = [
    "DEFAULT_SERVICE_LATENCY",
    "Service",
    "ServiceClient",
    "ServiceException",
    "ServiceNetwork",
    "ServiceProxy",
    "ServiceStats",
    "ServiceStatsDict",
    "ServiceTimeout",
    "convert_return_to_response",
    "network_of",
    "wait_for_service",
]
