"""Exercise 1: the reference earns 100 %, the starter at most 20 %, typical bugs lose their
criteria; the key script and hidden scenarios; the student's launch file runs in a console."""

from __future__ import annotations

import os
import shutil
from pathlib import Path

import pytest

import ddes
from ddes.grading import REGISTRY, grade
from ddes.grading.exercises.ex1_console import key_script, scenarios
from ddes.graph.world import World

REPO = Path(__file__).resolve().parents[2]
SOLUTION = REPO / "solutions" / "ex1_console"
STARTER = REPO / "exercises" / "ex1_console"
LAUNCH = "smb_common/launch/smb_teleop.launch"
TELEOP = "teleop_twist_keyboard/scripts/teleop_twist_keyboard.py"


def points(report):
    return {c.id: c.points for c in report.criteria}


def variant(tmp_path: Path, rel: str, old: str, new: str) -> Path:
    dst = tmp_path / "submission"
    if not dst.exists():
        shutil.copytree(SOLUTION, dst)
    text = (dst / rel).read_text()
    assert old in text
    (dst / rel).write_text(text.replace(old, new))
    return dst


def test_reference_scores_full_marks():
    report = grade(REGISTRY.get("ex1_console"), SOLUTION)
    assert points(report) == {"1.1": 32, "1.2": 48, "1.3": 20}, report.to_text()
    # one grading's wall time (3 scenarios of 6 simulated seconds, a sandboxed child each)
    print(f"ex1_console reference: {report.execution_time:.2f} s wall")
    assert report.execution_time < 60


def test_starter_scores_at_most_20_percent():
    report = grade(REGISTRY.get("ex1_console"), STARTER)
    assert report.score <= 0.2 * report.max_score
    assert points(report) == {"1.1": 0, "1.2": 0, "1.3": 0}, report.to_text()


def test_default_world_loses_the_world_points_only(tmp_path):
    sub = variant(tmp_path, LAUNCH, 'value="robocup_field"', 'value="empty"')
    report = grade(REGISTRY.get("ex1_console"), sub)
    assert points(report) == {"1.1": 32, "1.2": 36, "1.3": 20}
    assert any("default world 'empty'" in line for line in report.criteria[1].evidence)


def test_teleop_on_the_wrong_topic_loses_topic_and_driving(tmp_path):
    sub = variant(tmp_path, TELEOP, "rospy.Publisher('cmd_vel', Twist",
                  "rospy.Publisher('cmd_vel_teleop', Twist")
    report = grade(REGISTRY.get("ex1_console"), sub, public=True)
    # the node runs from source and answers the keys (1.1), but the robot never hears it
    assert points(report) == {"1.1": 32, "1.2": 12, "1.3": 20}
    assert any("publishes Twists on /cmd_vel_teleop; the simulator listens on /cmd_vel" in line
               for line in report.criteria[1].evidence)


def test_bundled_teleop_loses_teleop_from_source(tmp_path):
    sub = tmp_path / "submission"
    shutil.copytree(SOLUTION, sub)
    shutil.rmtree(sub / "teleop_twist_keyboard")
    got = points(grade(REGISTRY.get("ex1_console"), sub, public=True))
    assert got == {"1.1": 0, "1.2": 48, "1.3": 20}


def test_ignored_stop_key_and_wrong_answers(tmp_path):
    # a teleop that keeps the last motion on keys without a binding, and two wrong answers
    variant(tmp_path, TELEOP, "                x = 0\n                y = 0\n                z = 0\n"
            "                th = 0\n                if key", "                if key")
    variant(tmp_path, "answers.yaml", "scan_rate_hz: 10", "scan_rate_hz: 50")
    sub = variant(tmp_path, "answers.yaml", "odom_publisher: /simulator",
                  "odom_publisher: /teleop_twist_keyboard")
    report = grade(REGISTRY.get("ex1_console"), sub, public=True)
    got = points(report)
    assert got == {"1.1": 16, "1.2": 36, "1.3": 12}, report.to_text()
    lines = report.criteria[2].evidence
    assert any("scan_rate_hz: 50 is not" in x for x in lines)
    assert any("odom_publisher: '/teleop_twist_keyboard' is not" in x for x in lines)


def test_missing_launch_file_and_answers_are_named(tmp_path):
    sub = tmp_path / "submission"
    shutil.copytree(SOLUTION, sub)
    (sub / LAUNCH).unlink()
    (sub / "answers.yaml").write_text("- not a mapping\n")
    report = grade(REGISTRY.get("ex1_console"), sub, public=True)
    assert report.score == 0
    assert any(LAUNCH in p for p in report.problems)
    assert any("must map each question" in x for x in report.criteria[2].evidence)


def test_key_script_and_hidden_scenarios():
    public = scenarios(0, True)[0].params
    keys = key_script(public)
    assert keys[0] == (1_000_000_000, "i") and len(keys) == 61
    assert keys[-1] == (4_000_000_000, "k")
    assert keys[1][0] - keys[0][0] == 50_000_000
    a, b = scenarios(3, False), scenarios(3, False)
    assert [s.name for s in a] == ["public", "hidden-1", "hidden-2"]
    strip = [{k: v for k, v in s.params.items() if k != "after_launch"} for s in a]
    assert strip == [{k: v for k, v in s.params.items() if k != "after_launch"} for s in b]
    other = [{k: v for k, v in s.params.items() if k != "after_launch"}
             for s in scenarios(4, False)]
    assert strip[1:] != other[1:]
    for p in strip[1:]:
        assert p["world_yaml"] and p["stop"] not in "iIuoqwe"


def test_the_launch_file_runs_in_a_console_with_the_workspace():
    console = ddes.Console(world=World(seed=0, package_path=[os.fspath(SOLUTION)]))
    console.run(f"roslaunch {SOLUTION / LAUNCH} &")
    assert console.run("rospack find teleop_twist_keyboard").strip() == \
        os.fspath(SOLUTION / "teleop_twist_keyboard")
    console.run('rostopic pub -r 20 /teleop_twist_keyboard/keys std_msgs/String "data: i" &')
    console.run("sleep 2")
    speed = float(console.run("rostopic echo -n 1 /odom/twist/twist/linear/x").split()[0])
    assert speed == pytest.approx(0.5, abs=0.05)
