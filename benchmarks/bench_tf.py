"""TF lookups per second: ddes.tf2.BufferCore against the real tf2 BufferCore (C++, tf2_py).

Both sides load the same tree (a 4-link dynamic chain map -> odom -> base -> arm -> hand with 100
stamps per link over 10 s, plus a static camera under base) and answer the same 2000 lookups
hand -> map and camera -> map at random (interpolated) times, each returning a
geometry_msgs/TransformStamped; ``can_transform`` is timed on the same queries.  Rates are CPU
time (``time.process_time``), best of 5, both measured in this run; the real tf2 runs under
Debian's system Python (``/usr/bin/python3``) and its rows are left out when tf2_py is absent.
"""

from __future__ import annotations

import json
import os
import random
import subprocess
import time
from typing import Any

from common import repeats, row, size

from ddes.msg import get_message_class
from ddes.tf2 import BufferCore
from ddes.time import Time

N = size(2000)
LINKS = [("map", "odom"), ("odom", "base"), ("base", "arm"), ("arm", "hand")]


def _plan() -> dict[str, Any]:
    rnd = random.Random(3)
    sets = []
    for k in range(100):
        stamp = 1_000_000_000 + k * 100_000_000
        for parent, child in LINKS:
            q = [rnd.gauss(0, 1) for _ in range(4)]
            n = sum(v * v for v in q) ** 0.5
            sets.append([parent, child, stamp, [rnd.uniform(-1, 1) for _ in range(3)],
                         [v / n for v in q]])
    queries = [[rnd.choice(["hand", "camera"]), rnd.randint(1_000_000_000, 10_900_000_000)]
               for _ in range(N)]
    return {"sets": sets, "queries": queries}


_REAL = r"""
import json, sys, time
import rospy, tf2_py
from geometry_msgs.msg import TransformStamped
plan = json.load(sys.stdin)
b = tf2_py.BufferCore()
def ts(p, c, stamp, tr, q, static=False):
    m = TransformStamped()
    m.header.frame_id, m.child_frame_id = p, c
    m.header.stamp = rospy.Time(stamp // 10**9, stamp % 10**9)
    m.transform.translation.x, m.transform.translation.y, m.transform.translation.z = tr
    m.transform.rotation.x, m.transform.rotation.y, m.transform.rotation.z, m.transform.rotation.w = q
    return m
for p, c, stamp, tr, q in plan["sets"]:
    b.set_transform(ts(p, c, stamp, tr, q), "bench")
b.set_transform_static(ts("base", "camera", 0, [0.1, 0, 0.3], [0, 0, 0, 1]), "bench")
queries = [(f, rospy.Time(t // 10**9, t % 10**9)) for f, t in plan["queries"]]
best_l = best_c = 0.0
for _ in range(5):
    t0 = time.process_time()
    for f, t in queries:
        b.lookup_transform_core("map", f, t)
    best_l = max(best_l, len(queries) / (time.process_time() - t0))
    t0 = time.process_time()
    for f, t in queries:
        b.can_transform_core("map", f, t)
    best_c = max(best_c, len(queries) / (time.process_time() - t0))
print(json.dumps({"lookup": best_l, "can": best_c}))
"""


def _real(plan: dict[str, Any]) -> dict[str, float] | None:
    interp = "/usr/bin/python3"
    if not os.path.exists(interp):
        return None
    env = {k: v for k, v in os.environ.items() if not k.startswith("PYTHON")}
    probe = subprocess.run([interp, "-c", "import tf2_py, rospy"], capture_output=True, env=env)
    if probe.returncode != 0:
        return None
    proc = subprocess.run([interp, "-c", _REAL], input=json.dumps(plan), capture_output=True,
                          text=True, env=env, timeout=600)
    if proc.returncode != 0:
        return None
    result: dict[str, float] = json.loads(proc.stdout)
    return result


def _ddes(plan: dict[str, Any]) -> dict[str, float]:
    ts_class = get_message_class("geometry_msgs/TransformStamped")

    def ts(p: str, c: str, stamp: int, tr: list[float], q: list[float]) -> Any:
        m = ts_class()
        m.header.frame_id, m.child_frame_id = p, c
        m.header.stamp = Time.from_nsec(stamp)
        t, r = m.transform.translation, m.transform.rotation
        t.x, t.y, t.z = tr
        r.x, r.y, r.z, r.w = q
        return m

    b = BufferCore()
    for p, c, stamp, tr, q in plan["sets"]:
        b.set_transform(ts(p, c, stamp, tr, q), "bench")
    b.set_transform_static(ts("base", "camera", 0, [0.1, 0, 0.3], [0, 0, 0, 1]), "bench")
    queries = [(f, Time.from_nsec(t)) for f, t in plan["queries"]]
    best_l = best_c = 0.0
    for _ in range(repeats(5)):
        t0 = time.process_time()
        for f, t in queries:
            b.lookup_transform_core("map", f, t)
        best_l = max(best_l, len(queries) / (time.process_time() - t0))
        t0 = time.process_time()
        for f, t in queries:
            b.can_transform_core("map", f, t)
        best_c = max(best_c, len(queries) / (time.process_time() - t0))
    return {"lookup": best_l, "can": best_c}


def benchmarks() -> list[dict[str, Any]]:
    plan = _plan()
    mine = _ddes(plan)
    theirs = _real(plan)
    if theirs is None:
        return [row("tf_lookup", mine["lookup"], "lookups/s (CPU)", mine["lookup"],
                    "none (tf2_py not installed)", n=N)]
    return [
        row("tf_lookup_vs_tf2", mine["lookup"], "lookups/s (CPU)", theirs["lookup"],
            "tf2_py.BufferCore (C++, system python)", n=N, chain_links=4),
        row("tf_can_transform_vs_tf2", mine["can"], "queries/s (CPU)", theirs["can"],
            "tf2_py.BufferCore (C++, system python)", n=N, chain_links=4),
    ]
