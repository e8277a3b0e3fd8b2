"""The simulator's noise: Irwin-Hall Gaussians from ``random()`` calls and exact operations.

A Gaussian of standard deviation ``sigma`` is ``sigma * ((U1 + ... + U12) - 6.0)`` with twelve
``rng.random()`` calls summed left to right: only IEEE basic operations, so the same stream
gives the same bits on every machine (``random.gauss`` uses libm's log, cos and sqrt).

:func:`scan_ranges` adds the laser's per-beam noise and applies REP 117's limits to a whole
scan (the simulator and the benchmark's raw loop share it).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

if TYPE_CHECKING:
    import random

__all__ = ["RANGE_MAX", "RANGE_MIN", "gauss", "scan_ranges"]

RANGE_MIN = 0.45
RANGE_MAX = 50.0
_INF = float("inf")


def gauss(rng: random.Random, sigma: float) -> float:
    """``sigma * ((U1 + ... + U12) - 6.0)``: twelve ``rng.random()`` calls, left to right."""
    r = rng.random
    s = (r() + r() + r() + r() + r() + r() + r() + r() + r() + r() + r() + r())
    return sigma * (s - 6.0)


def scan_ranges(raw: list[float], rng: random.Random | None, sigma: float = 0.01
                ) -> list[float]:
    """The published ranges of one scan, as a list.

    ``raw`` holds the true distances (``inf`` where nothing is hit); each finite beam, in beam
    order, gets ``gauss(rng, sigma)`` added (none when ``rng`` is None), then REP 117's limits:
    below ``RANGE_MIN`` -inf, above ``RANGE_MAX`` +inf.  One comprehension, the draws and the
    limits inline (CPython specialises the float additions; a function call per beam costs more
    than the arithmetic).
    """
    if rng is None:
        return [t if RANGE_MIN <= t <= RANGE_MAX else (-_INF if t < RANGE_MIN else _INF)
                for t in raw]
    r = rng.random
    return [t if t == _INF else (
        v if RANGE_MIN <= (v := t + sigma * ((r() + r() + r() + r() + r() + r() + r() + r() + r()
                                              + r() + r() + r()) - 6.0)) <= RANGE_MAX
        else (-_INF if v < RANGE_MIN else _INF)) for t in raw]
