"""The deterministic 2D robot: a Super Mega Bot in a world of pillars, walls and boxes.

``Simulator(world, WorldSpec.load("single_pillar"), x=0, y=0, yaw=0, noise=True)`` starts the
simulator node (``/cmd_vel`` in; ``/scan``, ``/odom``, ``/imu/data``, ``/tf``,
``/tf_static``, ``/clock`` out); ``rosrun ddes_sim simulator _world:=single_pillar`` and
``roslaunch ddes_sim ddes_sim.launch`` start it the ROS way.  See docs/sim.md.
"""

from ddes.sim.geometry import Footprint
from ddes.sim.simulator import (
    ANGLE_INCREMENT,
    ANGLE_MAX,
    ANGLE_MIN,
    IMU_OFFSET,
    LASER_OFFSET,
    N_BEAMS,
    RANGE_MAX,
    RANGE_MIN,
    Collision,
    History,
    Pose2D,
    RobotLimits,
    Simulator,
    Truth,
)
from ddes.sim.worlds import Box, Circle, Segment, WorldFileError, WorldSpec, bundled_world_names

__all__ = [
    "ANGLE_INCREMENT",
    "ANGLE_MAX",
    "ANGLE_MIN",
    "IMU_OFFSET",
    "LASER_OFFSET",
    "N_BEAMS",
    "RANGE_MAX",
    "RANGE_MIN",
    "Box",
    "Circle",
    "Collision",
    "Footprint",
    "History",
    "Pose2D",
    "RobotLimits",
    "Segment",
    "Simulator",
    "Truth",
    "WorldFileError",
    "WorldSpec",
    "bundled_world_names",
]
