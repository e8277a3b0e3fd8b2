"""The algorithm, free of ROS: it can be tested without a robot."""

import math


def smallest_range(ranges, range_min, range_max):
    """The smallest range r with range_min <= r <= range_max (inf when there is none)."""
    ### BEGIN SOLUTION
    valid = [r for r in ranges if range_min <= r <= range_max]
    return min(valid) if valid else math.inf
    ### END SOLUTION
