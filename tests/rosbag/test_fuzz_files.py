"""Fuzzing bag files (issue 13): flipped, inserted and deleted bytes in real small bags.

Every outcome of opening, reading, ``str(bag)`` (``rosbag info``) and the YAML info is a valid,
printable result or a DdesError with a printable message, within 2 s of CPU time; never another
exception.
"""

from __future__ import annotations

import tracemalloc
from functools import cache

import yaml
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from ddes import Time
from ddes.errors import DdesError
from ddes.rosbag import Bag

from .conftest import Int32, String, sample_bag

_KINDS = ("none", "bz2", "lz4", "mcap")


@cache
def _sample(kind: str) -> bytes:
    bag = sample_bag()
    bag.write("/chatter", String(data="caf\u00e9 " * 3), Time(2))
    bag.write("/n", Int32(data=-7), Time(3))
    if kind == "mcap":
        return bag.to_bytes("mcap")
    return bag.to_bytes(compression=kind)


_edit = st.tuples(st.sampled_from(["flip", "insert", "delete"]), st.floats(0, 1, exclude_max=True),
                  st.integers(0, 255))


def _mutate(data: bytes, edits: list[tuple[str, float, int]]) -> bytes:
    out = bytearray(data)
    for op, where, byte in edits:
        pos = int(where * len(out))
        if op == "flip":
            out[pos] = byte
        elif op == "insert":
            out[pos:pos] = bytes([byte])
        else:
            del out[pos]
    return bytes(out)


def _use(data: bytes) -> None:
    bag = Bag.from_bytes(data)
    for msg in bag.read_messages(return_connection_header=True):
        repr(msg.message)
    for _ in bag.read_messages(raw=True):
        pass
    str(bag).encode("utf-8")
    text = bag.yaml_info()
    text.encode("utf-8")
    yaml.safe_load(text)
    bag.yaml_info(key="topics").encode("utf-8")
    bag.get_type_and_topic_info()
    bag.get_compression_info()


@settings(max_examples=300, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(kind=st.sampled_from(_KINDS), edits=st.lists(_edit, min_size=1, max_size=4))
def test_mutated_bags_give_a_result_or_a_ddes_error(kind: str,
                                                    edits: list[tuple[str, float, int]]) -> None:
    data = _mutate(_sample(kind), edits)
    tracemalloc.start()  # a memory bound, not CPU time: lying sizes never allocate
    try:
        try:
            _use(data)
        except DdesError as exc:
            str(exc).encode("utf-8")  # a hostile name never makes the error unprintable
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    assert peak < 32 * 2**20, peak


@settings(max_examples=100, deadline=None)
@given(kind=st.sampled_from(_KINDS), cut=st.floats(0, 1), junk=st.binary(max_size=64))
def test_truncated_and_padded_bags_give_a_result_or_a_ddes_error(kind: str, cut: float,
                                                                 junk: bytes) -> None:
    data = _sample(kind)
    data = data[:int(cut * len(data))] + junk
    tracemalloc.start()  # a memory bound, not CPU time: lying sizes never allocate
    try:
        try:
            _use(data)
        except DdesError as exc:
            str(exc).encode("utf-8")
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    assert peak < 32 * 2**20, peak


def test_the_samples_read_unchanged() -> None:
    for kind in _KINDS:
        _use(_sample(kind))
        assert Bag.from_bytes(_sample(kind)).get_message_count() == 5
