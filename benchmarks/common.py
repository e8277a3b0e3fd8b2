"""Helpers shared by the benchmark modules (best-of-N timing, row format)."""

from __future__ import annotations

import time
from collections.abc import Callable
from typing import Any


def best_rate(fn: Callable[[], int], repeat: int = 5) -> float:
    """Run ``fn`` (which returns an operation count) ``repeat`` times; best ops/s."""
    best = 0.0
    for _ in range(repeat):
        t0 = time.perf_counter()
        n = fn()
        dt = time.perf_counter() - t0
        best = max(best, n / dt)
    return best


def compare(ddes_fn: Callable[[], int], base_fn: Callable[[], int],
            repeat: int = 9) -> tuple[float, float]:
    """ops/s of ddes and of the baseline, measured in back-to-back pairs.

    Each pair runs the baseline then ddes; the reported figures are the
    pair with the median ratio, so a burst of load on this shared machine
    hits one pair, not the result.
    """
    pairs = []
    for _ in range(repeat):
        b = best_rate(base_fn, 1)
        d = best_rate(ddes_fn, 1)
        pairs.append((d / b, d, b))
    pairs.sort()
    _, d, b = pairs[len(pairs) // 2]
    return d, b


def row(name: str, value: float, unit: str, baseline: float, baseline_name: str,
        **extra: Any) -> dict[str, Any]:
    """One benchmark result line."""
    return {
        "name": name,
        "value": round(value, 1),
        "unit": unit,
        "baseline": round(baseline, 1),
        "baseline_name": baseline_name,
        "ratio": round(value / baseline, 3),
        **extra,
    }
