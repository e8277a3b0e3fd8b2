"""ddes.sim.noise: the whole-scan noise is bit for bit the per-beam loop it replaced (the same
random() calls in the same order, the same operations), and gauss is the Irwin-Hall sum."""

from __future__ import annotations

import random
import struct

from ddes.sim.noise import RANGE_MAX, RANGE_MIN, gauss, scan_ranges

INF = float("inf")


def per_beam(raw: list[float], rng: random.Random | None) -> list[float]:
    def limit(t: float) -> float:
        return -INF if t < RANGE_MIN else (INF if t > RANGE_MAX else t)

    if rng is None:
        return [limit(t) for t in raw]
    r = rng.random
    return [limit(t + 0.01 * ((r() + r() + r() + r() + r() + r() + r() + r() + r() + r() + r()
                               + r()) - 6.0)) if t != INF else t for t in raw]


def bits(xs: list[float]) -> bytes:
    return struct.pack(f"<{len(xs)}d", *xs)


def test_scan_ranges_equal_the_per_beam_loop_bit_for_bit() -> None:
    pick = random.Random(18)
    for case in range(300):
        n = pick.choice((0, 1, 12, 361))
        raw = [pick.choice((INF, pick.uniform(0.0, 50.0), pick.uniform(0.0, 0.5),
                            pick.uniform(49.9, 50.0), 0.0, RANGE_MIN, RANGE_MAX))
               for _ in range(n)]
        if case % 7 == 0:
            raw = [INF] * n
        a, b = random.Random(case), random.Random(case)
        assert bits(scan_ranges(raw, a)) == bits(per_beam(raw, b))
        assert a.random() == b.random()  # the streams went equally far
        assert bits(scan_ranges(raw, None)) == bits(per_beam(raw, None))


def test_gauss_is_the_irwin_hall_sum() -> None:
    a, b = random.Random(3), random.Random(3)
    for _ in range(100):
        u = [b.random() for _ in range(12)]
        acc = u[0]
        for x in u[1:]:
            acc = acc + x
        assert gauss(a, 0.05) == 0.05 * (acc - 6.0)
