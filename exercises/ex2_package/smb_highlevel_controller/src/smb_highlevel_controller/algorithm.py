"""The algorithm, free of ROS: it can be tested without a robot."""

import math


def smallest_range(ranges, range_min, range_max):
    """The smallest range r with range_min <= r <= range_max (inf when there is none)."""
    raise NotImplementedError("your code here")
