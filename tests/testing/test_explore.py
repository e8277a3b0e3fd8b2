"""The schedule explorer (ddes.testing.explore): perturbations replay exactly, the tie order keeps
what ROS keeps in order, and a node that assumes one message order is found and shrunk."""

from __future__ import annotations

import functools
from collections.abc import Generator
from typing import Any

import pytest

import ddes
from ddes.errors import DdesTypeError, DdesValueError
from ddes.msg import get_message_class
from ddes.testing.explore import (
    ExplorationFailure,
    Perturbation,
    TieBreaker,
    explore,
    replay,
    run_perturbed,
)

Float64 = get_message_class("std_msgs/Float64")


def scenario(world: ddes.World) -> list[float]:
    """A controller sends its gain on /gain, then a command on /cmd, in the same instant; the
    driver scales each command by the last gain.  Planted bug: the driver assumes the gain
    always arrives first (two topics are two connections: ROS orders neither against the other)."""
    out: list[float] = []
    controller = world.create_node("controller")
    gain = controller.advertise("/gain", Float64, queue_size=10)
    cmd = controller.advertise("/cmd", Float64, queue_size=10)
    driver = world.create_node("driver")
    state: dict[str, float] = {}
    driver.subscribe("/gain", Float64, lambda m: state.__setitem__("gain", m.data))
    driver.subscribe("/cmd", Float64, lambda m: out.append(state.get("gain", 0.0) * m.data))

    def main() -> Generator[Any, Any, None]:
        yield controller.sleep(0.1)
        for k in range(1, 4):
            gain.publish(Float64(float(k)))
            cmd.publish(Float64(10.0))
            yield controller.sleep(0.1)

    controller.process(main())
    return out


def check(world: ddes.World, out: list[float]) -> None:
    assert out == [10.0, 20.0, 30.0], f"driver output {out}"


@functools.lru_cache(maxsize=1)
def order_failure() -> ExplorationFailure:
    with pytest.raises(ExplorationFailure) as info:
        explore(scenario, check, runs=60, until=1.0, derandomize=True, database=None)
    return info.value


def test_a_node_that_assumes_one_message_order_is_found_and_shrunk() -> None:
    f = order_failure()
    print(f)
    p = f.perturbation
    # shrunk: one thing perturbed (a latency on /gain, jitter, or one tie), nothing else
    changed = [bool({k: v for k, v in p.latencies.items() if v}), bool(p.jitter),
               any(p.ties), p.connect_delay is not None, bool(p.service_latencies)]
    assert sum(changed) == 1 and p.seed == 0, f
    assert sum(1 for t in p.ties if t) <= 1, f
    assert f.replay.startswith("replay(scenario, check, seed=0, ")
    with pytest.raises(AssertionError, match="driver output"):
        eval(f.replay, {"replay": replay, "scenario": scenario, "check": check})  # noqa: S307


def test_a_swapped_tie_alone_breaks_the_assumption() -> None:
    run_perturbed(scenario, check, Perturbation(), until=1.0)
    broke = []
    for k in range(12):  # swap the k-th contested instant only
        try:
            replay(scenario, check, ties=(0,) * k + (1,), until=1.0)
        except AssertionError:
            broke.append(k)
    assert broke, "no single swapped tie reorders /gain and /cmd"


def burst(world: ddes.World) -> dict[str, list[float]]:
    """A talker sends 0..4 in one instant to two listeners (at 0.2 s: after every connection
    delay the explorer tries), and a client calls a service."""
    out: dict[str, list[float]] = {"a": [], "b": [], "sum": []}
    pub = world.create_node("talker").advertise("/x", Float64, queue_size=100)
    for name in ("a", "b"):
        world.create_node(name).subscribe("/x", Float64, lambda m, n=name: out[n].append(m.data))
    world.call_at(200_000_000, lambda: [pub.publish(Float64(float(i))) for i in range(5)])
    AddTwoInts = ddes.get_service_class("rospy_tutorials/AddTwoInts")
    ddes.Service(world.create_node("server"), "/add", AddTwoInts, lambda r: r.a + r.b)
    client = world.create_node("client")
    proxy = ddes.ServiceProxy(client, "/add", AddTwoInts, persistent=True)

    def calls() -> Generator[Any, Any, None]:
        for i in range(3):
            out["sum"].append((yield proxy(i, i)).sum)

    client.process(calls())
    return out


def in_order(world: ddes.World, out: dict[str, list[float]]) -> None:
    assert out["a"] == out["b"] == [0.0, 1.0, 2.0, 3.0, 4.0], out
    assert out["sum"] == [0, 2, 4], out


def test_perturbations_keep_what_ros_keeps_in_order() -> None:
    explore(burst, in_order, runs=40, until=1.0, derandomize=True, database=None)


def test_a_perturbation_replays_exactly() -> None:
    p = Perturbation(seed=3, latencies={"/x": 0.002}, jitter=0.0005, ties=(1, 2, 3, 1, 2, 3, 1))
    digests = {run_perturbed(burst, in_order, p, until=1.0).digest() for _ in range(2)}
    assert len(digests) == 1
    assert run_perturbed(burst, in_order, Perturbation(), until=1.0).digest() not in digests


def test_the_tie_breaker_counts_its_choices() -> None:
    world = ddes.World(0, strict=True)
    breaker = TieBreaker(world, (1, 1, 1))
    seen: list[str] = []
    world.call_at(5, lambda: seen.append("first"))
    world.call_at(5, lambda: seen.append("second"))
    world.run(until=1.0)
    assert seen == ["second", "first"] and breaker.choices == [(5, 2, 1)]


def test_explore_checks_its_arguments_and_the_unperturbed_run() -> None:
    with pytest.raises(DdesTypeError):
        explore("scenario", check)  # type: ignore[arg-type]
    with pytest.raises(DdesValueError):
        explore(scenario, check, runs=0)
    with pytest.raises(ExplorationFailure, match="replay\\(scenario, bad, seed=0, until=1.0\\)"):
        def bad(world: ddes.World, out: list[float]) -> bool:
            return False
        explore(scenario, bad, runs=5, until=1.0)
