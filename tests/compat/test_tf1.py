"""tf1's Python API in rospy scripts (ddes.compat.tf): the broadcaster, the listener's lookups,
waits on simulated time and message transforms, its exceptions, and real Noetic's answers."""

from __future__ import annotations

import inspect
import json
import textwrap
from pathlib import Path
from typing import Any

import numpy
import pytest

import ddes
from ddes import transformations as T
from ddes.compat import rospy, tf, tf2_ros
from ddes.compat.scripts import run_script
from ddes.msg import get_message_class

BROADCASTER = """
import rospy
import tf
rospy.init_node("robot")
br = tf.TransformBroadcaster()
rate = rospy.Rate(10)
i = 0
while not rospy.is_shutdown():
    now = rospy.Time.now()
    br.sendTransform((0.1 * i, 0.0, 0.0), tf.transformations.quaternion_from_euler(0, 0, 0.5),
                     now, "base_link", "odom")
    br.sendTransform((0.2, 0.0, 0.3), (0.0, 0.0, 0.0, 1.0), now, "laser", "base_link")
    i += 1
    rate.sleep()
"""

LISTENER = """
import rospy
import tf
import tf2_ros
from geometry_msgs.msg import PointStamped, PoseStamped, QuaternionStamped, Vector3Stamped
rospy.init_node("user")
listener = tf.TransformListener()
start = rospy.get_time()
try:
    listener.waitForTransform("odom", "laser", rospy.Time(0), rospy.Duration(0.5))
except tf.Exception as e:
    print("waited", rospy.get_time() - start, type(e).__name__, e)
listener.waitForTransform("/odom", "/laser", rospy.Time(0), rospy.Duration(10.0))
print("ready", listener.canTransform("odom", "laser", rospy.Time(0)))
listener.waitForTransform("odom", "laser", rospy.Time(3), rospy.Duration(10.0))
print("at", rospy.get_time())
trans, rot = listener.lookupTransform("odom", "laser", rospy.Time(3))
print("lookup", type(trans).__name__, [round(v, 9) for v in trans], [round(v, 9) for v in rot])
p = PointStamped()
p.header.frame_id = "laser"
p.header.stamp = rospy.Time(3)
p.point.x = 1.0
out = listener.transformPoint("odom", p)
print("point", out.header.frame_id, out.header.stamp.to_sec(),
      [round(v, 9) for v in (out.point.x, out.point.y, out.point.z)])
v = Vector3Stamped()
v.header = p.header
v.vector.x = 1.0
out = listener.transformVector3("odom", v)
print("vector", [round(x, 9) for x in (out.vector.x, out.vector.y, out.vector.z)])
pose = PoseStamped()
pose.header = p.header
pose.pose.orientation.w = 1.0
out = listener.transformPose("odom", pose)
print("pose", [round(x, 9) for x in (out.pose.position.x, out.pose.orientation.z,
                                      out.pose.orientation.w)])
q = QuaternionStamped()
q.header = p.header
q.quaternion.w = 1.0
out = listener.transformQuaternion("odom", q)
print("quat", round(out.quaternion.z, 9), out.header.frame_id)
m = listener.asMatrix("odom", p.header)
print("matrix", type(m).__name__, m.shape)
for exc in (tf.LookupException, tf2_ros.LookupException):
    try:
        listener.lookupTransform("odom", "nowhere", rospy.Time(0))
    except exc as e:
        print("caught", exc.__module__ == tf2_ros.LookupException.__module__, e)
try:
    listener.lookupTransform("odom", "laser", rospy.Time(100))
except tf.ExtrapolationException as e:
    print("extrapolation", isinstance(e, tf2_ros.TransformException))
print("frames", listener.frameExists("laser"), listener.frameExists("odom"),
      sorted(listener.getFrameStrings()))
print("latest", listener.getLatestCommonTime("odom", "laser").to_sec())
trans, rot = listener.lookupTransformFull("laser", rospy.Time(3), "laser", rospy.Time(2),
                                          "odom")
print("full", [round(x, 9) for x in trans])
listener.waitForTransformFull("laser", rospy.Time(3), "laser", rospy.Time(2), "odom",
                              rospy.Duration(1))
"""


def _world_with(tmp_path: Path, listener: str, *, start_robot_at: float = 1.0
                ) -> tuple[ddes.World, list[str], Any]:
    (tmp_path / "robot.py").write_text(textwrap.dedent(BROADCASTER))
    (tmp_path / "user.py").write_text(textwrap.dedent(listener))
    world = ddes.World()
    printed: list[str] = []
    done, _ = run_script(world, tmp_path / "user.py", print_line=lambda t, _e: printed.append(t))
    world.run(until=start_robot_at)
    run_script(world, tmp_path / "robot.py")
    return world, printed, done


def test_a_listener_script_waits_looks_up_and_transforms(tmp_path: Path) -> None:
    world, printed, done = _world_with(tmp_path, LISTENER)
    world.run(until=10)
    assert done.ok and done.value == 0, printed
    # the first wait times out at exactly 0.5 s of simulated time, with tf2's text
    assert printed[0] == ("waited 0.5 TransformException canTransform: target_frame odom does "
                          "not exist. canTransform: source_frame laser does not exist.")
    assert printed[1] == "ready True"
    assert printed[2] == "at 3.0"  # the wait for Time(3) ends in the instant it arrives
    c, s = T.cos(0.25), T.sin(0.25)  # rotation by 0.5 about z (half angles)
    x3 = round(0.1 * 20, 9)  # ticks 0..20 from t=1.0 to 3.0
    yaw_c, yaw_s = T.cos(0.5), T.sin(0.5)
    laser = [round(x3 + 0.2 * yaw_c, 9), round(0.2 * yaw_s, 9), 0.3]
    assert printed[3] == f"lookup list {laser} {[0.0, 0.0, round(s, 9), round(c, 9)]}"
    point = [round(x3 + 1.2 * yaw_c, 9), round(1.2 * yaw_s, 9), 0.3]
    assert printed[4] == f"point odom 3.0 {point}"
    assert printed[5] == f"vector {[round(yaw_c, 9), round(yaw_s, 9), 0.0]}"
    assert printed[6] == f"pose {[round(x3 + 0.2 * yaw_c, 9), round(s, 9), round(c, 9)]}"
    assert printed[7] == f"quat {round(s, 9)} odom"
    assert printed[8] == "matrix ndarray (4, 4)"
    lookup = '"nowhere" passed to lookupTransform argument source_frame does not exist. '
    assert printed[9:11] == [f"caught True {lookup}"] * 2
    assert printed[11] == "extrapolation True"
    assert printed[12] == "frames True False ['base_link', 'laser']"
    assert printed[13] == "latest 3.0"  # the newest transforms of both links
    # laser at t=2 seen from laser at t=3, odom fixed: 1 s of driving (1.0 m along odom's x)
    # back, in the laser frame turned by the yaw of 0.5
    assert printed[14] == f"full {[round(-yaw_c, 9), round(yaw_s, 9), 0.0]}"


def test_wait_for_transform_times_out_on_simulated_time(tmp_path: Path) -> None:
    script = """
    import rospy
    import tf
    rospy.init_node("user")
    listener = tf.TransformListener()
    rospy.sleep(2.0)
    for timeout in (0.0, 0.25, 3.0):
        start = rospy.get_time()
        try:
            listener.waitForTransform("odom", "base_link", rospy.Time(60), rospy.Duration(timeout))
        except tf.Exception as e:
            print(timeout, rospy.get_time() - start, type(e).__name__, e)
    plain = tf.Transformer()
    try:
        plain.waitForTransform("odom", "base_link", rospy.Time(0), rospy.Duration(1))
    except tf.Exception as e:
        print(rospy.get_time(), e)
    """
    world, printed, done = _world_with(tmp_path, script)
    world.run(until=20)
    assert done.ok and done.value == 0, printed
    def text(latest: float) -> str:
        return (f"Lookup would require extrapolation {60 - latest:.9f}s into the future.  "
                f"Requested time 60.000000000 but the latest data is at time {latest:.9f}, when "
                "looking up transform from frame [base_link] to frame [odom]")

    # the robot starts at 1.0 and broadcasts every 0.1 s; the user waits from 2.0
    assert printed == [
        f"0.0 0.0 TransformException {text(1.9)}",
        f"0.25 0.25 TransformException {text(2.2)}",
        f"3.0 3.0 TransformException {text(5.2)}",
        "5.25 cannot wait for transform without a dedicated thread that listens to incoming TF "
        "messages",
    ]


def test_send_transform_message_and_a_transformer_offline() -> None:
    TransformStamped = get_message_class("geometry_msgs/TransformStamped")
    t = TransformStamped()
    t.header.frame_id = "map"
    t.header.stamp = rospy.Time(1)
    t.child_frame_id = "/odom"
    t.transform.translation.x = 2.0
    t.transform.rotation.w = 1.0
    tr = tf.TransformerROS(True, rospy.Duration(10))
    tr.setTransform(t)
    assert tr.lookupTransform("/map", "odom", rospy.Time(0)) == ([2.0, 0.0, 0.0],
                                                                [0.0, 0.0, 0.0, 1.0])
    assert "odom" in tr.allFramesAsString() and tr.getTFPrefix() == ""
    assert tr.chain("map", rospy.Time(0), "odom", rospy.Time(0), "map") == ["odom", "map"]
    tr.clear()
    assert not tr.canTransform("map", "odom", rospy.Time(0))
    m = tr.fromTranslationRotation((1.0, 2.0, 3.0), T.quaternion_from_euler(0.1, 0.2, 0.3))
    assert type(m) is numpy.ndarray and m.dtype == numpy.float64
    assert m.tolist() == T.concatenate_matrices(T.translation_matrix((1.0, 2.0, 3.0)),
                                                T.quaternion_matrix(
                                                    T.quaternion_from_euler(0.1, 0.2, 0.3)))


def test_send_transform_message_publishes_one_transform(tmp_path: Path) -> None:
    script = """
    import rospy
    import tf
    from geometry_msgs.msg import TransformStamped
    rospy.init_node("robot")
    listener = tf.TransformListener()
    br = tf.TransformBroadcaster(queue_size=5)
    rospy.sleep(0.5)
    t = TransformStamped()
    t.header.frame_id = "map"
    t.header.stamp = rospy.Time.now()
    t.child_frame_id = "odom"
    t.transform.translation.y = -1.5
    t.transform.rotation.w = 1.0
    br.sendTransformMessage(t)
    listener.waitForTransform("map", "odom", rospy.Time(0), rospy.Duration(1))
    print(listener.lookupTransform("map", "odom", rospy.Time(0)))
    """
    path = tmp_path / "robot.py"
    path.write_text(textwrap.dedent(script))
    world = ddes.World()
    printed: list[str] = []
    done, _ = run_script(world, path, print_line=lambda t, _e: printed.append(t))
    world.run(until=5)
    assert done.ok and done.value == 0
    assert printed == ["([0.0, -1.5, 0.0], [0.0, 0.0, 0.0, 1.0])"]


def test_tfs_exceptions_are_tf2s() -> None:
    assert tf.Exception is tf2_ros.TransformException
    assert tf.LookupException is tf2_ros.LookupException
    assert tf.ConnectivityException is tf2_ros.ConnectivityException
    assert tf.ExtrapolationException is tf2_ros.ExtrapolationException
    assert tf.transformations.__name__ == "ddes.compat.tf.transformations"


# -- real Noetic ---------------------------------------------------------------------------------
HIERARCHY = """
import json, sys
import tf, tf2_ros
names = ["Exception", "LookupException", "ConnectivityException", "ExtrapolationException"]
tf2 = ["TransformException", "LookupException", "ConnectivityException",
       "ExtrapolationException", "InvalidArgumentException", "TimeoutException"]
print(json.dumps({a + "<" + b: issubclass(getattr(tf, a), getattr(tf2_ros, b))
                  for a in names for b in tf2}
                 | {a + "<builtins.Exception": issubclass(getattr(tf, a), Exception)
                    for a in names}
                 | {a + " is " + b: getattr(tf, a) is getattr(tf2_ros, b)
                    for a in names for b in tf2}))
"""


@pytest.mark.ros
def test_the_exception_hierarchy_is_noetics(ros_python: Any) -> None:
    theirs = ros_python(HIERARCHY, as_json=True)
    captured: list[str] = []
    ns: dict[str, Any] = {"tf": tf, "tf2_ros": tf2_ros, "json": json, "print": captured.append}
    source = HIERARCHY.replace("import json, sys", "").replace("import tf, tf2_ros", "")
    exec(source, ns)  # noqa: S102 - the same check on ddes's modules
    assert json.loads(captured[0]) == theirs
    assert sum(theirs.values()) > 10  # the relations hold, not only the negatives


def scenario(tf: Any, Time: Any, Duration: Any, msgs: dict[str, Any]) -> dict[str, Any]:
    """A tf.TransformerROS with two transforms, its answers as JSON-able values."""
    out: dict[str, Any] = {}

    def stamped(parent: str, child: str, secs: int, xyz: Any, q: Any) -> Any:
        t = msgs["TransformStamped"]()
        t.header.frame_id = parent
        t.header.stamp = Time(secs)
        t.child_frame_id = child
        (t.transform.translation.x, t.transform.translation.y,
         t.transform.translation.z) = xyz
        (t.transform.rotation.x, t.transform.rotation.y, t.transform.rotation.z,
         t.transform.rotation.w) = q
        return t

    tr = tf.TransformerROS(True, Duration(10))
    q1 = tf.transformations.quaternion_from_euler(0.1, -0.2, 0.7)
    q2 = tf.transformations.quaternion_from_euler(-0.4, 0.3, 0.2)
    for s in (1, 2):
        tr.setTransform(stamped("odom", "base_link", s, (0.5 * s, -0.25, 0.1), q1))
        tr.setTransform(stamped("base_link", "laser", s, (0.2, 0.1 * s, 0.3), q2))
    out["lookup"] = tr.lookupTransform("odom", "laser", Time(0))
    out["lookup_mid"] = tr.lookupTransform("/odom", "/laser", Time(1, 500000000))
    out["full"] = tr.lookupTransformFull("laser", Time(2), "laser", Time(1), "odom")
    out["can"] = [tr.canTransform("odom", "laser", Time(0)),
                  tr.canTransform("odom", "laser", Time(5))]
    out["exists"] = [tr.frameExists(f) for f in ("odom", "base_link", "laser", "nope")]
    out["frames"] = sorted(tr.getFrameStrings())
    out["latest"] = tr.getLatestCommonTime("odom", "laser").to_sec()
    out["chain"] = [tr.chain("odom", Time(0), "laser", Time(0), "odom"),
                    tr.chain("laser", Time(0), "odom", Time(0), "odom")]
    m = tr.fromTranslationRotation((1.0, -2.0, 0.5), q2)
    out["matrix"] = [type(m).__name__, m.tolist()]
    hdr = msgs["Header"]()
    hdr.frame_id = "laser"
    hdr.stamp = Time(2)
    out["as_matrix"] = tr.asMatrix("odom", hdr).tolist()
    ps = msgs["PointStamped"]()
    ps.header = hdr
    ps.point.x, ps.point.y, ps.point.z = 1.0, -0.5, 2.0
    r = tr.transformPoint("odom", ps)
    out["point"] = [r.header.frame_id, r.header.stamp.to_sec(), r.point.x, r.point.y, r.point.z]
    vs = msgs["Vector3Stamped"]()
    vs.header = hdr
    vs.vector.x, vs.vector.y, vs.vector.z = 1.0, -0.5, 2.0
    r = tr.transformVector3("odom", vs)
    out["vector"] = [r.header.frame_id, r.vector.x, r.vector.y, r.vector.z]
    qs = msgs["QuaternionStamped"]()
    qs.header = hdr
    qs.quaternion.x, qs.quaternion.y, qs.quaternion.z, qs.quaternion.w = q1
    r = tr.transformQuaternion("odom", qs)
    out["quaternion"] = [r.quaternion.x, r.quaternion.y, r.quaternion.z, r.quaternion.w]
    pose = msgs["PoseStamped"]()
    pose.header = hdr
    pose.pose.position.x, pose.pose.position.y = 0.3, 0.4
    (pose.pose.orientation.x, pose.pose.orientation.y, pose.pose.orientation.z,
     pose.pose.orientation.w) = q2
    r = tr.transformPose("odom", pose)
    out["pose"] = [r.header.frame_id, r.pose.position.x, r.pose.position.y, r.pose.position.z,
                   r.pose.orientation.x, r.pose.orientation.y, r.pose.orientation.z,
                   r.pose.orientation.w]
    tr.setUsingDedicatedThread(True)
    errors = []
    for target, source, secs in (("odom", "nope", 0), ("x", "y", 0), ("odom", "laser", 9),
                                 ("odom", "laser", 0)):
        try:
            tr.waitForTransform(target, source, Time(secs), Duration(0))
            errors.append("ok")
        except tf.Exception as e:
            errors.append(type(e).__name__ + ": " + str(e))
    for target, source in (("odom", "nope"), ("nope", "laser")):
        try:
            tr.lookupTransform(target, source, Time(0))
        except tf.LookupException as e:
            errors.append(type(e).__name__ + ": " + str(e))
    try:
        tr.lookupTransform("odom", "laser", Time(9))
    except tf.ExtrapolationException as e:
        errors.append(type(e).__name__ + ": " + str(e))
    out["errors"] = errors
    return out


SCENARIO = """
import json, sys
import rospy, tf
from geometry_msgs.msg import (PointStamped, PoseStamped, QuaternionStamped, TransformStamped,
                               Vector3Stamped)
from std_msgs.msg import Header
ns = {}
exec(sys.stdin.read(), ns)
msgs = dict(PointStamped=PointStamped, PoseStamped=PoseStamped, Header=Header,
            QuaternionStamped=QuaternionStamped, TransformStamped=TransformStamped,
            Vector3Stamped=Vector3Stamped)
print(json.dumps(ns["scenario"](tf, rospy.Time, rospy.Duration, msgs)))
"""


def close(mine: Any, ref: Any, where: str) -> None:
    if isinstance(ref, list):
        assert isinstance(mine, list) and len(mine) == len(ref), f"{where}: {mine} != {ref}"
        for x, y in zip(mine, ref, strict=True):
            close(x, y, where)
    elif isinstance(ref, (bool, str)) or ref is None:
        assert mine == ref, f"{where}: {mine!r} != {ref!r}"
    else:
        assert abs(mine - ref) <= 1e-12 * max(1.0, abs(ref)), f"{where}: {mine} != {ref}"


@pytest.mark.ros
def test_a_transformer_answers_as_noetics(ros_python: Any) -> None:
    source = "from typing import Any\n" + inspect.getsource(scenario)
    theirs = ros_python(SCENARIO, as_json=True, stdin=source)
    msgs = {name.split("/")[1]: get_message_class(name) for name in (
        "geometry_msgs/PointStamped", "geometry_msgs/PoseStamped", "std_msgs/Header",
        "geometry_msgs/QuaternionStamped", "geometry_msgs/TransformStamped",
        "geometry_msgs/Vector3Stamped")}
    mine = json.loads(json.dumps(scenario(tf, rospy.Time, rospy.Duration, msgs)))
    assert mine.keys() == theirs.keys()
    for key in theirs:
        close(mine[key], theirs[key], key)
