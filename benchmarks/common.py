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
            repeat: int = 7) -> tuple[float, float]:
    """Best ops/s of each, alternating runs so machine load hits both alike."""
    best_d = best_b = 0.0
    for _ in range(repeat):
        best_b = max(best_b, best_rate(base_fn, 1))
        best_d = max(best_d, best_rate(ddes_fn, 1))
    return best_d, best_b


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
