"""The simulator's noise: Irwin-Hall Gaussians from ``random()`` calls and exact operations.

A Gaussian of standard deviation ``sigma`` is ``sigma * ((U1 + ... + U12) - 6.0)`` with twelve
``rng.random()`` calls summed left to right: only IEEE basic operations, so the same stream
gives the same bits on every machine (``random.gauss`` uses libm's log, cos and sqrt).

:func:`scan_ranges` does the laser's per-beam noise for a whole scan at once, with the same
``random()`` calls in the same order and the same operations as the per-beam loop.
"""

from __future__ import annotations

from collections.abc import Iterator
from itertools import repeat, starmap
from operator import add, mul, sub
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
    below ``RANGE_MIN`` -inf, above ``RANGE_MAX`` +inf.

    Bit for bit the per-beam ``t + sigma * ((r() + ... + r()) - 6.0)``: all draws at once
    (C-level ``starmap``), the twelve-term sums left to right as ``map(add, ...)`` passes, and
    one comprehension for the limits.
    """
    if rng is not None:
        finite = [t for t in raw if t != _INF]
        if finite:
            u = list(starmap(rng.random, repeat((), 12 * len(finite))))
            total: Iterator[float] = map(add, u[0::12], u[1::12])
            for k in range(2, 12):
                total = map(add, total, u[k::12])
            noisy = map(add, finite, map(mul, repeat(sigma), map(sub, total, repeat(6.0))))
            nxt = noisy.__next__
            return [t if t == _INF else (
                v if RANGE_MIN <= (v := nxt()) <= RANGE_MAX else (-_INF if v < RANGE_MIN else _INF))
                for t in raw]
    return [t if RANGE_MIN <= t <= RANGE_MAX else (-_INF if t < RANGE_MIN else _INF)
            for t in raw]
