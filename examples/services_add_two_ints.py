"""Lecture 4, services: the add_two_ints server and client, on simulated time.

Run it with ``python examples/services_add_two_ints.py``.  Everything below
happens in one deterministic world:

1. a roscpp-style server (``handler(req, res) -> bool``) logs as the C++
   tutorial does;
2. a rospy client waits for the service (an event: it wakes at the very
   instant the server registers), calls it three ways, and prints the
   round-trip times: 0.4 ms on a new connection, 0.2 ms on a persistent one
   (the default one-way latency is 0.1 ms);
3. a call to a missing service shows rospy's error text;
4. a slow handler and a call timeout (a ddes extension) show that the
   server keeps working and its late response is discarded;
5. the console tools print what ``rosservice`` and ``rossrv`` print.
"""

from __future__ import annotations

from collections.abc import Generator
from typing import Any

import ddes
from ddes.console.tooling import run_command
from ddes.msg import get_service_class
from ddes.services import Service, ServiceException, ServiceProxy, ServiceTimeout, wait_for_service


def main() -> None:
    world = ddes.World(seed=0)
    world.log_output = lambda line, level: print(line)
    two_ints = get_service_class("roscpp_tutorials/TwoInts")

    server = world.create_node("add_two_ints_server", log_style="roscpp")

    def add(req: Any, res: Any) -> Generator[Any, Any, bool]:
        if req.a == 99:  # a slow request, for the timeout below
            yield server.sleep(2.0)
        res.sum = req.a + req.b
        server.loginfo("request: x=%ld, y=%ld", req.a, req.b)
        server.loginfo("  sending back response: [%ld]", res.sum)
        return True

    # the server starts half a second after the client
    world.call_at(500_000_000, lambda: Service(server, "add_two_ints", two_ints, add,
                                               style="roscpp"))

    client = world.create_node("add_two_ints_client")

    def run_client() -> Generator[Any, Any, None]:
        yield wait_for_service(client, "add_two_ints")
        print(f"t={world.now / 1e9:.6f} s: add_two_ints is available")
        add_two_ints = ServiceProxy(client, "add_two_ints", two_ints)
        for args, kwds in (((10, 5), {}), ((), {"a": 1, "b": 2}),
                           ((two_ints._request_class(3, 4),), {})):
            t0 = world.now
            resp = yield add_two_ints(*args, **kwds)
            print(f"Sum: {resp.sum}  (round trip {(world.now - t0) / 1e6:.1f} ms)")

        persistent = ServiceProxy(client, "add_two_ints", two_ints, persistent=True)
        for i in range(2):
            t0 = world.now
            resp = yield persistent(i, i)
            print(f"persistent call {i}: Sum: {resp.sum}  (round trip {(world.now - t0) / 1e6:.1f} ms)")

        try:
            yield ServiceProxy(client, "no_such_service", two_ints)(1, 2)
        except ServiceException as exc:
            print(f"Service call failed: {exc}")

        try:
            yield add_two_ints.call(99, 1, timeout=0.5)
        except ServiceTimeout as exc:
            print(f"t={world.now / 1e9:.6f} s: {exc}")

    client.process(run_client())
    world.run(until=5.0)

    for line in ("rosservice list", "rosservice info /add_two_ints",
                 "rossrv show roscpp_tutorials/TwoInts", "rosservice call /add_two_ints 20 22"):
        print(f"$ {line}")
        print(run_command(world, line), end="")

    stats = world.service_stats("/add_two_ints")
    print(f"/add_two_ints: {stats['calls']} calls, {stats['succeeded']} answered, "
          f"{stats['errors']['timeout']} timed out, {stats['discarded']} late response discarded")
    print(f"trace digest: {world.digest()}")


if __name__ == "__main__":
    main()
