"""Exercise 4c (ROS time): the reference earns everything, the starter nothing; the grader's
clock sources (kernel time, the simulator at half speed, paused and restarted, rosbag play
--clock -r 2 and --loop) are what the checks read; a hard-coded rate loses the hidden scenarios;
one grading's wall time is printed.  The mutants and the 20-seed sweep are in
test_sensitivity.py."""

from __future__ import annotations

import shutil
import time
from pathlib import Path

from ddes.grading import REGISTRY, grade
from ddes.grading.exercises.ex4c_time import HIDDEN_RATE, scenarios
from ddes.grading.grader import run_scenario
from ddes.grading.submission import prepare

ROOT = Path(__file__).resolve().parents[2]
SOLUTION = ROOT / "solutions" / "ex4c_time"
STARTER = ROOT / "exercises" / "ex4c_time"
NODE = "smb_watchdog/scripts/watchdog_node.py"
EX = REGISTRY.get("ex4c_time")


def points(report):  # type: ignore[no-untyped-def]
    return {c.id: c.points for c in report.criteria}


def test_reference_earns_everything_and_one_grading_is_timed() -> None:
    start = time.perf_counter()
    report = grade(EX, SOLUTION, seed=0)
    wall = time.perf_counter() - start
    print(f"ex4c_time: one grading (6 scenarios of {EX.duration:g} s) took {wall:.2f} s wall")
    assert report.score == 100, [c.evidence for c in report.criteria]
    assert not report.problems, report.problems


def test_starter_earns_at_most_20_percent() -> None:
    assert grade(EX, STARTER, seed=0).score <= 20


def test_a_hard_coded_rate_loses_the_hidden_scenarios(tmp_path: Path) -> None:
    sub = tmp_path / "sub"
    shutil.copytree(SOLUTION, sub, ignore=shutil.ignore_patterns("mutants"))
    node = sub / NODE
    text = node.read_text()
    old = 'self.rate = float(rospy.get_param("~rate"))'
    assert old in text
    node.write_text(text.replace(old, "self.rate = 2.0"))
    got = points(grade(EX, sub, seed=0))
    assert got["4c.1"] == 10.0  # the three public scenarios keep their points, hidden ones not
    assert got["4c.2"] == 15.0 and got["4c.7"] == 10.0


def test_the_scenarios_clock_sources_are_what_the_student_node_reads(tmp_path: Path) -> None:
    """Under /use_sim_time the node's stamps are /clock values: the simulator's (at half the
    kernel's speed, standing still while paused, from zero again after the restart) and the
    bag's (from 100 s, at twice the kernel's speed)."""
    sub = tmp_path / "sub"
    prepare(SOLUTION, sub)
    sim, bag = [s for s in scenarios(0, True)
                if not s.hidden and s.params["kind"] in ("simulator", "bag")]
    world, facts = run_scenario(EX, sim, sub, None)
    beats = [(t, m.stamp.to_nsec()) for t, who, m in facts.messages("/heartbeat")
             if who == "/watchdog"]
    assert world.use_sim_time and beats
    pause0, length = sim.params["pause"]
    assert not [t for t, _ in beats if pause0 * 1e9 + 0.1e9 < t < (pause0 + length) * 1e9]
    before = [s for t, s in beats if t < sim.params["restart"] * 1e9]
    after = [s for t, s in beats if t > sim.params["restart"] * 1e9]
    assert 10.0e9 < before[-1] < 11.5e9 and after and after[0] < 1e9
    world, facts = run_scenario(EX, bag, sub, None)
    stamps = [m.stamp.to_nsec() for _t, who, m in facts.messages("/heartbeat")
              if who == "/watchdog"]
    assert min(stamps) >= 100e9 and max(stamps) <= 114.1e9


def test_hidden_scenarios_come_from_the_seed() -> None:
    a, b = scenarios(5, False), scenarios(5, False)
    assert a == b and [s.name for s in a if s.hidden] == [
        "hidden-1", "hidden-2", "hidden-3"]
    assert [s.params["kind"] for s in a if s.hidden] == ["kernel", "simulator", "bag"]
    assert all(s.params["rate"] == HIDDEN_RATE for s in a if s.hidden)
    assert [s.params for s in a if s.hidden] != [s.params for s in scenarios(6, False)
                                                  if s.hidden]
    assert [s.params for s in a if not s.hidden] == [s.params for s in scenarios(6, False)
                                                      if not s.hidden]
