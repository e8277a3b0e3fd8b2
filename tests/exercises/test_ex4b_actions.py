"""Exercise 4b: the reference earns 100 %, the starter at most 20 %, the hidden scenarios follow
the seed, a run ends when the grader's schedule is over; one grading's wall time is printed
(target 10 s).  The mutants' kill matrix and the 20-seed sweep are in test_sensitivity.py."""

from __future__ import annotations

import shutil
import tempfile
import time
from pathlib import Path

from ddes.grading import REGISTRY, grade
from ddes.grading.exercises.ex4b_actions import DURATION, scenarios
from ddes.grading.grader import prepare, run_scenario

REPO = Path(__file__).resolve().parents[2]
SOLUTION = REPO / "solutions" / "ex4b_actions"
STARTER = REPO / "exercises" / "ex4b_actions"
EX = REGISTRY.get("ex4b_actions")
FULL = {"4b.1": 10, "4b.2": 25, "4b.3": 15, "4b.4": 10, "4b.5": 15, "4b.6": 15, "4b.7": 10}


def points(report):  # type: ignore[no-untyped-def]
    return {c.id: c.points for c in report.criteria}


def test_hidden_scenarios_follow_the_seed() -> None:
    a, b = scenarios(7, False), scenarios(7, False)
    assert a == b and [s.name for s in a] == ["public", "hidden-1", "hidden-2"]
    assert scenarios(8, False)[1].params != a[1].params
    for s in a[1:]:
        p = s.params
        assert s.hidden and p["action"] != "follow_path"
        assert len(p["follow"]) == 3 and 1.0 <= p["cancel_after"] <= 2.5
        assert 1.0 <= p["client_side"] <= 3.0 and 1.5 <= p["client_cancel"] <= 3.5


def test_reference_scores_full_marks() -> None:
    start = time.perf_counter()
    report = grade(EX, SOLUTION)
    wall = time.perf_counter() - start
    assert points(report) == FULL, report.to_text()
    print(f"ex4b_actions reference: one grading (3 scenarios) took {wall:.2f} s wall")


def test_the_run_ends_when_the_schedule_is_over() -> None:
    tmp = Path(tempfile.mkdtemp())
    try:
        prepare(SOLUTION, tmp / "submission")
        world, facts = run_scenario(EX, scenarios(0, False)[0], tmp / "submission", None)
    finally:
        shutil.rmtree(tmp)
    run, client = world._ddes_ex4b, world._ddes_ex4b_client
    assert run.finished and client.result_ns > 0 and client.listening_at_result
    # every phase ran, the last goal ended, and the world stopped well before the cap
    assert [g.phase for g in run.goals] == ["follow", "empty", "cancel", "old", "new", "blocked"]
    assert run.goals[-1].done_ns is not None and world.now < DURATION * 1e9 / 2


def test_starter_scores_at_most_20_percent() -> None:
    report = grade(EX, STARTER)
    assert report.percent <= 20.0, report.to_text()


# -- the class rule of 4b.1 and 4b.7 accepts every correct form (docs/grading.md) ----------------

import pytest  # noqa: E402

from ddes.grading.exercise import Facts  # noqa: E402
from ddes.grading.exercises.ex4b_actions import _CLIENT_CALLS, _class_rule  # noqa: E402

CLIENT_SCRIPT = '''import actionlib
import actionlib as al
import rospy
from actionlib import SimpleActionClient as Client


class FollowPathClient:
    def __init__(self):
        self.client = actionlib.SimpleActionClient("follow_path", object)

    def send_goal(self):
        self.client.send_goal(None)

    def wait_for_result(self):
        return self.client.wait_for_result()


if __name__ == "__main__":
    rospy.init_node("follow_path_client")
{main}
'''


@pytest.mark.parametrize("main, why", [
    ("    FollowPathClient().send_goal()", ""),
    ("    client = FollowPathClient()\n    client.send_goal()\n    client.wait_for_result()", ""),
    ("    def main():\n        c = FollowPathClient()\n        c.send_goal()\n    main()", ""),
    ("    client = FollowPathClient()\n    client.client.send_goal(None)", "send_goal"),
    ("    FollowPathClient()\n    al.SimpleActionClient('x', object)", "SimpleActionClient"),
    ("    FollowPathClient()\n    Client('x', object).wait_for_server()",
     "SimpleActionClient, wait_for_server"),
    ("    rospy.spin()", "does not define (or import) a class"),
])
def test_the_client_s_main_part(tmp_path: Path, main: str, why: str) -> None:
    rel = tmp_path / "smb_follow_path" / "scripts" / "follow_path_client.py"
    rel.parent.mkdir(parents=True)
    rel.write_text(CLIENT_SCRIPT.format(main=main))
    facts = Facts(exercise=None, scenario=None, world=None, outcome=None, refused=[],
                  submission=tmp_path, student_nodes=[])
    got = _class_rule(facts, "follow_path_client.py", _CLIENT_CALLS)
    assert (why in got and got != "") if why else got == "", got
