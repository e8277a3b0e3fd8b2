"""Scaling: per-node cost of worlds from 10 to 1,000 nodes (and 100 to 10,000 topics).

Each world has N nodes in a ring; node i advertises ten topics ``/n<i>/t0..t9``
and subscribes to ``/n<i+1>/t0``, on which it publishes a std_msgs/String at
10 Hz (a 10 Hz timer per node); so a world has N nodes, 10·N topics and N
publishing links.  Two figures per size, in CPU time:

* ``scaling_setup_n<N>``: nodes set up per CPU second (create, advertise ten,
  subscribe one, connect), against the same figure at the smallest size
  (ratio 1.0 = flat per-node cost); ``settle_cpu_s`` beside it is one full
  ``gc.collect()`` right after, timed on its own: the cyclic collector's settling
  of the new world's objects.  Without it the collector's first full
  collections after a big set-up (two at 1,000 nodes: 35-65 ms each, most of the
  process's tracked objects being new) land in the timed run, whose 2 simulated
  seconds they would dominate; so the run below is the steady state;
* ``scaling_run_n<N>``: node-seconds simulated per CPU second (N nodes × the
  simulated seconds, each node publishing and receiving 10 msgs/s), against
  raw SimPy running the same schedule with the same N (N processes waking at
  10 Hz, each scheduling one delivery event with a callback): a flat
  ``ratio`` over N means ddes's per-node cost grows as SimPy's own does (its
  event heap is log N deep, and a bigger world misses the caches more);
  ``vs_smallest`` is the figure over the smallest size's.

Each timed call starts after an untimed ``gc.collect()`` (as ``common.interleave`` does), so
the cycles of the previous, larger or smaller, world are not freed inside the next one's timing.

``exponent`` is the log-log slope of total CPU against N from the previous
size (1.0 = linear, i.e. flat per-node cost).  The sizes run interleaved,
``repeat`` rounds, medians.
"""

from __future__ import annotations

import gc
import math
import statistics
import sys
import time
from pathlib import Path
from typing import Any

sys.path.insert(0, str(Path(__file__).resolve().parent))

import simpy  # noqa: E402
from common import TINY, repeats  # noqa: E402

import ddes  # noqa: E402
from ddes.msg import get_message_class  # noqa: E402

String = get_message_class("std_msgs/String")
SIZES = (3, 10, 30) if TINY else (10, 100, 300, 1000)
SIM_SECONDS = 0.2 if TINY else 2.0
TOPICS_PER_NODE = 10


def one(n: int) -> tuple[float, float, float]:
    """(set-up, settling, run) CPU seconds of a world of ``n`` nodes (see the module docstring)."""
    t0 = time.process_time()
    world = ddes.World()
    nodes = [world.create_node(f"n{i}", disable_rosout=True) for i in range(n)]
    pubs = [[node.advertise(f"~t{k}", String, queue_size=10) for k in range(TOPICS_PER_NODE)]
            for node in nodes]
    got = [0]

    def cb(_msg: Any) -> None:
        got[0] += 1

    for i, node in enumerate(nodes):
        node.subscribe(f"/n{(i + 1) % n}/t0", String, cb, queue_size=10)
    msg = String(data="hello")
    for i, node in enumerate(nodes):
        pub = pubs[i][0]
        node.create_timer(0.1, lambda _ev, pub=pub: pub.publish(msg))
    world.run(until=0.01)  # connections form
    # The collector's settling of the new world, timed on its own: a world of 1,000 nodes adds
    # ~120,000 tracked objects, several times what the process held, so the collector's next
    # full collections (two, 35-65 ms each, measured with gc.callbacks) would otherwise land in
    # the first simulated second whatever the run does.
    t1 = time.process_time()
    gc.collect()
    t1b = time.process_time()
    world.run(until=0.01 + SIM_SECONDS)
    t2 = time.process_time()
    expected = n * int(SIM_SECONDS * 10)
    if not expected * 0.8 <= got[0] <= expected * 1.2:
        raise AssertionError(f"{n} nodes delivered {got[0]} messages, expected about {expected}")
    return t1 - t0, t1b - t1, t2 - t1b


def raw(n: int) -> float:
    """Run CPU seconds of raw SimPy on the same schedule as :func:`one`'s run phase."""
    env = simpy.Environment()
    got = [0]

    def cb(_ev: Any) -> None:
        got[0] += 1

    def proc() -> Any:
        while True:
            yield env.timeout(100_000_000)
            env.timeout(0, "hello").callbacks.append(cb)

    for _ in range(n):
        env.process(proc())
    env.run(until=10_000_000)
    t0 = time.process_time()
    env.run(until=10_000_000 + int(SIM_SECONDS * 1e9))
    return time.process_time() - t0


def benchmarks() -> list[dict[str, Any]]:
    rounds: dict[int, list[tuple[float, float, float]]] = {n: [] for n in SIZES}
    raws: dict[int, list[float]] = {n: [] for n in SIZES}
    for r in range(repeats(3)):
        order = SIZES if r % 2 == 0 else tuple(reversed(SIZES))
        for n in order:
            gc.collect()  # untimed: an earlier world's garbage is not freed inside this one
            raws[n].append(raw(n))
            gc.collect()
            rounds[n].append(one(n))  # (set-up, settling, run) CPU seconds
    out = []
    base_setup = base_run = None
    prev: tuple[int, float, float] | None = None
    for n in SIZES:
        setup = statistics.median(s for s, _, _ in rounds[n])
        settle = statistics.median(c for _, c, _ in rounds[n])
        run = statistics.median(r for _, _, r in rounds[n])
        ratios = [n * SIM_SECONDS / d / (n * SIM_SECONDS / b)
                  for (_, _, d), b in zip(rounds[n], raws[n])]
        raw_rate = n * SIM_SECONDS / statistics.median(raws[n])
        setup_rate = n / setup
        run_rate = n * SIM_SECONDS / run
        if base_setup is None or base_run is None:
            base_setup, base_run = setup_rate, run_rate
        extra_s: dict[str, Any] = {"nodes": n, "topics": n * TOPICS_PER_NODE,
                                   "cpu_s": round(setup, 3), "settle_cpu_s": round(settle, 4)}
        extra_r: dict[str, Any] = {"nodes": n, "topics": n * TOPICS_PER_NODE,
                                   "cpu_s": round(run, 3)}
        if prev is not None:
            pn, ps, pr = prev
            extra_s["exponent"] = round(math.log(setup / ps) / math.log(n / pn), 2)
            extra_r["exponent"] = round(math.log(run / pr) / math.log(n / pn), 2)
        out.append({"name": f"scaling_setup_n{n}", "value": round(setup_rate, 1),
                    "unit": "nodes set up/s", "baseline": round(base_setup, 1),
                    "baseline_name": f"the same at {SIZES[0]} nodes",
                    "ratio": round(setup_rate / base_setup, 3), **extra_s})
        out.append({"name": f"scaling_run_n{n}", "value": round(run_rate, 1),
                    "unit": "node-seconds/s", "baseline": round(raw_rate, 1),
                    "baseline_name": "raw SimPy, the same schedule and N",
                    "ratio": round(statistics.median(ratios), 3),
                    "ratio_min": round(min(ratios), 3), "ratio_max": round(max(ratios), 3),
                    "rounds": len(ratios), "vs_smallest": round(run_rate / base_run, 3),
                    **extra_r})
        prev = (n, setup, run)
    return out


if __name__ == "__main__":
    import json

    for r in benchmarks():
        print(json.dumps(r))
