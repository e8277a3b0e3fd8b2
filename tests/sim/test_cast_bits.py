"""The ray caster's fast paths give, bit for bit, the per-beam reference: for every beam the
nearest ``ray_distance`` over all obstacles (no culling), ``inf`` beyond ``range_max``."""

from __future__ import annotations

import random

import pytest

from ddes.sim import ANGLE_INCREMENT, ANGLE_MIN, N_BEAMS, RANGE_MAX, WorldSpec
from ddes.sim._trig import sincos
from ddes.sim.geometry import LaserGeometry, Prepared, prepare, ray_distance
from ddes.sim.worlds import Circle, bundled_world_names

INF = float("inf")


def reference(laser: LaserGeometry, obstacles: list[Prepared], ox: float, oy: float,
              yaw: float) -> list[float]:
    sy, cy = sincos(yaw)
    out = []
    for sa, ca in laser.dirs:
        dx = cy * ca - sy * sa
        dy = sy * ca + cy * sa
        best = min((ray_distance(p, ox, oy, dx, dy) for p in obstacles), default=INF)
        out.append(INF if best > laser.range_max else best)
    return out


@pytest.mark.parametrize("name", bundled_world_names())
def test_cast_equals_the_per_beam_reference_bit_for_bit(name: str) -> None:
    obstacles = [prepare(ob) for ob in WorldSpec.load(name).obstacles]
    laser = LaserGeometry(ANGLE_MIN, ANGLE_INCREMENT, N_BEAMS, RANGE_MAX)
    rng = random.Random(name)
    for _ in range(40):
        ox, oy = rng.uniform(-30.0, 30.0), rng.uniform(-30.0, 30.0)
        yaw = rng.uniform(-3.2, 3.2)
        got = laser.cast(obstacles, ox, oy, yaw)
        want = reference(laser, obstacles, ox, oy, yaw)
        assert [t.hex() for t in got] == [t.hex() for t in want]


def test_circles_seen_from_inside_behind_and_across_the_seam() -> None:
    laser = LaserGeometry(-3.0, 0.0174, 345, 8.0)  # almost all round: windows wrap
    obstacles = [prepare(Circle(0.0, 0.0, 2.0, "around")), prepare(Circle(-3.0, 0.1, 0.5, "back")),
                 prepare(Circle(4.0, 0.0, 1.0, "front")), prepare(Circle(12.0, 0.0, 1.0, "far"))]
    for ox, oy, yaw in ((0.0, 0.0, 0.0), (0.5, -0.2, 3.1), (-1.0, 1.0, -3.1), (3.0, 0.0, 1.5)):
        got = laser.cast(obstacles, ox, oy, yaw)
        assert [t.hex() for t in got] == \
            [t.hex() for t in reference(laser, obstacles, ox, oy, yaw)]
        assert all(0.0 <= t <= 8.0 or t == INF for t in got)
