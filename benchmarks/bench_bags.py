"""Bags: recording throughput, .bag write/read throughput, memory per recorded message.

* ``bag_record_in_memory``: a Recorder on a 1→1 topic, messages recorded per
  CPU second, against the same world delivering to a plain
  subscriber callback (the price of recording on top of delivery);
* ``bag_write_file`` / ``bag_read_file``: writing N serialized messages to a
  .bag file and reading them back raw, against the ``rosbags`` library used
  directly on the same data in the same run; when real ROS is installed, rows
  ``*_vs_rosbag`` compare with ``rosbag.Bag`` under the system Python, timing
  its own loop in a subprocess;
* ``bag_memory_per_message``: bytes the world holds more per recorded message
  (tracemalloc, trace off; the serialized bytes included), against the bytes
  of the serialized message itself.
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
import tempfile
import time
import tracemalloc
from pathlib import Path
from typing import Any

sys.path.insert(0, str(Path(__file__).resolve().parent))

from common import TINY, compare, repeats, result, row, size  # noqa: E402

import ddes  # noqa: E402
from ddes.msg import get_message_class  # noqa: E402
from ddes.rosbag import Bag, Recorder  # noqa: E402

N = size(20_000)
String = get_message_class("std_msgs/String")
Odometry = get_message_class("nav_msgs/Odometry")


def _world(record: bool) -> Any:
    def run() -> int:
        world = ddes.World()
        talker = world.create_node("talker", disable_rosout=True)
        pub = talker.advertise("chatter", String, queue_size=10)
        got = [0]
        if record:
            rec = Recorder(world, ["/chatter"], in_memory=True, quiet=True)
        else:
            world.create_node("listener", disable_rosout=True).subscribe(
                "chatter", String, lambda m: got.__setitem__(0, got[0] + 1), queue_size=10)
        world.run(until=0.01)
        msg = String(data="hello world")

        def loop() -> Any:
            for _ in range(N):
                pub.publish(msg)
                yield world.env.timeout(1_000_000)

        talker.process(loop())
        world.run(until=0.02 + N * 1e-3)
        if record:
            count = rec.bag.get_message_count()
            rec.stop()
            return int(count)
        return got[0]

    return run


def _payload() -> list[tuple[int, bytes]]:
    out = []
    for i in range(N):
        odom = Odometry()
        odom.header.seq = i
        odom.header.frame_id = "odom"
        odom.pose.pose.position.x = i * 0.01
        out.append((10**18 + i * 10_000_000, odom._serialize_to_bytes()))
    return out


def _ddes_write(payload: list[tuple[int, bytes]], path: str) -> Any:
    def run() -> int:
        if os.path.exists(path):
            os.remove(path)
        bag = Bag(path, "w")
        raw = (Odometry._type, b"", Odometry._md5sum, Odometry)
        for t, data in payload:
            bag.write("/odom", (raw[0], data, raw[2], raw[3]), ddes.Time._from_ns(t), raw=True)
        bag.close()
        return len(payload)

    return run


def _rosbags_write(payload: list[tuple[int, bytes]], path: str) -> Any:
    from rosbags.rosbag1 import Writer
    from rosbags.typesys.msg import normalize_msgtype

    def run() -> int:
        if os.path.exists(path):
            os.remove(path)
        with Writer(path) as writer:
            writer.chunk_threshold = 768 * 1024
            conn = writer.add_connection("/odom", normalize_msgtype(Odometry._type),
                                         msgdef=Odometry._full_text, md5sum=Odometry._md5sum)
            for t, data in payload:
                writer.write(conn, t, data)
        return len(payload)

    return run


def _ddes_read(path: str) -> Any:
    def run() -> int:
        n = 0
        for _m in Bag(path).read_messages(raw=True):
            n += 1
        return n

    return run


def _rosbags_read(path: str) -> Any:
    from rosbags.rosbag1 import Reader

    def run() -> int:
        n = 0
        with Reader(path) as reader:
            for _m in reader.messages():
                n += 1
        return n

    return run


_ROS_SCRIPT = r"""
import json, sys, time, rosbag, genpy, roslib.message
req = json.load(sys.stdin)
cls = roslib.message.get_message_class("nav_msgs/Odometry")
payload = [(t, bytes.fromhex(h)) for t, h in req["payload"]]
best_w = best_r = 0.0
for _ in range(3):
    t0 = time.process_time()
    with rosbag.Bag(req["path"], "w") as bag:
        for t, data in payload:
            bag.write("/odom", ("nav_msgs/Odometry", data, cls._md5sum, cls),
                      genpy.Time(t // 10**9, t % 10**9), raw=True)
    best_w = max(best_w, len(payload) / (time.process_time() - t0))
    t0 = time.process_time()
    n = sum(1 for _ in rosbag.Bag(req["path"]).read_messages(raw=True))
    best_r = max(best_r, n / (time.process_time() - t0))
print(json.dumps({"write": best_w, "read": best_r}))
"""


def _real_rosbag(payload: list[tuple[int, bytes]], path: str) -> dict[str, float] | None:
    interp = "/usr/bin/python3"
    if not shutil.which("rosbag") or not os.path.exists(interp):
        return None
    env = {k: v for k, v in os.environ.items() if not k.startswith("PYTHON")}
    request = json.dumps({"path": path, "payload": [(t, d.hex()) for t, d in payload]})
    proc = subprocess.run([interp, "-c", _ROS_SCRIPT], input=request, capture_output=True,
                          text=True, env=env, timeout=600)
    if proc.returncode != 0:
        return None
    result: dict[str, float] = json.loads(proc.stdout)
    return result


def _memory_per_message() -> tuple[float, float]:
    world = ddes.World()
    talker = world.create_node("talker", disable_rosout=True)
    pub = talker.advertise("odom", Odometry, queue_size=10)
    rec = Recorder(world, ["/odom"], in_memory=True, quiet=True)
    world.run(until=0.01)
    msg = Odometry()
    msg.header.frame_id = "odom"
    size = len(msg._serialize_to_bytes())

    def loop() -> Any:
        for _ in range(N):
            pub.publish(msg)
            yield world.env.timeout(1_000_000)

    talker.process(loop())
    world.trace.enabled = False
    tracemalloc.start()
    before = tracemalloc.take_snapshot()
    world.run(until=0.02 + N * 1e-3)
    after = tracemalloc.take_snapshot()
    tracemalloc.stop()
    held = sum(s.size_diff for s in after.compare_to(before, "filename"))
    count = rec.bag.get_message_count()
    return held / count, float(size)


def benchmarks() -> list[dict[str, Any]]:
    out = []
    c = compare(_world(True), _world(False), repeat=5)
    out.append(result("bag_record_in_memory", c, "messages/s",
                      "plain delivery to a subscriber callback", n=N))
    payload = _payload()
    tmp = tempfile.mkdtemp(prefix="ddes-bench-bags-")
    try:
        mine, theirs = os.path.join(tmp, "ddes.bag"), os.path.join(tmp, "rosbags.bag")
        c = compare(_ddes_write(payload, mine), _rosbags_write(payload, theirs), repeat=7)
        out.append(result("bag_write_file", c, "messages/s",
                          "rosbags.rosbag1.Writer", n=N, type="nav_msgs/Odometry"))
        c = compare(_ddes_read(mine), _rosbags_read(theirs), repeat=7)
        out.append(result("bag_read_file", c, "messages/s",
                          "rosbags.rosbag1.Reader (raw)", n=N, type="nav_msgs/Odometry"))
        ros = None if TINY else _real_rosbag(payload, os.path.join(tmp, "ros.bag"))
        if ros is not None:
            best_w = len(payload) / _timed(_ddes_write(payload, mine))
            out.append(row("bag_write_file_vs_rosbag", best_w, "messages/s", ros["write"],
                           "rosbag.Bag (system python)", n=N))
            best_r = len(payload) / _timed(_ddes_read(mine))
            out.append(row("bag_read_file_vs_rosbag", best_r, "messages/s", ros["read"],
                           "rosbag.Bag (system python, raw)", n=N))
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    per, size = _memory_per_message()
    out.append(row("bag_memory_per_message", per, "bytes/message", size,
                   "serialized message size", n=N, type="nav_msgs/Odometry"))
    return out


def _timed(fn: Any) -> float:
    best = float("inf")
    for _ in range(repeats(3)):
        t0 = time.process_time()
        fn()
        best = min(best, time.process_time() - t0)
    return best
