"""Node types of ``ddes_sim``: the deterministic 2D robot (``rosrun ddes_sim simulator``).

``simulator`` reads its private parameters as Gazebo's launch arguments are passed to it::

    rosrun ddes_sim simulator _world:=single_pillar _x:=0 _y:=0 _yaw:=0 _noise:=false

``~world`` (a bundled world's name, default ``empty``) or ``~world_file`` (a ``.yaml`` or
Gazebo ``.world`` path; wins when set), ``~x``, ``~y``, ``~yaw`` (start pose), ``~noise``
(default true), ``~real_time_factor`` (1.0), ``~laser_enabled`` (true), ``~imu_rate`` (100),
``~publish_odom_tf`` (true), ``~ground_truth`` (false), ``~odom_topic`` (``odom``),
``~paused`` (false), ``~pointcloud`` (false: ``/rslidar_points`` too), ``~laser_pipeline``
(``direct``; ``smb``: only ``/rslidar_points``, for ``pointcloud_to_laserscan``),
``~joint_states`` (false).  See docs/sim.md.

``pointcloud_to_laserscan`` is the noetic node of that name (``cloud_in`` in, ``scan`` out, its
parameters and defaults; :mod:`ddes.sim.pointcloud`); ``target_frame`` must be empty (the
scan stays in the cloud's frame).
"""

from __future__ import annotations

import struct
from typing import TYPE_CHECKING, Any

from ddes.errors import DdesValueError
from ddes.msg import get_message_class
from ddes.nodes import NodeType
from ddes.sim import Simulator, WorldSpec
from ddes.sim.frames import robot_frames
from ddes.sim.pointcloud import cloud_to_ranges, cloud_xyz

if TYPE_CHECKING:
    from ddes.graph.node import Node


def _bool(node: Node, name: str, default: bool) -> bool:
    value: Any = node.get_param("~" + name, default)
    if isinstance(value, str) and value.lower() in ("true", "false", "1", "0"):
        return value.lower() in ("true", "1")
    if isinstance(value, (bool, int)) and not isinstance(value, float):
        return bool(value)
    raise DdesValueError(f"{node.name}: parameter ~{name} must be true or false, got {value!r}")


def _float(node: Node, name: str, default: float) -> float:
    value: Any = node.get_param("~" + name, default)
    if isinstance(value, bool):
        raise DdesValueError(f"{node.name}: parameter ~{name} must be a number, got {value!r}")
    try:
        return float(value)
    except (TypeError, ValueError):
        raise DdesValueError(f"{node.name}: parameter ~{name} must be a number, "
                             f"got {value!r}") from None


def simulator(node: Node) -> None:
    """Start the simulator on ``node`` (then it spins, as gazebo does)."""
    world_file = str(node.get_param("~world_file", "") or "")
    spec = WorldSpec.load(world_file or str(node.get_param("~world", "empty")))
    Simulator(
        node.world, spec,
        x=_float(node, "x", 0.0), y=_float(node, "y", 0.0), yaw=_float(node, "yaw", 0.0),
        noise=_bool(node, "noise", True), node=node,
        real_time_factor=_float(node, "real_time_factor", 1.0),
        laser=_bool(node, "laser_enabled", True),
        imu_rate=_float(node, "imu_rate", 100.0),
        publish_odom_tf=_bool(node, "publish_odom_tf", True),
        ground_truth=_bool(node, "ground_truth", False),
        odom_topic=str(node.get_param("~odom_topic", "odom")),
        paused=_bool(node, "paused", False),
        pointcloud=_bool(node, "pointcloud", False),
        laser_pipeline=str(node.get_param("~laser_pipeline", "direct")),
        joint_states=_bool(node, "joint_states", False),
    )
    node.loginfo("ddes_sim: world %s (%d obstacles), robot at (%s, %s, yaw %s)", spec.name,
                 len(spec), node.get_param("~x", 0.0), node.get_param("~y", 0.0),
                 node.get_param("~yaw", 0.0))


_DBL_MAX = 1.7976931348623157e308
_DBL_MIN = 2.2250738585072014e-308


def pointcloud_to_laserscan(node: Node) -> None:
    """``cloud_in`` (sensor_msgs/PointCloud2) to ``scan`` (sensor_msgs/LaserScan), as noetic's."""
    if str(node.get_param("~target_frame", "") or ""):
        raise DdesValueError(f"{node.name}: ~target_frame "
                             f"{node.get_param('~target_frame')!r} is not supported (the scan "
                             "is made in the cloud's frame); leave it empty")
    p = {name: _float(node, name, default) for name, default in (
        ("angle_min", -3.141592653589793), ("angle_max", 3.141592653589793),
        ("angle_increment", 3.141592653589793 / 180.0), ("scan_time", 1.0 / 30.0),
        ("range_min", 0.0), ("range_max", _DBL_MAX), ("inf_epsilon", 1.0),
        ("min_height", _DBL_MIN), ("max_height", _DBL_MAX))}
    if not p["angle_increment"] > 0.0 or not p["angle_max"] > p["angle_min"]:
        raise DdesValueError(f"{node.name}: need angle_increment > 0 and angle_max > angle_min, "
                             f"got {p['angle_increment']!r}, {p['angle_min']!r}, "
                             f"{p['angle_max']!r}")
    use_inf = _bool(node, "use_inf", True)
    scan_type = get_message_class("sensor_msgs/LaserScan")
    pub = node.advertise("scan", scan_type, queue_size=10)
    # upstream computes with the float32 fields of the message after assigning them
    amin, amax, inc = struct.unpack("<3f", struct.pack("<3f", p["angle_min"], p["angle_max"],
                                                       p["angle_increment"]))

    def on_cloud(cloud: Any) -> None:
        ranges = cloud_to_ranges(cloud_xyz(cloud), amin, amax, inc, p["range_min"], p["range_max"],
                                 p["min_height"], p["max_height"], use_inf, p["inf_epsilon"])
        pub.publish(scan_type(header=cloud.header, angle_min=p["angle_min"],
                              angle_max=p["angle_max"], angle_increment=p["angle_increment"],
                              time_increment=0.0, scan_time=p["scan_time"],
                              range_min=p["range_min"], range_max=p["range_max"],
                              ranges=ranges))

    node.subscribe("cloud_in", get_message_class("sensor_msgs/PointCloud2"), on_cloud,
                   queue_size=1)


NODES = {
    "simulator": NodeType(simulator, name="simulator",
                          doc="the deterministic 2D SMB: /cmd_vel in; /scan, /odom, /imu/data, "
                              "/tf, /tf_static, /clock out"),
    "pointcloud_to_laserscan": NodeType(
        pointcloud_to_laserscan, name="pointcloud_to_laserscan",
        doc="sensor_msgs/PointCloud2 (cloud_in) to sensor_msgs/LaserScan (scan), as noetic's"),
    "robot_frames": NodeType(robot_frames, name="robot_state_publisher",
                             doc="the SMB's fixed frames on latched /tf_static (ddes.sim.frames)"),
}
