"""Node types of ``robot_localization``: ``ekf_localization_node`` (docs/localization.md).

robot_localization's ``RosFilter`` (noetic, ``src/ros_filter.cpp``) around the planar EKF of
:mod:`ddes.sim.ekf`.  Private parameters, with upstream's names and defaults: ``frequency``
(30), ``sensor_timeout`` (1/frequency), ``two_d_mode`` (false; this filter is planar, so false
is refused with an error naming the fix), ``map_frame`` (map), ``odom_frame`` (odom),
``base_link_frame`` (base_link), ``world_frame`` (odom_frame), ``publish_tf`` (true),
``transform_time_offset`` (0), ``process_noise_covariance`` and ``initial_estimate_covariance``
(15×15 row-major, upstream's defaults), and per sensor ``odomN`` / ``imuN`` (N = 0, 1, … until
one is missing) with ``_config`` (the 15 booleans X Y Z, ROLL PITCH YAW, VX VY VZ, VROLL VPITCH
VYAW, AX AY AZ), ``_queue_size`` (10), ``_rejection_threshold`` and
``_pose_rejection_threshold`` / ``_twist_rejection_threshold`` /
``_linear_acceleration_rejection_threshold`` (inf), ``imuN_remove_gravitational_acceleration``.

It subscribes the sensor topics (node-relative names, as upstream's public NodeHandle), listens
to TF for the IMU's mount (``imu_link`` → ``base_link``: a measurement whose frame cannot be
transformed is dropped with upstream's warning), and on a roscpp timer at ``frequency`` (ROS
time) integrates the queued measurements and publishes ``odometry/filtered`` (stamped with the
last measurement's time) and, with ``publish_tf``, ``world_frame`` → ``base_link_frame`` on
``/tf``.

**Measurements stamped in the future of ROS time** wait in the queue until ROS time reaches
them: upstream's ``integrateMeasurements`` stops at the first queued measurement with
``time_ > currentTime`` ("it should wait until a future iteration").  So with a bag stamped in
2021 and ``use_sim_time`` false, ddes's ROS time (kernel time, near 0) never reaches the stamps
and nothing is fused, and no ``odometry/filtered`` is published.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from ddes.nodes import NodeType
from ddes.sim.localization import EkfLocalizationNode

if TYPE_CHECKING:
    from ddes.graph.node import Node


def ekf_localization_node(node: Node) -> None:
    """Start the filter on ``node`` (then it spins)."""
    EkfLocalizationNode(node)


NODES = {
    "ekf_localization_node": NodeType(
        ekf_localization_node, name="ekf_navigation_node", log_style="roscpp",
        doc="planar EKF after robot_localization: odomN/imuN in; odometry/filtered and "
            "odom→base_link on /tf out"),
}
