"""Every module docs/rospy.md's table lists works inside a graded node (``ddes grade``), not
only under ``ddes roslaunch``: one student node imports and uses each, and publishes what it
got; the grader reads the results from the trusted side.  Each row of the table is a test."""

from __future__ import annotations

import re
import textwrap
from pathlib import Path
from typing import Any

import pytest

from ddes.grading import Criterion, Exercise, grade
from ddes.grading.exercise import Facts

DOC = Path(__file__).resolve().parents[2] / "docs" / "rospy.md"

#: module -> (the code that uses it, leaving its answer in ``result``; the answer printed).
ROWS: dict[str, tuple[str, str]] = {
    "numpy": ("import numpy as np\n"
              "result = float(np.linalg.norm(np.array([3.0, 4.0])))", "5.0"),
    "tf.transformations": (
        "import tf.transformations as T\n"
        "q = T.quaternion_from_euler(0.0, 0.0, 0.5)\n"
        "result = (type(q).__name__, round(T.euler_from_quaternion(q)[2], 9))",
        "('ndarray', 0.5)"),
    "tf": (
        "import tf\n"
        "listener = tf.TransformListener()\n"
        "broadcaster = tf.TransformBroadcaster()\n"
        "rospy.sleep(0.1)  # as on ROS: a message sent before the connection is up is lost\n"
        "broadcaster.sendTransform((1.0, 2.0, 0.0), (0.0, 0.0, 0.0, 1.0),\n"
        "                          rospy.Time.now(), 'child', 'parent')\n"
        "listener.waitForTransform('parent', 'child', rospy.Time(0), rospy.Duration(1.0))\n"
        "trans, rot = listener.lookupTransform('parent', 'child', rospy.Time(0))\n"
        "try:\n"
        "    listener.lookupTransform('parent', 'nowhere', rospy.Time(0))\n"
        "except tf.LookupException:\n"
        "    trans = trans + ['lookup error caught']\n"
        "result = trans", "[1.0, 2.0, 0.0, 'lookup error caught']"),
    "tf2_geometry_msgs": (
        "import tf2_ros\n"
        "import tf2_geometry_msgs\n"
        "from geometry_msgs.msg import PointStamped, TransformStamped\n"
        "buf = tf2_ros.Buffer()\n"
        "t = TransformStamped()\n"
        "t.header.frame_id, t.child_frame_id = 'map', 'base'\n"
        "t.transform.translation.x, t.transform.rotation.w = 2.0, 1.0\n"
        "buf.set_transform_static(t, 'test')\n"
        "p = PointStamped()\n"
        "p.header.frame_id, p.point.x = 'base', 0.5\n"
        "a = buf.transform(p, 'map').point.x\n"
        "b = tf2_geometry_msgs.do_transform_point(p, t).point.x\n"
        "result = (a, b)", "(2.5, 2.5)"),
    "tf_conversions": (
        "import tf_conversions\n"
        "result = [round(float(x), 9) for x in\n"
        "          tf_conversions.transformations.quaternion_from_euler(0.0, 0.0, 0.0)]",
        "[0.0, 0.0, 0.0, 1.0]"),
    "message_filters": (
        "import message_filters\n"
        "from std_msgs.msg import Header\n"
        "from geometry_msgs.msg import PointStamped\n"
        "pairs = []\n"
        "a = message_filters.Subscriber('/mf_a', PointStamped)\n"
        "b = message_filters.Subscriber('/mf_b', PointStamped)\n"
        "cache = message_filters.Cache(a, 5)\n"
        "sync = message_filters.TimeSynchronizer([a, b], 10)\n"
        "sync.registerCallback(lambda x, y: pairs.append((x.point.x, y.point.x)))\n"
        "approx = message_filters.ApproximateTimeSynchronizer([a, b], 10, 0.1)\n"
        "approx.registerCallback(lambda x, y: pairs.append(('approx', x.point.x)))\n"
        "pa = rospy.Publisher('/mf_a', PointStamped, queue_size=10)\n"
        "pb = rospy.Publisher('/mf_b', PointStamped, queue_size=10)\n"
        "rospy.sleep(0.1)\n"
        "for i, (x, y) in enumerate([(1.0, 10.0), (2.0, 20.0)]):\n"
        "    stamp = rospy.Time(5 + i)\n"
        "    pa.publish(PointStamped(header=Header(stamp=stamp), point=None))\n"
        "    m = PointStamped(); m.header.stamp = stamp; m.point.x = y\n"
        "    pb.publish(m)\n"
        "    rospy.sleep(0.1)\n"
        "result = (len(pairs), len(cache.getInterval(rospy.Time(0), rospy.Time(10))))",
        "(4, 2)"),
    "sensor_msgs.point_cloud2": (
        "from sensor_msgs import point_cloud2\n"
        "from std_msgs.msg import Header\n"
        "cloud = point_cloud2.create_cloud_xyz32(Header(frame_id='base'), [(1.0, 2.0, 3.0)])\n"
        "result = list(point_cloud2.read_points(cloud, field_names=('x', 'z')))",
        "[(1.0, 3.0)]"),
    "laser_geometry": (
        "from laser_geometry import LaserProjection\n"
        "from sensor_msgs.msg import LaserScan\n"
        "from sensor_msgs import point_cloud2\n"
        "scan = LaserScan(angle_min=0.0, angle_max=0.0, angle_increment=0.1, range_min=0.1,\n"
        "                 range_max=10.0, ranges=[2.0])\n"
        "cloud = LaserProjection().projectLaser(scan)\n"
        "result = [round(v, 6) for v in next(point_cloud2.read_points(cloud, ('x', 'y')))]",
        "[2.0, 0.0]"),
    "angles": (
        "import angles, math\n"
        "result = round(angles.shortest_angular_distance(0.1, 2 * math.pi - 0.1), 9)",
        "-0.2"),
    "roslib": (
        "import roslib\n"
        "roslib.load_manifest('rospy_tutorials')\n"
        "import roslib.message\n"
        "result = roslib.message.get_message_class('std_msgs/String')._type",
        "std_msgs/String"),
}


def _script() -> str:
    parts = ["import rospy", "from std_msgs.msg import String", "rospy.init_node('user')",
             "pub = rospy.Publisher('/results', String, queue_size=100)", "rospy.sleep(0.2)"]
    for label, (code, _want) in ROWS.items():
        parts += ["try:", textwrap.indent(code, "    "),
                  f"    pub.publish({label!r} + ' = ' + str(result))",
                  "except Exception as exc:",
                  f"    pub.publish({label!r} + ' ! ' + type(exc).__name__ + ': ' + str(exc))",
                  "rospy.sleep(0.01)"]
    parts.append("rospy.spin()")
    return "\n".join(parts) + "\n"


def _listen(world: Any, _scenario: Any) -> None:
    node = world.create_node("/grader_listener")
    node.subscribe("/results", world.messages.get_message_class("std_msgs/String"),
                   lambda m: None)


SAID: list[str] = []


def _all_said(facts: Facts) -> tuple[float, list[str]]:
    said = [m.data for _t, who, m in facts.messages("/results") if who in facts.student_nodes]
    SAID[:] = said
    return float(len(said) == len(ROWS)), [f"{len(said)} of {len(ROWS)} rows answered"]


@pytest.fixture(scope="module")
def results(tmp_path_factory: pytest.TempPathFactory) -> dict[str, str]:
    sub = tmp_path_factory.mktemp("imports")
    (sub / "user.py").write_text(_script())
    ex = Exercise(id="imports", title="ROS imports", duration=3.0, build=_listen,
                  scripts=(("user.py", ()),),
                  criteria=(Criterion("1", "every row answered", 1, _all_said),))
    report = grade(ex, sub)
    assert report.problems == [], report.problems
    assert report.score == report.max_score, report.to_text()
    out: dict[str, str] = {}
    for text in SAID:
        label, _sep, rest = text.partition(" ")
        out[label] = rest
    return out


def _rows_of_the_doc() -> list[str]:
    text = DOC.read_text(encoding="utf-8")
    section = text.split("## Modules a node imports", 1)[1].split("\n## ", 1)[0]
    return re.findall(r"^\| `([^`]+)` \|", section, flags=re.M)


def test_the_doc_table_lists_every_tested_module() -> None:
    assert _rows_of_the_doc() == list(ROWS)


@pytest.mark.parametrize("module", list(ROWS))
def test_the_module_works_inside_a_graded_node(module: str, results: dict[str, str]) -> None:
    assert results[module] == "= " + ROWS[module][1], results[module]
