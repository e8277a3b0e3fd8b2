"""ROS Noetic's ``angles`` Python module: ``import angles`` in a rospy script.

Follows the Python module of the ``angles`` package (ros/angles, ``angles/__init__.py`` as
Debian's Noetic ships it): the same functions with the same arguments, the same floating-point
steps (so the same results, bit for bit: only ``%``, ``math.fmod`` and ``math.fabs``, which are
exact) and the same return conventions:

* :func:`normalize_angle_positive` in ``[0, 2*pi)`` (Python's float ``%``: ``2*pi`` itself for a
  tiny negative angle, as in ROS), :func:`normalize_angle` in ``(-pi, pi]``;
* :func:`shortest_angular_distance` ``normalize_angle(to - from)``;
* :func:`two_pi_complement` the other way round the circle (``2*pi`` for 0);
* :func:`_find_min_max_delta` a tuple ``(valid, min_delta, max_delta)``;
* :func:`shortest_angular_distance_with_limits` and
  :func:`shortest_angular_distance_with_large_limits` a tuple ``(valid, shortest_angle)``
  (the C++ returns the flag and writes the angle through a reference).

Deliberate deviation: none in behaviour.  The C++ library's ``from_degrees`` and ``to_degrees``
are not offered because Noetic's Python module does not have them (a script using them would
fail on ROS); use ``math.radians`` and ``math.degrees``.
"""

from __future__ import annotations

import math

__all__ = [
    "normalize_angle",
    "normalize_angle_positive",
    "shortest_angular_distance",
    "shortest_angular_distance_with_large_limits",
    "shortest_angular_distance_with_limits",
    "two_pi_complement",
]

_PI = math.pi
_TWO_PI = 2.0 * math.pi


def normalize_angle_positive(angle: float) -> float:
    """``angle`` (radians) brought into ``[0, 2*pi)``."""
    return angle % _TWO_PI


def normalize_angle(angle: float) -> float:
    """``angle`` (radians) brought into ``(-pi, pi]``."""
    positive = normalize_angle_positive(angle)
    return positive - _TWO_PI if positive > _PI else positive


def shortest_angular_distance(from_angle: float, to_angle: float) -> float:
    """The signed shortest turn from ``from_angle`` to ``to_angle``, in ``[-pi, pi]``:
    ``from_angle`` plus it is an angle equivalent to ``to_angle``."""
    return normalize_angle(to_angle - from_angle)


def two_pi_complement(angle: float) -> float:
    """The same position reached the other way round the circle, in ``[-2*pi, 2*pi]``:
    ``two_pi_complement(-pi/4) == 7*pi/4``, ``two_pi_complement(pi/4) == -7*pi/4``, and
    ``2*pi`` for 0.  An angle beyond ``+-2*pi`` is first reduced with ``fmod``."""
    if angle < -_TWO_PI or angle > _TWO_PI:
        angle = math.fmod(angle, _TWO_PI)
    if angle > 0:
        return angle - _TWO_PI
    if angle < 0:
        return angle + _TWO_PI
    return _TWO_PI


def _find_min_max_delta(from_angle: float, left_limit: float,
                        right_limit: float) -> tuple[bool, float, float]:
    """``(valid, min_delta, max_delta)``: how far one may turn from ``from_angle`` (in
    ``[-pi, pi)``) towards ``left_limit`` and ``right_limit`` (both in ``[-pi, pi]``) before a
    stop; ``valid`` is False when ``from_angle`` lies outside ``[left_limit, right_limit]``.
    Internal to the angles library, as in ROS."""
    to_left = shortest_angular_distance(from_angle, left_limit)
    to_right = shortest_angular_distance(from_angle, right_limit)
    to_left_other = two_pi_complement(to_left)
    to_right_other = two_pi_complement(to_right)

    if to_left == 0:
        return True, to_left, max(to_right, to_right_other)
    if to_right == 0:
        return True, min(to_left, to_left_other), to_right

    if to_left_other < to_left:
        lowest, lowest_other = to_left_other, to_left
    else:
        lowest, lowest_other = to_left, to_left_other
    if to_right_other > to_right:
        highest, highest_other = to_right_other, to_right
    else:
        highest, highest_other = to_right, to_right_other

    if lowest <= highest_other or highest >= lowest_other:
        whole_circle = left_limit == -_PI and right_limit == _PI
        return whole_circle, highest_other, lowest_other
    return True, lowest, highest


def _pick_by_limits(near: float, far: float, delta: float, other: float,
                    prefer_max_when_near_smaller: bool) -> float:
    """The turn chosen when a limit is in the way: by which stop is nearer, else the shorter."""
    if math.fabs(near) < math.fabs(far):
        return max(delta, other) if prefer_max_when_near_smaller else min(delta, other)
    if math.fabs(near) > math.fabs(far):
        return min(delta, other) if prefer_max_when_near_smaller else max(delta, other)
    return delta if math.fabs(delta) < math.fabs(other) else other


def shortest_angular_distance_with_limits(from_angle: float, to_angle: float,
                                          left_limit: float,
                                          right_limit: float) -> tuple[bool, float]:
    """``(valid, shortest_angle)``: the turn from ``from_angle`` to ``to_angle`` that stays in
    the valid interval ``[left_limit, right_limit]`` (limits in ``[-pi, pi]``, on the unit
    circle: ``[0.25, -0.25]`` is the wide interval containing pi).

    ``valid`` is False when ``from_angle`` or ``to_angle`` is outside the interval; the angle is
    then the turn ROS's heuristic picks.  ``(-0.5, 0.5, 0.25, -0.25)`` gives
    ``(True, -(2*pi - 1.0))``, the long way round through pi (Noetic's docstring gives its
    magnitude).
    """
    valid, min_delta, max_delta = _find_min_max_delta(from_angle, left_limit, right_limit)
    delta = shortest_angular_distance(from_angle, to_angle)
    other = two_pi_complement(delta)

    if not valid:  # "from" is outside the limits
        return False, _pick_by_limits(min_delta, max_delta, delta, other, False)
    if min_delta <= delta <= max_delta:
        return True, delta
    if min_delta <= other <= max_delta:
        return True, other
    # "to" is outside the limits
    _, min_to, max_to = _find_min_max_delta(to_angle, left_limit, right_limit)
    return False, _pick_by_limits(min_to, max_to, delta, other, True)


def shortest_angular_distance_with_large_limits(from_angle: float, to_angle: float,
                                                left_limit: float,
                                                right_limit: float) -> tuple[bool, float]:
    """``(valid, shortest_angle)`` for limits that may lie beyond ``[-pi, pi]``
    (``left_limit < right_limit`` required): the shortest turn, or else its complement, that
    ends inside the limits; ``valid`` also says that ``from_angle`` is inside them.
    ``(0, 10.5*pi, -2*pi, 2*pi)`` gives ``(True, 0.5*pi)``."""
    delta = shortest_angular_distance(from_angle, to_angle)
    other = two_pi_complement(delta)
    if math.fabs(delta) > math.fabs(other):
        delta, other = other, delta
    if left_limit > right_limit:
        return False, delta
    from_inside = left_limit <= from_angle <= right_limit
    for turn in (delta, other):
        end = from_angle + turn
        if left_limit <= end <= right_limit:
            return from_inside, turn
    return False, delta
