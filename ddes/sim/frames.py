"""``ddes_sim/robot_frames``: the robot_state_publisher stand-in that puts the SMB's fixed frames
on latched ``/tf_static``.

The simulator publishes these frames itself; a bag has none (the course's ``smb_navigation.bag``
carries no TF), so a launch that plays a bag starts ``robot_frames`` for the frames the EKF needs
to take the IMU's data into ``base_link`` (robot_localization drops a measurement whose frame it
cannot transform).  Frames: ``base_link`` → ``base_laser`` (:data:`~ddes.sim.LASER_OFFSET`) and
``base_link`` → ``imu_link`` (:data:`~ddes.sim.IMU_OFFSET`), unrotated, stamped with the node's
ROS time at start (zero under ``use_sim_time`` before the first ``/clock``, as
robot_state_publisher's static transforms are).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from ddes.sim.simulator import IMU_OFFSET, LASER_OFFSET
from ddes.tf2_ros import StaticTransformBroadcaster

if TYPE_CHECKING:
    from ddes.graph.node import Node

__all__ = ["FRAMES", "robot_frames"]

#: child frame → (x, y, z) of its mount on ``base_link``.
FRAMES = {"base_laser": LASER_OFFSET, "imu_link": IMU_OFFSET}


def robot_frames(node: Node) -> None:
    """Send the SMB's fixed frames once on latched /tf_static, then spin."""
    ts = node.world.messages.get_message_class("geometry_msgs/TransformStamped")
    out = []
    for child, (x, y, z) in FRAMES.items():
        t = ts()
        t.header.stamp = node.get_rostime()
        t.header.frame_id = "base_link"
        t.child_frame_id = child
        t.transform.translation.x, t.transform.translation.y = float(x), float(y)
        t.transform.translation.z = float(z)
        t.transform.rotation.w = 1.0
        out.append(t)
    StaticTransformBroadcaster(node).sendTransform(out)
    node.loginfo("robot_frames: publishing %s on /tf_static", ", ".join(
        f"base_link -> {child}" for child in FRAMES))
