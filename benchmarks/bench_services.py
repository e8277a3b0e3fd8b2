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

The fair baselines are the same Store model plus exactly the work the ROS
semantics require: build and serialize the request, deserialize it on the
server, build and serialize the response, deserialize it on the client, and
the three trace rows (``service.call``, ``service.request``,
``service.response``); for a new connection also the header round trip (two
more hops).  ddes's trace rows also hold an independent copy of the request
and response (one more deserialization each); the fair baseline does not.
"""

from __future__ import annotations

import sys
from pathlib import Path
from typing import Any

import simpy

sys.path.insert(0, str(Path(__file__).resolve().parent))

from common import compare, result, size  # noqa: E402

import ddes  # noqa: E402
from ddes.kernel.trace import Trace  # noqa: E402
from ddes.msg import get_service_class  # noqa: E402
from ddes.services import Service, ServiceProxy  # noqa: E402

N = size(10_000)
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


Request, Response = AddTwoInts._request_class, AddTwoInts._response_class


def fair(persistent: bool) -> Any:
    def run() -> int:
        env = simpy.Environment()
        store: simpy.Store = simpy.Store(env)
        trace = Trace()
        append = trace.append_row
        call_keys, req_keys = ("service", "call", "persistent", "request"), ("service", "call", "client")
        resp_keys = ("service", "call", "latency", "response")
        done = [0]

        def server() -> Any:
            while True:
                call, data, reply = yield store.get()
                req = Request.__new__(Request)._deserialize_from(data)
                append((env.now, "service.request", "/add_two_ints_server", req_keys,
                        "/add_two_ints", call, "/client"))
                out = Response(sum=req.a + req.b)._serialize_to_bytes()
                yield env.timeout(LATENCY_NS)
                reply.succeed(out)

        def client() -> Any:
            for i in range(N):
                t0 = env.now
                data = Request(a=i, b=1)._serialize_to_bytes()
                append((t0, "service.call", "/client", call_keys, "/add_two_ints", i, persistent,
                        None))
                if not persistent:  # the header exchange: client -> server -> client
                    yield env.timeout(LATENCY_NS)
                    yield env.timeout(LATENCY_NS)
                reply = env.event()
                yield env.timeout(LATENCY_NS)
                yield store.put((i, data, reply))
                out = yield reply
                resp = Response.__new__(Response)._deserialize_from(out)
                append((env.now, "service.response", "/client", resp_keys, "/add_two_ints", i,
                        env.now - t0, None))
                if resp.sum == i + 1:
                    done[0] += 1

        env.process(server())
        env.process(client())
        env.run()
        return done[0]

    return run


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
    persistent = compare(ddes_calls(True), raw_simpy, fair_fn=fair(True))
    plain = compare(ddes_calls(False), raw_simpy, fair_fn=fair(False))
    return [
        result("service_round_trips_persistent", persistent, "calls/s",
               "simpy Store request + reply event",
               "+ (de)serialize request and response, 3 trace rows", n=N),
        result("service_round_trips", plain, "calls/s", "simpy Store request + reply event",
               "+ (de)serialize request and response, 3 trace rows, header round trip", n=N),
    ]


if __name__ == "__main__":
    for r in benchmarks():
        print(r)
