"""Helpers shared by the benchmark modules: CPU-time rates, interleaved comparisons, rows.

Honest measurement on a shared, loaded machine:

* **CPU time** (:func:`time.process_time`), not wall time: another process
  taking the core does not count against the run being timed.
* **Interleaved**: :func:`compare` runs the baseline(s) and ddes in turn, in
  a rotating order, ``repeat`` times; a burst of load hits one round, not one
  side.
* **Median and spread**: every figure is the median over the rounds; the
  ratio is the median of the per-round ratios, with its minimum and maximum
  (``ratio_min``/``ratio_max``) beside it.
* **No earlier round's garbage**: :func:`interleave` calls :func:`gc.collect`
  before each timed call, outside its timing, so the cyclic garbage an earlier
  call left (a finished world is a web of cycles) is not freed inside
  whichever later call happens to start a full collection.  Collections that
  a call's own allocations start are still timed (the collector stays on,
  unlike :mod:`timeit`'s default).
* **Fair baselines**: beside the raw baseline (a hand-written SimPy model of
  the same schedule) a benchmark may give a *fair* one: raw SimPy plus
  exactly the work the ROS semantics require (serialize, deserialize, the
  trace rows, the hops).  ``fair_ratio`` says how close ddes is to what its
  semantics cost; ``ratio`` how close it is to bare SimPy.

``DDES_BENCH_TINY=1`` runs every benchmark at a tiny size with one round
(``tests/test_benchmarks.py`` does, so the benchmarks cannot rot); its
figures mean nothing.
"""

from __future__ import annotations

import gc
import os
import statistics
import time
from collections.abc import Callable, Sequence
from typing import Any

#: Tiny mode: sizes divided, one round (for the test that keeps the benchmarks running).
TINY = os.environ.get("DDES_BENCH_TINY", "") not in ("", "0")


def size(n: int) -> int:
    """A benchmark's operation count: ``n``, or a tiny fraction of it in tiny mode."""
    return max(2, n // 500) if TINY else n


def repeats(n: int) -> int:
    """How many interleaved rounds: ``n``, or 1 in tiny mode."""
    return 1 if TINY else n


def cpu_rate(fn: Callable[[], float]) -> float:
    """``fn()`` (an operation count) over the CPU seconds it took: operations per CPU second."""
    t0 = time.process_time()
    n = fn()
    dt = time.process_time() - t0
    return n / max(dt, 1e-6)


def best_rate(fn: Callable[[], int], repeat: int = 5) -> float:
    """The best of ``repeat`` CPU-time rates of ``fn`` (ops per CPU second)."""
    return max(cpu_rate(fn) for _ in range(repeats(repeat)))


class Comparison(tuple[float, float]):
    """``(ddes, baseline)`` medians of an interleaved comparison, with the spread as attributes.

    Unpacks as the old ``(value, baseline)`` pair.  ``rounds`` holds every
    round's rates, keyed ``"ddes"``, ``"base"`` and ``"fair"`` (if any).
    """

    ratio: float
    ratio_min: float
    ratio_max: float
    fair: float | None
    fair_ratio: float | None
    fair_ratio_min: float | None
    fair_ratio_max: float | None
    rounds: dict[str, list[float]]

    def __new__(cls, rounds: dict[str, list[float]]) -> Comparison:
        d, b = rounds["ddes"], rounds["base"]
        self = super().__new__(cls, (statistics.median(d), statistics.median(b)))
        self.rounds = rounds
        ratios = [x / y for x, y in zip(d, b)]
        self.ratio = statistics.median(ratios)
        self.ratio_min, self.ratio_max = min(ratios), max(ratios)
        f = rounds.get("fair")
        if f:
            fr = [x / y for x, y in zip(d, f)]
            self.fair = statistics.median(f)
            self.fair_ratio = statistics.median(fr)
            self.fair_ratio_min, self.fair_ratio_max = min(fr), max(fr)
        else:
            self.fair = self.fair_ratio = self.fair_ratio_min = self.fair_ratio_max = None
        return self


def interleave(fns: dict[str, Callable[[], float]], repeat: int,
               rate: Callable[[Callable[[], float]], float] = cpu_rate) -> dict[str, list[float]]:
    """Run every named function once per round, rotating the order; every round's rate.

    Each call starts after a full collection (untimed): see the module docstring."""
    names = list(fns)
    out: dict[str, list[float]] = {name: [] for name in names}
    for i in range(repeats(repeat)):
        k = i % len(names)
        for name in names[k:] + names[:k]:
            gc.collect()
            out[name].append(rate(fns[name]))
    return out


def compare(ddes_fn: Callable[[], float], base_fn: Callable[[], float], repeat: int = 9,
            fair_fn: Callable[[], float] | None = None) -> Comparison:
    """Rates (per CPU second) of ddes, the raw baseline and the fair one, interleaved.

    Returns a :class:`Comparison` (unpacks as ``(ddes, base)`` medians).
    """
    fns = {"base": base_fn, "ddes": ddes_fn}
    if fair_fn is not None:
        fns["fair"] = fair_fn
    return Comparison(interleave(fns, repeat))


def compare_values(values: dict[str, Callable[[], float]], repeat: int) -> Comparison:
    """Like :func:`compare` for functions that return the figure itself (a higher-is-better rate)."""
    return Comparison(interleave(values, repeat, rate=lambda fn: fn()))


def _r(x: float | None, nd: int = 3) -> float | None:
    return None if x is None else round(x, nd)


def result(name: str, c: Comparison, unit: str, baseline_name: str,
           fair_name: str | None = None, **extra: Any) -> dict[str, Any]:
    """One benchmark line from a :class:`Comparison`: medians, ratio and its spread."""
    out: dict[str, Any] = {
        "name": name,
        "value": round(c[0], 1),
        "unit": unit,
        "baseline": round(c[1], 1),
        "baseline_name": baseline_name,
        "ratio": _r(c.ratio),
        "ratio_min": _r(c.ratio_min),
        "ratio_max": _r(c.ratio_max),
        "rounds": len(c.rounds["ddes"]),
    }
    if c.fair is not None:
        out.update(fair=round(c.fair, 1), fair_name=fair_name, fair_ratio=_r(c.fair_ratio),
                   fair_ratio_min=_r(c.fair_ratio_min), fair_ratio_max=_r(c.fair_ratio_max))
    out.update(extra)
    return out


def row(name: str, value: float, unit: str, baseline: float, baseline_name: str,
        **extra: Any) -> dict[str, Any]:
    """One benchmark line from two figures measured once (no spread)."""
    return {
        "name": name,
        "value": round(value, 1),
        "unit": unit,
        "baseline": round(baseline, 1),
        "baseline_name": baseline_name,
        "ratio": round(value / baseline, 3),
        **extra,
    }


def median_spread(xs: Sequence[float]) -> tuple[float, float, float]:
    """(median, min, max)."""
    return statistics.median(xs), min(xs), max(xs)
