"""Exercise 4b: the reference earns 100 %, the starter at most 20 %, the hidden scenarios follow
the seed; one grading's wall time is printed (target 10 s)."""

from __future__ import annotations

from pathlib import Path

from ddes.grading import REGISTRY, grade
from ddes.grading.exercises.ex4b_actions import scenarios

REPO = Path(__file__).resolve().parents[2]
SOLUTION = REPO / "solutions" / "ex4b_actions"
STARTER = REPO / "exercises" / "ex4b_actions"
FULL = {"4b.1": 10, "4b.2": 25, "4b.3": 15, "4b.4": 10, "4b.5": 20, "4b.6": 20}


def points(report):
    return {c.id: c.points for c in report.criteria}


def test_hidden_scenarios_follow_the_seed():
    a, b = scenarios(7, False), scenarios(7, False)
    assert a == b and [s.name for s in a] == ["public", "hidden-1", "hidden-2"]
    assert scenarios(8, False)[1].params != a[1].params
    for s in a[1:]:
        assert s.hidden and s.params["action"] != "follow_path"
        assert len(s.params["follow"]) == 3 and 1.0 <= s.params["cancel_after"] <= 2.5


def test_reference_scores_full_marks():
    report = grade(REGISTRY.get("ex4b_actions"), SOLUTION)
    assert points(report) == FULL, report.to_text()
    print(f"ex4b_actions reference: {report.execution_time:.2f} s wall")


def test_reference_has_no_false_failures_on_other_seeds():
    for seed in (3, 11):
        report = grade(REGISTRY.get("ex4b_actions"), SOLUTION, seed=seed)
        assert points(report) == FULL, report.to_text()


def test_starter_scores_at_most_20_percent():
    report = grade(REGISTRY.get("ex4b_actions"), STARTER)
    assert report.percent <= 20.0, report.to_text()


def test_sensitivity_gates_hold():
    from ddes.grading.mutants import sensitivity

    result = sensitivity(REGISTRY.get("ex4b_actions"), REPO / "solutions")
    assert result.ok, result.to_text()
