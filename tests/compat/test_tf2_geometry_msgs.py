"""tf2_geometry_msgs in rospy scripts: importing it registers its types with Buffer.transform (per
world), its do_transform_* functions, tf2_ros.TransformRegistration, and Noetic's answers."""

from __future__ import annotations

import inspect
import json
import textwrap
from pathlib import Path
from typing import Any

import pytest

import ddes
from ddes.compat import tf2_geometry_msgs
from ddes.compat.scripts import run_script
from ddes.compat.tf2_ros import TransformRegistration, TypeException
from ddes.errors import DdesValueError
from ddes.msg import get_message_class
from ddes.tf2_ros import Buffer as YieldBuffer
from ddes.tf2_ros import geometry

PointStamped = get_message_class("geometry_msgs/PointStamped")
TransformStamped = get_message_class("geometry_msgs/TransformStamped")

#: Publishes odom -> laser (static), then imports tf2_geometry_msgs after trying once.
BEFORE_AND_AFTER = """
import rospy
import tf2_ros
from geometry_msgs.msg import PointStamped, TransformStamped, WrenchStamped
rospy.init_node("user")
buf = tf2_ros.Buffer()
tf2_ros.TransformListener(buf)
t = TransformStamped()
t.header.frame_id = "odom"
t.child_frame_id = "laser"
t.transform.translation.x = 1.0
t.transform.rotation.z = 1.0
tf2_ros.StaticTransformBroadcaster().sendTransform(t)
buf.can_transform("odom", "laser", rospy.Time(0), rospy.Duration(1))
p = PointStamped()
p.header.frame_id = "laser"
p.point.x = 2.0
try:
    buf.transform(p, "odom")
except tf2_ros.TypeException as e:
    print("refused:", e)
try:
    tf2_ros.TransformRegistration().get(PointStamped)
except tf2_ros.TypeException as e:
    print("unregistered:", e)
import tf2_geometry_msgs
out = buf.transform(p, "odom", rospy.Duration(1))
print("accepted:", out.header.frame_id, out.point.x, out.point.y, type(out).__name__)
print(tf2_ros.TransformRegistration().get(PointStamped) is tf2_geometry_msgs.do_transform_point)
w = WrenchStamped()
w.header.frame_id = "laser"
w.wrench.force.x = 1.0
w.wrench.torque.y = 1.0
out = buf.transform(w, "odom")
print("wrench:", out.wrench.force.x, out.wrench.force.y, out.wrench.torque.x,
      out.wrench.torque.y)
try:
    buf.transform(t, "odom")
except tf2_ros.TypeException as e:
    print("still refused:", e)
"""


def _run(tmp_path: Path, world: ddes.World, body: str, name: str = "user.py") -> list[str]:
    path = tmp_path / name
    path.write_text(textwrap.dedent(body))
    printed: list[str] = []
    done, _ = run_script(world, path, print_line=lambda t, _e: printed.append(t))
    world.run(until=world.now / 1e9 + 5)
    assert done.ok and done.value == 0, printed
    return printed


def _text(cls: Any) -> str:
    return f"Type {cls} if not loaded or supported"


def test_transform_refuses_a_point_until_tf2_geometry_msgs_is_imported(tmp_path: Path) -> None:
    printed = _run(tmp_path, ddes.World(), BEFORE_AND_AFTER)
    assert printed == [
        f"refused: {_text(PointStamped)}",
        f"unregistered: {_text(PointStamped)}",
        "accepted: odom -1.0 0.0 PointStamped",  # turned by pi about z, then 1 m along x
        "True",
        "wrench: -1.0 0.0 0.0 -1.0",
        f"still refused: {_text(TransformStamped)}",
    ]


def test_two_worlds_do_not_share_the_registration(tmp_path: Path) -> None:
    first = ddes.World()
    _run(tmp_path, first, "import rospy\nimport tf2_geometry_msgs\nrospy.init_node('a')\n",
         "a.py")
    second = ddes.World()
    printed = _run(tmp_path, second, BEFORE_AND_AFTER)
    assert printed[0] == f"refused: {_text(PointStamped)}"  # the first world's import is its own
    # and a third world's script that never imports it is refused after the others did
    third = ddes.World()
    lines = _run(tmp_path, third, BEFORE_AND_AFTER.split("import tf2_geometry_msgs\n")[0])
    assert lines == printed[:2]


def test_a_script_registers_its_own_type(tmp_path: Path) -> None:
    script = """
    import rospy
    import tf2_ros
    from geometry_msgs.msg import PointStamped, TransformStamped
    rospy.init_node("user")
    buf = tf2_ros.Buffer()
    t = TransformStamped()
    t.header.frame_id = "odom"
    t.child_frame_id = "laser"
    t.transform.rotation.w = 1.0
    buf.set_transform_static(t, "me")

    def mine(obj, transform):
        return ("mine", obj.header.frame_id, transform.header.frame_id)

    tf2_ros.TransformRegistration().add(PointStamped, mine)
    p = PointStamped()
    p.header.frame_id = "laser"
    print(buf.transform(p, "odom"))
    import tf2_geometry_msgs  # the world's first import registers its functions
    print(buf.transform(p, "odom").header.frame_id)
    tf2_ros.TransformRegistration().add(PointStamped, mine)
    import tf2_geometry_msgs  # a later import leaves the registry as it is (ROS: cached module)
    print(buf.transform(p, "odom"))
    tf2_ros.TransformRegistration().add(PointStamped, tf2_geometry_msgs.do_transform_point)
    print(buf.transform(p, "odom", new_type=PointStamped).header.frame_id)
    try:
        buf.transform(p, "odom", new_type=TransformStamped)
    except tf2_ros.TypeException as e:
        print(str(e).split(" (")[0])
    """
    printed = _run(tmp_path, ddes.World(), script)
    assert printed == ["('mine', 'laser', 'odom')", "odom", "('mine', 'laser', 'odom')", "odom",
                       _text(TransformStamped)]


def test_the_yield_style_buffer_keeps_its_three_types() -> None:
    buf = YieldBuffer()
    t = TransformStamped()
    t.header.frame_id = "odom"
    t.child_frame_id = "laser"
    t.transform.rotation.w = 1.0
    buf.set_transform_static(t, "me")
    p = PointStamped()
    p.header.frame_id = "laser"
    p.point.x = 1.0
    assert buf.transform(p, "odom").point.x == 1.0
    with pytest.raises(DdesValueError, match="running world"):
        TransformRegistration()


def test_the_module_has_noetics_names() -> None:
    assert tf2_geometry_msgs.do_transform_pose_stamped is tf2_geometry_msgs.do_transform_pose
    assert tf2_geometry_msgs.do_transform_point is geometry.do_transform_point
    p = PointStamped()
    assert tf2_geometry_msgs.to_msg_msg(p) is p and tf2_geometry_msgs.from_msg_msg(p) is p
    assert not hasattr(tf2_geometry_msgs, "transform_to_kdl")
    assert issubclass(TypeException, Exception)


# -- real Noetic ---------------------------------------------------------------------------------
def transforms(m: Any, msgs: dict[str, Any]) -> dict[str, Any]:
    """do_transform_* of tf2_geometry_msgs on fixed inputs, as JSON-able values."""
    out: dict[str, Any] = {}
    rotations = ([0.0, 0.0, 0.0, 1.0], [0.1, -0.2, 0.3, 0.9], [0.0, 0.0, 1.0, 0.0],
                 [0.5, 0.5, -0.5, 0.5], [0.2, 0.4, 0.1, -0.3])  # the last not normalised
    for k, q in enumerate(rotations):
        t = msgs["TransformStamped"]()
        t.header.frame_id = "odom"
        t.header.stamp.secs = 7
        t.header.seq = 3
        t.child_frame_id = "laser"
        t.transform.translation.x, t.transform.translation.y = 1.5, -0.25
        t.transform.translation.z = 0.75
        t.transform.rotation.x, t.transform.rotation.y = q[0], q[1]
        t.transform.rotation.z, t.transform.rotation.w = q[2], q[3]
        p = msgs["PointStamped"]()
        p.header.frame_id = "laser"
        p.point.x, p.point.y, p.point.z = 1.0, 2.0, -3.0
        r = m.do_transform_point(p, t)
        out[f"point{k}"] = [r.header.frame_id, r.header.stamp.secs, r.header.seq,
                            r.point.x, r.point.y, r.point.z]
        v = msgs["Vector3Stamped"]()
        v.vector.x, v.vector.y, v.vector.z = -1.0, 0.5, 2.0
        r = m.do_transform_vector3(v, t)
        out[f"vector{k}"] = [r.header.frame_id, r.vector.x, r.vector.y, r.vector.z]
        pose = msgs["PoseStamped"]()
        pose.pose.position.x, pose.pose.position.y = 0.3, -0.6
        pose.pose.orientation.x, pose.pose.orientation.y = 0.0, 0.6
        pose.pose.orientation.z, pose.pose.orientation.w = 0.0, 0.8
        r = m.do_transform_pose(pose, t)
        out[f"pose{k}"] = [r.header.frame_id, r.pose.position.x, r.pose.position.y,
                           r.pose.position.z, r.pose.orientation.x, r.pose.orientation.y,
                           r.pose.orientation.z, r.pose.orientation.w]
        w = msgs["WrenchStamped"]()
        w.wrench.force.x, w.wrench.force.z = 2.0, -1.0
        w.wrench.torque.y = 0.5
        r = m.do_transform_wrench(w, t)
        out[f"wrench{k}"] = [r.header.frame_id, r.wrench.force.x, r.wrench.force.y,
                             r.wrench.force.z, r.wrench.torque.x, r.wrench.torque.y,
                             r.wrench.torque.z]
    return out


NOETIC = """
import json, sys
import tf2_geometry_msgs
from geometry_msgs.msg import (PointStamped, PoseStamped, TransformStamped, Vector3Stamped,
                               WrenchStamped)
ns = {}
exec(sys.stdin.read(), ns)
msgs = dict(PointStamped=PointStamped, PoseStamped=PoseStamped,
            TransformStamped=TransformStamped, Vector3Stamped=Vector3Stamped,
            WrenchStamped=WrenchStamped)
names = sorted(n for n in dir(tf2_geometry_msgs) if n.startswith(("do_", "to_", "from_")))
print(json.dumps([ns["transforms"](tf2_geometry_msgs, msgs), names]))
"""


@pytest.mark.ros
def test_do_transform_matches_noetic(ros_python: Any) -> None:
    theirs, names = ros_python(NOETIC, as_json=True,
                               stdin="from typing import Any\n" + inspect.getsource(transforms))
    msgs = {n: get_message_class(f"geometry_msgs/{n}") for n in (
        "PointStamped", "PoseStamped", "TransformStamped", "Vector3Stamped", "WrenchStamped")}
    mine = json.loads(json.dumps(transforms(tf2_geometry_msgs, msgs)))
    assert mine.keys() == theirs.keys()
    for key, ref in theirs.items():
        assert mine[key][0] == ref[0], key
        for a, b in zip(mine[key][1:], ref[1:], strict=True):
            assert abs(a - b) <= 1e-12 * max(1.0, abs(b)), f"{key}: {mine[key]} != {ref}"
    # every do_/to_/from_ name of Noetic's module is here (ddes adds do_transform_pose_stamped)
    assert set(names) <= set(tf2_geometry_msgs.__all__)
    assert set(tf2_geometry_msgs.__all__) - set(names) == {"do_transform_pose_stamped"}


TYPE_TEXT = """
import json
import tf2_ros
from geometry_msgs.msg import PointStamped
out = []
try:
    tf2_ros.Buffer(debug=False).transform(PointStamped(), "odom")
except tf2_ros.TypeException as e:
    out.append(str(e))
try:
    tf2_ros.TransformRegistration().get(PointStamped)
except tf2_ros.TypeException as e:
    out.append(str(e))
import tf2_geometry_msgs
out.append(tf2_ros.TransformRegistration().get(PointStamped).__name__)
print(json.dumps([out, str(PointStamped)]))
"""


@pytest.mark.ros
def test_the_refusal_is_noetics(ros_python: Any, tmp_path: Path) -> None:
    (texts, cls) = ros_python(TYPE_TEXT, as_json=True)
    # Noetic's text with its class's name; ddes's with the world's class
    assert texts == [_text(cls), _text(cls), "do_transform_point"]
    printed = _run(tmp_path, ddes.World(), BEFORE_AND_AFTER)
    assert printed[:2] == [f"refused: {texts[0].replace(cls, str(PointStamped))}",
                           f"unregistered: {texts[1].replace(cls, str(PointStamped))}"]
