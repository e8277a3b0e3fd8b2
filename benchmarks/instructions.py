"""The benchmarks' ratios in instructions: what ddes and its baselines execute, without the noise.

CPU time on a shared machine moves by a third from run to run, more than most changes weigh.
This script runs the same functions as the CPU-time benchmarks (``bench_*.py``) under valgrind's
callgrind and counts the instructions each executes per operation: a count that is the same on
every run (``PYTHONHASHSEED=0``; the runs differ by well under 0.1 %), so a change that makes ddes
execute less shows at once, however loaded the machine.

Each function runs in a child process: imported and built, called once to warm up (message
classes, generated code, caches), then called again with counting on for that call alone
(``--toggle-collect`` on ``operator.call``, through which the child calls it).  The operation
count is what the function returns (the ``compare`` benchmarks' convention), or for the
simulator its simulated seconds.

``ratio`` is baseline instructions over ddes instructions per operation: as the CPU-time ratio, above
1 when ddes executes less.  It is *not* the CPU-time ratio: instructions do not count cache
misses, branch mispredictions or the kernel's work (page faults, file writes), and ddes, which
keeps its trace and touches more memory per operation, runs fewer instructions per cycle than a
raw SimPy loop: its CPU-time ratios come out lower than these (docs/benchmarks.md compares the
two).  The targets stay on CPU time; this is the tool to tell whether a change did less work.

    python benchmarks/instructions.py                    # every case
    python benchmarks/instructions.py timer_ticks sim    # cases whose name contains a word
    python benchmarks/instructions.py --json -j 4        # JSON lines only, four at a time
    python benchmarks/instructions.py --tiny             # tiny sizes (a smoke test)

Needs valgrind (Debian's ``valgrind`` package) and CPython 3.11 or newer.
"""

from __future__ import annotations

import argparse
import atexit
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile
from collections.abc import Callable
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path
from typing import Any

HERE = Path(__file__).resolve().parent

#: Each case: its CPU-time benchmark's name, then per role (ddes, base, fair) how the child gets
#: the function: (module, attribute, arguments); arguments None means the attribute is the
#: function, else the attribute is called with them and returns it.  ``ops`` names a module
#: attribute holding the operation count when the function returns a rate instead of a count.
CASES: dict[str, dict[str, Any]] = {
    "topic_delivery_1to1": {"ddes": ("bench_graph", "ddes_delivery", [1]),
                            "base": ("bench_graph", "raw", [1]),
                            "fair": ("bench_graph", "fair", [1])},
    "topic_delivery_1to4": {"ddes": ("bench_graph", "ddes_delivery", [4]),
                            "base": ("bench_graph", "raw", [4]),
                            "fair": ("bench_graph", "fair", [4])},
    "timer_ticks": {"ddes": ("bench_time", "ddes_timer", None),
                    "base": ("bench_time", "raw_simpy", None),
                    "fair": ("bench_time", "fair_timer", None)},
    "rate_sleeps": {"ddes": ("bench_time", "ddes_rate", None),
                    "base": ("bench_time", "raw_simpy", None),
                    "fair": ("bench_time", "fair_rate", None)},
    "service_round_trips_persistent": {"ddes": ("bench_services", "ddes_calls", [True]),
                                       "base": ("bench_services", "raw_simpy", None),
                                       "fair": ("bench_services", "fair", [True])},
    "service_round_trips": {"ddes": ("bench_services", "ddes_calls", [False]),
                            "base": ("bench_services", "raw_simpy", None),
                            "fair": ("bench_services", "fair", [False])},
    "action_goals": {"ddes": ("bench_actions", "ddes_goals", None),
                     "base": ("bench_actions", "raw", None),
                     "fair": ("bench_actions", "fair", None)},
    "msg_roundtrip_string": {"ddes": ("instructions", "msg_case", ["string", "ddes"]),
                             "base": ("instructions", "msg_case", ["string", "rosbags"])},
    "msg_roundtrip_laserscan720_numpy": {
        "ddes": ("instructions", "msg_case", ["laserscan720_numpy", "ddes"]),
        "base": ("instructions", "msg_case", ["laserscan720_numpy", "rosbags"])},
    "bag_write_file": {"ddes": ("instructions", "bag_case", ["write", "ddes"]),
                       "base": ("instructions", "bag_case", ["write", "rosbags"])},
    "bag_read_file": {"ddes": ("instructions", "bag_case", ["read", "ddes"]),
                      "base": ("instructions", "bag_case", ["read", "rosbags"])},
    "trace_digest_per_event": {"ddes": ("instructions", "digest_case", ["ddes"]),
                               "base": ("instructions", "digest_case", ["reference"])},
    "sim_pillar_rtf": {"ddes": ("bench_sim", "ddes_pillar", None),
                       "base": ("bench_sim", "raw_pillar", None), "ops": "SIM_SECONDS"},
}

# -- factories for the benchmarks whose functions are closures inside ``benchmarks()`` --------


def msg_case(which: str, side: str) -> Callable[[], int]:
    """bench_msg's round trip of one message (``bench_msg.round_trips``), as a counted loop."""
    import bench_msg as b

    if which == "string":
        msg, n, numpy = b._string(), b.size(20_000), False
    else:  # "laserscan720_numpy"
        msg, n, numpy = b._laser_scan(), b.size(3_000), True
    ddes_round_trip, rosbags_round_trip, _data = b.round_trips(msg, numpy)
    return b._loop(ddes_round_trip if side == "ddes" else rosbags_round_trip, n)


def bag_case(op: str, side: str) -> Callable[[], int]:
    """bench_bags' file write or read (the file to read written first, not counted)."""
    import bench_bags as b

    payload = b._payload()
    tmp = tempfile.mkdtemp(prefix="ddes-instructions-")
    atexit.register(shutil.rmtree, tmp, True)
    path = os.path.join(tmp, f"{side}.bag")
    writer = (b._ddes_write if side == "ddes" else b._rosbags_write)(payload, path)
    if op == "write":
        return writer
    writer()
    return b._ddes_read(path) if side == "ddes" else b._rosbags_read(path)


def digest_case(side: str) -> Callable[[], int]:
    """bench_trace's digest of a recorded run (``bench_trace.digests``): ddes's or the reference."""
    import bench_trace as b

    new, old = b.digests(b._recorded())
    return new if side == "ddes" else old


# -- running ------------------------------------------------------------------------------------

_CHILD = r"""
import importlib, json, operator, signal, sys
# World.run's wall-budget watchdog arms SIGALRM and, when the run ends, disarms it and puts
# back the default action (end the process).  Valgrind delivers a signal late, so an alarm
# due just before the disarm could arrive after it and end the child: ignored instead.
signal.signal(signal.SIGALRM, signal.SIG_IGN)
sys.path.insert(0, {here!r})
module, attr, args, ops = json.loads({spec!r})
mod = importlib.import_module(module)
fn = getattr(mod, attr)
if args is not None:
    fn = fn(*args)
fn()  # warm-up: not counted
out = operator.call(fn)  # counted: callgrind collects inside operator.call only (toggled
#   on entry and exit, so code under test must not call operator.call: none in ddes, SimPy, rosbags)
print(json.dumps(getattr(mod, ops) if ops else out))
"""

_REFS = re.compile(r"I\s+refs:\s+([\d,]+)")


class InstructionCountError(RuntimeError):
    """A child run failed or printed no count."""


def count(module: str, attr: str, args: list[Any] | None,
          ops: str | None = None) -> tuple[int, float]:
    """(instructions executed by one warm call, its operation count), counted by callgrind."""
    spec = json.dumps([module, attr, args, ops])
    code = _CHILD.format(here=str(HERE), spec=spec)
    child_env = dict(os.environ)
    child_env["PYTHONHASHSEED"] = "0"
    proc = subprocess.run(
        ["valgrind", "--tool=callgrind", "--callgrind-out-file=/dev/null",
         "--collect-atstart=no", "--toggle-collect=_operator_call*", sys.executable, "-c", code],
        capture_output=True, text=True, env=child_env, check=False)
    refs = _REFS.findall(proc.stderr)
    if proc.returncode != 0 or not refs:
        raise InstructionCountError(f"{module}.{attr}{tuple(args or ())}: valgrind exited "
                                    f"{proc.returncode}:\n{proc.stderr[-2000:]}")
    return int(refs[-1].replace(",", "")), float(json.loads(proc.stdout.strip().splitlines()[-1]))


def _row(name: str, per_op: dict[str, float]) -> dict[str, Any]:
    out: dict[str, Any] = {"name": name, "unit": "instructions/op",
                           "ddes": round(per_op["ddes"]), "base": round(per_op["base"]),
                           "ratio": round(per_op["base"] / per_op["ddes"], 3)}
    if "fair" in per_op:
        out.update(fair=round(per_op["fair"]), fair_ratio=round(per_op["fair"] / per_op["ddes"], 3))
    return out


def measure(names: list[str], jobs: int = 2) -> list[dict[str, Any]]:
    """Instructions per operation of each case's roles, and the ratios; ``jobs`` children at once.

    Rows come in the order of ``names``, each as soon as its case and those before it are done
    (see :func:`main`)."""
    with ThreadPoolExecutor(max_workers=max(1, jobs)) as pool:
        futures = {(name, role): pool.submit(count, *CASES[name][role], CASES[name].get("ops"))
                   for name in names for role in ("ddes", "base", "fair") if role in CASES[name]}
        rows = []
        for name in names:
            per_op = {}
            for (n, role), fut in futures.items():
                if n == name:
                    instructions, ops = fut.result()
                    per_op[role] = instructions / ops
            rows.append(_row(name, per_op))
            print(json.dumps(rows[-1]), flush=True)
    return rows


def table(rows: list[dict[str, Any]]) -> str:
    lines = [f"{'case':<34} {'ddes Ir/op':>12} {'base Ir/op':>12} {'ratio':>7} "
             f"{'fair Ir/op':>12} {'fair ratio':>10}"]
    for r in rows:
        fair = (f"{r['fair']:>12,} {r['fair_ratio']:>10.3f}" if "fair" in r else "")
        lines.append(f"{r['name']:<34} {r['ddes']:>12,} {r['base']:>12,} {r['ratio']:>7.3f} {fair}")
    return "\n".join(lines)


def main(argv: list[str]) -> int:
    parser = argparse.ArgumentParser(
        prog="instructions.py",
        description="The benchmarks' comparisons in instructions counted by callgrind.")
    parser.add_argument("words", nargs="*", metavar="WORD",
                        help="run the cases whose name contains a WORD (default: every case)")
    parser.add_argument("-j", "--jobs", type=int, default=os.cpu_count() or 1,
                        help="children counted at once (default: the number of CPUs)")
    parser.add_argument("--json", action="store_true", help="JSON lines only, no table")
    parser.add_argument("--tiny", action="store_true", help="tiny sizes (a smoke test)")
    args = parser.parse_args(argv)
    if args.jobs < 1:
        parser.error(f"--jobs must be 1 or more, got {args.jobs}")
    if shutil.which("valgrind") is None:
        print("instructions.py needs valgrind (Debian: apt-get install valgrind)", file=sys.stderr)
        return 2
    if args.tiny:
        os.environ["DDES_BENCH_TINY"] = "1"
    names = [n for n in CASES if not args.words or any(w in n for w in args.words)]
    if not names:
        parser.error(f"no case matches {' '.join(args.words)}; cases: {', '.join(CASES)}")
    rows = measure(names, args.jobs)
    if not args.json:
        print()
        print(table(rows))
    return 0


if __name__ == "__main__":
    sys.path.insert(0, str(HERE))
    sys.exit(main(sys.argv[1:]))
