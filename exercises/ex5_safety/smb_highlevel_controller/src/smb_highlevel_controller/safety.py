"""The two automatic emergency stops' decisions, free of ROS: they can be tested without a
robot."""

import math


def closest_in_sector(ranges, angle_min, angle_increment, range_min, range_max, half_angle):
    """The smallest valid range (range_min <= r <= range_max) of the beams whose angle
    ``angle_min + i * angle_increment`` lies within ``half_angle`` of straight ahead (inf when
    there is none)."""
    raise NotImplementedError("your code here")


def too_close(distance, min_distance):
    """True when an obstacle at ``distance`` is closer than ``min_distance``."""
    raise NotImplementedError("your code here")


def is_crash(linear_acceleration_x, threshold):
    """True when the forward acceleration (m/s^2, gravity is along z) is larger in magnitude
    than ``threshold``: an impact, not braking or starting (at most 2 m/s^2 on the SMB)."""
    raise NotImplementedError("your code here")
