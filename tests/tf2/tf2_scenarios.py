"""Randomised BufferCore scenarios, and one runner that plays them on ddes or on the real tf2_py.

``RUNNER`` is Python source that runs unchanged under the venv (ddes.tf2.BufferCore) and under
Debian's system Python (tf2_py.BufferCore): a scenario is a list of operations in JSON, and the
runner returns, for each, ``["ok", ...]`` or ``["err", exception class name, text]``.
"""

from __future__ import annotations

import math
import random
from typing import Any

RUNNER = r'''
import math

def run_scenario(ops, make_core, make_ts, make_time):
    core = None
    out = []
    for op in ops:
        kind = op[0]
        try:
            if kind == "new":
                core = make_core(op[1])
                out.append(["ok"])
            elif kind in ("set", "static"):
                _, parent, child, stamp, tr, q, auth = op
                m = make_ts(parent, child, stamp, tr, q)
                (core.set_transform_static if kind == "static" else core.set_transform)(m, auth)
                out.append(["ok"])
            elif kind == "lookup":
                r = core.lookup_transform_core(op[1], op[2], make_time(op[3]))
                out.append(["ok", msg(r)])
            elif kind == "full":
                r = core.lookup_transform_full_core(op[1], make_time(op[2]), op[3],
                                                    make_time(op[4]), op[5])
                out.append(["ok", msg(r)])
            elif kind == "can":
                ok, text = core.can_transform_core(op[1], op[2], make_time(op[3]))
                out.append(["ok", bool(ok), text])
            elif kind == "canfull":
                ok, text = core.can_transform_full_core(op[1], make_time(op[2]), op[3],
                                                        make_time(op[4]), op[5])
                out.append(["ok", bool(ok), text])
            elif kind == "lct":
                t = core.get_latest_common_time(op[1], op[2])
                out.append(["ok", t.secs * 1000000000 + t.nsecs])
            elif kind == "yaml":
                out.append(["ok", core.all_frames_as_yaml()])
            elif kind == "string":
                out.append(["ok", core.all_frames_as_string()])
            elif kind == "frames":
                out.append(["ok", list(core._getFrameStrings())])
            elif kind == "clear":
                core.clear()
                out.append(["ok"])
            else:
                raise ValueError(kind)
        except Exception as e:  # noqa: BLE001 - the comparison wants every error
            out.append(["err", type(e).__name__, str(e)])
    return out

def msg(r):
    t, q = r.transform.translation, r.transform.rotation
    return [r.header.stamp.secs * 1000000000 + r.header.stamp.nsecs, r.header.frame_id,
            r.child_frame_id, [t.x, t.y, t.z, q.x, q.y, q.z, q.w]]
'''

#: The system-Python side: reads scenarios (JSON) on stdin, prints results and tf2's log lines.
REAL_SCRIPT = RUNNER + r'''
import json, os, sys, tempfile
import rospy, tf2_py
from geometry_msgs.msg import TransformStamped

def make_ts(parent, child, stamp, tr, q):
    m = TransformStamped()
    m.header.frame_id = parent
    m.child_frame_id = child
    m.header.stamp = rospy.Time(stamp // 1000000000, stamp % 1000000000)
    m.transform.translation.x, m.transform.translation.y, m.transform.translation.z = tr
    (m.transform.rotation.x, m.transform.rotation.y, m.transform.rotation.z,
     m.transform.rotation.w) = q
    return m

def make_time(ns):
    return rospy.Time(ns // 1000000000, ns % 1000000000)

def make_core(cache_ns):
    return tf2_py.BufferCore(rospy.Duration(cache_ns // 1000000000, cache_ns % 1000000000))

scenarios = json.load(sys.stdin)
results = []
logs = []
for ops in scenarios:
    # tf2 logs through console_bridge to stderr: capture fd 2 per scenario.
    with tempfile.TemporaryFile() as tmp:
        sys.stderr.flush()
        saved = os.dup(2)
        os.dup2(tmp.fileno(), 2)
        try:
            results.append(run_scenario(ops, make_core, make_ts, make_time))
        finally:
            os.dup2(saved, 2)
            os.close(saved)
        tmp.seek(0)
        text = tmp.read().decode()
    lines = []
    for line in text.splitlines():
        for prefix in ("Warning: ", "Error:   "):
            if line.startswith(prefix):
                lines.append(line[len(prefix):])
    logs.append(lines)
print(json.dumps({"results": results, "logs": logs}))
'''


def unit_quaternion(rnd: random.Random) -> list[float]:
    while True:
        q = [rnd.gauss(0, 1) for _ in range(4)]
        n = math.sqrt(sum(v * v for v in q))
        if n > 1e-3:
            return [v / n for v in q]


def scenario(seed: int) -> list[list[Any]]:
    """A random tree (chain, star or random parents, possibly several trees), random stamps
    (ms and odd ns), static and dynamic links, parent changes, bad inputs, and lookups at
    exact, interpolated, past, future and zero times, plus full (fixed-frame) lookups."""
    rnd = random.Random(seed)
    n = rnd.randint(2, 9)
    names = [f"f{i}" for i in range(n)]
    shape = rnd.choice(["chain", "star", "random", "forest"])
    parent = {}
    for i in range(1, n):
        if shape == "chain":
            p = i - 1
        elif shape == "star":
            p = 0
        else:
            p = rnd.randrange(i)
        if shape == "forest" and rnd.random() < 0.3:
            continue  # a root of its own: disconnected trees
        parent[i] = p
    cache_s = rnd.choice([1, 2, 10])
    ops: list[list[Any]] = [["new", cache_s * 1_000_000_000]]
    static = {i for i in parent if rnd.random() < 0.3}
    t0 = rnd.randint(1, 50) * 1_000_000_000
    times: list[int] = []
    for step in range(rnd.randint(1, 12)):
        t = t0 + step * rnd.choice([100_000_000, 250_000_000, 1_000_000_000]) \
            + rnd.choice([0, 0, 0, 1, 123_457])
        times.append(t)
        for i, p in parent.items():
            if i in static and step:
                continue
            if rnd.random() < 0.15:
                continue  # this link misses this step
            pname = names[p]
            if rnd.random() < 0.05 and i not in static:
                pname = names[rnd.randrange(n)]  # a parent change (or a self transform)
            q = unit_quaternion(rnd)
            tr = [rnd.uniform(-5, 5) for _ in range(3)]
            if rnd.random() < 0.03:
                q = [v * 1.5 for v in q]  # denormalised
            if rnd.random() < 0.02:
                tr[1] = float("nan")
            child = names[i]
            if rnd.random() < 0.05:
                child = "/" + child
            ops.append(["static" if i in static else "set", pname, child, t, tr, q,
                        f"/node{rnd.randrange(3)}"])
        if rnd.random() < 0.1:  # a repeated stamp, or data from the past
            i = rnd.choice(list(parent) or [1])
            if i in parent and i not in static:
                back = rnd.choice([0, cache_s * 1_000_000_000 + 1])
                ops.append(["set", names[parent[i]], names[i], max(t - back, 1), [1, 2, 3],
                            [0, 0, 0, 1], "/late"])
    if rnd.random() < 0.1:
        ops.append(["set", "", names[0], t0, [0, 0, 0], [0, 0, 0, 1], "/x"])
        ops.append(["set", names[0], "", t0, [0, 0, 0], [0, 0, 0, 1], "/x"])
    lo, hi = min(times), max(times)
    pool = names + ["ghost", ""] + (["/" + names[0]] if rnd.random() < 0.2 else [])

    def a_time() -> int:
        r = rnd.random()
        if r < 0.2:
            return 0
        if r < 0.45:
            return rnd.choice(times)
        if r < 0.8:
            return rnd.randint(lo, hi)
        return max(1, rnd.randint(lo - 3_000_000_000, hi + 3_000_000_000))

    def a_frame() -> str:
        return rnd.choice(names) if rnd.random() < 0.9 else rnd.choice(pool)

    for _ in range(rnd.randint(10, 30)):
        r = rnd.random()
        if r < 0.45:
            ops.append(["lookup", a_frame(), a_frame(), a_time()])
        elif r < 0.65:
            ops.append(["can", a_frame(), a_frame(), a_time()])
        elif r < 0.8:
            ops.append(["full", a_frame(), a_time(), a_frame(), a_time(), a_frame()])
        elif r < 0.88:
            ops.append(["canfull", a_frame(), a_time(), a_frame(), a_time(), a_frame()])
        elif r < 0.95:
            ops.append(["lct", a_frame(), a_frame()])
        else:
            ops.append([rnd.choice(["yaml", "string", "frames"])])
    if rnd.random() < 0.2:
        ops.append(["clear"])
        ops.append(["lookup", names[0], names[-1], 0])
        ops.append(["lookup", names[0], names[-1], hi])
        ops.append(["yaml"])
    return ops


def loop_scenario() -> list[list[Any]]:
    """Two frames each the other's parent: tf2's loop detection and its text."""
    return [["new", 10_000_000_000],
            ["set", "a", "b", 1_000_000_000, [1, 0, 0], [0, 0, 0, 1], "/n"],
            ["set", "b", "a", 1_000_000_000, [1, 0, 0], [0, 0, 0, 1], "/n"],
            ["set", "b", "c", 1_000_000_000, [1, 0, 0], [0, 0, 0, 1], "/n"],
            ["set", "x", "y", 1_000_000_000, [1, 0, 0], [0, 0, 0, 1], "/n"],
            ["lookup", "c", "y", 0], ["lookup", "y", "c", 1_000_000_000], ["lct", "c", "y"],
            ["can", "c", "y", 0], ["lookup", "a", "c", 0], ["lookup", "c", "a", 1_000_000_000]]
