"""Property tests: random request streams against a model of the serving rules.

Model of a call on a new connection with one-way latency ``L``: the request
reaches the server ``3L`` after the call; the server node's callback queue
serves requests in arrival order with ``spinner`` workers (FIFO multi-server:
a request starts when it has arrived and a worker is free); the response
arrives ``L`` after the handler ends.
"""

from __future__ import annotations

from collections.abc import Generator
from typing import Any

from hypothesis import given, settings
from hypothesis import strategies as st

import ddes
from ddes.errors import ServiceTimeout
from ddes.msg import get_service_class
from ddes.services import Service, ServiceProxy

AddTwoInts = get_service_class("rospy_tutorials/AddTwoInts")
MS = 1_000_000

calls_st = st.lists(
    st.tuples(st.integers(0, 3),            # client index
              st.integers(0, 20),           # issue time (ms; ties are likely)
              st.integers(0, 8)),           # handler duration (ms; 0 = no yield at all)
    min_size=1, max_size=25)


def _server(world: ddes.World, spinner: int | str) -> list[int]:
    """A server whose handler sleeps ``req.b`` ms and returns ``req.a``; returns the start order."""
    server = world.create_node("server", spinner=spinner)
    starts: list[int] = []

    def handler(req: Any) -> Generator[Any, Any, Any]:
        starts.append(req.a)
        if req.b:
            yield server.sleep(ddes.Duration(0, req.b * MS))
        return req.a

    Service(server, "s", AddTwoInts, handler)
    return starts


@settings(max_examples=60, deadline=None)
@given(calls=calls_st, workers=st.integers(1, 3), latency_us=st.sampled_from([0, 50, 100, 1000]))
def test_every_call_gets_exactly_one_reply_when_the_model_says(
        calls: list[tuple[int, int, int]], workers: int, latency_us: int) -> None:
    world = ddes.World(0)
    lat = latency_us * 1000
    world.set_service_link(latency=ddes.Duration(0, lat))
    starts = _server(world, "single" if workers == 1 else workers)
    clients = [world.create_node(f"client{k}") for k in range(4)]
    proxies = [ServiceProxy(c, "s", AddTwoInts) for c in clients]
    replies: dict[int, list[int]] = {}

    def one(i: int, client: int, t_ms: int, d_ms: int) -> Generator[Any, Any, None]:
        yield world.timeout(ddes.Duration(0, t_ms * MS))
        resp = yield proxies[client](i, d_ms)
        replies.setdefault(resp.sum, []).append(world.now)

    for i, (client, t_ms, d_ms) in enumerate(calls):
        clients[client].process(one(i, client, t_ms, d_ms))
    world.run()

    # model: arrival order is issue order (same latency for all), ties by index
    order = sorted(range(len(calls)), key=lambda i: (calls[i][1], i))
    free = [0] * workers
    expected: dict[int, list[int]] = {}
    for i in order:
        arrival = calls[i][1] * MS + 3 * lat
        w = min(range(workers), key=lambda k: free[k])
        start = max(arrival, free[w])
        free[w] = start + calls[i][2] * MS
        expected[i] = [free[w] + lat]
    assert replies == expected
    # handlers start in arrival order (FIFO), one response per call in the trace
    assert starts == order
    responses = [e.details["call"] for e in world.trace.filter(kind="service.response")]
    assert sorted(responses) == list(range(1, len(calls) + 1))
    stats = world.service_stats("/s")
    assert (stats["calls"], stats["succeeded"], stats["failed"], stats["served"]) == (
        len(calls), len(calls), 0, len(calls))


@settings(max_examples=80, deadline=None)
@given(steps=st.lists(st.tuples(st.integers(0, 3), st.integers(0, 6)), min_size=1, max_size=12),
       timeout_ns=st.sampled_from([50_000, 100_000, 199_999, 200_000, 300_000, 400_000, 400_001,
                                   1 * MS, 2 * MS, 3_500_000, 7 * MS]))
def test_timeouts_against_a_sequential_model(steps: list[tuple[int, int]], timeout_ns: int) -> None:
    """One client calls in sequence with a call timeout; abandoned requests still occupy the server."""
    lat = 100_000
    world = ddes.World(0)
    _server(world, "single")
    client = world.create_node("client")
    proxy = ServiceProxy(client, "s", AddTwoInts, timeout=ddes.Duration(0, timeout_ns))
    seen: list[tuple[str, int]] = []

    def main() -> Generator[Any, Any, None]:
        for i, (think_ms, d_ms) in enumerate(steps):
            yield world.timeout(ddes.Duration(0, think_ms * MS))
            try:
                resp = yield proxy(i, d_ms)
                seen.append(("ok", world.now))
                assert resp.sum == i
            except ServiceTimeout:
                seen.append(("timeout", world.now))

    client.process(main())
    world.run()

    t = free = 0
    model: list[tuple[str, int]] = []
    discarded = served = 0
    for think_ms, d_ms in steps:
        t += think_ms * MS
        reply = None
        if timeout_ns >= 2 * lat:  # the request left before the client gave up
            served += 1
            start = max(t + 3 * lat, free)
            free = start + d_ms * MS
            reply = free + lat
        if reply is not None and reply < t + timeout_ns:
            model.append(("ok", reply))
            t = reply
        else:
            model.append(("timeout", t + timeout_ns))
            t += timeout_ns
            discarded += reply is not None
    assert seen == model
    stats = world.service_stats("/s")
    assert (stats["served"], stats["discarded"]) == (served, discarded)
    assert stats["errors"]["timeout"] == sum(1 for kind, _ in model if kind == "timeout")
