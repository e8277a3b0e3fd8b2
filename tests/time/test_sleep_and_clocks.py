"""sleep() and clocks: kernel vs simulated time, first /clock, backwards jumps."""

from __future__ import annotations

from collections.abc import Generator
from typing import Any

import pytest

import ddes
from ddes.errors import ROSTimeMovedBackwardsException
from ddes.time.clock import KernelClock, SimClock

MS = 1_000_000


def test_kernel_clock_sleep_and_negative_sleep(world: ddes.World) -> None:
    node = world.create_node("n")
    assert isinstance(node.clock, KernelClock)
    stamps: list[int] = []

    def main() -> Generator[Any, Any, None]:
        yield node.sleep(0.25)
        stamps.append(world.now)
        yield node.sleep(ddes.Duration(-5))
        stamps.append(world.now)
        yield ddes.sleep(node, ddes.Duration(0, 5))
        stamps.append(world.now)

    node.process(main())
    world.run()
    assert stamps == [250 * MS, 250 * MS, 250 * MS + 5]


def test_sim_time_reads_zero_until_first_clock(world: ddes.World) -> None:
    node = world.create_node("sim", use_sim_time=True)
    assert isinstance(node.clock, SimClock)
    assert node.get_rostime() == ddes.Time(0) and not node.clock.is_valid()
    world.run(until=1)
    assert node.get_time() == 0.0
    node.clock.update(ddes.Time(42))  # type: ignore[attr-defined]
    assert node.get_rostime() == ddes.Time(42)
    assert node.get_walltime() == ddes.WallTime(1)  # wall = kernel clock


def test_use_sim_time_world_default(world: ddes.World) -> None:
    world.use_sim_time = True
    assert world.create_node("a").use_sim_time
    assert not world.create_node("b", use_sim_time=False).use_sim_time


def test_sim_sleep_waits_for_first_clock_then_sleeps(world: ddes.World) -> None:
    node = world.create_node("sim", use_sim_time=True)
    woke: list[tuple[int, float]] = []

    def main() -> Generator[Any, Any, None]:
        yield node.sleep(1.0)
        woke.append((world.now // MS, node.get_time()))

    node.process(main())

    def drive() -> Generator[Any, Any, None]:
        for k in range(10):
            yield world.timeout(0.1)
            node.clock.update(ddes.Time(100 + k * 0.25))  # type: ignore[attr-defined]

    world.process(drive())
    world.run()
    # first /clock at kernel 0.1 s reads 100.0; the sleep ends at >= 101.0 (kernel 0.5 s)
    assert woke == [(500, 101.0)]


def test_sim_sleep_raises_on_backwards_jump(world: ddes.World) -> None:
    node = world.create_node("sim", use_sim_time=True)
    node.clock.update(ddes.Time(10))  # type: ignore[attr-defined]
    caught: list[float] = []

    def main() -> Generator[Any, Any, None]:
        try:
            yield node.sleep(5)
        except ROSTimeMovedBackwardsException as exc:
            caught.append(exc.time)

    node.process(main())
    world.run(until=0.1)
    node.clock.update(ddes.Time(7))  # type: ignore[attr-defined]
    world.run(until=0.2)
    assert caught == [3.0]


def test_duration_sleep_reports_like_roscpp(world: ddes.World) -> None:
    node = world.create_node("sim", use_sim_time=True)
    node.clock.update(ddes.Time(10))  # type: ignore[attr-defined]
    results: list[bool] = []

    def main() -> Generator[Any, Any, None]:
        results.append((yield node.duration_sleep(1.0)))
        results.append((yield node.duration_sleep(1.0)))

    node.process(main())
    world.run(until=0.1)
    node.clock.update(ddes.Time(11))  # type: ignore[attr-defined]
    world.run(until=0.2)
    node.clock.update(ddes.Time(5))  # jump back during the second sleep
    world.run(until=0.3)
    assert results == [True, False]


def test_wall_sleep_on_sim_node_uses_kernel_time(world: ddes.World) -> None:
    node = world.create_node("sim", use_sim_time=True)
    stamps: list[int] = []

    def main() -> Generator[Any, Any, None]:
        yield node.wall_sleep(0.5)
        stamps.append(world.now)

    node.process(main())
    world.run()
    assert stamps == [500 * MS]


@pytest.mark.parametrize("bad", ["1", None, ddes.Time(1), float("nan")])
def test_sleep_rejects_bad_durations(world: ddes.World, bad: Any) -> None:
    node = world.create_node("n")
    with pytest.raises(ddes.DdesError):
        node.sleep(bad)
