"""benchmarks/run.py keeps running: every benchmark at a tiny size, every figure present.

No timing is asserted (the figures of a tiny run mean nothing): only that each
benchmark runs to the end and reports its rows in the documented shape.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

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
