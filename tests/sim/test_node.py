"""The simulator started the ROS way: rosrun and roslaunch with smb_gazebo.launch's arguments;
``_noise:=false`` odometry equals the truth; frames and the latched /tf_static."""

from __future__ import annotations

import math

import pytest

import ddes
from ddes.errors import DdesValueError
from ddes.msg import get_message_class
from ddes.sim import Simulator
from ddes.sim.worlds import BUNDLED_WORLDS


def simulator_of(console: ddes.Console) -> Simulator:
    node = console.world.master.lookup_node("/simulator")
    assert node is not None
    (sim,) = [e for e in node.entities if isinstance(e, Simulator)]
    return sim


def test_roslaunch_passes_the_gazebo_arguments() -> None:
    console = ddes.Console(seed=0)
    world_file = BUNDLED_WORLDS / "single_pillar.world"
    console.run(f"roslaunch ddes_sim ddes_sim.launch world_file:={world_file} x:=2.5 y:=-1 "
                "yaw:=0.5 noise:=false imu_rate:=50 &")
    sim = simulator_of(console)
    assert sim.spec.name == "single_pillar" and sim.noise is False
    assert sim.truth[:3] == (2.5, -1.0, 0.5)
    assert console.run("rosparam get /use_sim_time") == "true\n"
    topics = console.run("rostopic list").split()
    for topic in ("/clock", "/cmd_vel", "/imu/data", "/odom", "/scan", "/tf", "/tf_static"):
        assert topic in topics
    assert "/simulator/reset_world" in console.run("rosservice list")


def test_rosrun_params_and_bad_values() -> None:
    console = ddes.Console(seed=0)
    console.run("rosrun ddes_sim simulator _world:=corridor _x:=1 _yaw:=3.0 &")
    sim = simulator_of(console)
    assert sim.spec.name == "corridor" and sim.truth[:3] == (1.0, 0.0, 3.0) and sim.noise
    world = ddes.World()
    with pytest.raises(DdesValueError, match="imu_rate must divide"):
        Simulator(world, imu_rate=30)
    with pytest.raises(DdesValueError, match="real_time_factor"):
        Simulator(world, real_time_factor=0)


def test_noise_false_odometry_is_the_truth_and_frames_are_smb() -> None:
    world = ddes.World(seed=3)
    sim = Simulator(world, x=1.0, y=2.0, yaw=0.5, noise=False)
    probe = world.create_node("probe")
    twist = get_message_class("geometry_msgs/Twist")
    vec = get_message_class("geometry_msgs/Vector3")
    pub = probe.advertise("/cmd_vel", twist, queue_size=1)
    probe.create_timer(0.1, lambda e: pub.publish(twist(linear=vec(x=0.7), angular=vec(z=0.4))))
    odoms: list[object] = []
    statics: list[object] = []
    tfs: list[object] = []
    probe.subscribe("/odom", get_message_class("nav_msgs/Odometry"), odoms.append)
    probe.subscribe("/tf_static", get_message_class("tf2_msgs/TFMessage"), statics.append)
    probe.subscribe("/tf", get_message_class("tf2_msgs/TFMessage"), tfs.append)
    world.run(until=3.985)  # the last step is the odometry's (3.98 s)
    last = odoms[-1]
    assert last.header.stamp.to_nsec() == 3_980_000_000 and last.header.frame_id == "odom"
    # the odom frame starts at the robot: truth expressed in the start frame
    x0, y0, yaw0 = 1.0, 2.0, 0.5
    t = sim.truth
    dx, dy = t.x - x0, t.y - y0
    ex = math.cos(yaw0) * dx + math.sin(yaw0) * dy
    ey = -math.sin(yaw0) * dx + math.cos(yaw0) * dy
    p = last.pose.pose.position
    assert p.x == pytest.approx(ex, abs=1e-12) and p.y == pytest.approx(ey, abs=1e-12)
    assert last.twist.twist.linear.x == t.v and last.twist.twist.angular.z == t.w
    assert 2 * math.atan2(last.pose.pose.orientation.z, last.pose.pose.orientation.w) == \
        pytest.approx(t.yaw - yaw0, abs=1e-12)
    (static,) = statics  # latched, once
    frames = {(tr.header.frame_id, tr.child_frame_id): tr.transform.translation
              for tr in static.transforms}
    assert frames[("base_link", "base_laser")].x == 0.20
    assert frames[("base_link", "imu_link")].y == -0.02397
    assert len(tfs) == 199 and tfs[-1].transforms[0].child_frame_id == "base_link"


def test_real_time_factor_and_starting_paused() -> None:
    world = ddes.World(seed=1)
    slow = Simulator(world, name="slow", real_time_factor=0.5, publish_clock=False)
    paused = Simulator(world, name="held", paused=True, publish_clock=False)
    world.run(until=2.0)
    assert slow.sim_time.to_nsec() == 990_000_000  # a 10 ms step every 20 ms of kernel time
    assert paused.sim_time.to_nsec() == 0 and paused.paused
    paused.resume()
    world.run(until=2.5)
    assert paused.sim_time.to_nsec() == 500_000_000
    kinds = [e.details["paused"] for e in world.trace.select(kind="sim.pause", source="/held")]
    assert kinds == [False]
