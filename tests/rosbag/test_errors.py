"""Bad input, table-driven: every malformed file or call raises a typed bag error
that names the file, the offset or record, and what is wrong; never a hang or a
silent partial read.  A fuzz test flips and cuts bytes of real bags."""

from __future__ import annotations

import io
import struct
from collections.abc import Callable
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from ddes import Time
from ddes.errors import (
    ROSBagEncryptNotSupportedException,
    ROSBagException,
    ROSBagFormatException,
    ROSBagUnindexedException,
)
from ddes.rosbag import Bag, filter_bag
from ddes.rosbag.bagfile import decode
from ddes.rosbag.records import MAGIC, Cursor, encode_header

from .conftest import Int32, String


def good(compression: str = "none") -> bytes:
    bag = Bag(chunk_threshold=200)
    for i in range(12):
        bag.write("/a", String(data=f"message {i}"), Time(i))
        bag.write("/b", Int32(data=i), Time(i, 5))
    return bag.to_bytes(compression=compression)


def layout(data: bytes) -> dict[str, int]:
    """Offsets of interesting records of a bag file."""
    cur = Cursor(data, "x")
    head = cur.record(len(MAGIC))
    chunk = cur.record(head.end)
    index = cur.record(chunk.end)
    pos = head.u64("index_pos")
    for _ in range(head.u32("conn_count")):
        pos = cur.record(pos).end
    info = cur.record(pos)
    return {"header": head.pos, "first_chunk": chunk.pos, "chunk_data": chunk.data_pos,
            "index_data": index.data_pos, "index_pos": head.u64("index_pos"),
            "chunk_info_data": info.data_pos, "chunk_info": info.pos}


def replace(data: bytes, old: bytes, new: bytes) -> bytes:
    assert old in data and len(old) == len(new)
    return data.replace(old, new, 1)


def patch(data: bytes, at: int, new: bytes) -> bytes:
    return data[:at] + new + data[at + len(new):]


def set_index_pos(data: bytes, value: int) -> bytes:
    at = data.index(b"index_pos=") + len(b"index_pos=")
    return patch(data, at, struct.pack("<Q", value))


def encrypted(data: bytes) -> bytes:
    cur = Cursor(data, "x")
    head = cur.record(len(MAGIC))
    fields = dict(head.fields)
    fields["encryptor"] = b"rosbag/AesCbcEncryptor"
    raw = encode_header(fields)
    pad = b" " * (4096 - len(raw))
    return (data[:head.pos] + struct.pack("<L", len(raw)) + raw + struct.pack("<L", len(pad)) +
            pad + data[head.end:])


def bag_with(header: dict[str, str], payload: bytes) -> bytes:
    bag = Bag()
    bag._write_raw("/x", header, payload, 1)
    return bag.to_bytes()


STR_HEADER = {"topic": "/x", "type": String._type, "md5sum": String._md5sum,
              "message_definition": String._full_text}
L = layout(good())

# (case, bytes, expected exception, substrings the message must contain)
FILE_CASES: list[tuple[str, Callable[[], bytes], type[Exception], list[str]]] = [
    ("empty file", lambda: b"", ROSBagFormatException, ["empty file"]),
    ("not a bag", lambda: b"hello world\n" * 10, ROSBagFormatException,
     ["does not appear to be a bag file"]),
    ("version 1.2", lambda: b"#ROSBAG V1.2\n" + good()[13:], ROSBagFormatException,
     ["'1.2'", "not supported"]),
    ("cut inside the file header", lambda: good()[:100], ROSBagFormatException,
     ["file header at offset 13", "truncated"]),
    ("unindexed", lambda: set_index_pos(good(), 0), ROSBagUnindexedException,
     ["index position is 0", "rosbag reindex"]),
    ("cut in the chunks", lambda: good()[:L["chunk_data"] + 50], ROSBagUnindexedException,
     ["beyond the end of the file", "truncated", "rosbag reindex"]),
    ("cut in the index", lambda: good()[:L["chunk_info"] + 20], ROSBagFormatException,
     ["chunk info record at offset", "truncated"]),
    ("index position inside the header", lambda: set_index_pos(good(), 20),
     ROSBagFormatException, ["points into the file header"]),
    ("unknown compression", lambda: replace(good(), b"compression=none", b"compression=zstd"),
     ROSBagException, ["unsupported compression type: zstd", f"chunk at offset {L['first_chunk']}"]),
    ("corrupt bz2 chunk", lambda: patch(good("bz2"), layout(good("bz2"))["chunk_data"] + 12,
                                        b"\x00\x01\x02\x03"),
     ROSBagFormatException, ["bz2 data", "corrupt"]),
    ("corrupt lz4 chunk", lambda: patch(good("lz4"), layout(good("lz4"))["chunk_data"] + 7,
                                        b"\xff\xff\xff\xff\xff\xff\xff\xff"),
     ROSBagFormatException, ["lz4 data", "corrupt"]),
    ("chunk size lies", lambda: replace(good(), b"size=" + struct.pack("<L", struct.unpack(
        "<L", good()[good().index(b"size=") + 5:good().index(b"size=") + 9])[0]),
        b"size=" + struct.pack("<L", 3)), ROSBagFormatException, ["says 3 bytes uncompressed"]),
    ("index entry points nowhere", lambda: patch(good(), L["index_data"] + 8,
                                                 struct.pack("<L", 3)),
     ROSBagFormatException, ["points to offset 3", "index is corrupt"]),
    ("chunk info counts disagree", lambda: patch(good(), L["chunk_info_data"] + 4,
                                                 struct.pack("<L", 99)),
     ROSBagFormatException, ["counts", "index is corrupt"]),
    ("wrong op in the file header", lambda: patch(good(), good().index(b"op=\x03") + 3, b"\x07"),
     ROSBagFormatException, ["expected a FILE_HEADER record", "found CONNECTION"]),
    ("header field without '='", lambda: replace(good(), b"index_pos=", b"index_pos:"),
     ROSBagFormatException, ["has no '='"]),
    ("connection without md5sum", lambda: replace(
        bag_with({**STR_HEADER, "md5sum": "0" * 32}, b"\x00\x00\x00\x00"), b"md5sum=", b"md5sux="),
     ROSBagFormatException, ["connection header field md5sum not found", "offset"]),
    ("encrypted", lambda: encrypted(good()), ROSBagEncryptNotSupportedException,
     ["AesCbcEncryptor"]),
    ("mcap cut short", lambda: Bag.from_bytes(good()).to_bytes("mcap")[:-30],
     ROSBagFormatException, ["truncated MCAP"]),
]


@pytest.mark.parametrize("case,make,exc,words", FILE_CASES, ids=[c[0] for c in FILE_CASES])
def test_bad_files(tmp_path: Path, case: str, make: Callable[[], bytes], exc: type[Exception],
                   words: list[str]) -> None:
    path = tmp_path / "bad.bag"
    path.write_bytes(make())
    with pytest.raises(exc) as info:
        Bag(str(path))
    assert type(info.value) is exc
    text = str(info.value)
    assert text.startswith(str(path)), text
    for word in words:
        assert word in text, (word, text)


# (case, action, expected exception, substrings)
READ_CASES: list[tuple[str, Callable[[Path], object], type[Exception], list[str]]] = [
    ("missing file", lambda p: Bag(str(p / "nope.bag")), ROSBagException, ["no such bag file"]),
    ("a directory", lambda p: Bag(str(p)), ROSBagException, ["is a directory"]),
    ("unknown type without definition", lambda p: list(Bag.from_bytes(bag_with(
        {"topic": "/x", "type": "foo_msgs/Bar", "md5sum": "0" * 32, "message_definition": ""},
        b"")).read_messages()),
     ROSBagException, ["Cannot deserialize messages of type [foo_msgs/Bar]", "connection 0"]),
    ("definition that does not parse", lambda p: list(Bag.from_bytes(bag_with(
        {**STR_HEADER, "type": "foo_msgs/Bad", "message_definition": "in32 x y z"},
        b"")).read_messages()),
     ROSBagFormatException, ["cannot rebuild [foo_msgs/Bad]", "/x"]),
    ("corrupt message bytes", lambda p: list(Bag.from_bytes(bag_with(
        STR_HEADER, b"\xff\x00\x00\x00ab")).read_messages()),
     ROSBagFormatException, ["on /x", "cannot be deserialized"]),
    ("mcap with a cdr channel", lambda p: Bag.from_bytes(_cdr_mcap()), ROSBagFormatException,
     ["message encoding 'cdr'", "ros1 profile"]),
    ("bad filter syntax", lambda p: filter_bag(Bag.from_bytes(good()), Bag(), "topic =="),
     ROSBagException, ["not a valid Python expression"]),
    ("forbidden filter name", lambda p: filter_bag(Bag.from_bytes(good()), Bag(),
                                                   "m.__class__"),
     ROSBagException, ["names starting with '_'"]),
    ("filter failing on a message", lambda p: filter_bag(Bag.from_bytes(good()), Bag(),
                                                         "m.data > 3"),
     ROSBagException, ["failed on message 0", "/a", "TypeError"]),
    ("wrong compression on write", lambda p: Bag.from_bytes(good()).to_bytes(compression="zip"),
     ROSBagException, ["unsupported compression type: zip"]),
]


def _cdr_mcap() -> bytes:
    from mcap.writer import Writer

    out = io.BytesIO()
    writer = Writer(out)
    writer.start(profile="ros2", library="test")
    schema = writer.register_schema(name="std_msgs/msg/String", encoding="ros2msg", data=b"string data")
    channel = writer.register_channel(topic="/c", message_encoding="cdr", schema_id=schema)
    writer.add_message(channel_id=channel, log_time=1, data=b"\x00\x01", publish_time=1)
    writer.finish()
    return out.getvalue()


@pytest.mark.parametrize("case,action,exc,words", READ_CASES, ids=[c[0] for c in READ_CASES])
def test_bad_reads_and_calls(tmp_path: Path, case: str, action: Callable[[Path], object],
                             exc: type[Exception], words: list[str]) -> None:
    with pytest.raises(exc) as info:
        action(tmp_path)
    assert isinstance(info.value, exc)
    for word in words:
        assert word in str(info.value), (word, str(info.value))


def test_allow_unindexed_recovers_complete_chunks_and_says_what_it_dropped() -> None:
    data = good()
    whole = Bag.from_bytes(data)
    decoded = decode(data, "x")
    second = decoded.stats.chunks[1]
    cut = data[:second.pos + 30]  # the index and most chunks are gone
    with pytest.raises(ROSBagUnindexedException):
        Bag.from_bytes(cut)
    back = Bag.from_bytes(cut, allow_unindexed=True)
    first_count = sum(decoded.stats.chunks[0].counts.values())
    assert back.get_message_count() == first_count
    expected = list(whole.read_messages())
    assert [(m.topic, m.timestamp) for m in back.read_messages()] == \
        [(m.topic, m.timestamp) for m in expected if m.timestamp <= back_end(back)]
    assert back.recovered is not None
    assert "recovered" in back.recovered and f"offset {second.pos}" in back.recovered
    unindexed = set_index_pos(data, 0)
    assert [m.timestamp for m in Bag.from_bytes(unindexed, allow_unindexed=True)
            .read_messages()] == [m.timestamp for m in expected]


def back_end(bag: Bag) -> Time:
    return Time.from_sec(bag.get_end_time())


@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(compression=st.sampled_from(["none", "bz2", "lz4"]), data=st.data())
def test_fuzzed_files_fail_only_with_bag_errors(compression: str, data: st.DataObject) -> None:
    blob = bytearray(good(compression))
    edits = data.draw(st.lists(st.tuples(st.integers(0, len(blob) - 1), st.integers(0, 255)),
                               max_size=4))
    for at, value in edits:
        blob[at] = value
    cut = data.draw(st.integers(0, len(blob)))
    sample = bytes(blob[:cut])
    for allow in (False, True):
        try:
            bag = Bag.from_bytes(sample, allow_unindexed=allow)
        except ROSBagException:
            continue
        try:
            for _ in bag.read_messages():
                pass
        except ROSBagException:
            pass
