"""benchmarks/run.py keeps running: every benchmark at a tiny size, every figure present.

No timing is asserted (the figures of a tiny run mean nothing): only that each
benchmark runs to the end and reports its rows in the documented shape.
"""

from __future__ import annotations

import importlib.util
import json
import os
import subprocess
import sys
from pathlib import Path
from typing import Any

import pytest

ROOT = Path(__file__).resolve().parent.parent

#: Every figure issue 23 asks for, by row name.
FIGURES = {
    "topic_delivery_1to1", "topic_delivery_1to4", "timer_ticks", "rate_sleeps",
    "service_round_trips_persistent", "service_round_trips", "action_goals",
    "msg_roundtrip_string", "msg_roundtrip_laserscan720", "bag_write_file", "bag_read_file",
    "sim_pillar_rtf", "trace_digest_per_event", "trace_memory_per_event",
}
#: The rows that must carry a fair baseline beside the raw one.
FAIR = {"topic_delivery_1to1", "topic_delivery_1to4", "timer_ticks", "rate_sleeps",
        "service_round_trips_persistent", "service_round_trips", "action_goals"}


def test_run_py_tiny_prints_every_figure() -> None:
    env = {k: v for k, v in os.environ.items() if k != "DDES_BENCH_TINY"}
    proc = subprocess.run([sys.executable, str(ROOT / "benchmarks" / "run.py"), "--tiny"],
                          capture_output=True, text=True, env=env, cwd=ROOT, timeout=600)
    assert proc.returncode == 0, proc.stderr[-4000:]
    rows = [json.loads(line) for line in proc.stdout.splitlines() if line.startswith("{")]
    by_name = {r["name"]: r for r in rows}
    assert by_name["conditions"]["tiny"] is True
    assert by_name["conditions"]["clock"] == "process_time"
    assert "loadavg_end" in by_name["conditions_end"]
    missing = FIGURES - set(by_name)
    assert not missing, f"figures missing from run.py: {sorted(missing)}"
    for r in rows:
        if r["name"].startswith("conditions"):
            continue
        assert "error" not in r, r
        for key in ("value", "unit", "baseline", "baseline_name", "ratio"):
            assert key in r, (r["name"], key)
        assert r["value"] > 0 and r["baseline"] > 0, r
    for name in FAIR:
        r = by_name[name]
        assert r["fair"] > 0 and r["fair_name"], r
        assert r["fair_ratio_min"] <= r["fair_ratio"] <= r["fair_ratio_max"], r
        assert r["ratio_min"] <= r["ratio"] <= r["ratio_max"], r
    scaling = [r for r in rows if r["name"].startswith("scaling_run_n")]
    assert len(scaling) >= 3 and all("exponent" in r for r in scaling[1:]), scaling
    # the table after the JSON lines names every figure
    table = proc.stdout.split("\n\n", 1)[1]
    for name in FIGURES:
        assert name in table


def _run_py() -> Any:
    """benchmarks/run.py as a module (it is a script, not a package member)."""
    spec = importlib.util.spec_from_file_location("bench_run", ROOT / "benchmarks" / "run.py")
    assert spec and spec.loader
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@pytest.mark.parametrize(("body", "status", "error"), [
    ("def benchmarks():\n    return [{'name': 'a', 'value': 1}, {'name': 'b', 'value': 2}]\n",
     True, None),
    ("def benchmarks():\n    raise ValueError('no such scenario')\n",
     False, "ValueError: no such scenario"),
    ("import os\nprint('a stray line')\nprint('{not json')\ndef benchmarks():\n    os._exit(3)\n",
     False, "the benchmark's process ended with status 3"),
])
def test_each_benchmark_module_runs_in_a_process_of_its_own(
        tmp_path: Path, capsys: pytest.CaptureFixture[str], body: str, status: bool,
        error: str | None) -> None:
    """run.py runs every bench_*.py in a fresh interpreter (what one leaves behind cannot slow
    the next): its rows come back, a failure becomes an error row naming it, a process that
    dies without one gets one naming its exit status, and a stray printed line (JSON or not)
    goes to stderr."""
    path = tmp_path / "bench_probe.py"
    path.write_text(body)
    rows, ok = _run_py()._run_child(path)
    assert ok is status
    if error is None:
        assert rows == [{"name": "a", "value": 1}, {"name": "b", "value": 2}]
    else:
        assert rows[-1] == {"name": "bench_probe", "error": error}
    if "stray" in body:
        err = capsys.readouterr().err
        assert "a stray line" in err and "{not json" in err
