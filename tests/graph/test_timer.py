"""Timers: rospy's schedule (ddes.Timer) and roscpp's (RoscppTimer), TimerEvent fields.

Each rospy behaviour below is one that tests/graph/test_timer_vs_rospy.py
checks against real rospy; these run without ROS.
"""

from __future__ import annotations

from collections.abc import Generator
from typing import Any

import pytest

import ddes
from ddes.errors import DdesError
from ddes.graph.timer import RoscppTimer, Timer, TimerEvent, rospy_timer_sleep_ns

MS = 1_000_000


def _ms(t: Any) -> Any:
    return None if t is None else t.to_nsec() // MS


def _rows(events: list[TimerEvent]) -> list[tuple[Any, Any]]:
    return [(_ms(e.current_expected), _ms(e.current_real)) for e in events]


def _drive_clock(world: ddes.World, node: ddes.Node, values_ms: list[int]) -> None:
    """Set the node's simulated clock to each value in turn, 10 ms of kernel time apart."""
    clock = node.clock

    def drive() -> Generator[Any, Any, None]:
        for value in values_ms:
            yield world.timeout(0.01)
            clock.update(value * MS)  # type: ignore[attr-defined]  # a SimClock

    world.process(drive())


# -- rospy's schedule (ddes.Timer) ------------------------------------------------------------


def test_periodic_timer_events(world: ddes.World) -> None:
    node = world.create_node("n")
    events: list[TimerEvent] = []
    timer = node.create_timer(0.25, events.append)
    assert isinstance(timer, Timer) and isinstance(ddes.Timer(node, 5, print), Timer)
    world.run(until=1.01)
    assert _rows(events) == [(250, 250), (500, 500), (750, 750), (1000, 1000)]
    first, second = events[0], events[1]
    assert first.last_expected is None and first.last_real is None and first.last_duration is None
    assert _ms(second.last_expected) == 250 and _ms(second.last_real) == 250
    assert second.last_duration == 0.0


def test_slow_callback_is_caught_up_by_immediate_fires_as_rospy(world: ddes.World) -> None:
    # rospy: current_expected only ever grows by the period; after a 250 ms callback the
    # Rate inside the timer is behind (not more than two periods), so the next fires come
    # at once until it has caught up.
    node = world.create_node("n")
    events: list[TimerEvent] = []

    def cb(ev: TimerEvent) -> Generator[Any, Any, None]:
        events.append(ev)
        if len(events) == 1:
            yield node.sleep(0.25)

    node.create_timer(0.1, cb)
    world.run(until=0.55)
    assert _rows(events) == [(100, 100), (200, 350), (300, 350), (400, 400), (500, 500)]
    assert [e.last_duration for e in events] == [None, 0.25, 0.0, 0.0, 0.0]
    assert [(_ms(e.last_expected), _ms(e.last_real)) for e in events[1:3]] == [(100, 100),
                                                                               (200, 350)]


def test_more_than_two_periods_behind_drops_the_backlog(world: ddes.World) -> None:
    node = world.create_node("n")
    events: list[TimerEvent] = []

    def cb(ev: TimerEvent) -> Generator[Any, Any, None]:
        events.append(ev)
        if len(events) == 1:
            yield node.sleep(1.0)

    node.create_timer(0.1, cb)
    world.run(until=1.35)
    # the sleep after the slow callback returns at once (the Rate is 900 ms behind) and
    # drops the backlog, so the period restarts from 1.1 s; current_expected still counts
    # 100, 200, 300 ...
    assert _rows(events) == [(100, 100), (200, 1100), (300, 1200), (400, 1300)]


def test_slightly_slow_callback(world: ddes.World) -> None:
    node = world.create_node("n")
    events: list[TimerEvent] = []

    def cb(ev: TimerEvent) -> Generator[Any, Any, None]:
        events.append(ev)
        if len(events) == 1:
            yield node.sleep(1.5)

    node.create_timer(1.0, cb)
    world.run(until=4.5)
    assert _rows(events) == [(1000, 1000), (2000, 2500), (3000, 3000), (4000, 4000)]


def test_rate_period_loses_a_nanosecond_as_rospy(world: ddes.World) -> None:
    # rospy.Timer sleeps with Rate(1.0 / period.to_sec()): Duration(0, int(1e9 / hz))
    assert rospy_timer_sleep_ns(110 * MS) == 109_999_999
    assert rospy_timer_sleep_ns(30 * MS) == 29_999_999
    assert rospy_timer_sleep_ns(300 * MS) == 300 * MS
    assert rospy_timer_sleep_ns(1) == 1
    node = world.create_node("n")
    events: list[TimerEvent] = []
    node.create_timer(0.11, events.append)
    one: list[TimerEvent] = []
    node.create_timer(0.11, one.append, oneshot=True)
    world.run(until=0.5)
    assert [(e.current_expected.to_nsec(), e.current_real.to_nsec()) for e in events] == [
        (110_000_000, 109_999_999), (220_000_000, 219_999_998), (330_000_000, 329_999_997),
        (440_000_000, 439_999_996)]
    assert [e.current_real.to_nsec() for e in one] == [109_999_999]


def test_oneshot_and_shutdown(world: ddes.World) -> None:
    node = world.create_node("n")
    fired: list[int] = []
    one = node.create_timer(0.5, lambda e: fired.append(world.now), oneshot=True)
    periodic = node.create_timer(0.25, lambda e: fired.append(-world.now))
    world.run(until=0.6)
    periodic.shutdown()
    world.run(until=3.0)
    assert fired == [-250 * MS, 500 * MS, -500 * MS]
    assert not one.is_alive() and not periodic.is_alive()


def test_shutdown_inside_the_callback_stops_it(world: ddes.World) -> None:
    node = world.create_node("n")
    fired: list[int] = []
    timers: list[Timer] = []

    def cb(ev: TimerEvent) -> None:
        fired.append(world.now // MS)
        if len(fired) == 3:
            timers[0].shutdown()

    timers.append(node.create_timer(0.1, cb))
    world.run(until=1.0)
    assert fired == [100, 200, 300] and not timers[0].is_alive()


def test_timers_stop_with_their_node(world: ddes.World) -> None:
    node = world.create_node("n")
    fired: list[int] = []
    timer = node.create_timer(0.1, lambda e: fired.append(world.now))
    world.run(until=0.25)
    node.shutdown()
    world.run(until=1.0)
    assert len(fired) == 2 and not timer.is_alive()
    with pytest.raises(ddes.errors.NodeShutdownError):
        node.create_timer(0.1, lambda e: None)


def test_sim_time_timer_created_at_zero_counts_expected_from_zero(world: ddes.World) -> None:
    # rospy: current_expected = 0 + period; the first sleep starts at the first /clock
    # (100 s), so the Rate is far behind: one immediate fire, then the period.
    node = world.create_node("n", use_sim_time=True)
    events: list[TimerEvent] = []
    node.create_timer(1.0, events.append)
    _drive_clock(world, node, [100_000, 100_500, 101_000, 101_500, 102_000])
    world.run()
    assert _rows(events) == [(1000, 101_000), (2000, 101_000), (3000, 102_000)]


def test_sim_time_forward_jump_fires_twice_then_keeps_the_period(world: ddes.World) -> None:
    node = world.create_node("n", use_sim_time=True)
    events: list[TimerEvent] = []
    node.create_timer(0.1, events.append)
    _drive_clock(world, node, [1000, 1050, 1100, 1150, 1200, 5000, 5050, 5100, 5150, 5200])
    world.run()
    assert _rows(events) == [(100, 1100), (200, 1100), (300, 1200), (400, 5000), (500, 5000),
                             (600, 5100), (700, 5200)]


@pytest.mark.parametrize("reset", [True, False])
def test_sim_time_backwards_jump_fires_at_once_as_rospy_with_reset(
        world: ddes.World, reset: bool) -> None:
    # rospy with reset=True: the sleep ends at the jump and the callback runs at once; without
    # reset rospy's timer thread dies, a ddes timer does the same as with it (docs/time.md).
    node = world.create_node("n", use_sim_time=True)
    events: list[TimerEvent] = []
    timer = node.create_timer(1.0, events.append, reset=reset)
    _drive_clock(world, node, [100_000, 100_500, 101_000, 101_500, 102_000,
                               50_000, 50_500, 51_000, 51_500, 52_000])
    world.run()
    assert _rows(events) == [(1000, 101_000), (2000, 101_000), (3000, 102_000), (4000, 50_000),
                             (5000, 51_000), (6000, 52_000)]
    assert timer.is_alive()


def test_sim_time_backwards_jump_above_the_sleep_start_keeps_sleeping(world: ddes.World) -> None:
    node = world.create_node("n", use_sim_time=True)
    events: list[TimerEvent] = []
    node.create_timer(0.1, events.append)
    _drive_clock(world, node, [1000, 1100, 1150, 1120, 1190, 1200])
    world.run()
    assert _rows(events) == [(100, 1100), (200, 1100), (300, 1200)]


@pytest.mark.parametrize("period", [0, -1.0, ddes.Duration(-1), float("nan"), "1"])
def test_bad_periods(world: ddes.World, period: Any) -> None:
    node = world.create_node("n")
    with pytest.raises(DdesError):
        node.create_timer(period, lambda e: None)
    with pytest.raises(DdesError):
        node.create_roscpp_timer(period, lambda e: None)


def _bad(ev: TimerEvent) -> None:
    raise RuntimeError("boom")


def test_callback_exception_propagates_in_strict_worlds(world: ddes.World) -> None:
    node = world.create_node("n")
    node.create_timer(0.1, _bad)
    with pytest.raises(RuntimeError, match="boom"):
        world.run(until=1)


def test_callback_exception_ends_a_rospy_timer() -> None:
    # rospy: the exception ends the timer's thread; ddes logs it and the timer stops
    w = ddes.World(strict=False)
    w.log_output = lambda line, level: None
    node = w.create_node("n")
    timer = node.create_timer(0.1, _bad)

    def slow_bad(ev: TimerEvent) -> Generator[Any, Any, None]:
        yield node.sleep(0.05)
        raise RuntimeError("late boom")

    sim = w.create_node("s", use_sim_time=True)
    sim_timer = sim.create_timer(0.1, _bad)
    slow = node.create_timer(0.1, slow_bad)
    _drive_clock(w, sim, [1000, 1100, 1200, 1300])
    w.run(until=0.35)
    assert len(w.callback_errors) == 3
    assert [e.kind for e in w.trace.filter(prefix="callback.")] == ["callback.exception"] * 3
    assert not timer.is_alive() and not sim_timer.is_alive() and not slow.is_alive()


# -- roscpp's schedule (RoscppTimer) ----------------------------------------------------------


def test_roscpp_slow_callback_skips_missed_fires(world: ddes.World) -> None:
    # Period 1 s; the first callback takes 2.5 s of simulated time.
    node = world.create_node("n")
    events: list[TimerEvent] = []

    def cb(ev: TimerEvent) -> Generator[Any, Any, None]:
        events.append(ev)
        if len(events) == 1:
            yield node.sleep(2.5)

    timer = node.create_roscpp_timer(1.0, cb)
    assert isinstance(timer, RoscppTimer)
    world.run(until=8.5)
    rows = [(_ms(e.current_expected), _ms(e.current_real), _ms(e.last_expected), e.last_duration)
            for e in events]
    assert rows == [
        (1000, 1000, None, None),
        (3500, 3500, 1000, 2.5),   # next+period < now after the slow callback: next = now
        (4500, 4500, 3500, 0.0),
        (5500, 5500, 4500, 0.0),
        (6500, 6500, 5500, 0.0),
        (7500, 7500, 6500, 0.0),
    ]


def test_roscpp_slightly_slow_callback_keeps_grid(world: ddes.World) -> None:
    node = world.create_node("n")
    events: list[TimerEvent] = []

    def cb(ev: TimerEvent) -> Generator[Any, Any, None]:
        events.append(ev)
        if len(events) == 1:
            yield node.sleep(1.5)

    node.create_roscpp_timer(1.0, cb)
    world.run(until=4.5)
    # after the 1.5 s callback (ends at 2.5): next = 2 (due, not more than a period late)
    assert _rows(events) == [(1000, 1000), (2000, 2500), (3000, 3000), (4000, 4000)]


def test_roscpp_oneshot_and_exact_period(world: ddes.World) -> None:
    node = world.create_node("n")
    fired: list[int] = []
    one = node.create_roscpp_timer(0.5, lambda e: fired.append(world.now), oneshot=True)
    periodic = node.create_roscpp_timer(0.11, lambda e: fired.append(-world.now))
    world.run(until=0.25)
    periodic.shutdown()
    world.run(until=3.0)
    assert fired == [-110 * MS, -220 * MS, 500 * MS]
    assert not one.is_alive() and not periodic.is_alive()


def test_roscpp_sim_time_timer_starts_at_first_clock_and_resets_on_jump(world: ddes.World) -> None:
    node = world.create_node("n", use_sim_time=True)
    events: list[TimerEvent] = []
    node.create_roscpp_timer(1.0, events.append)
    _drive_clock(world, node, [100_000, 100_500, 101_000, 101_500, 102_000,
                               50_000, 50_500, 51_000, 51_500, 52_000])
    world.run()
    assert _rows(events) == [(101_000, 101_000), (102_000, 102_000), (51_000, 51_000),
                             (52_000, 52_000)]


def test_roscpp_callback_exception_is_logged_and_the_timer_goes_on() -> None:
    w = ddes.World(strict=False)
    w.log_output = lambda line, level: None
    node = w.create_node("n")
    timer = node.create_roscpp_timer(0.1, _bad)
    w.run(until=0.35)
    assert len(w.callback_errors) == 3 and timer.is_alive()
