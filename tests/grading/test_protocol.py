"""The framed protocol: round trips, and every malformed frame refused with ProtocolError."""

from __future__ import annotations

import pytest
from hypothesis import given
from hypothesis import strategies as st

from ddes.errors import ProtocolError
from ddes.grading import protocol as p

names = st.text(min_size=0, max_size=40)


def roundtrip(data: bytes) -> object:
    kind, length = p.decode_header(data[:p.HEADER.size])
    assert length == len(data) - p.HEADER.size
    return p.decode_frame(kind, data[p.HEADER.size:])


@given(names, names, st.integers(-2**63, 2**63 - 1), st.binary(max_size=200))
def test_msg_round_trip(node: str, topic: str, t: int, data: bytes) -> None:
    assert roundtrip(p.encode_msg(node, topic, t, data)) == p.Msg(node, topic, t, data)


@given(st.integers(0, 2**62), st.lists(st.tuples(names, names, names, st.binary(max_size=50)),
                                       max_size=5))
def test_step_round_trip(t: int, msgs: list[tuple[str, str, str, bytes]]) -> None:
    assert roundtrip(p.encode_step(t, msgs)) == p.Step(t, tuple(msgs))


def test_the_other_frames_round_trip() -> None:
    assert roundtrip(p.encode_adv("/a", "/t", "std_msgs/String", "x" * 32, True)) == \
        p.Adv("/a", "/t", "std_msgs/String", "x" * 32, True)
    assert roundtrip(p.encode_sub("/a", "/t", "T", "m", -1)) == p.Sub("/a", "/t", "T", "m", -1)
    assert roundtrip(p.encode_gone("/a")) == p.Gone("/a")
    assert roundtrip(p.encode_done(-1)) == p.Done(-1)
    assert roundtrip(p.encode_end()) is None


@pytest.mark.parametrize("header, text", [
    (b"XX\x0c\x00\x00\x00\x00", "bad frame magic"),
    (b"DG\x63\x00\x00\x00\x00", "unknown frame kind"),
    (b"DG\x0c\xff\xff\xff\xff", "announces"),
    (b"DG\x0c", "cut frame header"),
])
def test_bad_headers_are_refused(header: bytes, text: str) -> None:
    with pytest.raises(ProtocolError, match=text):
        p.decode_header(header)


def test_bad_payloads_are_refused() -> None:
    good = p.encode_msg("/a", "/t", 5, b"xyz")[p.HEADER.size:]
    with pytest.raises(ProtocolError, match="runs past"):
        p.decode_frame(p.MSG, good[:-1])
    with pytest.raises(ProtocolError, match="stray bytes"):
        p.decode_frame(p.MSG, good + b"!")
    with pytest.raises(ProtocolError, match="not UTF-8"):
        p.decode_frame(p.GONE, b"\x00\x02\xff\xfe")
    with pytest.raises(ProtocolError, match="latch flag"):
        p.decode_frame(p.ADV, p.encode_adv("/a", "/t", "T", "m", True)[p.HEADER.size:-1] + b"\x07")
    with pytest.raises(ProtocolError, match="string field"):
        p.encode_gone("x" * (p.MAX_STR + 1))


@given(st.binary(max_size=64))
def test_random_payloads_never_escape_as_other_errors(data: bytes) -> None:
    for kind in (p.ADV, p.SUB, p.MSG, p.GONE, p.DONE, p.STEP):
        try:
            p.decode_frame(kind, data)
        except ProtocolError:
            pass


@given(names, st.integers(-2**63, 2**63 - 1), st.booleans(), st.text(max_size=300))
def test_died_round_trip(node: str, t: int, fatal: bool, text: str) -> None:
    # a lone surrogate in the child's text crosses as "?" (UTF-8 has no surrogates)
    shown = text.encode("utf-8", "replace").decode("utf-8")
    assert roundtrip(p.encode_died(node, t, fatal, text)) == p.Died(node, t, fatal, shown)


def test_a_long_death_text_is_cut_at_a_character() -> None:
    frame = roundtrip(p.encode_died("/n", 0, True, "é" * p.MAX_ERROR))
    assert isinstance(frame, p.Died)
    assert frame.text == "é" * (p.MAX_ERROR // 2)


@given(names, names, st.booleans())
def test_read_round_trip(node: str, key: str, found: bool) -> None:
    assert roundtrip(p.encode_read(node, key, found)) == p.Read(node, key, found)


def test_bad_died_and_read_frames_are_refused() -> None:
    died = p.encode_died("/a", 5, True, "boom")[p.HEADER.size:]
    with pytest.raises(ProtocolError, match="fatal flag"):
        p.decode_frame(p.DIED, died[:4 + 8] + b"\x07" + died[4 + 8 + 1:])
    with pytest.raises(ProtocolError, match="not UTF-8"):
        p.decode_frame(p.DIED, died[:4 + 8 + 1] + b"\x00\x00\x00\x02\xff\xfe")
    long = (b"\x00\x02/a" + (5).to_bytes(8, "big") + b"\x01"
            + (p.MAX_ERROR + 1).to_bytes(4, "big") + b"x" * (p.MAX_ERROR + 1))
    with pytest.raises(ProtocolError, match="death text"):
        p.decode_frame(p.DIED, long)
    read = p.encode_read("/a", "/k", True)[p.HEADER.size:]
    with pytest.raises(ProtocolError, match="found flag"):
        p.decode_frame(p.READ, read[:-1] + b"\x02")
