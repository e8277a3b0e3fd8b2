"""Hostile bag files: decompression bombs, lying lengths, bytes that are not UTF-8 (issue 13).

Every hostile file ends in a typed ddes error naming the value and the fix, or in a faithful
result; a bomb is refused before ddes allocates what it declares, or stopped at the declared
size (measured with tracemalloc).
"""

from __future__ import annotations

import bz2
import struct
import tracemalloc
from collections.abc import Callable
from typing import Any

import lz4.frame
import pytest
import yaml

from ddes import Time
from ddes.errors import (
    DdesTypeError,
    DdesValueError,
    ResourceLimitError,
    ROSBagFormatException,
)
from ddes.rosbag import Bag, bagfile
from ddes.rosbag.records import Cursor, encode_record

from .conftest import String, sample_bag

_MB = 1 << 20
_CHUNK = 4117  # the first chunk of a ddes/rosbag file: magic (13) + the padded file header


def _peak(fn: Callable[[], Any]) -> tuple[int, BaseException | None]:
    """Peak traced bytes and the error of ``fn()`` (memory, not CPU time: it holds under load)."""
    tracemalloc.start()
    err: BaseException | None = None
    try:
        fn()
    except BaseException as exc:  # noqa: BLE001 - returned to the test, which checks its type
        err = exc
    peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    return peak, err


def with_chunk(data: bytes, payload: bytes, size: int) -> bytes:
    """``data`` (a one-chunk bag) with the first chunk's data and declared size replaced."""
    cur = Cursor(data, "t")
    head = cur.record(13)
    chunk = cur.record(head.end)
    assert chunk.pos == _CHUNK
    fields = dict(chunk.fields)
    fields["size"] = struct.pack("<L", size)
    out = data[:chunk.pos] + encode_record(fields, payload) + data[chunk.end:]
    index_pos = head.u64("index_pos") + len(out) - len(data)
    i = out.index(b"index_pos=") + 10
    return out[:i] + struct.pack("<Q", index_pos) + out[i + 8:]


def declared_size(data: bytes) -> int:
    return Cursor(data, "t").record(_CHUNK).u32("size")


# -- .bag v2.0 chunks ------------------------------------------------------------------------

@pytest.mark.parametrize("kind", ["bz2", "lz4"])
def test_a_chunk_that_inflates_past_its_declared_size_stops_there(kind: str) -> None:
    good = sample_bag(compression=kind).to_bytes()
    zeros = b"\0" * (64 * _MB)
    payload = bz2.compress(zeros, 9) if kind == "bz2" else lz4.frame.compress(zeros)
    hostile = with_chunk(good, payload, declared_size(good))
    assert len(hostile) < 300_000  # lz4 squeezes at most ~255x
    peak, err = _peak(lambda: Bag.from_bytes(hostile))
    assert isinstance(err, ROSBagFormatException)
    text = str(err)
    assert f"chunk at offset {_CHUNK}" in text
    assert f"says {declared_size(good)} bytes uncompressed" in text
    assert "inflates past" in text
    assert peak < 8 * _MB + 2 * len(hostile)  # never the 64 MiB the data holds


@pytest.mark.parametrize("kind", ["bz2", "lz4"])
def test_a_5kb_bag_declaring_2gb_is_refused_before_decompressing(kind: str) -> None:
    good = sample_bag(compression=kind).to_bytes()
    hostile = with_chunk(good, Cursor(good, "t").data(Cursor(good, "t").record(_CHUNK)), 2 << 30)
    assert len(hostile) < 5200  # a 5 KB bag
    peak, err = _peak(lambda: Bag.from_bytes(hostile))
    assert isinstance(err, ResourceLimitError)
    text = str(err)
    assert f"chunk at offset {_CHUNK}" in text and str(2 << 30) in text
    assert "max_chunk_size=1073741824" in text and "Bag(path, max_chunk_size=" in text
    assert peak < 4 * _MB


def test_a_declared_size_far_past_the_file_size_is_refused() -> None:
    good = sample_bag(compression="bz2").to_bytes()
    chunk = Cursor(good, "t").record(_CHUNK)
    hostile = with_chunk(good, Cursor(good, "t").data(chunk), 200 * _MB)  # < 1 GiB, > 1000x
    peak, err = _peak(lambda: Bag.from_bytes(hostile))
    assert isinstance(err, ResourceLimitError)
    assert "1000x the file's" in str(err) and "decompression bomb" in str(err)
    assert peak < 4 * _MB


def test_max_chunk_size_trusts_a_genuine_very_compressible_bag(
        monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(bagfile, "INFLATE_FLOOR", 10_000)  # a small floor stands in for 64 MiB
    bag = Bag(compression="bz2")
    bag.write("/zeros", String(data="\0" * 8_000_000), Time(1))
    data = bag.to_bytes()
    assert len(data) * bagfile.INFLATE_RATIO < 8_000_000  # bz2 squeezes zeros past 1000x
    with pytest.raises(ResourceLimitError, match="max_chunk_size="):
        Bag.from_bytes(data)
    back = Bag.from_bytes(data, max_chunk_size=16_000_000)
    assert next(back.read_messages()).message.data == "\0" * 8_000_000
    with pytest.raises(ResourceLimitError, match="over the limit max_chunk_size=1000"):
        Bag.from_bytes(data, max_chunk_size=1000)


def test_max_chunk_size_is_checked() -> None:
    data = sample_bag().to_bytes()
    with pytest.raises(DdesTypeError, match="max_chunk_size must be an int"):
        Bag.from_bytes(data, max_chunk_size="big")  # type: ignore[arg-type]
    with pytest.raises(DdesValueError, match="at least 1 byte"):
        Bag.from_bytes(data, max_chunk_size=0)


def test_recovery_of_an_unindexed_bag_keeps_the_limits() -> None:
    good = sample_bag(compression="bz2").to_bytes()
    hostile = with_chunk(good, Cursor(good, "t").data(Cursor(good, "t").record(_CHUNK)), 2 << 30)
    i = hostile.index(b"index_pos=") + 10
    unindexed = hostile[:i] + bytes(8) + hostile[i + 8:]
    with pytest.raises(ResourceLimitError, match="max_chunk_size"):
        Bag.from_bytes(unindexed, allow_unindexed=True)


@pytest.mark.parametrize("where", ["header", "data"])
def test_lying_record_lengths_allocate_nothing(where: str) -> None:
    good = sample_bag().to_bytes()
    pos = _CHUNK if where == "header" else _CHUNK + 4 + struct.unpack_from("<L", good, _CHUNK)[0]
    hostile = good[:pos] + struct.pack("<L", 0xFFFFFFF0) + good[pos + 4:]
    peak, err = _peak(lambda: Bag.from_bytes(hostile))
    assert isinstance(err, ROSBagFormatException)
    assert f"{where} claims {0xFFFFFFF0} bytes" in str(err) and "truncated or corrupt" in str(err)
    assert peak < 2 * _MB


# -- MCAP chunks -----------------------------------------------------------------------------

def mcap_chunk_size_at(data: bytes) -> int:
    """Offset of the ``uncompressed_size`` field of the first chunk of an MCAP file."""
    pos = 8
    while True:
        op, length = data[pos], struct.unpack_from("<Q", data, pos + 1)[0]
        if op == 0x06:
            return pos + 9 + 16
        pos += 9 + length


@pytest.mark.parametrize("kind", ["lz4", "zstd"])
def test_an_mcap_chunk_inflating_past_its_declared_size_stops_there(kind: str) -> None:
    bag = Bag()
    bag.write("/zeros", String(data="\0" * 4_000_000), Time(1))
    data = bag.to_bytes("mcap", compression=kind)
    at = mcap_chunk_size_at(data)
    hostile = data[:at] + struct.pack("<Q", 100) + data[at + 8:]
    peak, err = _peak(lambda: Bag.from_bytes(hostile))
    assert isinstance(err, ROSBagFormatException)
    assert "says 100 bytes uncompressed" in str(err) and "inflates past" in str(err)
    assert "chunk at offset" in str(err)
    assert peak < 4 * _MB  # the chunk holds 4 MB
    assert Bag.from_bytes(data).get_message_count() == 1


@pytest.mark.parametrize("kind", ["lz4", "zstd"])
def test_an_mcap_chunk_declaring_a_terabyte_is_refused(kind: str) -> None:
    data = sample_bag().to_bytes("mcap", compression=kind)
    at = mcap_chunk_size_at(data)
    hostile = data[:at] + struct.pack("<Q", 1 << 40) + data[at + 8:]
    peak, err = _peak(lambda: Bag.from_bytes(hostile))
    assert isinstance(err, ResourceLimitError)
    assert str(1 << 40) in str(err) and "max_chunk_size" in str(err)
    assert peak < 2 * _MB


# -- bytes that are not UTF-8 ----------------------------------------------------------------

def _odd(raw: bytes) -> str:
    return raw.decode("utf-8", "surrogateescape")


def test_non_utf8_topic_type_and_definition_read_and_print() -> None:
    bag = Bag()
    header = {"topic": _odd(b"/caf\xe9"), "type": String._type, "md5sum": String._md5sum,
              "message_definition": _odd(b"# commentaire en Latin-1: caf\xe9\n") + String._full_text,
              "callerid": _odd(b"/n\xff\x1b[31m")}
    bag.write(_odd(b"/caf\xe9"), String(data="a"), Time(1), connection_header=header)
    back = Bag.from_bytes(bag.to_bytes())
    (msg,) = list(back.read_messages(return_connection_header=True))
    assert msg.topic == _odd(b"/caf\xe9") and msg.message.data == "a"  # faithful
    assert msg.connection_header == header
    text = str(back)
    text.encode("utf-8")  # printable: rosbag raises UnicodeDecodeError on such a topic
    assert "/caf\\xe9" in text
    info = yaml.safe_load(back.yaml_info())
    assert info["topics"][0]["topic"] == "/caf\\xe9"
    assert back.yaml_info(key="topics[0].topic") == "/caf\\xe9"


def test_a_type_name_that_is_not_text_is_a_format_error() -> None:
    bag = Bag()
    header = {"topic": "/t", "type": _odd(b"std_msgs/Str\xefng"), "md5sum": String._md5sum,
              "message_definition": String._full_text}
    bag.write("/t", String(data="a"), Time(1), connection_header=header)
    back = Bag.from_bytes(bag.to_bytes())
    str(back).encode("utf-8")
    back.yaml_info().encode("utf-8")
    with pytest.raises(ROSBagFormatException, match=r"Str\\\\xefng") as info:
        list(back.read_messages())
    str(info.value).encode("utf-8")
    assert "not a ROS type name" in str(info.value)


def test_control_characters_in_names_are_escaped_in_info() -> None:
    bag = Bag()
    bag.write("/evil\n\x1b[2J: x", String(data="a"), Time(1))
    back = Bag.from_bytes(bag.to_bytes())
    assert "\x1b" not in str(back) and "/evil\\n\\x1b[2J: x" in str(back)
    assert yaml.safe_load(back.yaml_info())["topics"][0]["topic"] == "/evil\\n\\x1b[2J: x"
