"""Fuzz the message parser, codegen and wire reader (issue 13).

Every example ends in a valid result or a :class:`~ddes.errors.DdesError`, within
a 32 MiB peak of memory (tracemalloc), never another exception.
"""

from __future__ import annotations

import tracemalloc
from collections.abc import Callable
from pathlib import Path

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import ddes
from ddes.errors import DdesError
from ddes.msg import get_message_class
from ddes.msg.registry import message_class_from_definition, parse_definition
from ddes.msg.wire import deserialize_message, serialize_message

PACKAGES = Path(ddes.__file__).parent / "packages"
REAL = sorted(PACKAGES.glob("*/msg/*.msg"))
BOUND_BYTES = 32 * 2**20
FUZZ = settings(max_examples=150, deadline=None,
                suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much])


def _bounded(step: Callable[[], object]) -> None:
    tracemalloc.start()  # a memory bound, not CPU time: it holds on a loaded machine
    try:
        try:
            step()
        except DdesError:
            pass
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    assert peak < BOUND_BYTES, f"allocated {peak} bytes at peak"


def _whole_pipeline(type_name: str, text: str | bytes) -> None:
    specs = parse_definition(type_name, text)
    assert specs[0].full_name == type_name
    cls = message_class_from_definition(type_name, text)
    assert len(cls._md5sum) == 32
    data = serialize_message(cls())
    assert serialize_message(deserialize_message(cls, data)) == data


# --- grammar-aware definitions --------------------------------------------------------

_PRIMS = ["bool", "int8", "uint8", "int16", "uint16", "int32", "uint32", "int64", "uint64",
          "float32", "float64", "string", "time", "duration", "byte", "char", "Header"]
_LOCAL = ["fz/M1", "fz/M2", "fz/M3", "M1", "std_msgs/Empty"]
_NAMES = st.one_of(st.sampled_from(["x", "data", "A_1", "header", "X"]),
                   st.text("abcxyzAB_0129 %[]/=#é\t\x00", min_size=0, max_size=8))
_SUFFIX = st.sampled_from(["", "", "[]", "[3]", "[0]", "[", "[x]", "[]]", "[99999999999]"])
_VALUES = st.one_of(st.integers(-(2**70), 2**70).map(str), st.floats().map(str),
                    st.sampled_from(["True", "'a'", "", "1e999", "[[[[", "#", "abc"]))


@st.composite
def _line(draw: st.DrawFn) -> str:
    base = draw(st.sampled_from(_PRIMS + _LOCAL))
    type_ = base + draw(_SUFFIX)
    name = draw(_NAMES)
    if draw(st.booleans()):
        return f"{type_} {name}"
    return f"{base} {name.upper()}={draw(_VALUES)}"


@st.composite
def _definition(draw: st.DrawFn) -> str:
    bodies = [
        "\n".join(draw(st.lists(_line() | st.text(max_size=20), max_size=6)))
        for _ in range(draw(st.integers(1, 4)))
    ]
    names = draw(st.lists(st.sampled_from(["fz/M1", "fz/M2", "fz/M3", "std_msgs/Empty",
                                           "Header", "bad name", "fz/Top"]),
                          min_size=len(bodies) - 1, max_size=len(bodies) - 1))
    text = bodies[0]
    for name, body in zip(names, bodies[1:]):
        text += f"\n{'=' * 80}\nMSG: {name}\n{body}"
    return text


@FUZZ
@given(_definition())
def test_grammar_aware_definitions(text: str) -> None:
    _bounded(lambda: _whole_pipeline("fz/Top", text))


# --- mutations of the bundled .msg files ------------------------------------------------

@st.composite
def _mutated(draw: st.DrawFn) -> bytes:
    data = bytearray(draw(st.sampled_from(REAL)).read_bytes())
    for _ in range(draw(st.integers(1, 6))):
        op = draw(st.sampled_from(["flip", "insert", "delete", "dup"]))
        at = draw(st.integers(0, max(len(data) - 1, 0)))
        if op == "flip" and data:
            data[at] = draw(st.integers(0, 255))
        elif op == "insert":
            data[at:at] = draw(st.sampled_from(
                [b"[]", b"[7]", b"=", b"#", b"\n", b"\xff", b"\xc3", b"/", b" ", b"\t", b"%s",
                 b"\x00", b"---\n", b"Header h\n", b"fz/Top t\n", b"std_msgs/Empty[] e\n"]))
        elif op == "delete":
            del data[at:at + draw(st.integers(1, 8))]
        else:
            data[at:at] = data[at:at + draw(st.integers(1, 40))]
    return bytes(data)


@FUZZ
@given(_mutated(), st.booleans())
def test_mutated_bundled_files(data: bytes, as_text: bool) -> None:
    def step() -> None:
        text: str | bytes = data
        if as_text:
            text = data.decode("utf-8", "surrogateescape")  # what a careless bag reader does
        _whole_pipeline("fz/Top", text)
    _bounded(step)


# --- random wire bytes -----------------------------------------------------------------

_WIRE_TYPES = ["nav_msgs/Odometry", "sensor_msgs/LaserScan", "sensor_msgs/JointState",
               "rosgraph_msgs/Log", "visualization_msgs/InteractiveMarkerUpdate"]


@st.composite
def _wire(draw: st.DrawFn) -> tuple[str, bytes]:
    type_name = draw(st.sampled_from(_WIRE_TYPES))
    cls = get_message_class(type_name)
    if draw(st.booleans()):
        return type_name, draw(st.binary(max_size=400))
    data = bytearray(serialize_message(cls()))
    for _ in range(draw(st.integers(0, 6))):
        at = draw(st.integers(0, max(len(data) - 1, 0)))
        if data and draw(st.booleans()):
            data[at] = draw(st.sampled_from([0xFF, 0x80, 0x7F, 0x00, 0x01, 0xC3]))
        else:
            data[at:at] = draw(st.sampled_from([b"\xff\xff\xff\xff", b"\x00\x00\x00\x80",
                                                b"\x05\x00\x00\x00", b"\xff\xfe"]))
    return type_name, bytes(data[: draw(st.integers(0, len(data)))])


@FUZZ
@given(_wire())
def test_random_wire_bytes(case: tuple[str, bytes]) -> None:
    type_name, data = case
    cls = get_message_class(type_name)

    def step() -> None:
        msg = deserialize_message(cls, data)
        # what was read serializes back to the same bytes (compared as bytes: NaN != NaN)
        again = serialize_message(msg)
        assert serialize_message(deserialize_message(cls, again)) == again
    _bounded(step)
