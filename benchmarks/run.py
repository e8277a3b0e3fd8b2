"""Run every benchmark: one JSON object per line, then a table of every figure.

Each line has at least ``name``, ``value``, ``unit``, ``baseline`` and
``ratio`` (ddes's value over the baseline's, both measured in this run, on
this machine).  Lines from an interleaved comparison (``common.compare``)
also have the ratio's spread over the rounds (``ratio_min``/``ratio_max``,
``rounds``) and, where a benchmark has one, the *fair* baseline (raw SimPy
plus exactly the work the ROS semantics require) with ``fair_ratio`` and its
spread.  All rates are per CPU second (``time.process_time``).  The first
line, ``conditions``, records the machine's load when the run started and
ended.  Benchmarks live in ``bench_*.py`` modules beside this file, each
exposing ``benchmarks() -> list[dict]``.  Each module runs in a child process
of its own (``run.py --module PATH``), so what one leaves behind (a Dask
cluster's threads, a grown heap, caches, imported modules) cannot slow the next.

    python benchmarks/run.py              # all
    python benchmarks/run.py time msg     # only bench_time.py and bench_msg.py
    python benchmarks/run.py --tiny       # every benchmark at a tiny size (a smoke test)
    python benchmarks/run.py --json       # JSON lines only, no table
"""

from __future__ import annotations

import importlib.util
import json
import os
import platform
import subprocess
import sys
import time
import traceback
from pathlib import Path
from typing import Any

HERE = Path(__file__).resolve().parent


def _load() -> list[float]:
    try:
        return [round(x, 2) for x in os.getloadavg()]
    except OSError:  # pragma: no cover - not on Unix
        return []


def _spread(lo: Any, hi: Any) -> str:
    return "" if lo is None or hi is None else f" [{lo:.3f}-{hi:.3f}]"


def table(rows: list[dict[str, Any]]) -> str:
    """Every figure of ``rows`` as an aligned text table."""
    lines = [f"{'benchmark':<34} {'ddes':>14} {'unit':<18} {'ratio [min-max]':<22} "
             f"{'fair ratio [min-max]':<22} baseline; fair baseline"]
    for r in rows:
        if r.get("name") == "conditions":
            continue
        if "error" in r:
            lines.append(f"{r['name']:<34} ERROR {r['error']}")
            continue
        ratio = f"{r['ratio']:.3f}{_spread(r.get('ratio_min'), r.get('ratio_max'))}"
        fair = ""
        if r.get("fair_ratio") is not None:
            fair = f"{r['fair_ratio']:.3f}{_spread(r.get('fair_ratio_min'), r.get('fair_ratio_max'))}"
        names = r.get("baseline_name", "")
        if r.get("fair_name"):
            names += f"; {r['fair_name']}"
        lines.append(f"{r['name']:<34} {r['value']:>14,.1f} {r['unit']:<18} {ratio:<22} "
                     f"{fair:<22} {names}")
    return "\n".join(lines)


def run_module(path: Path) -> int:
    """In the child: run one ``bench_*.py`` module, print its rows as JSON lines (0: it ran)."""
    sys.path.insert(0, str(HERE))
    try:
        spec = importlib.util.spec_from_file_location(path.stem, path)
        assert spec and spec.loader
        module = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(module)
        found = module.benchmarks()
    except Exception as exc:  # noqa: BLE001 - reported as a row; the parent's run goes on
        traceback.print_exc()
        error = {"name": path.stem, "error": f"{type(exc).__name__}: {exc}"}
        print(json.dumps(error), flush=True)
        return 1
    for row in found:
        print(json.dumps(row), flush=True)
    return 0


def _row(line: str) -> dict[str, Any] | None:
    """A child's output line as a row (a JSON object), or None for any other line."""
    if not line.startswith("{"):
        return None
    try:
        row = json.loads(line)
    except ValueError:
        return None
    return row if isinstance(row, dict) else None


def _run_child(path: Path) -> tuple[list[dict[str, Any]], bool]:
    """Run ``path`` in a fresh interpreter; its rows, and whether it ran to the end.

    The child's JSON-object lines are its rows; any other line it prints goes to stderr (as the
    child's stderr does, untouched).  A child that dies without an error row of its own
    (killed, out of memory) gets one naming its exit status."""
    cmd = [sys.executable, str(Path(__file__).resolve()), "--module", str(path)]
    found: list[dict[str, Any]] = []
    with subprocess.Popen(cmd, stdout=subprocess.PIPE, text=True) as child:
        assert child.stdout is not None
        for line in child.stdout:
            row = _row(line)
            if row is None:
                sys.stderr.write(line)
            else:
                found.append(row)
    rc = child.returncode
    if rc != 0 and not any("error" in r for r in found):
        found.append({"name": path.stem, "error": f"the benchmark's process ended with status {rc}"})
    return found, rc == 0


def main(argv: list[str]) -> int:
    if argv[:1] == ["--module"] and len(argv) == 2:
        return run_module(Path(argv[1]))
    tiny = "--tiny" in argv
    json_only = "--json" in argv
    if tiny:
        os.environ["DDES_BENCH_TINY"] = "1"
    wanted = {a for a in argv if not a.startswith("--")}
    start = {"name": "conditions", "loadavg_start": _load(), "cpus": os.cpu_count(),
             "python": platform.python_version(), "tiny": tiny, "clock": "process_time"}
    print(json.dumps(start), flush=True)
    rows: list[dict[str, Any]] = [start]
    failed = 0
    t0 = time.perf_counter()
    for path in sorted(HERE.glob("bench_*.py")):
        short = path.stem.removeprefix("bench_")
        if wanted and short not in wanted:
            continue
        found, ok = _run_child(path)
        failed += not ok
        for row in found:
            rows.append(row)
            print(json.dumps(row), flush=True)
    end = {"name": "conditions_end", "loadavg_end": _load(),
           "wall_s": round(time.perf_counter() - t0, 1)}
    print(json.dumps(end), flush=True)
    if not json_only:
        print()
        print(f"# load average at start {start['loadavg_start']}, at end {end['loadavg_end']}, "
              f"{start['cpus']} CPUs; rates per CPU second, medians of interleaved rounds")
        print(table(rows))
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
