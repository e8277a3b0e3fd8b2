"""The ROS-time machine (ddes.testing.rostime): rospy's Timer, Rate and sleep keep their rules
under pauses, jumps and real-time factors; nodes that assume wall time, or that time never goes
back, are found and shrunk."""

from __future__ import annotations

import functools
from typing import Any

import matplotlib

matplotlib.use("Agg")

import pytest  # noqa: E402

from ddes.errors import DdesTypeError, DdesValueError  # noqa: E402
from ddes.testing._replay import VIOLATION_GID  # noqa: E402
from ddes.testing.rostime import (  # noqa: E402
    TimeProtocolMachine,
    TimeViolation,
    replay_time_schedule,
    run_time_machine,
)


class Stopwatch:
    """A planted bug: it measures how long it has been running with the wall clock, so it is
    wrong whenever ROS time does not run at the wall clock's pace."""

    def __init__(self, node: Any) -> None:
        self.node = node
        self.first_ros: Any = None
        self.first_wall: Any = None
        self.elapsed = 0.0
        node.create_timer(0.1, self.tick)

    def tick(self, event: Any) -> None:
        if self.first_ros is None:
            self.first_ros, self.first_wall = event.current_real, self.node.get_walltime()
        self.last_ros = event.current_real
        self.elapsed = (self.node.get_walltime() - self.first_wall).to_sec()  # BUG: wall clock


def make_stopwatch(world: Any, node: Any) -> Stopwatch:
    return Stopwatch(node)


def stopwatch_check(sw: Stopwatch, node: Any) -> None:
    if sw.first_ros is not None:
        ros = (sw.last_ros - sw.first_ros).to_sec()
        assert abs(sw.elapsed - ros) < 1e-6, f"elapsed {sw.elapsed:.6f}s, ROS time {ros:.6f}s"


class RateEstimator:
    """A planted bug: it assumes time never goes back (the period it measures must be > 0)."""

    def __init__(self, node: Any) -> None:
        self.last: Any = None
        self.periods: list[float] = []
        node.create_timer(0.1, self.tick)

    def tick(self, event: Any) -> None:
        if self.last is not None:
            self.periods.append((event.current_real - self.last).to_sec())
        self.last = event.current_real


def make_estimator(world: Any, node: Any) -> RateEstimator:
    return RateEstimator(node)


def estimator_check(est: RateEstimator, node: Any) -> bool:
    return all(p >= 0 for p in est.periods)


TestProbesOnly = TimeProtocolMachine.for_node(max_examples=40, derandomize=True)


@functools.lru_cache(maxsize=1)
def stopwatch_violation() -> TimeViolation:
    with pytest.raises(TimeViolation) as info:
        run_time_machine(make_stopwatch, stopwatch_check, max_examples=40, derandomize=True,
                         database=None)
    return info.value


def test_a_node_that_measures_with_the_wall_clock_is_found_and_shrunk() -> None:
    v = stopwatch_violation()
    print(v)
    assert "your check failed: elapsed" in v.problem
    assert len(v.steps) <= 4, v  # 1-2 steps on Python 3.11/3.12; 3.13 draws and shrinks to 4
    assert f"replay_time_schedule({v.steps!r}, seed={v.seed}, make_node=make_stopwatch, " \
           "check=stopwatch_check)" in str(v)
    replay = eval(v.replay, {"replay_time_schedule": replay_time_schedule,  # noqa: S307
                             "make_stopwatch": make_stopwatch, "stopwatch_check": stopwatch_check})
    assert replay.violation is not None and replay.violation.problem == v.problem
    fig = replay.plot()
    marks = [a for a in fig.axes[0].get_children() if a.get_gid() == VIOLATION_GID]
    assert any(getattr(a, "get_text", lambda: "")().startswith(f"step {v.step}") for a in marks)
    # at a real-time factor of 1, without pauses or jumps, the bug does not show
    assert replay_time_schedule([("tick", 0.1, 10, 1.0)], make_node=make_stopwatch,
                                check=stopwatch_check).violation is None


def test_a_node_that_assumes_time_never_goes_back_is_found() -> None:
    with pytest.raises(TimeViolation) as info:
        run_time_machine(make_estimator, estimator_check, max_examples=40, derandomize=True,
                         database=None)
    v = info.value
    assert v.problem == "your check returned False"
    assert any(s[0] == "jump_back" for s in v.steps) and len(v.steps) <= 3, v


def test_rospy_rules_hold_tick_for_tick() -> None:
    steps = [("tick", 0.05, 4, 2.0), ("pause", 0.5), ("jump", 1.0), ("jump_back", 5.0),
             ("tick", 0.1, 10, 10.0), ("jump_back", 0.3), ("tick", 0.01, 10, 0.5)]
    replay = replay_time_schedule(steps)
    assert replay.violation is None, replay.violation
    assert len(replay.fires) > 5


def test_machine_arguments_are_checked() -> None:
    with pytest.raises(DdesTypeError):
        TimeProtocolMachine.machine_for("node")  # type: ignore[arg-type]
    with pytest.raises(DdesValueError, match="unknown step"):
        replay_time_schedule([("rewind", 1.0)])
