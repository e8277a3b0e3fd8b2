"""Exact 2D geometry of the simulator: laser rays and footprint collisions.

Only ``+ - * /``, comparisons, ``math.sqrt`` (correctly rounded by IEEE 754, so the same
bits everywhere) and the deterministic trig of :mod:`ddes.sim._trig` are used: the same
world and pose give the same ranges on every machine.

* Ray vs circle: ``t = b - sqrt(b*b - c)`` with ``b = d.(C - O)``, ``c = |C - O|^2 - r^2``
  (``b + sqrt`` when the origin is inside the circle).
* Ray vs segment: the 2x2 cross-product solve; a parallel ray misses.
* Box: its four sides.
* Footprint (a rectangle centred on base_link) vs circle: the centre in the body frame,
  clamped to the half extents, within ``r``; vs segment: the separating-axis test in the body
  frame; vs box: any side, or the robot's centre inside the box.  Touching counts.

The caster culls obstacles by their bounding circle (too far, or outside a conservative
bearing window around them), then tests the beams left exactly; the culling only skips
beams that cannot hit, so ranges do not depend on it.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

from ddes.sim._trig import atan2, sincos
from ddes.sim.worlds import Box, Circle, Obstacle

__all__ = ["Footprint", "LaserGeometry", "Prepared", "collides", "contact_normal", "prepare",
           "ray_distance"]

_INF = float("inf")
_PI = 3.141592653589793
_TWO_PI = 6.283185307179586
_HALF_PI = 1.5707963267948966


@dataclass(frozen=True)
class Prepared:
    """An obstacle made ready for casting: its circles and segments and a bounding circle."""

    obstacle: Obstacle
    circles: tuple[tuple[float, float, float], ...]          # (cx, cy, r*r)
    segments: tuple[tuple[float, float, float, float], ...]  # (ax, ay, ex, ey): A and B - A
    bx: float
    by: float
    br: float


def prepare(ob: Obstacle) -> Prepared:
    """The casting form of one obstacle."""
    bx, by, br = ob.bounds()
    if isinstance(ob, Circle):
        return Prepared(ob, ((ob.x, ob.y, ob.radius * ob.radius),), (), bx, by, br)
    segs = ob.edges() if isinstance(ob, Box) else (ob,)
    return Prepared(ob, (), tuple((s.x1, s.y1, s.x2 - s.x1, s.y2 - s.y1) for s in segs),
                    bx, by, br)


def ray_distance(p: Prepared, ox: float, oy: float, dx: float, dy: float) -> float:
    """The distance along the ray ``O + t*d`` (``t >= 0``) to ``p``, ``inf`` on a miss."""
    best = _INF
    for cx, cy, r2 in p.circles:
        fx = cx - ox
        fy = cy - oy
        b = dx * fx + dy * fy
        disc = b * b - (fx * fx + fy * fy - r2)
        if disc < 0.0:
            continue
        sq = math.sqrt(disc)
        t = b - sq
        if t < 0.0:
            t = b + sq
        if 0.0 <= t < best:
            best = t
    for ax, ay, ex, ey in p.segments:
        denom = dx * ey - dy * ex
        if denom == 0.0:
            continue
        wx = ax - ox
        wy = ay - oy
        t = (wx * ey - wy * ex) / denom
        if t < 0.0 or t >= best:
            continue
        s = (wx * dy - wy * dx) / denom
        if 0.0 <= s <= 1.0:
            best = t
    return best


class LaserGeometry:
    """The beams of a planar laser: ``n`` beams at ``angle_min + i*increment`` (sensor frame).

    ``cast(obstacles, ox, oy, yaw)`` gives the true distance of every beam (``inf`` where
    nothing is hit within ``range_max``).
    """

    def __init__(self, angle_min: float, increment: float, n: int, range_max: float):
        self.angle_min = angle_min
        self.increment = increment
        self.n = n
        self.range_max = range_max
        self.angles = tuple(angle_min + i * increment for i in range(n))
        self.dirs = tuple(sincos(a) for a in self.angles)  # (sin, cos) per beam
        #: Extra beams each side of a bearing window (rounding of the window's ends).
        self.margin = 2

    def cast(self, obstacles: Sequence[Prepared], ox: float, oy: float, yaw: float) -> list[float]:
        n = self.n
        out = [_INF] * n
        sy, cy = sincos(yaw)
        dirs = self.dirs
        rmax = self.range_max
        inc = self.increment
        amin = self.angle_min
        for p in obstacles:
            fx = p.bx - ox
            fy = p.by - oy
            d2 = fx * fx + fy * fy
            reach = rmax + p.br
            if d2 > reach * reach:
                continue
            beams: Sequence[int]
            if d2 <= p.br * p.br * 1.0001 + 1e-12:
                beams = range(n)
            else:
                dist = math.sqrt(d2)
                # a window at least as wide as the true asin(br/dist): asin(s) <= s*pi/2
                half = _HALF_PI * p.br / dist
                bearing = atan2(fy, fx) - yaw
                ranges = []
                for shift in (-_TWO_PI, 0.0, _TWO_PI):
                    lo = math.floor((bearing + shift - half - amin) / inc) - self.margin
                    hi = math.ceil((bearing + shift + half - amin) / inc) + self.margin
                    lo = max(lo, 0)
                    hi = min(hi, n - 1)
                    if lo <= hi:
                        ranges.append(range(lo, hi + 1))
                if not ranges:
                    continue
                beams = ranges[0] if len(ranges) == 1 else [i for r in ranges for i in r]
            if len(p.circles) == 1 and not p.segments:  # one circle: ray_distance, inlined
                (ccx, ccy, r2), = p.circles
                fx = ccx - ox
                fy = ccy - oy
                k = fx * fx + fy * fy - r2
                sqrt = math.sqrt
                for i in beams:
                    sa, ca = dirs[i]
                    dx = cy * ca - sy * sa
                    dy = sy * ca + cy * sa
                    b = dx * fx + dy * fy
                    disc = b * b - k
                    if disc < 0.0:
                        continue
                    sq = sqrt(disc)
                    t = b - sq
                    if t < 0.0:
                        t = b + sq
                    if 0.0 <= t < out[i]:
                        out[i] = t
                continue
            for i in beams:
                sa, ca = dirs[i]
                dx = cy * ca - sy * sa
                dy = sy * ca + cy * sa
                t = ray_distance(p, ox, oy, dx, dy)
                if t < out[i]:
                    out[i] = t
        for i in range(n):
            if out[i] > rmax:
                out[i] = _INF
        return out


@dataclass(frozen=True)
class Footprint:
    """A rectangle ``length`` x ``width`` centred on base_link (x forward)."""

    length: float = 0.605
    width: float = 0.410

    @property
    def hx(self) -> float:
        return 0.5 * self.length

    @property
    def hy(self) -> float:
        return 0.5 * self.width

    @property
    def radius(self) -> float:
        """The radius of the circle round the rectangle."""
        return math.sqrt(self.hx * self.hx + self.hy * self.hy)

    def parts(self) -> tuple[float, float, float]:
        """``(hx, hy, radius)``, for the hot path."""
        return self.hx, self.hy, self.radius


def _seg_hits(hx: float, hy: float, ax: float, ay: float, bx: float, by: float) -> bool:
    """Separating-axis test of the rectangle [-hx, hx] x [-hy, hy] and segment AB (body frame)."""
    if (ax > hx and bx > hx) or (ax < -hx and bx < -hx):
        return False
    if (ay > hy and by > hy) or (ay < -hy and by < -hy):
        return False
    nx = ay - by
    ny = bx - ax
    proj = nx * ax + ny * ay
    radius = hx * abs(nx) + hy * abs(ny)
    return -radius <= proj <= radius


def collides(fp: Footprint | tuple[float, float, float], x: float, y: float, s: float, c: float,
             p: Prepared) -> bool:
    """Whether the footprint at ``(x, y)`` with heading ``(sin, cos) = (s, c)`` touches ``p``.

    ``fp`` is a :class:`Footprint` or its :meth:`Footprint.parts`.
    """
    hx, hy, radius = fp.parts() if isinstance(fp, Footprint) else fp
    fx = p.bx - x
    fy = p.by - y
    reach = radius + p.br
    if fx * fx + fy * fy > reach * reach * 1.0001 + 1e-12:
        return False
    ob = p.obstacle
    if isinstance(ob, Circle):
        bx = c * fx + s * fy
        by = -s * fx + c * fy
        qx = hx if bx > hx else (-hx if bx < -hx else bx)
        qy = hy if by > hy else (-hy if by < -hy else by)
        ddx = bx - qx
        ddy = by - qy
        return ddx * ddx + ddy * ddy <= ob.radius * ob.radius
    for ax, ay, ex, ey in p.segments:
        px = ax - x
        py = ay - y
        qx = px + ex
        qy = py + ey
        if _seg_hits(hx, hy, c * px + s * py, -s * px + c * py,
                     c * qx + s * qy, -s * qx + c * qy):
            return True
    if isinstance(ob, Box):  # the robot wholly inside the box
        bs, bc = sincos(ob.yaw)
        rx = x - ob.x
        ry = y - ob.y
        lx = bc * rx + bs * ry
        ly = -bs * rx + bc * ry
        return abs(lx) <= 0.5 * ob.size_x and abs(ly) <= 0.5 * ob.size_y
    return False


def contact_normal(p: Prepared, x: float, y: float, heading: tuple[float, float]
                   ) -> tuple[float, float]:
    """A unit vector (world frame) from the obstacle's nearest point towards the robot centre.

    ``heading`` is ``(sin, cos)`` of the robot's yaw; when the centre lies on the obstacle the
    normal points backwards along it.
    """
    ob = p.obstacle
    if isinstance(ob, Circle):
        nx, ny = x - ob.x, y - ob.y
    else:
        best = _INF
        nx = ny = 0.0
        for ax, ay, ex, ey in p.segments:
            ll = ex * ex + ey * ey
            u = ((x - ax) * ex + (y - ay) * ey) / ll
            u = 0.0 if u < 0.0 else (1.0 if u > 1.0 else u)
            cx = x - (ax + u * ex)
            cy = y - (ay + u * ey)
            d2 = cx * cx + cy * cy
            if d2 < best:
                best, nx, ny = d2, cx, cy
    norm = math.sqrt(nx * nx + ny * ny)
    if norm == 0.0:
        return -heading[1], -heading[0]
    return nx / norm, ny / norm


def wrap_angle(a: float) -> float:
    """``a`` wrapped into (-pi, pi] (for angles within one turn of that interval)."""
    if a > _PI:
        a -= _TWO_PI
    elif a <= -_PI:
        a += _TWO_PI
    return a
