"""Float sums that give the same bits on every Python ddes supports.

From Python 3.12, ``sum()`` of floats compensates rounding (Neumaier), so the same
numbers sum to other last bits on 3.11 and on 3.12+.  A score, a printed rate or a
message value must not depend on the interpreter's version, so ddes adds floats left to
right from 0.0: what ``sum()`` did up to 3.11, and what rospy's own tools (Python 3.8
under Noetic) do.
"""

from __future__ import annotations

from collections.abc import Iterable

__all__ = ["left_sum"]


def left_sum(values: Iterable[float]) -> float:
    """``0.0 + v0 + v1 + …`` added left to right (``sum()`` of floats up to Python 3.11)."""
    total = 0.0
    for v in values:
        total += v
    return total
