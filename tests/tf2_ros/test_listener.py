"""TransformListener and the broadcasters over a world: authority, static latching and
accumulation, the jump back in time, a listener's wait, and rospy scripts with ``import tf2_ros``."""

from __future__ import annotations

import textwrap
from pathlib import Path
from typing import Any

import pytest

import ddes
from ddes.compat.scripts import run_script
from ddes.errors import DdesTypeError
from ddes.msg import get_message_class
from ddes.tf2_ros import (
    Buffer,
    StaticTransformBroadcaster,
    TransformBroadcaster,
    TransformListener,
)
from ddes.time.rostime import Time

TransformStamped = get_message_class("geometry_msgs/TransformStamped")


def stamped(parent: str, child: str, stamp: Any, x: float) -> Any:
    ts = TransformStamped()
    ts.header.stamp = stamp
    ts.header.frame_id = parent
    ts.child_frame_id = child
    ts.transform.translation.x = x
    ts.transform.rotation.w = 1.0
    return ts


def robot_world() -> tuple[Any, Any, Buffer]:
    """/robot: base_link->laser static, odom->base_link at 10 Hz moving 0.1 m per tick."""
    world = ddes.World()
    robot = world.create_node("robot")
    listener = world.create_node("listener")
    buf = Buffer()
    TransformListener(listener, buf)
    StaticTransformBroadcaster(robot).sendTransform(
        stamped("base_link", "laser", robot.get_rostime(), 0.2))
    br = TransformBroadcaster(robot)

    def drive() -> Any:
        rate = ddes.Rate(robot, 10)
        i = 0
        while True:
            br.sendTransform(stamped("odom", "base_link", robot.get_rostime(), 0.1 * i))
            i += 1
            yield rate.sleep()

    robot.process(drive())
    return world, listener, buf


def test_the_listener_fills_the_buffer_with_the_publishers_authority() -> None:
    world, _listener, buf = robot_world()
    world.run(until=1.05)
    t = buf.lookup_transform("odom", "laser", Time(0, 500_000_000))
    assert t.transform.translation.x == pytest.approx(0.7)
    frames = buf.all_frames_as_yaml()
    assert "broadcaster: '/robot'" in frames
    assert buf.all_frames_as_string().splitlines() == [  # tf2's order: frames as they came
        "Frame laser exists with parent base_link.", "Frame base_link exists with parent odom."]


def test_static_transforms_are_latched_and_accumulate() -> None:
    world = ddes.World()
    pub = world.create_node("pub")
    sb = StaticTransformBroadcaster(pub)
    sb.sendTransform(stamped("base", "laser", Time(), 0.2))
    sb.sendTransform([stamped("base", "camera", Time(), 0.3)])
    sb.sendTransform(stamped("base", "laser", Time(), 0.25))  # replaces laser's
    world.run(until=1.0)
    late = world.create_node("late")  # subscribes long after: gets the latched message
    buf = Buffer()
    TransformListener(late, buf)
    world.run(until=2.0)
    assert buf.lookup_transform("base", "laser", Time()).transform.translation.x == 0.25
    assert buf.lookup_transform("base", "camera", Time()).transform.translation.x == 0.3
    assert "broadcaster: '/pub'" in buf.all_frames_as_yaml()


def test_a_jump_back_in_time_clears_the_buffer_with_rospys_text() -> None:
    world = ddes.World()
    world.use_sim_time = True
    clock_pub = world.create_node("clock")
    Clock = get_message_class("rosgraph_msgs/Clock")
    clock = ddes.Publisher(clock_pub, "/clock", Clock, queue_size=10)
    listener = world.create_node("listener", use_sim_time=True)
    lines: list[str] = []
    world.log_output = lambda line, _level: lines.append(line)
    buf = Buffer()
    TransformListener(listener, buf)
    br = TransformBroadcaster(world.create_node("robot"))

    def play() -> Any:
        for sec in (5, 6, 2):  # a bag loop starts again at 2 s
            yield world.env.timeout(100_000_000)
            clock.publish(Clock(clock=Time(sec)))
            yield world.env.timeout(10_000_000)
            br.sendTransform(stamped("odom", "base", Time(sec), float(sec)))
            yield world.env.timeout(10_000_000)
            if sec == 6:
                assert buf.can_transform("odom", "base", Time(5))

    world.process(play())
    world.run(until=1.0)
    assert [x for x in lines if "jump" in x] == [
        "[WARN] [0.350000, 2.000000]: Detected jump back in time of 4.000000s. Clearing TF buffer."]
    assert not buf.can_transform("odom", "base", Time(5))  # cleared, then only the 2 s one
    assert buf.can_transform("odom", "base", Time(2))


def test_the_node_comes_first() -> None:
    world = ddes.World()
    with pytest.raises(DdesTypeError, match=r"TransformListener\(node, buffer\)"):
        TransformListener(Buffer(), world.create_node("n"))  # type: ignore[arg-type]
    with pytest.raises(DdesTypeError, match="takes the node first"):
        TransformBroadcaster("robot")  # type: ignore[arg-type]


def test_a_rospy_script_blocks_on_lookup_transform(tmp_path: Path) -> None:
    script = tmp_path / "tf_user.py"
    script.write_text(textwrap.dedent("""
        import rospy
        import tf2_ros
        import tf2_geometry_msgs  # registers PointStamped with Buffer.transform, as on ROS
        from geometry_msgs.msg import PointStamped
        rospy.init_node("tf_user")
        buf = tf2_ros.Buffer()
        listener = tf2_ros.TransformListener(buf)
        try:
            buf.lookup_transform("odom", "laser", rospy.Time(3), rospy.Duration(0.5))
        except tf2_ros.ExtrapolationException as e:
            print("after", rospy.get_time(), type(e).__name__)
        t = buf.lookup_transform("odom", "laser", rospy.Time(3), rospy.Duration(5))
        print("at", rospy.get_time(), round(t.transform.translation.x, 9))
        print(buf.can_transform("odom", "laser", rospy.Time(20), rospy.Duration(1)),
              rospy.get_time())
        p = PointStamped()
        p.header.frame_id = "laser"
        p.header.stamp = rospy.Time(3)
        print(round(buf.transform(p, "odom").point.x, 9))
    """))
    world, _listener, _buf = robot_world()
    printed: list[str] = []
    done, _ = run_script(world, script, print_line=lambda t, _e: printed.append(t))
    world.run(until=10)
    assert done.value == 0
    assert printed[0].startswith("after 0.5 ExtrapolationException")
    assert printed[1:] == ["at 3.0 3.2", "False 4.0", "3.2"]
