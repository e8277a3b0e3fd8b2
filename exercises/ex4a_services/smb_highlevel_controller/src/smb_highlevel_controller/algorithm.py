"""The algorithm, free of ROS: it can be tested without a robot."""

import math


def smallest_range(ranges, range_min, range_max):
    """The smallest range r with range_min <= r <= range_max (inf when there is none)."""
    valid = [r for r in ranges if range_min <= r <= range_max]
    return min(valid) if valid else math.inf


def find_pillar(ranges, angle_min, angle_increment, range_min, range_max):
    """The pillar is the closest valid return: ``(distance, angle)`` of the beam with the smallest
    range in [range_min, range_max] (beam i points at angle_min + i * angle_increment), or None
    when no beam has a valid return."""
    raise NotImplementedError("your code here")


def p_control(gain, angle):
    """The P controller's turn rate: proportional to the pillar's bearing (positive = left)."""
    raise NotImplementedError("your code here")


def polar_to_point(distance, angle):
    """The point ``(x, y, 0)`` at ``distance`` and ``angle`` in the laser's frame."""
    raise NotImplementedError("your code here")


def transform_point(translation, rotation, point):
    """``rotation * point + translation``: ``translation`` (x, y, z), ``rotation`` a unit
    quaternion (x, y, z, w), as in a geometry_msgs/Transform."""
    raise NotImplementedError("your code here")
