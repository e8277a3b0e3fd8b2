"""The SMB's optional outputs: ``/rslidar_points`` (the scan as a PointCloud2), the
``laser_pipeline:=smb`` path through ``ddes_sim/pointcloud_to_laserscan``, ``/joint_states`` of
the four wheels, ``publish_odom_tf:=false`` and ``odom_topic``; with all of them off nothing
changes (the golden digests of test_determinism.py cover that too)."""

from __future__ import annotations

import math
import struct
from typing import Any

import pytest

import ddes
from ddes.errors import DdesValueError
from ddes.msg import get_message_class
from ddes.sim import ANGLE_INCREMENT, ANGLE_MIN, Simulator, WorldSpec
from ddes.sim.pointcloud import cloud_to_ranges, cloud_xyz
from ddes.sim.simulator import WHEEL_JOINTS, WHEEL_RADIUS, WHEEL_SEPARATION

Twist = get_message_class("geometry_msgs/Twist")
Vector3 = get_message_class("geometry_msgs/Vector3")
INF = float("inf")


def _f32(x: float) -> float:
    return float(struct.unpack("<f", struct.pack("<f", x))[0])


def drive(seed: int = 4, until: float = 2.05, v: float = 0.8, w: float = 0.3,
          world_name: str = "pillars_field", topics: tuple[str, ...] = ("/scan",),
          **options: Any) -> tuple[ddes.World, Simulator, dict[str, list[Any]]]:
    world = ddes.World(seed=seed)
    sim = Simulator(world, WorldSpec.load(world_name), **options)
    probe = world.create_node("probe")
    pub = probe.advertise("/cmd_vel", Twist, queue_size=1)
    probe.create_timer(0.1, lambda e: pub.publish(Twist(linear=Vector3(x=v),
                                                        angular=Vector3(z=w))))
    got: dict[str, list[Any]] = {t: [] for t in topics}
    for t in topics:
        ddes.Subscriber(probe, t, ddes.AnyMsg, got[t].append)
    world.run(until=until)
    return world, sim, got


def typed(msgs: list[Any], type_name: str) -> list[Any]:
    cls = get_message_class(type_name)
    return [cls().deserialize(m._buff) for m in msgs]


def test_all_options_off_advertise_nothing_new() -> None:
    world, _, _ = drive()
    topics = {t for t, _ in world.master.get_published_topics()}
    assert "/rslidar_points" not in topics and "/joint_states" not in topics
    assert {"/scan", "/odom", "/tf"} <= topics


def test_pointcloud_holds_the_valid_returns_of_each_scan_and_shifts_no_draws() -> None:
    topics = ("/scan", "/odom", "/imu/data", "/rslidar_points")
    _, _, plain = drive(topics=topics[:3])
    _, _, with_cloud = drive(topics=topics, pointcloud=True)
    for t in topics[:3]:  # the same bytes on the other topics: the cloud draws nothing
        assert [m._buff for m in plain[t]] == [m._buff for m in with_cloud[t]]
    scans = typed(with_cloud["/scan"], "sensor_msgs/LaserScan")
    clouds = typed(with_cloud["/rslidar_points"], "sensor_msgs/PointCloud2")
    assert len(clouds) == len(scans) >= 20
    for scan, cloud in zip(scans, clouds, strict=True):
        assert cloud.header.stamp == scan.header.stamp
        assert cloud.header.frame_id == "base_laser" and cloud.height == 1
        assert [(f.name, f.offset, f.datatype, f.count) for f in cloud.fields] == \
            [("x", 0, 7, 1), ("y", 4, 7, 1), ("z", 8, 7, 1)]
        assert cloud.point_step == 12 and cloud.row_step == 12 * cloud.width
        assert cloud.is_dense and not cloud.is_bigendian
        beams = [i for i, r in enumerate(scan.ranges) if math.isfinite(r)]
        points = cloud_xyz(cloud)
        assert len(points) == cloud.width == len(beams)
        for i, (x, y, z) in zip(beams, points, strict=True):
            a = ANGLE_MIN + i * ANGLE_INCREMENT
            assert z == 0.0
            assert math.hypot(x, y) == pytest.approx(scan.ranges[i], abs=1e-5)
            assert math.atan2(y, x) == pytest.approx(a, abs=1e-6)
    assert any(c.width > 0 for c in clouds)


def test_pointcloud_to_laserscan_is_noetics_algorithm() -> None:
    pts = [(1.0, 0.0, 0.0), (2.0, 0.0, 0.0),       # same bin: the nearer stays
           (0.0, 1.0, 0.0),                        # bearing pi/2: bin 1
           (1.0, 1e-9, 0.5),                       # too high
           (3.0, 0.0, -0.5),                       # too low
           (0.1, 0.0, 0.0), (60.0, 0.0, 0.0),      # below range_min, above range_max
           (math.nan, 0.0, 0.0), (-1.0, -1e-9, 0.0)]  # NaN; bearing -pi+: outside
    ranges = cloud_to_ranges(pts, -0.1, 2.0, 1.5, 0.45, 50.0, -0.2, 0.2)
    assert ranges == [1.0, 1.0]  # ceil(2.1 / 1.5) = 2 bins; int(1.6708 / 1.5) = 1
    assert cloud_to_ranges([], -1.0, 1.0, 0.5, 0.0, 10.0, -1.0, 1.0, use_inf=False,
                           inf_epsilon=1.0) == [11.0] * 4
    # upstream's default min_height is the smallest positive double: a cloud at z = 0 is empty
    assert cloud_to_ranges([(1.0, 0.0, 0.0)], -1.0, 1.0, 0.5, 0.0, 10.0,
                           2.2250738585072014e-308, 1e308) == [INF] * 4


def test_laser_pipeline_smb_gives_the_scan_through_pointcloud_to_laserscan() -> None:
    direct = ddes.Console(seed=3)
    direct.run("roslaunch ddes_sim ddes_sim.launch world:=single_pillar x:=17 y:=4 "
                "pointcloud:=true &")
    smb = ddes.Console(seed=3)
    smb.run("roslaunch ddes_sim ddes_sim.launch world:=single_pillar x:=17 y:=4 "
            "laser_pipeline:=smb &")
    info = smb.run("rostopic info /scan")
    assert "/pointcloud_to_laserscan" in info and "/simulator" not in info.split("Subscribers")[0]
    assert "/rslidar_points" in smb.run("rostopic list")
    scans: list[Any] = []
    clouds: list[Any] = []
    node = smb.world.create_node("probe")
    node.subscribe("/scan", get_message_class("sensor_msgs/LaserScan"), scans.append)
    node2 = direct.world.create_node("probe")
    node2.subscribe("/rslidar_points", get_message_class("sensor_msgs/PointCloud2"),
                    clouds.append)
    smb.world.run(until=1.0)
    direct.world.run(until=1.0)
    # the same cloud in both worlds (same seed, same draws), flattened with SMB's parameters
    scan = scans[-1]
    cloud = [c for c in clouds if c.header.stamp == scan.header.stamp][0]
    assert scan.header.frame_id == "base_laser"
    assert scan.angle_increment == _f32(0.0087) and scan.angle_min == _f32(-1.5708)
    assert len(scan.ranges) == 362 and scan.range_min == _f32(0.45)
    finite = sorted(r for r in scan.ranges if math.isfinite(r))
    expected = sorted(math.hypot(x, y) for x, y, _ in cloud_xyz(cloud))
    assert len(finite) == len(expected) > 10   # 0.5 degree points, 0.0087 rad bins: one each
    assert finite == pytest.approx(expected, abs=1e-5)


def test_joint_states_turn_at_the_odometry_rates() -> None:
    world, sim, got = drive(topics=("/joint_states", "/odom"), joint_states=True, until=1.0)
    joints = typed(got["/joint_states"], "sensor_msgs/JointState")
    odoms = typed(got["/odom"], "nav_msgs/Odometry")
    assert len(joints) == len(odoms) >= 45  # 50 Hz, with the odometry
    half = 0.5 * WHEEL_SEPARATION
    for js, od in zip(joints, odoms, strict=True):
        assert js.header.stamp == od.header.stamp and js.header.frame_id == ""
        assert tuple(js.name) == WHEEL_JOINTS == ("LF_WHEEL_JOINT", "RF_WHEEL_JOINT",
                                                   "LH_WHEEL_JOINT", "RH_WHEEL_JOINT")
        v, w = od.twist.twist.linear.x, od.twist.twist.angular.z
        left, right = (v - half * w) / WHEEL_RADIUS, (v + half * w) / WHEEL_RADIUS
        assert list(js.velocity) == pytest.approx([left, right, left, right], rel=1e-12)
        assert list(js.effort) == [0.0] * 4
    assert joints[-1].position[1] > joints[-1].position[0] > 0.0  # turning left, driving on
    # noiseless, straight: each wheel has turned the distance over the radius
    _, sim2, got2 = drive(topics=("/joint_states",), joint_states=True, noise=False, w=0.0,
                          world_name="empty", until=1.985)  # the last step: 1.98 s
    last = typed(got2["/joint_states"], "sensor_msgs/JointState")[-1]
    assert last.header.stamp.to_nsec() == 1_980_000_000
    assert list(last.position) == pytest.approx([sim2.truth.x / WHEEL_RADIUS] * 4, rel=1e-9)


def test_odom_topic_and_no_odom_tf() -> None:
    world, _, got = drive(topics=("/smb_velocity_controller/odom", "/tf"),
                          odom_topic="smb_velocity_controller/odom", publish_odom_tf=False,
                          until=0.5)
    assert len(got["/smb_velocity_controller/odom"]) >= 20 and got["/tf"] == []
    topics = {t for t, _ in world.master.get_published_topics()}
    assert "/tf" not in topics and "/odom" not in topics


def test_launch_arguments_and_bad_values() -> None:
    console = ddes.Console(seed=0)
    console.run("roslaunch ddes_sim ddes_sim.launch pointcloud:=true joint_states:=true "
                "publish_odom_tf:=false odom_topic:=smb_velocity_controller/odom &")
    topics = console.run("rostopic list").split()
    for t in ("/rslidar_points", "/joint_states", "/scan", "/smb_velocity_controller/odom"):
        assert t in topics
    assert "/tf" not in topics and "/odom" not in topics
    assert console.run("rostopic type /rslidar_points") == "sensor_msgs/PointCloud2\n"
    assert "pointcloud_to_laserscan" not in console.run("rosnode list")
    with pytest.raises(DdesValueError, match="laser_pipeline must be 'direct'"):
        Simulator(ddes.World(), laser_pipeline="velodyne")
    # laser off: neither /scan nor the cloud
    world, _, _ = drive(laser=False, pointcloud=True, until=0.3)
    topics2 = {t for t, _ in world.master.get_published_topics()}
    assert "/rslidar_points" not in topics2 and "/scan" not in topics2
