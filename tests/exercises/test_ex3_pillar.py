"""Exercise 3: the reference earns 100 %, the starter at most 20 %, typical bugs lose their
criteria (a wrong sign of the gain: the P law and the hit; a marker left in the laser's frame:
the marker's placement); the algorithm's functions; the hidden scenarios."""

from __future__ import annotations

import math
import shutil
import sys
from pathlib import Path

import pytest

from ddes.grading import REGISTRY, grade
from ddes.grading.exercises.ex3_pillar import pillar_bearings, scenarios

REPO = Path(__file__).resolve().parents[2]
SOLUTION = REPO / "solutions" / "ex3_pillar"
STARTER = REPO / "exercises" / "ex3_pillar"
NODE = "smb_highlevel_controller/scripts/smb_highlevel_controller_node.py"
ALGORITHM = "smb_highlevel_controller/src/smb_highlevel_controller/algorithm.py"


def points(report):
    return {c.id: c.points for c in report.criteria}


def variant(tmp_path: Path, old: str, new: str, rel: str = NODE) -> Path:
    dst = tmp_path / "submission"
    shutil.copytree(SOLUTION, dst)
    text = (dst / rel).read_text()
    assert old in text
    (dst / rel).write_text(text.replace(old, new))
    return dst


def test_algorithm_functions():
    sys.path.insert(0, str(SOLUTION / "smb_highlevel_controller" / "src"))
    try:
        from smb_highlevel_controller import algorithm as a
    finally:
        sys.path.pop(0)
    inf = math.inf
    assert a.find_pillar([inf, 3.0, 0.2, 2.0], -1.0, 0.5, 0.45, 50.0) == (2.0, 0.5)
    assert a.find_pillar([inf, -inf], -1.0, 0.5, 0.45, 50.0) is None
    assert a.p_control(-2.0, 0.25) == -0.5
    # a quarter turn about z, then a shift: (1, 0, 0) -> (0, 1, 0) + (1, 2, 3)
    s = math.sqrt(0.5)
    got = a.transform_point((1.0, 2.0, 3.0), (0.0, 0.0, s, s), (1.0, 0.0, 0.0))
    assert got == pytest.approx((1.0, 3.0, 3.0), abs=1e-12)


def test_hidden_scenarios_follow_the_seed():
    a, b = scenarios(7, False), scenarios(7, False)
    assert a == b and [s.name for s in a] == ["public", "hidden-1", "hidden-2"]
    assert scenarios(8, False)[1].params != a[1].params
    for s in a[1:]:
        cx, cy, r = s.params["pillar"]
        assert 4.0 - 1e-3 <= math.hypot(cx, cy) <= 8.0 + 1e-3 and 0.2 <= r <= 1.0
        assert 0.6 <= s.params["p_gain"] <= 1.8
    assert all(s.hidden for s in a[1:]) and not a[0].hidden


def test_pillar_bearings_takes_every_tie():
    class Scan:
        ranges = [5.0, 2.0, 0.1, 2.0]
        angle_min, angle_increment, range_min, range_max = -1.0, 0.5, 0.45, 50.0

    assert pillar_bearings(Scan()) == [-0.5, 0.5]


def test_reference_scores_full_marks():
    report = grade(REGISTRY.get("ex3_pillar"), SOLUTION)
    assert points(report) == {"3.1": 20, "3.2": 30, "3.3": 20, "3.4": 30}, report.to_text()
    # one grading's wall time (3 scenarios of 15 simulated seconds, a sandboxed child each)
    print(f"ex3_pillar reference: {report.execution_time:.2f} s wall")
    assert report.execution_time < 60


def test_starter_scores_at_most_20_percent():
    report = grade(REGISTRY.get("ex3_pillar"), STARTER)
    assert report.score <= 0.2 * report.max_score
    assert points(report) == {"3.1": 0, "3.2": 0, "3.3": 8, "3.4": 0}, report.to_text()


def test_wrong_sign_of_the_gain_loses_the_p_law_and_the_hit(tmp_path):
    sub = variant(tmp_path, "return gain * angle", "return -gain * angle", rel=ALGORITHM)
    got = points(grade(REGISTRY.get("ex3_pillar"), sub, public=True))
    assert got["3.2"] == 0 and got["3.1"] <= 5, got
    assert got["3.3"] == 20


def test_marker_left_in_the_laser_frame_loses_its_placement(tmp_path):
    sub = variant(tmp_path, '''        x, y, z = transform_point((t.translation.x, t.translation.y, t.translation.z),
                                  (t.rotation.x, t.rotation.y, t.rotation.z, t.rotation.w),
                                  polar_to_point(distance, angle))
        marker = Marker()
        marker.header.frame_id = "odom"''', '''        x, y, z = polar_to_point(distance, angle)
        marker = Marker()
        marker.header.frame_id = header.frame_id''')
    got = points(grade(REGISTRY.get("ex3_pillar"), sub, public=True))
    assert got == {"3.1": 20, "3.2": 30, "3.3": 20, "3.4": 10}, got


def test_hard_coded_gain_loses_the_p_law_in_hidden_scenarios(tmp_path):
    sub = variant(tmp_path, 'self.p_gain = float(rospy.get_param("~p_gain"))',
                  "self.p_gain = 1.0")
    got = points(grade(REGISTRY.get("ex3_pillar"), sub))
    # the public scenario uses the student's own 1.0; the two hidden ones another gain
    assert got["3.1"] == pytest.approx(5 + 15 / 3, abs=1e-3), got
    assert got["3.3"] == 17 and got["3.4"] == 30


# -- 3.3's source facts in any spelling (docs/grading.md, "Source checks") -----------------------

from ddes.grading.exercise import Facts  # noqa: E402
from ddes.grading.exercises.common import (  # noqa: E402
    argument,
    bound_to_self,
    rospy_subscribers,
    student_script,
)

SCRIPT_3 = '''import message_filters
import rospy
import tf2_ros as tf
from functools import partial
from geometry_msgs.msg import Twist
from rospy import Publisher as Pub
from sensor_msgs.msg import LaserScan


class Controller:
    def __init__(self):
        self.cmd = Pub("/cmd_vel", data_class=Twist, queue_size=1)
        self.listener = tf.TransformListener(tf.Buffer())
        self.synced = message_filters.Subscriber("/scan", LaserScan)
        self.sub = rospy.Subscriber("/scan", LaserScan, partial(self.on_scan))

    def on_scan(self, scan):
        pass


if __name__ == "__main__":
    rospy.init_node("smb_highlevel_controller")
    Controller()
    {main}
'''


def test_the_structure_s_source_facts_in_any_spelling(tmp_path: Path) -> None:
    for name, main, in_main in (("a", "rospy.spin()", set()),
                                ("b", "marker = rospy.Publisher('m', object)", {"Publisher"})):
        root = tmp_path / name
        (root / NODE).parent.mkdir(parents=True)
        (root / NODE).write_text(SCRIPT_3.format(main=main))
        facts = Facts(exercise=None, scenario=None, world=None, outcome=None, refused=[],
                      submission=root, student_nodes=[])
        node = student_script(facts, NODE)
        made = {src.called(c) for src, c, _m in node.class_calls()}
        assert {"Publisher", "TransformListener", "Buffer"} <= made
        # message_filters' Subscriber takes no callback: only rospy's counts
        subs = rospy_subscribers(node)
        assert len(subs) == 1
        assert all(bound_to_self(s, argument(c, 2, "callback"), m) for s, c, m in subs)
        assert node.main_called() & {"Publisher", "Buffer", "TransformListener"} == in_main
