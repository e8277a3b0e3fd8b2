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
    best, index = math.inf, -1
    for i, r in enumerate(ranges):
        if range_min <= r <= range_max and r < best:
            best, index = r, i
    if index < 0:
        return None
    return best, angle_min + index * angle_increment


def p_control(gain, angle):
    """The P controller's turn rate: proportional to the pillar's bearing (positive = left)."""
    return gain * angle


def polar_to_point(distance, angle):
    """The point ``(x, y, 0)`` at ``distance`` and ``angle`` in the laser's frame."""
    return distance * math.cos(angle), distance * math.sin(angle), 0.0


def transform_point(translation, rotation, point):
    """``rotation * point + translation``: ``translation`` (x, y, z), ``rotation`` a unit
    quaternion (x, y, z, w), as in a geometry_msgs/Transform."""
    qx, qy, qz, qw = rotation
    px, py, pz = point
    # v' = v + w t + q x t, with t = 2 q x v
    tx = 2.0 * (qy * pz - qz * py)
    ty = 2.0 * (qz * px - qx * pz)
    tz = 2.0 * (qx * py - qy * px)
    return (px + qw * tx + (qy * tz - qz * ty) + translation[0],
            py + qw * ty + (qz * tx - qx * tz) + translation[1],
            pz + qw * tz + (qx * ty - qy * tx) + translation[2])
