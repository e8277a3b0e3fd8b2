"""The trace's fast line encoder (ddes.kernel.trace_lines): the same text as the reference path.

Its branches write strings without json's escaper and check a whole chunk at once, so the rows
here repeat a few shapes (enough to be given branches) and carry values built to slip past
that check: quotes, backslashes, newlines, control characters, values of another type than
the shape showed, non-finite floats.
"""

from __future__ import annotations

import enum
from typing import Any

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import ddes
from ddes.kernel.trace import Trace, _row_line
from ddes.kernel.trace_lines import (
    LEARN_AT,
    MAX_BRANCHES,
    LineEncoder,
    holds_wire,
    signature,
    wire_field,
    wire_keys,
)

from .test_trace_scale import reference_digest

String = ddes.get_message_class("std_msgs/String")

A = ("topic", "publisher", "seq")
B = ("topic", "seq", "connections", "data")
C = ("expected", "real")
D = ("x", "y", "yaw")
E = ()
SHAPES = (A, B, C, D, E)


class Level(enum.IntEnum):
    WARN = 4


class Name(str):
    pass


def reference(rows: list[Any]) -> str:
    return "".join(_row_line(r) + "\n" for r in rows)


def plain_row(keys: tuple[str, ...], i: int) -> tuple[Any, ...]:
    values: dict[str, Any] = {"topic": "/chatter", "publisher": "/talker", "seq": i,
                              "connections": 2, "data": b"\x05\x00\x00\x00hello",
                              "expected": 10 * i, "real": 10 * i + 1, "x": 0.5 * i, "y": -1e-7,
                              "yaw": 3.0}
    return (i * 1000, "topic.deliver", "/listener", keys, *(values[k] for k in keys))


def chunks(enc: LineEncoder, rows: list[Any], size: int) -> str:
    return "".join(enc.lines(rows[i:i + size]) for i in range(0, len(rows), size))


def test_frequent_shapes_get_branches_and_plain_rows_pass_the_check() -> None:
    rows = [plain_row(SHAPES[i % len(SHAPES)], i) for i in range(400)]
    enc = LineEncoder(_row_line)
    assert chunks(enc, rows, 100) == reference(rows)
    assert {keys for keys, _ in enc._shapes} == set(SHAPES)
    assert enc.fallbacks == 0
    assert dict(enc._shapes)[B] == ("i", "s", "s", "s", "i", "i", "b")
    assert dict(enc._shapes)[D] == ("i", "s", "s", "f", "f", "f")


def test_a_quote_in_a_branch_string_sends_the_chunk_back_once_and_escapes_from_then_on() -> None:
    rows = [plain_row(A, i) for i in range(200)]
    enc = LineEncoder(_row_line)
    enc.lines(rows[:100])
    assert dict(enc._shapes)[A] == ("i", "s", "s", "s", "s", "i")
    bad = [(t, kind, src, keys, 'say "hi"' if j % 3 == 0 else topic, pub, seq)
           for j, (t, kind, src, keys, topic, pub, seq) in enumerate(rows[100:])]
    assert enc.lines(bad[:50]) == reference(bad[:50])
    assert enc.fallbacks == 1
    assert dict(enc._shapes)[A] == ("i", "s", "s", "S", "s", "i")  # the topic slot escaped
    assert enc.lines(bad[50:]) == reference(bad[50:])
    assert enc.fallbacks == 1


@pytest.mark.parametrize("value", ["a\nb", "back\\slash", "tab\there", "bell\x07", "nul\x00",
                                   "\x1f", 'q"', "\u2028sep\x85", "é ✓ \x7f"])
def test_any_string_that_json_escapes_is_caught(value: str) -> None:
    rows = [plain_row(A, i) for i in range(40)]
    enc = LineEncoder(_row_line)
    enc.lines(rows[:20])
    rows[30] = rows[30][:5] + (value, rows[30][6])  # the publisher slot
    assert enc.lines(rows[20:]) == reference(rows[20:])


@pytest.mark.parametrize("value", [True, None, 2.5, float("nan"), float("inf"), -float("inf"),
                                   Level.WARN, Name("/n"), 7, b"x", ("t",), ddes.Time(1, 2)])
def test_a_value_of_another_type_than_the_shape_showed_takes_the_reference_path(value: Any
                                                                                ) -> None:
    rows = [plain_row(D, i) for i in range(40)] + [plain_row(A, i) for i in range(40)]
    enc = LineEncoder(_row_line)
    enc.lines(rows[:20] + rows[40:60])
    for at, slot in ((30, 4), (70, 4), (75, 6), (33, 2), (34, 1), (35, 0)):
        row = list(rows[at])
        row[slot] = value
        rows[at] = tuple(row)
    text = enc.lines(rows[20:40] + rows[60:])
    assert text == reference(rows[20:40] + rows[60:])


def test_rows_of_the_wrong_length_or_dict_form_take_the_reference_path() -> None:
    rows: list[Any] = [plain_row(C, i) for i in range(40)]
    enc = LineEncoder(_row_line)
    enc.lines(rows[:20])
    rows[25] = rows[25][:-1]  # a value short
    rows[26] = (*rows[26], "extra")
    rows[27] = (5, "log", "/n", {"msg": 'he said "x"\n', "level": 2})
    assert enc.lines(rows[20:]) == reference(rows[20:])
    assert enc.fallbacks == 0  # the reference lines' own quotes and backslashes were counted


def test_keys_that_json_escapes_or_repeat_get_no_branch_and_odd_plain_keys_do() -> None:
    odd = ("a'b", "{c}", "d\u2028", "é", "');import os;('")
    assert signature((0, "k", "s", odd, 1, 2, 3, 4, 5)) == ("i", "s", "s", "i", "i", "i", "i", "i")
    assert signature((0, "k", "s", ('a"b',), 1)) is None
    assert signature((0, "k", "s", ("a\nb",), 1)) is None
    assert signature((0, "k", "s", ("a", "a"), 1, 2)) is None
    assert signature((0, "k", "s", ("a",), [1])) is None
    assert signature((0.0, "k", "s", ("a",), 1)) is None
    rows = [(i, "k", "s", odd, i, "x", 1.5, b"", -i) for i in range(50)]
    enc = LineEncoder(_row_line)
    assert chunks(enc, rows, 25) == reference(rows)
    assert [keys for keys, _ in enc._shapes] == [odd]


def test_at_most_max_branches_shapes() -> None:
    shapes = [tuple(f"k{n}" for _ in range(1)) + (f"x{n}",) for n in range(MAX_BRANCHES + 3)]
    rows = [(i, "k", "s", shapes[i % len(shapes)], i, i) for i in range(40 * len(shapes))]
    enc = LineEncoder(_row_line)
    assert chunks(enc, rows, 20 * len(shapes)) == reference(rows)
    assert len(enc._shapes) == MAX_BRANCHES


text = st.text(st.characters(codec="utf-8"), max_size=6) | st.sampled_from(
    ["/a", 'q"', "\\", "\n", "\x00", "\x1f", "\u2028", "<X at 0x1f>"])
value = st.one_of(text, st.integers(), st.floats(), st.binary(max_size=100), st.booleans(),
                  st.none(), st.just(Level.WARN), st.builds(Name, text))


@settings(max_examples=150, deadline=None)
@given(st.lists(st.tuples(st.sampled_from(SHAPES), st.lists(value, min_size=7, max_size=7),
                          st.integers(0, 10), text, text),
                min_size=1, max_size=40),
       st.integers(1, 4), st.integers(1, 60))
def test_runs_of_shapes_with_any_values_give_the_reference_text(
        runs: list[Any], repeat: int, size: int) -> None:
    rows = []
    for keys, vals, n, kind, source in runs:
        for i in range(n * repeat):  # runs long enough for branches to be learned
            rows.append((i, kind, source, keys, *vals[:len(keys)]))
    enc = LineEncoder(_row_line)
    assert chunks(enc, rows, size) == reference(rows)


def test_a_trace_digest_uses_its_encoder_and_equals_the_reference() -> None:
    world = ddes.World(seed=2)
    pub = world.create_node("talker", disable_rosout=True).advertise("chatter", String,
                                                                      queue_size=10)
    world.create_node("listener", disable_rosout=True).subscribe("chatter", String,
                                                                 lambda m: None)
    world.run(until=0.01)
    for i in range(3 * LEARN_AT):
        pub.publish(String(data=f'say "{i}"\n'))
        world.run_for(0.001)
    trace = world.trace
    assert world.digest() == reference_digest(trace)
    assert list(trace.lines()) == [ev.to_json() for ev in trace]
    assert trace._encoder._shapes  # the deliveries and publications got branches
    copied = Trace.__new__(Trace)
    copied.__setstate__(trace.__getstate__())
    assert copied.digest() == world.digest()


def test_misses_add_up_across_small_calls() -> None:
    """A digest asked after every few events still gives the frequent shapes their branches."""
    rows = [plain_row(SHAPES[i % 2], i) for i in range(4 * LEARN_AT)]
    enc = LineEncoder(_row_line)
    assert chunks(enc, rows, 3) == reference(rows)
    assert {keys for keys, _ in enc._shapes} == {A, B}
    trace = Trace()
    for i in range(4 * LEARN_AT):
        trace.append_row(plain_row(A, i))
        trace.digest()
    assert [keys for keys, _ in trace._encoder._shapes] == [A]
    assert trace.digest() == reference_digest(trace)


def test_small_and_large_bytes_hash_alike_on_either_side_of_small_bytes() -> None:
    from ddes.kernel.trace_lines import SMALL_BYTES

    sizes = [0, 1, SMALL_BYTES - 1, SMALL_BYTES, SMALL_BYTES + 1, 4000]
    rows = [(i, "topic.publish", "/talker", B, "/chatter", i, 1, bytes(range(7)) * (n // 7)
             + bytes(n % 7)) for i, n in enumerate(sizes * 20)]
    enc = LineEncoder(_row_line)
    assert chunks(enc, rows, 40) == reference(rows)
    assert dict(enc._shapes)[B] == ("i", "s", "s", "s", "i", "i", "b")  # the branch wrote them


def test_wire_rows_get_no_branch_and_read_as_the_rows_that_held_the_value() -> None:
    keys = ("topic", "data")
    wire = wire_keys(keys, "data", lambda b: String(data=b.decode("utf-8")))
    assert wire == keys and wire is not keys and wire_field(wire) is not None
    assert wire_field(keys) is None and wire_field(tuple(list(wire))) is None
    fast, plain = Trace(), Trace()
    for i in range(3 * LEARN_AT):
        text = f"msg {i}" if i % 7 else 'a "quoted" \\ one'
        fast.append_row((i, "topic.publish", "/n", wire, "/t", text.encode("utf-8")))
        plain.append_row((i, "topic.publish", "/n", keys, "/t", String(data=text)))
    assert signature(fast._raw[0]) is None
    assert holds_wire(fast._raw) and not holds_wire(plain._raw) and not holds_wire([])
    assert list(fast.lines()) == list(plain.lines())
    assert fast.digest() == plain.digest() == reference_digest(plain)
    assert not any(k is wire for k, _ in fast._encoder._shapes)
    assert fast[5].details == {"topic": "/t", "data": String(data="msg 5")}


def test_wire_keys_must_name_one_of_the_keys() -> None:
    with pytest.raises(ddes.errors.DdesValueError, match="'payload' is not one of the keys"):
        wire_keys(("topic", "data"), "payload", bytes)
