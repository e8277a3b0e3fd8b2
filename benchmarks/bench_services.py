"""Service round trips per second against a raw SimPy request/reply model.

The baseline is what a hand-written SimPy model of a service does: the
client puts a request into a ``simpy.Store`` after the request latency, the
server process takes it, computes the sum and triggers the request's reply
event after the response latency; the client waits on that event.

ddes does, per call: build the request from the arguments (rospy rules),
serialize it, trace the call, look the service up, schedule the hops
(header exchange on a new connection; request; response), deserialize on
each side, run the handler through the server node's callback queue,
convert its return value by rospy's rules, and trace the request and the
response.  Two ddes figures: a persistent proxy (request + response hops,
the same work as the baseline) and a plain proxy (plus the header exchange,
one more round trip per call, as TCPROS does).
"""

from __future__ import annotations

import sys
from pathlib import Path
from typing import Any

import simpy

sys.path.insert(0, str(Path(__file__).resolve().parent))

from common import compare, row  # noqa: E402

import ddes  # noqa: E402
from ddes.msg import get_service_class  # noqa: E402
from ddes.services import Service, ServiceProxy  # noqa: E402

N = 10_000
LATENCY_NS = 100_000
AddTwoInts = get_service_class("rospy_tutorials/AddTwoInts")


def raw_simpy() -> int:
    env = simpy.Environment()
    store: simpy.Store = simpy.Store(env)
    done = [0]

    def server() -> Any:
        while True:
            a, b, reply = yield store.get()
            yield env.timeout(LATENCY_NS)
            reply.succeed(a + b)

    def client() -> Any:
        for i in range(N):
            reply = env.event()
            yield env.timeout(LATENCY_NS)
            yield store.put((i, 1, reply))
            total = yield reply
            if total == i + 1:
                done[0] += 1

    env.process(server())
    env.process(client())
    env.run()
    return done[0]


def ddes_calls(persistent: bool) -> Any:
    def run() -> int:
        world = ddes.World()
        server = world.create_node("add_two_ints_server", disable_rosout=True)
        Service(server, "add_two_ints", AddTwoInts, lambda req: req.a + req.b)
        client = world.create_node("client", disable_rosout=True)
        proxy = ServiceProxy(client, "add_two_ints", AddTwoInts, persistent=persistent)
        done = [0]

        def loop() -> Any:
            for i in range(N):
                resp = yield proxy(i, 1)
                if resp.sum == i + 1:
                    done[0] += 1

        client.process(loop())
        world.run()
        return done[0]

    return run


def benchmarks() -> list[dict[str, Any]]:
    persistent, base = compare(ddes_calls(True), raw_simpy)
    plain, base2 = compare(ddes_calls(False), raw_simpy)
    return [
        row("service_round_trips_persistent", persistent, "calls/s", base,
            "simpy Store request + reply event", n=N),
        row("service_round_trips", plain, "calls/s", base2,
            "simpy Store request + reply event", n=N),
    ]


if __name__ == "__main__":
    for r in benchmarks():
        print(r)
