"""The ROS bag v2.0 layout ddes writes, and interop with the rosbags library both ways."""

from __future__ import annotations

import os
import struct
from pathlib import Path
from typing import Any

import pytest
from rosbags.rosbag1 import Reader, Writer
from rosbags.typesys.msg import normalize_msgtype

from ddes import Time
from ddes.msg import get_message_class
from ddes.rosbag import Bag
from ddes.rosbag.bagfile import decode
from ddes.rosbag.records import MAGIC, OP_CHUNK, OP_CHUNK_INFO, OP_CONNECTION, Cursor

from .conftest import Int32, String, contents

Odometry = get_message_class("nav_msgs/Odometry")


def busy_bag(n: int = 60, **kwargs: Any) -> Bag:
    """Three topics, one latched with a callerid, interleaved, some stamps shared."""
    bag = Bag(**kwargs)
    latched = {"topic": "/status", "type": String._type, "md5sum": String._md5sum,
               "message_definition": String._full_text, "callerid": "/robot", "latching": "1"}
    for i in range(n):
        t = Time(100 + i // 3, (i % 3) * 1000)
        bag.write("/count", Int32(data=i), t)
        if i % 2 == 0:
            odom = Odometry()
            odom.header.frame_id = "odom"
            odom.pose.pose.position.x = float(i)
            bag.write("/odom", odom, t)
        if i % 10 == 0:
            bag.write("/status", String(data=f"s{i}" * 20), t, connection_header=latched)
    return bag


def test_file_starts_with_magic_and_a_4096_byte_padded_header() -> None:
    data = busy_bag(5).to_bytes()
    assert data.startswith(MAGIC)
    cur = Cursor(data, "x")
    head = cur.record(len(MAGIC))
    assert head.end == len(MAGIC) + 4 + 4096 + 4  # rosbag pads header+data to 4096 bytes
    assert cur.data(head).strip(b" ") == b""
    index_pos = head.u64("index_pos")
    assert (head.u32("conn_count"), head.u32("chunk_count")) == (3, 1)
    first = cur.record(index_pos)
    assert first.op() == OP_CONNECTION
    assert cur.record(head.end).op() == OP_CHUNK


def test_chunks_close_past_the_threshold_and_index_every_message() -> None:
    bag = busy_bag(60, chunk_threshold=500)
    data = bag.to_bytes()
    decoded = decode(data, "x")
    chunks = decoded.stats.chunks
    assert len(chunks) > 5
    assert sum(sum(c.counts.values()) for c in chunks) == bag.get_message_count()
    cur = Cursor(data, "x")
    head = cur.record(len(MAGIC))
    pos = head.u64("index_pos")
    for _ in range(3):
        pos = cur.record(pos).end
    infos = [cur.record(pos)]
    while infos[-1].end < len(data):
        infos.append(cur.record(infos[-1].end))
    assert all(r.op() == OP_CHUNK_INFO for r in infos) and len(infos) == len(chunks)
    assert [r.u64("chunk_pos") for r in infos] == [c.pos for c in chunks]
    assert contents(Bag.from_bytes(data)) == contents(bag)
    one_per_chunk = busy_bag(4, chunk_threshold=0)
    assert len(decode(one_per_chunk.to_bytes(), "x").stats.chunks) == \
        one_per_chunk.get_message_count()


@pytest.mark.parametrize("compression", ["none", "bz2", "lz4"])
def test_round_trip_through_every_compression(compression: str) -> None:
    bag = busy_bag(40, chunk_threshold=2000)
    data = bag.to_bytes(compression=compression)
    back = Bag.from_bytes(data)
    assert contents(back) == contents(bag)
    assert {c.compression for c in decode(data, "x").stats.chunks} == {compression}
    assert back.get_compression_info().compression == compression


@pytest.mark.parametrize("compression", ["none", "bz2", "lz4"])
def test_rosbags_reads_what_ddes_writes(tmp_path: Path, compression: str) -> None:
    bag = busy_bag(40, chunk_threshold=3000)
    path = tmp_path / "x.bag"
    bag.save(str(path), compression=compression)
    with Reader(path) as reader:
        got = [(c.topic, t, bytes(raw), c.msgtype, c.digest, c.msgdef.data,
                getattr(c.ext, "callerid", None), getattr(c.ext, "latching", None))
               for c, t, raw in reader.messages()]
    want = []
    for topic, t, data, header in contents(bag):
        latching = header.get("latching")
        want.append((topic, t, data, normalize_msgtype(header["type"]), header["md5sum"],
                     header["message_definition"], header.get("callerid"),
                     None if latching is None else int(latching)))
    assert got == want


def test_ddes_reads_what_rosbags_writes(tmp_path: Path) -> None:
    path = tmp_path / "w.bag"
    msgs = [(Time(1, 0), "/a", String(data="x")), (Time(0, 5), "/b", Int32(data=7)),
            (Time(2, 0), "/a", String(data="y"))]
    with Writer(path) as writer:
        conns = {}
        for cls, topic in ((String, "/a"), (Int32, "/b")):
            conns[topic] = writer.add_connection(topic, normalize_msgtype(cls._type),
                                                 msgdef=cls._full_text,
                                                 md5sum=cls._md5sum, callerid="/w", latching=0)
        for t, topic, msg in msgs:
            writer.write(conns[topic], t.to_nsec(), msg._serialize_to_bytes())
    bag = Bag(str(path))
    assert [(m.topic, m.message, m.timestamp) for m in bag.read_messages()] == \
        [("/b", Int32(data=7), Time(0, 5)), ("/a", String(data="x"), Time(1)),
         ("/a", String(data="y"), Time(2))]
    assert bag.get_connections()[0].header["callerid"] == "/w"


def test_saved_files_match_to_bytes_and_report_their_size(tmp_path: Path) -> None:
    bag = busy_bag(10)
    path = str(tmp_path / "s.bag")
    bag.save(path)
    with open(path, "rb") as f:
        assert f.read() == bag.to_bytes()
    assert Bag(path).size == os.path.getsize(path) == bag.size


def test_header_values_that_are_not_utf8_survive() -> None:
    bag = Bag()
    odd = {"topic": "/t", "type": String._type, "md5sum": String._md5sum,
           "message_definition": String._full_text,
           "blob": b"\xff\xfe".decode("utf-8", "surrogateescape")}
    bag.write("/t", String(data="a"), Time(1), connection_header=odd)
    back = Bag.from_bytes(bag.to_bytes())
    assert back.get_connections()[0].header == odd
    assert b"blob=\xff\xfe" in bag.to_bytes()


def test_index_entries_are_12_bytes_time_then_offset() -> None:
    bag = Bag()
    bag.write("/a", Int32(data=1), Time(3, 4))
    data = bag.to_bytes()
    cur = Cursor(data, "x")
    chunk = cur.record(cur.record(len(MAGIC)).end)
    index = cur.record(chunk.end)
    assert (index.u32("ver"), index.u32("conn"), index.u32("count")) == (1, 0, 1)
    secs, nsecs, offset = struct.unpack("<LLL", cur.data(index))
    assert (secs, nsecs) == (3, 4)
    inner = Cursor(cur.data(chunk), "chunk")
    assert inner.record(offset).time("time") == 3_000_000_004


def test_a_chunk_index_lists_late_messages_in_time_order_equal_stamps_in_write_order() -> None:
    # rosbag inserts each index entry in time order (bisect.insort_right): an entry older than
    # the connection's latest goes before it, and entries of equal stamps keep write order
    bag = Bag()
    stamps = [(5, 0), (3, 0), (5, 0), (4, 7), (3, 0), (9, 1), (4, 7)]
    for k, (secs, nsecs) in enumerate(stamps):
        bag.write("/a", Int32(data=k), Time(secs, nsecs))
        bag.write("/b", Int32(data=100 + k), Time(10 + k))  # in order: its index is untouched
    data = bag.to_bytes()
    cur = Cursor(data, "x")
    chunk = cur.record(cur.record(len(MAGIC)).end)
    inner = Cursor(cur.data(chunk), "chunk")
    seen = {}
    pos = chunk.end
    for _ in range(2):
        index = cur.record(pos)
        body = cur.data(index)
        entries = [struct.unpack_from("<LLL", body, 12 * k) for k in range(index.u32("count"))]
        values = []
        for secs, nsecs, offset in entries:
            rec = inner.record(offset)
            assert rec.time("time") == secs * 10**9 + nsecs
            values.append(((secs, nsecs), struct.unpack("<i", inner.data(rec))[0]))
        seen[index.u32("conn")] = values
        pos = index.end
    assert seen[0] == sorted(((s, k) for k, s in enumerate(stamps)), key=lambda v: v[0])
    assert seen[1] == [((10 + k, 0), 100 + k) for k in range(len(stamps))]
