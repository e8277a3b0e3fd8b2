"""Rate: rospy's algorithm (default) and roscpp's, tick for tick on worked examples."""

from __future__ import annotations

from collections.abc import Generator
from typing import Any

import pytest

import ddes
from ddes.errors import DdesError, ROSTimeMovedBackwardsException
from ddes.time.rate import Rate, RoscppRate, WallRate, roscpp_period_ns

MS = 1_000_000


def _loop(world: ddes.World, rate: Any, bodies_ms: list[int], log: list[Any]) -> Generator[Any, Any, None]:
    for body in bodies_ms:
        log.append(("start", world.now // MS))
        if body:
            yield world.timeout(ddes.Duration.from_nsec(body * MS))
        ok = yield rate.sleep()
        log.append(("woke", world.now // MS, ok))


def test_period_truncation_rospy_vs_roscpp(world: ddes.World) -> None:
    node = world.create_node("n")
    assert Rate(node, 3).sleep_dur.to_nsec() == 333_333_333
    assert Rate(node, 7).sleep_dur.to_nsec() == 142_857_142  # int(1e9/7): truncated
    assert roscpp_period_ns(7) == 142_857_143  # Duration(1.0/7): rounded
    assert RoscppRate(node, 7).expected_cycle_time().to_nsec() == 142_857_143


def test_rospy_rate_on_time(world: ddes.World) -> None:
    node = world.create_node("n")
    log: list[Any] = []
    node.process(_loop(world, node.create_rate(10), [0, 0, 0], log))
    world.run()
    assert [e[1] for e in log if e[0] == "woke"] == [100, 200, 300]


def test_rospy_rate_catches_up_within_two_periods(world: ddes.World) -> None:
    # 10 Hz; the second cycle's body takes 250 ms (less than 2 periods late):
    # rospy bursts to catch up (no sleep at 350 twice), then resumes the grid.
    node = world.create_node("n")
    log: list[Any] = []
    node.process(_loop(world, node.create_rate(10), [0, 250, 0, 0, 0], log))
    world.run()
    assert [e[1] for e in log if e[0] == "woke"] == [100, 350, 350, 400, 500]


def test_rospy_rate_drops_backlog_beyond_two_periods(world: ddes.World) -> None:
    # The body takes 350 ms: more than 2 periods behind, so last_time = now.
    node = world.create_node("n")
    log: list[Any] = []
    node.process(_loop(world, node.create_rate(10), [0, 350, 0, 0], log))
    world.run()
    assert [e[1] for e in log if e[0] == "woke"] == [100, 450, 550, 650]


def test_rospy_rate_remaining(world: ddes.World) -> None:
    node = world.create_node("n")
    rate = node.create_rate(4)
    world.run(until=0.1)
    assert rate.remaining() == ddes.Duration(0, 150_000_000)


def test_roscpp_rate_reports_missed_cycles(world: ddes.World) -> None:
    node = world.create_node("n")
    rate = node.create_roscpp_rate(10)
    log: list[Any] = []
    node.process(_loop(world, rate, [0, 250, 0, 0], log))
    world.run()
    woke = [(e[1], e[2]) for e in log if e[0] == "woke"]
    # cycle 2 misses (returns False) and, being > 1 period late, restarts at 350.
    assert woke == [(100, True), (350, False), (450, True), (550, True)]


def test_roscpp_rate_cycle_time(world: ddes.World) -> None:
    node = world.create_node("n")
    rate = RoscppRate(node, 10)
    times: list[int] = []

    def main() -> Generator[Any, Any, None]:
        yield rate.sleep()
        yield world.timeout(0.03)
        yield rate.sleep()
        times.append(rate.cycle_time().to_nsec())
        rate.reset()
        yield world.timeout(0.01)
        yield rate.sleep()
        times.append(world.now)

    node.process(main())
    world.run()
    assert times == [30 * MS, 300 * MS]


def test_roscpp_rate_slightly_late_keeps_grid(world: ddes.World) -> None:
    # Late by less than one period: returns False but keeps the original grid.
    node = world.create_node("n")
    log: list[Any] = []
    node.process(_loop(world, node.create_roscpp_rate(10), [0, 150, 0], log))
    world.run()
    assert [(e[1], e[2]) for e in log if e[0] == "woke"] == [(100, True), (250, False), (300, True)]


def test_wall_rate_ignores_sim_clock(world: ddes.World) -> None:
    node = world.create_node("n", use_sim_time=True)
    rate = node.create_wall_rate(2)
    assert isinstance(rate, WallRate)
    stamps: list[int] = []

    def main() -> Generator[Any, Any, None]:
        for _ in range(2):
            yield rate.sleep()
            stamps.append(world.now)

    node.process(main())
    world.run()
    assert stamps == [500 * MS, 1000 * MS]
    assert rate.sleep_dur == ddes.WallDuration(0, 500 * MS)


def _drive_clock(world: ddes.World, clock: Any, schedule: list[tuple[float, float]]) -> None:
    def proc() -> Generator[Any, Any, None]:
        for at, value in schedule:
            yield world.timeout(ddes.Duration.from_sec(at) - ddes.Duration.from_nsec(world.now))
            clock.update(ddes.Time.from_sec(value))

    world.process(proc())


def test_rate_backwards_jump_raises_unless_reset(world: ddes.World) -> None:
    strict = world.create_node("strict", use_sim_time=True)
    lenient = world.create_node("lenient", use_sim_time=True)
    outcome: dict[str, Any] = {}

    def loop(node: ddes.Node, reset: bool) -> Generator[Any, Any, None]:
        yield node.sleep(0)  # wait for the first /clock before starting the rate
        rate = node.create_rate(1, reset=reset)
        wakes = []
        try:
            for _ in range(3):
                yield rate.sleep()
                wakes.append(node.get_time())
        except ROSTimeMovedBackwardsException as exc:
            outcome[node.name] = ("raised", exc.time, wakes)
            return
        outcome[node.name] = ("ok", wakes)

    strict.process(loop(strict, False))
    lenient.process(loop(lenient, True))
    sched = [(0.1, 10.0), (0.2, 10.5), (0.3, 11.0), (0.4, 11.5), (0.5, 5.0), (0.6, 6.0), (0.7, 7.0)]
    _drive_clock(world, strict.clock, sched)
    _drive_clock(world, lenient.clock, sched)
    world.run()
    assert outcome["/strict"][0] == "raised"
    assert outcome["/strict"][1] == pytest.approx(6.0)  # the sleep started at 11.0; now 5.0
    assert outcome["/strict"][2] == [11.0]
    # reset=True: the jump returns from sleep with last_time = now (5.0).
    assert outcome["/lenient"] == ("ok", [11.0, 5.0, 6.0])


def test_rate_created_before_first_clock_bursts_like_rospy(world: ddes.World) -> None:
    # rospy quirk, reproduced: a Rate built while sim time is 0 has last_time 0,
    # so after the first /clock (10.0) it is far behind and drops the backlog.
    node = world.create_node("n", use_sim_time=True)
    rate = node.create_rate(1)
    wakes: list[float] = []

    def main() -> Generator[Any, Any, None]:
        for _ in range(3):
            yield rate.sleep()
            wakes.append(node.get_time())

    node.process(main())
    _drive_clock(world, node.clock, [(0.1, 10.0), (0.2, 10.5), (0.3, 11.0), (0.4, 11.5), (0.5, 12.0)])
    world.run()
    assert wakes == [11.0, 11.0, 12.0]


@pytest.mark.parametrize("hz", [0, -1, float("nan"), float("inf"), "10", None, 2e9])
def test_bad_rates(world: ddes.World, hz: Any) -> None:
    node = world.create_node("n")
    with pytest.raises(DdesError) as info:
        node.create_rate(hz)
    assert repr(hz)[:4] in str(info.value) or "nanosecond" in str(info.value)
