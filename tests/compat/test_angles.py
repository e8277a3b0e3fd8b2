"""ddes.compat.angles: ROS Noetic's ``angles`` module, in scripts and against the real one."""

from __future__ import annotations

import json
import math
import textwrap
from pathlib import Path

import pytest
from hypothesis import given
from hypothesis import strategies as st

import ddes
from ddes.compat import angles
from ddes.compat.scripts import run_script

PI = math.pi
finite = st.floats(min_value=-1e6, max_value=1e6, allow_nan=False)
on_circle = st.floats(min_value=-PI, max_value=PI, allow_nan=False)


def _run(tmp_path: Path, body: str) -> list[str]:
    path = tmp_path / "node.py"
    path.write_text(textwrap.dedent(body))
    printed: list[str] = []
    world = ddes.World(seed=3)
    done, _ = run_script(world, path, print_line=lambda text, _err: printed.append(text))
    world.run(until=1.0)
    assert done.triggered and done.ok and done.value == 0
    return printed


def test_a_script_imports_angles_and_gets_this_module(tmp_path: Path) -> None:
    printed = _run(tmp_path, """
        import math
        import angles
        import rospy
        rospy.init_node("turner")
        print(angles.__name__)
        print(repr(angles.normalize_angle(3 * math.pi / 2)))
        print(repr(angles.shortest_angular_distance(0.1, 2 * math.pi - 0.1)))
        print(angles.shortest_angular_distance_with_limits(-0.5, 0.5, 0.25, -0.25))
        print(hasattr(angles, "from_degrees"))
    """)
    assert printed == [
        "ddes.compat.angles",
        repr(-PI / 2),
        repr(angles.shortest_angular_distance(0.1, 2 * PI - 0.1)),
        str((True, -(2 * PI - 1.0))),
        "False",
    ]
    assert math.isclose(float(printed[2]), -0.2, abs_tol=1e-12)


def test_documented_examples() -> None:
    assert angles.normalize_angle_positive(-1e-300) == 2 * PI  # float %, as Noetic
    assert angles.two_pi_complement(-2 * PI) == 0.0
    assert angles.two_pi_complement(-PI / 4) == 7 * PI / 4
    assert angles.two_pi_complement(PI / 4) == -7 * PI / 4
    assert angles.two_pi_complement(0.0) == 2 * PI
    assert angles.normalize_angle(PI) == PI
    assert angles.normalize_angle(-PI) == PI
    assert angles.normalize_angle_positive(2 * PI) == 0.0
    # the long way round, through pi (Noetic's docstring gives the magnitude, 2*pi - 1.0)
    valid, delta = angles.shortest_angular_distance_with_limits(-0.5, 0.5, 0.25, -0.25)
    assert valid and math.isclose(delta, -(2 * PI - 1.0), abs_tol=1e-12)
    valid, _ = angles.shortest_angular_distance_with_limits(-0.5, 0.5, -0.25, 0.25)
    assert not valid
    valid, delta = angles.shortest_angular_distance_with_large_limits(0, 10.5 * PI, -2 * PI,
                                                                      2 * PI)
    assert valid and math.isclose(delta, 0.5 * PI, abs_tol=1e-9)
    valid, delta = angles.shortest_angular_distance_with_large_limits(0, 10.5 * PI, -2 * PI,
                                                                      0.1 * PI)
    assert valid and math.isclose(delta, -1.5 * PI, abs_tol=1e-9)
    assert angles.shortest_angular_distance_with_large_limits(10.5 * PI, 0, -2 * PI,
                                                              2 * PI)[0] is False
    assert angles.shortest_angular_distance_with_large_limits(0, 1, 1, -1)[0] is False


@given(finite)
def test_normalize_angle_positive_lies_in_zero_to_two_pi(a: float) -> None:
    n = angles.normalize_angle_positive(a)
    assert 0.0 <= n <= 2 * PI  # 2*pi itself for a tiny negative angle (float %, as in ROS)
    assert math.isclose(math.cos(n), math.cos(a), abs_tol=1e-6)
    assert math.isclose(math.sin(n), math.sin(a), abs_tol=1e-6)


@given(finite)
def test_normalize_angle_lies_in_minus_pi_to_pi(a: float) -> None:
    n = angles.normalize_angle(a)
    assert -PI < n <= PI
    assert math.isclose(math.cos(n), math.cos(a), abs_tol=1e-6)
    assert math.isclose(math.sin(n), math.sin(a), abs_tol=1e-6)


@given(finite, finite)
def test_shortest_distance_is_at_most_pi_and_reaches_the_target(a: float, b: float) -> None:
    d = angles.shortest_angular_distance(a, b)
    assert -PI <= d <= PI
    assert math.isclose(math.cos(a + d), math.cos(b), abs_tol=1e-6)
    assert math.isclose(math.sin(a + d), math.sin(b), abs_tol=1e-6)


@given(st.floats(min_value=-2 * PI, max_value=2 * PI, allow_nan=False))
def test_two_pi_complement_goes_the_other_way(a: float) -> None:
    c = angles.two_pi_complement(a)
    assert -2 * PI <= c <= 2 * PI
    if a != 0:
        assert math.isclose(abs(a - c), 2 * PI, rel_tol=1e-12)
        if c != 0:  # +-2*pi's complement is 0
            assert (a > 0) != (c > 0)


@given(on_circle, on_circle, on_circle, on_circle)
def test_a_valid_limited_turn_stays_inside_the_limits(a: float, b: float, left: float,
                                                      right: float) -> None:
    valid, delta = angles.shortest_angular_distance_with_limits(a, b, left, right)
    assert -2 * PI <= delta <= 2 * PI
    assert math.isclose(math.cos(a + delta), math.cos(b), abs_tol=1e-6)
    assert math.isclose(math.sin(a + delta), math.sin(b), abs_tol=1e-6)
    if valid:
        ok, lo, hi = angles._find_min_max_delta(a, left, right)
        assert ok and lo <= delta <= hi


_INPUTS = [0.0, -0.0, 1e-300, 0.5, -0.5, 1.0, PI / 4, -PI / 4, PI / 2, PI, -PI, 3.0, -3.0,
           2 * PI, -2 * PI, 7.0, -7.0, 100.0, -1234.5, 1e10, 3 * PI, -3 * PI + 1e-9, 0.25,
           -0.25]
_LIMITS = [(-0.25, 0.25), (0.25, -0.25), (-PI, PI), (-PI / 2, PI / 2), (PI / 2, -PI / 2),
           (0.0, 1.0), (-1.0, 0.0), (1.0, 1.0)]
_FROM_TO = [(-0.5, 0.5), (0.5, -0.5), (0.0, PI), (PI - 0.1, -PI + 0.1), (0.1, 0.2), (3.0, -3.0),
            (-3.0, 3.0), (0.0, 0.0), (1.5, -1.5), (0.3, 0.3), (-2.0, 2.5)]
_LARGE_LIMITS = [(-2 * PI, 2 * PI), (-2 * PI, 0.1 * PI), (-1.0, 1.0), (1.0, -1.0), (0.0, 3 * PI)]

# The same calls, run by this module and by Noetic's: repr of every result, line by line.
_CALLS = """
import json, math
PI = math.pi
out = []
for a in INPUTS:
    out.append(repr((angles.normalize_angle_positive(a), angles.normalize_angle(a),
                     angles.two_pi_complement(a))))
    for b in INPUTS:
        out.append(repr(angles.shortest_angular_distance(a, b)))
for left, right in LIMITS:
    for a, b in FROM_TO:
        out.append(repr(angles._find_min_max_delta(a, left, right)))
        out.append(repr(angles.shortest_angular_distance_with_limits(a, b, left, right)))
for left, right in LARGE_LIMITS:
    for a, b in FROM_TO + [(0.0, 10.5 * PI), (10.5 * PI, 0.0)]:
        out.append(repr(angles.shortest_angular_distance_with_large_limits(a, b, left, right)))
print(json.dumps(out))
"""


def _calls() -> str:
    return (f"INPUTS = {_INPUTS!r}\nLIMITS = {_LIMITS!r}\nFROM_TO = {_FROM_TO!r}\n"
            f"LARGE_LIMITS = {_LARGE_LIMITS!r}\n{_CALLS}")


@pytest.mark.ros
def test_every_function_matches_noetic_bit_for_bit(ros_python, tmp_path: Path) -> None:
    expected = ros_python("import angles\n" + _calls(), as_json=True)
    printed = _run(tmp_path, "import angles\n" + _calls())
    assert len(printed) == 1
    got = json.loads(printed[0])
    assert len(got) == len(expected) > 800
    assert got == expected
