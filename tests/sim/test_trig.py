"""ddes.sim._trig.sincos is bit for bit (ddes.transformations.sin(x), cos(x)): the simulator
reduces the argument once instead of twice, and no result bit may change for it."""

from __future__ import annotations

import math
import random
import struct

from hypothesis import given, settings
from hypothesis import strategies as st

from ddes.sim._trig import sincos
from ddes.transformations import cos, sin


def same(a: float, b: float) -> bool:
    return struct.pack("<d", a) == struct.pack("<d", b) or (math.isnan(a) and math.isnan(b))


def check(x: float) -> None:
    s, c = sincos(x)
    assert same(s, sin(x)), (x, s, sin(x))
    assert same(c, cos(x)), (x, c, cos(x))


EDGES = [0.0, -0.0, 5e-324, -5e-324, 1e-300, 2.0 ** -28, 2.0 ** -27, 2.0 ** -26, 1.4e-8, 1.5e-8,
         3e-8, -3e-8, 0.7853981633974483, 0.7853981633974484, -0.7853981633974483,
         0.785398163397448, math.pi / 2, math.pi, -math.pi, 2 * math.pi, 1e6, 2.0 ** 20 * math.pi,
         1e22, -1e22, 1e300, 1.7976931348623157e308, math.inf, -math.inf, math.nan]


def test_edges_and_kernel_boundaries() -> None:
    for x in EDGES:
        check(x)
        check(math.nextafter(x, math.inf))
        check(math.nextafter(x, -math.inf))


def test_many_values_over_the_ranges_the_simulator_uses() -> None:
    rng = random.Random(18)
    for _ in range(20000):
        check(rng.uniform(-4.0, 4.0))
        check(rng.uniform(-1.0, 1.0) * 2.0 ** rng.randint(-40, 40))


@settings(max_examples=2000, deadline=None)
@given(st.floats(allow_nan=True, allow_infinity=True))
def test_any_double(x: float) -> None:
    check(x)
