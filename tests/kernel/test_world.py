"""World: integer-ns kernel, run/until, same-time order, RNG streams, isolation."""

from __future__ import annotations

from collections.abc import Generator
from typing import Any

import pytest

import ddes
from ddes.errors import DdesError, WorldError


def test_now_is_integer_nanoseconds(world: ddes.World) -> None:
    def proc() -> Generator[Any, Any, None]:
        yield world.timeout(0.1)
        yield world.timeout(ddes.Duration(0, 3))
        yield world.timeout(1)

    world.process(proc())
    world.run()
    assert world.now == 1_100_000_003 and type(world.now) is int
    assert world.time() == ddes.Time(1, 100_000_003)


def test_run_until_time_duration_and_seconds(world: ddes.World) -> None:
    world.run(until=ddes.Time(1))
    assert world.now == 1_000_000_000
    world.run(until=ddes.Duration(0, 500))
    assert world.now == 1_000_000_500
    world.run(until=2.5)
    assert world.now == 2_500_000_000
    world.run_for(0.5)
    assert world.now == 3_000_000_000
    with pytest.raises(WorldError, match="already at"):
        world.run(until=1)
    with pytest.raises(DdesError):
        world.run(until="soon")


def test_run_until_excludes_events_at_the_instant(world: ddes.World) -> None:
    seen: list[int] = []
    world.call_at(1_000_000_000, lambda: seen.append(world.now))
    world.run(until=1)
    assert seen == []
    world.run(until=2)
    assert seen == [1_000_000_000]


def test_same_time_events_fire_in_scheduling_order(world: ddes.World) -> None:
    order: list[str] = []
    for name in ["c", "a", "b"]:
        world.call_at(5, lambda n=name: order.append(n))  # type: ignore[misc]

    def proc(tag: str) -> Generator[Any, Any, None]:
        yield world.timeout(ddes.Duration(0, 5))
        order.append(tag)

    world.process(proc("p1"))
    world.process(proc("p2"))
    world.run()
    assert order == ["c", "a", "b", "p1", "p2"]


def test_negative_delay_and_past_call_rejected(world: ddes.World) -> None:
    with pytest.raises(ddes.errors.DdesValueError, match="negative delay"):
        world.timeout(-0.1)
    world.run(until=1)
    with pytest.raises(WorldError, match="in the past"):
        world.call_at(5, lambda: None)


def test_rng_is_seeded_and_streams_are_independent() -> None:
    a, b = ddes.World(seed=7), ddes.World(seed=7)
    assert [a.rng.random() for _ in range(5)] == [b.rng.random() for _ in range(5)]
    assert a.rng_for("link").random() == b.rng_for("link").random()
    assert a.rng_for("link").random() != a.rng_for("other").random()
    assert ddes.World(seed=8).rng_for("link").random() != a.rng_for("link").random()
    with pytest.raises(DdesError):
        ddes.World(seed="x")  # type: ignore[arg-type]


def test_two_worlds_do_not_interfere() -> None:
    w1, w2 = ddes.World(), ddes.World()
    n1, n2 = w1.create_node("same"), w2.create_node("same")
    ticks1: list[int] = []
    n1.create_timer(0.1, lambda e: ticks1.append(w1.now))
    n2.create_timer(0.3, lambda e: None)
    w1.run(until=1)
    assert w2.now == 0 and len(ticks1) == 9
    assert not n2.is_shutdown() and list(w2.nodes) == ["/same"]
    assert w1.next_id("conn") == 1 and w2.next_id("conn") == 1 and w1.next_id("conn") == 2


def test_second_node_with_same_name_shuts_down_first(world: ddes.World) -> None:
    first = world.create_node("talker")
    second = world.create_node("/talker")
    assert first.is_shutdown() and not second.is_shutdown()
    assert world.nodes["/talker"] is second
    ev = world.trace.filter(kind="node.shutdown")[0]
    assert ev.details["reason"] == ("external shutdown request from [/master]: "
                                    "[[/talker] Reason: new node registered with same name]")


def test_trace_records_and_digests(world: ddes.World) -> None:
    world.record("custom", "/me", value=ddes.Duration(1), items=(1, 2))
    ev = world.trace[0]
    assert ev.to_json() == '[0,"custom","/me",{"items":[1,2],"value":1000000000}]'
    d1 = world.digest()
    world.record("custom", "/me")
    assert world.digest() != d1 and len(world.trace) == 2
    assert "custom" in world.trace.format()


def test_post_orders_exactly_like_timeout(world: ddes.World) -> None:
    from ddes.kernel.events import post

    order: list[str] = []
    env = world.env
    env.timeout(5).callbacks.append(lambda e: order.append("t1"))
    post(env, 5, "p1", lambda e: order.append(e.value))
    env.timeout(5).callbacks.append(lambda e: order.append("t2"))
    post(env, 0, "p0", lambda e: order.append(e.value))
    world.run()
    assert order == ["p0", "t1", "p1", "t2"]
