"""Exercise 5: the reference earns everything, the starter at most 20 %, a proximity threshold
compared the wrong way and a crash detector that includes gravity each lose their own criteria
(and their no-false-stop share); one grading's wall time is printed.  The mutants' kill matrix
and the 20-seed sweep are in test_sensitivity.py."""

from __future__ import annotations

import shutil
import time
from pathlib import Path

from ddes.grading import REGISTRY, grade
from ddes.grading.exercises.ex5_safety import scenarios

ROOT = Path(__file__).resolve().parents[2]
SOLUTION = ROOT / "solutions" / "ex5_safety"
STARTER = ROOT / "exercises" / "ex5_safety"
PKG = "smb_highlevel_controller"
EX = REGISTRY.get("ex5_safety")


def points(report):  # type: ignore[no-untyped-def]
    return {c.id: c.points for c in report.criteria}


def variant(tmp_path: Path, rel: str, old: str, new: str) -> Path:
    sub = tmp_path / "sub"
    shutil.copytree(SOLUTION, sub)
    path = sub / PKG / rel
    text = path.read_text()
    assert old in text
    path.write_text(text.replace(old, new))
    return sub


def test_reference_earns_everything_and_one_grading_is_timed() -> None:
    start = time.perf_counter()
    report = grade(EX, SOLUTION, seed=0)
    wall = time.perf_counter() - start
    print(f"ex5_safety: one grading (3 scenarios of {EX.duration:g} s) took {wall:.2f} s wall")
    assert report.score == 100, [c.evidence for c in report.criteria]


def test_starter_earns_at_most_20_percent() -> None:
    assert grade(EX, STARTER, seed=0).score <= 20


def test_a_threshold_compared_the_wrong_way_loses_the_proximity_criteria(tmp_path: Path) -> None:
    sub = variant(tmp_path, "src/smb_highlevel_controller/safety.py",
                  "return distance < min_distance", "return distance > min_distance")
    got = points(grade(EX, sub, seed=0))
    # it stops at the first scan: never at the pillar, and falsely while starting
    assert got == {"5.1": 0.0, "5.2": 40.0, "5.3": 10.0}


def test_a_crash_test_on_the_whole_acceleration_fires_on_gravity(tmp_path: Path) -> None:
    sub = variant(tmp_path, "scripts/crash_detector.py", "ax = imu.linear_acceleration.x",
                  "a = imu.linear_acceleration\n        ax = (a.x ** 2 + a.y ** 2 + a.z ** 2) ** 0.5")
    report = grade(EX, sub, seed=0)
    got = points(report)
    assert got == {"5.1": 40.0, "5.2": 0.0, "5.3": 10.0}
    assert any("before the impact" in line for line in report.criteria[1].evidence)


def test_hidden_scenarios_come_from_the_seed() -> None:
    a, b = scenarios(5, False), scenarios(5, False)
    assert a == b and a[1].params != scenarios(6, False)[1].params
    for s in a[1:]:
        p = s.params
        assert 0.8 <= p["min_distance"] <= 1.5 and 0.4 <= p["v_approach"] <= 1.1
        assert p["pass"][1] > 2 * p["min_distance"]  # passed at more than twice the threshold
        assert p["v_turn"] * p["w_turn"] <= 1.2 and p["service_a"] != p["service_b"]
