"""Batch grading throughput against the number of Dask workers (issue 22).

The workload is a course exercise's reference, starter (``exercises/<id>/``) and every mutant
(``solutions/<id>/mutants``), graded by the whole command ``ddes grade batch EXERCISE DIR --out
OUT --workers N`` in a subprocess, for N in 0 (serial, in-process), 1, 2 and 4 (a Dask
``LocalCluster`` of N one-thread processes, its start included: what an instructor waits for).

Honest on a shared, loaded machine:

* **interleaved**: each round runs every worker count once, in a rotating order, so a burst of
  other load hits one round, not one worker count; figures are medians over the rounds, and the
  speedups are medians of the per-round ratios (with their min and max);
* throughput is **wall** time (submissions per minute: parallel workers only show in wall time),
  beside the **CPU** seconds the whole process tree spent per submission (``RUSAGE_CHILDREN`` of
  the batch command, its workers and their sandboxes), which shows what the cluster costs;
* the load average is recorded before and after;
* every run's output folder must be byte-identical to the serial one, each grade's wall time
  (``execution_time``) set aside (else the benchmark fails).

Rows: ``batch_throughput_workers{N}`` (value: submissions per minute; baseline: the serial
batch's in the same rounds; ratio: the speedup), with ``efficiency`` = throughput(N) /
(N x throughput(1 worker)) and ``efficiency_vs_serial`` = throughput(N) / (N x serial).

    python benchmarks/run.py batch                                      # ex1_console, 3 rounds
    DDES_BENCH_BATCH_EXERCISES=all DDES_BENCH_BATCH_ROUNDS=1 python benchmarks/run.py batch

``DDES_BENCH_BATCH_EXERCISES``: a comma list of exercises or ``all`` (every exercise of
``solutions/`` with mutants and a starter); ``DDES_BENCH_BATCH_WORKERS``: the worker counts
(default ``0,1,2,4``).  ``DDES_BENCH_TINY=1``: the demo exercise's reference and one mutant,
workers 0 and 1, one round (its figures mean nothing).
"""

from __future__ import annotations

import os
import resource
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parent.parent
TINY = os.environ.get("DDES_BENCH_TINY", "") not in ("", "0")
DEMO = ROOT / "tests" / "grading" / "fixtures"


def _exercises() -> list[str]:
    wanted = os.environ.get("DDES_BENCH_BATCH_EXERCISES", "ex1_console")
    if wanted != "all":
        return [w for w in wanted.split(",") if w]
    return sorted(p.name for p in (ROOT / "solutions").iterdir()
                  if (p / "mutants" / "mutants.yaml").is_file()
                  and (ROOT / "exercises" / p.name).is_dir())


def _submissions(exercise: str, dest: Path) -> tuple[Path, list[str]]:
    """``dest/subs``: the reference, ``starter`` and ``mutant_<name>`` folders; the extra
    arguments of ``ddes grade`` (the demo exercise's file in tiny mode)."""
    from ddes.grading.exercise import REGISTRY
    from ddes.grading.mutants import load_mutants, write_subjects

    extra: list[str] = []
    solutions = ROOT / "solutions"
    if TINY:
        extra = ["--exercises", str(DEMO / "ex0_talker.py")]
        REGISTRY.load_file(extra[1])
        solutions = DEMO / "solutions"
    solution = solutions / exercise
    mutants = load_mutants(solution, REGISTRY.get(exercise))
    subjects = write_subjects(solution, mutants[:1] if TINY else mutants, dest / "subjects")
    subs = dest / "subs"
    subs.mkdir(parents=True)
    for name, kind, _, folder in subjects:
        folder.rename(subs / (name if kind == "reference" else f"mutant_{name}"))
    if not TINY:
        shutil.copytree(ROOT / "exercises" / exercise, subs / "starter",
                        ignore=shutil.ignore_patterns("__pycache__"))
    return subs, extra


def _children_cpu() -> float:
    ru = resource.getrusage(resource.RUSAGE_CHILDREN)
    return ru.ru_utime + ru.ru_stime


def _run(exercise: str, subs: Path, out: Path, workers: int, extra: list[str]) -> tuple[float,
                                                                                        float]:
    """Wall and CPU seconds of one whole ``ddes grade batch`` command."""
    cmd = [sys.executable, "-m", "ddes", "grade", *extra, "batch", exercise, str(subs),
           "--out", str(out), "--workers", str(workers)]
    cpu0, t0 = _children_cpu(), time.perf_counter()
    proc = subprocess.run(cmd, capture_output=True, text=True, cwd=ROOT)
    wall, cpu = time.perf_counter() - t0, _children_cpu() - cpu0
    if proc.returncode != 0:
        raise RuntimeError(f"{' '.join(cmd)} exited {proc.returncode}: {proc.stderr[-2000:]}")
    return wall, cpu


def _same_tree(a: Path, b: Path) -> bool:
    """The same files with the same bytes, each grade's wall time (results.json's
    execution_time, junit.xml's time) set aside."""
    from ddes.grading.batch import without_wall_time

    left = sorted(p.relative_to(a) for p in a.rglob("*") if p.is_file())
    right = sorted(p.relative_to(b) for p in b.rglob("*") if p.is_file())
    return left == right and all(
        without_wall_time(str(p), (a / p).read_bytes())
        == without_wall_time(str(p), (b / p).read_bytes()) for p in left)


def _load() -> list[float]:
    return [round(x, 2) for x in os.getloadavg()]


def benchmarks() -> list[dict[str, Any]]:
    counts = [int(w) for w in os.environ.get("DDES_BENCH_BATCH_WORKERS", "0,1,2,4").split(",")]
    if TINY:
        counts = [0, 1]
    if 0 not in counts:
        counts.insert(0, 0)
    rounds = 1 if TINY else int(os.environ.get("DDES_BENCH_BATCH_ROUNDS", "3"))
    exercises = ["ex0_talker"] if TINY else _exercises()
    load_start = _load()
    tmp = Path(tempfile.mkdtemp(prefix="ddes-bench-batch-"))
    wall: dict[int, list[float]] = {n: [] for n in counts}
    cpu: dict[int, list[float]] = {n: [] for n in counts}
    total = 0
    try:
        sets = {ex: _submissions(ex, tmp / ex) for ex in exercises}
        total = sum(len(list(subs.iterdir())) for subs, _ in sets.values())
        for r in range(rounds):
            order = counts[r % len(counts):] + counts[:r % len(counts)]
            for n in order:
                w = c = 0.0
                for ex, (subs, extra) in sets.items():
                    out = tmp / ex / f"out-{n}-{r}"
                    dw, dc = _run(ex, subs, out, n, extra)
                    w, c = w + dw, c + dc
                    reference = tmp / ex / "out-0-0"
                    if reference.is_dir() and not _same_tree(reference, out):
                        raise RuntimeError(f"{ex}: --workers {n} wrote other bytes than "
                                           "--workers 0")
                    if (n, r) != (0, 0):
                        shutil.rmtree(out)
                wall[n].append(w)
                cpu[n].append(c)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    load_end = _load()

    def rate(n: int, i: int) -> float:
        return total / wall[n][i] * 60.0

    serial = statistics.median(rate(0, i) for i in range(rounds))
    one = statistics.median(rate(1, i) for i in range(rounds)) if 1 in counts else None
    rows = []
    for n in counts:
        value = statistics.median(rate(n, i) for i in range(rounds))
        speedups = [rate(n, i) / rate(0, i) for i in range(rounds)]
        row: dict[str, Any] = {
            "name": f"batch_throughput_workers{n}", "value": round(value, 2),
            "unit": "submissions/min", "baseline": round(serial, 2),
            "baseline_name": "--workers 0 (serial, in-process), same rounds",
            "ratio": round(statistics.median(speedups), 3),
            "ratio_min": round(min(speedups), 3), "ratio_max": round(max(speedups), 3),
            "workers": n, "submissions": total, "exercises": exercises, "rounds": rounds,
            "wall_s_median": round(statistics.median(wall[n]), 2),
            "cpu_s_per_submission": round(statistics.median(cpu[n]) / total, 3),
            "cores": os.cpu_count(), "loadavg_start": load_start, "loadavg_end": load_end,
            "identical_bytes": True,
        }
        if n:
            row["efficiency_vs_serial"] = round(value / (n * serial), 3)
            if one is not None:
                row["efficiency"] = round(value / (n * one), 3)
        rows.append(row)
    return rows


if __name__ == "__main__":
    import json

    for r in benchmarks():
        print(json.dumps(r))
