"""BufferCore's results bit for bit: a golden digest of 3000 lookups, full lookups and
can_transform queries on a randomised 7-frame tree (interpolation both quaternion signs,
extrapolation, statics, fixed frames), recorded before the lookup path was optimised; a faster
path must give the same bits, texts and exceptions."""

from __future__ import annotations

import hashlib
import random
import struct

from ddes.msg import get_message_class
from ddes.tf2 import BufferCore, TransformException
from ddes.time import Time

GOLDEN = "d4c13648089ab0f3935c169b260390ba45055bed7431ecf2defd6c92c51a4a63"


def digest() -> str:
    ts_class = get_message_class("geometry_msgs/TransformStamped")
    rnd = random.Random(17)
    core = BufferCore()
    frames = ["map", "odom", "base", "arm", "hand", "cam", "wheel"]
    parents = {"odom": "map", "base": "odom", "arm": "base", "hand": "arm", "wheel": "base"}

    def put(parent: str, child: str, ns: int, static: bool = False) -> None:
        m = ts_class()
        m.header.frame_id, m.child_frame_id = parent, child
        m.header.stamp = Time._from_ns(ns)
        q = [rnd.gauss(0, 1) for _ in range(4)]
        # left to right, as Python 3.11's sum(): 3.12's sum() of floats is compensated
        n = (q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]) ** 0.5
        r, t = m.transform.rotation, m.transform.translation
        r.x, r.y, r.z, r.w = (v / n for v in q)
        t.x, t.y, t.z = (rnd.uniform(-2, 2) for _ in range(3))
        (core.set_transform_static if static else core.set_transform)(m, "d")

    for k in range(60):
        for child, parent in parents.items():
            if rnd.random() < 0.9:
                put(parent, child, 1_000_000_000 + k * 50_000_000 + rnd.randint(0, 20_000_000))
    put("arm", "cam", 0, static=True)
    h = hashlib.sha256()
    for _ in range(3000):
        a, b = rnd.choice(frames), rnd.choice(frames)
        t = rnd.choice([0, rnd.randint(900_000_000, 4_200_000_000)])
        try:
            if rnd.random() < 0.7:
                m = core.lookup_transform_core(a, b, Time._from_ns(t))
            else:
                t2 = rnd.randint(900_000_000, 4_200_000_000)
                m = core.lookup_transform_full_core(a, Time._from_ns(t), b, Time._from_ns(t2),
                                                    "map")
            tr, r = m.transform.translation, m.transform.rotation
            h.update(struct.pack("<7d", tr.x, tr.y, tr.z, r.x, r.y, r.z, r.w))
            h.update(f"{m.header.stamp.secs} {m.header.stamp.nsecs} {m.header.frame_id} "
                     f"{m.child_frame_id}".encode())
        except TransformException as e:
            h.update(f"{type(e).__name__}: {e}".encode())
        ok, text = core.can_transform_core(a, b, Time._from_ns(t))
        h.update(f"{ok} {text}".encode())
    return h.hexdigest()


def test_lookup_results_are_bit_identical_to_the_recorded_digest() -> None:
    assert digest() == GOLDEN


def test_the_result_message_is_an_ordinary_transform_stamped() -> None:
    ts_class = get_message_class("geometry_msgs/TransformStamped")
    core = BufferCore()
    m = ts_class()
    m.header.frame_id, m.child_frame_id, m.header.stamp = "map", "base", Time(1, 5)
    m.transform.translation.x, m.transform.rotation.z, m.transform.rotation.w = 1.5, 0.6, 0.8
    core.set_transform(m, "me")
    got = core.lookup_transform_core("map", "base", Time(0))
    want = ts_class()
    want.header.frame_id, want.child_frame_id, want.header.stamp = "map", "base", Time(1, 5)
    want.transform.translation.x = 1.5
    want.transform.rotation.z, want.transform.rotation.w = 0.6, 0.8
    assert type(got) is ts_class
    assert got == want
    assert repr(got) == repr(want)
    assert got._serialize_to_bytes() == want._serialize_to_bytes()
    assert got.header.seq == 0 and type(got.header.stamp) is Time
    got.header.stamp.secs = 7  # its own objects: nothing shared with the buffer
    assert core.lookup_transform_core("map", "base", Time(0)).header.stamp == Time(1, 5)
