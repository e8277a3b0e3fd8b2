"""Timers: TimerEvent fields, roscpp's skipping of missed fires, one-shot, sim time."""

from __future__ import annotations

from collections.abc import Generator
from typing import Any

import pytest

import ddes
from ddes.errors import DdesError
from ddes.graph.timer import TimerEvent

MS = 1_000_000


def _ms(t: Any) -> Any:
    return None if t is None else t.to_nsec() // MS


def test_periodic_timer_events(world: ddes.World) -> None:
    node = world.create_node("n")
    events: list[TimerEvent] = []
    node.create_timer(0.25, events.append)
    world.run(until=1.01)
    assert [(_ms(e.current_expected), _ms(e.current_real)) for e in events] == [
        (250, 250), (500, 500), (750, 750), (1000, 1000)]
    first, second = events[0], events[1]
    assert first.last_expected is None and first.last_real is None and first.last_duration is None
    assert _ms(second.last_expected) == 250 and _ms(second.last_real) == 250
    assert second.last_duration == 0.0


def test_slow_callback_skips_missed_fires_as_roscpp(world: ddes.World) -> None:
    # Period 1 s; the first callback takes 2.5 s of simulated time.
    node = world.create_node("n")
    events: list[TimerEvent] = []

    def cb(ev: TimerEvent) -> Generator[Any, Any, None]:
        events.append(ev)
        if len(events) == 1:
            yield node.sleep(2.5)

    node.create_timer(1.0, cb)
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


def test_slightly_slow_callback_keeps_grid(world: ddes.World) -> None:
    node = world.create_node("n")
    events: list[TimerEvent] = []

    def cb(ev: TimerEvent) -> Generator[Any, Any, None]:
        events.append(ev)
        if len(events) == 1:
            yield node.sleep(1.5)

    node.create_timer(1.0, cb)
    world.run(until=4.5)
    # after the 1.5 s callback (ends at 2.5): next = 2 (due, not more than a period late)
    assert [(_ms(e.current_expected), _ms(e.current_real)) for e in events] == [
        (1000, 1000), (2000, 2500), (3000, 3000), (4000, 4000)]


def test_oneshot_and_shutdown(world: ddes.World) -> None:
    node = world.create_node("n")
    fired: list[int] = []
    one = node.create_timer(0.5, lambda e: fired.append(world.now), oneshot=True)
    periodic = node.create_timer(0.3, lambda e: fired.append(-world.now))
    world.run(until=0.7)
    periodic.shutdown()
    world.run(until=3.0)
    assert fired == [-300 * MS, 500 * MS, -600 * MS]
    assert not one.is_alive() and not periodic.is_alive()


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


def test_sim_time_timer_starts_at_first_clock_and_resets_on_jump(world: ddes.World) -> None:
    node = world.create_node("n", use_sim_time=True)
    fired: list[tuple[float, float]] = []
    node.create_timer(1.0, lambda e: fired.append((e.current_expected.to_sec(), e.current_real.to_sec())))
    clock = node.clock

    def drive() -> Generator[Any, Any, None]:
        for value in [100.0, 100.5, 101.0, 101.5, 102.0, 50.0, 50.5, 51.0, 51.5, 52.0]:
            yield world.timeout(0.1)
            clock.update(ddes.Time.from_sec(value))  # type: ignore[attr-defined]

    world.process(drive())
    world.run()
    assert fired == [(101.0, 101.0), (102.0, 102.0), (51.0, 51.0), (52.0, 52.0)]


@pytest.mark.parametrize("period", [0, -1.0, ddes.Duration(-1), float("nan"), "1"])
def test_bad_periods(world: ddes.World, period: Any) -> None:
    node = world.create_node("n")
    with pytest.raises(DdesError):
        node.create_timer(period, lambda e: None)


def test_callback_exception_propagates_by_default_and_can_be_recorded(world: ddes.World) -> None:
    node = world.create_node("n")

    def bad(ev: TimerEvent) -> None:
        raise RuntimeError("boom")

    node.create_timer(0.1, bad)
    with pytest.raises(RuntimeError, match="boom"):
        world.run(until=1)
    w2 = ddes.World()
    w2.raise_callback_errors = False
    n2 = w2.create_node("n")
    n2.create_timer(0.1, bad)
    w2.run(until=0.35)
    assert len(w2.callback_errors) == 3
    assert [e.kind for e in w2.trace.filter(prefix="callback.")] == ["callback.exception"] * 3
