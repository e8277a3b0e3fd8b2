"""The named real-time mode (ddes.kernel.realtime) with a fake wall clock; run_for(0), settle,
run_through and the stale stops an interrupted run used to leave."""

from __future__ import annotations

import math

import pytest

from ddes.errors import DdesValueError, WorldError
from ddes.graph.world import World
from ddes.kernel.realtime import PacedResult, check_rtf, run_paced


class FakeWall:
    """A wall clock that moves only when slept on; records every sleep."""

    def __init__(self) -> None:
        self.now = 100.0
        self.sleeps: list[float] = []

    def clock(self) -> float:
        return self.now

    def sleep(self, seconds: float) -> None:
        self.sleeps.append(seconds)
        self.now += seconds


def ticking(world: World, log: list[tuple[int, float]], wall: FakeWall, period_ns: int):  # type: ignore[no-untyped-def]
    def proc():  # type: ignore[no-untyped-def]
        while True:
            log.append((world.now, wall.now))
            yield world.env.timeout(period_ns)
    return world.env.process(proc())


def test_simulated_time_is_reached_at_its_wall_time() -> None:
    world, wall, log = World(), FakeWall(), []
    ticking(world, log, wall, 250_000_000)
    end = world.env.timeout(1_000_000_000)
    result = run_paced(world, end, rtf=2.0, clock=wall.clock, sleep=wall.sleep)
    assert result == PacedResult.DONE
    # at rtf 2 a quarter simulated second takes an eighth of a wall second
    assert [(t, round(w - 100.0, 9)) for t, w in log] == [
        (0, 0.0), (250_000_000, 0.125), (500_000_000, 0.25), (750_000_000, 0.375)]
    assert world.now == 1_000_000_000
    assert all(s <= 0.05 + 1e-12 for s in wall.sleeps)  # Ctrl+C is looked at every POLL


def test_a_paced_run_leaves_the_same_world_as_an_unpaced_one() -> None:
    def scenario(paced: bool) -> tuple[str, int]:
        world = World(seed=3)
        string = world.messages.get_message_class("std_msgs/String")
        pub = world.create_node("a").advertise("/t", string)
        seen: list[str] = []
        world.create_node("b").subscribe("/t", string, lambda m: seen.append(m.data))
        world.create_node("a2").create_timer(0.1, lambda _e: pub.publish(data="x"))
        until = world.env.timeout(700_000_000)
        if paced:
            wall = FakeWall()
            run_paced(world, until, rtf=1.0, clock=wall.clock, sleep=wall.sleep)
        else:
            world.run(until)
        return world.digest(), len(seen)

    assert scenario(True) == scenario(False)


def test_stopped_ends_the_run_between_instants_and_idle_waits() -> None:
    world, wall = World(), FakeWall()
    never = world.env.event()
    calls = []

    def stopped() -> bool:
        calls.append(wall.now)
        return wall.now >= 100.3

    assert run_paced(world, never, rtf=1.0, stopped=stopped, clock=wall.clock,
                     sleep=wall.sleep) == PacedResult.STOPPED
    assert world.now == 0  # nothing was scheduled: the world was idle all along
    assert len(calls) >= 6


def test_infinite_rtf_never_sleeps() -> None:
    world, wall, log = World(), FakeWall(), []
    ticking(world, log, wall, 100_000_000)
    run_paced(world, world.env.timeout(10**9), rtf=math.inf, clock=wall.clock, sleep=wall.sleep)
    assert wall.sleeps == [] and len(log) == 10


@pytest.mark.parametrize("bad", [0, -1, "fast", None, float("nan")])
def test_a_bad_rtf_is_a_typed_error(bad: object) -> None:
    with pytest.raises(DdesValueError, match="real-time factor"):
        check_rtf(bad)  # type: ignore[arg-type]


def test_run_for_zero_processes_the_events_due_now() -> None:
    world = World()
    ran: list[int] = []

    def proc():  # type: ignore[no-untyped-def]
        ran.append(world.now)
        yield world.env.timeout(0)
        ran.append(world.now)

    world.env.process(proc())
    world.run_for(0)
    assert ran == [0, 0] and world.now == 0
    world.env.process(proc())
    world.run(until=world.time())  # an absolute run to now does the same
    assert ran == [0, 0, 0, 0]


def test_run_through_includes_the_final_instant_and_stops_at_its_event() -> None:
    world = World()
    at: list[int] = []
    for t in (5, 10, 10, 15):
        world.call_at(t, lambda t=t: at.append(t))
    world.run_through(10)
    assert at == [5, 10, 10] and world.now == 10
    world.run_through(12)
    assert world.now == 12 and at == [5, 10, 10]
    with pytest.raises(WorldError, match="never runs backwards"):
        world.run_through(11)
    stop = world.call_at(15, lambda: None)
    world.call_at(15, lambda: at.append(99))
    world.run_through(20, stop=stop)
    assert at == [5, 10, 10, 15] and world.now == 15  # ended right after `stop`, as run(until=)


def test_an_interrupted_run_leaves_no_stale_stop() -> None:
    """Ctrl+C inside run(until=...) used to leave SimPy's stop armed: a later run ended there."""
    world = World()
    node = world.create_node("n")

    def press(_ev: object) -> None:
        raise KeyboardInterrupt

    node.create_timer(1.0, press, oneshot=True)
    with pytest.raises(KeyboardInterrupt):
        world.run_for(10)
    assert world.now == 1_000_000_000
    world.run_for(20)  # not cut short at 10 s by the first run's stop
    assert world.now == 21_000_000_000
    done = world.env.event()
    node.create_timer(1.0, press, oneshot=True)
    with pytest.raises(KeyboardInterrupt):
        world.run(done)
    done.succeed()
    world.run_for(1)  # processing `done` no longer raises StopSimulation
    assert world.now == 23_000_000_000


def test_interrupt_flag_sets_the_flag_and_a_second_ctrl_c_raises() -> None:
    import signal

    from ddes.kernel.realtime import InterruptFlag

    with InterruptFlag(second_raises=True) as flag:
        signal.raise_signal(signal.SIGINT)
        assert flag()
        with pytest.raises(KeyboardInterrupt):
            signal.raise_signal(signal.SIGINT)
    with InterruptFlag() as once_only:
        signal.raise_signal(signal.SIGINT)
        signal.raise_signal(signal.SIGINT)  # without second_raises: still just the flag
        assert once_only()
