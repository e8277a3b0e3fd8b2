"""The generated code's fast paths give what the plain paths would (issue 23, messages).

Each test pins a behaviour the speed-ups must not change: keyword-only
``__init__`` parameters, the ``_fresh`` defaults, strict UTF-8 decoding with
its 'replace' rerun, native-order Structs for floats, straight-line writers.
"""

from __future__ import annotations

import math
import struct

import pytest

from ddes import Duration, Time
from ddes.errors import (
    DdesAttributeError,
    DdesTypeError,
    DeserializationError,
    ROSSerializationException,
)
from ddes.msg import (
    deserialize_message,
    get_message_class,
    message_class_from_definition,
    serialize_message,
)
from ddes.msg.gentools import SEPARATOR as SEP

String = get_message_class("std_msgs/String")
Point = get_message_class("geometry_msgs/Point")
Odometry = get_message_class("nav_msgs/Odometry")
LaserScan = get_message_class("sensor_msgs/LaserScan")
JointState = get_message_class("sensor_msgs/JointState")
TFMessage = get_message_class("tf2_msgs/TFMessage")
TransformStamped = get_message_class("geometry_msgs/TransformStamped")


# --- __init__ ----------------------------------------------------------------------------


def test_positional_and_keyword_together_is_refused_even_with_none() -> None:
    with pytest.raises(DdesTypeError, match="only use args OR keywords, not both"):
        String("x", data=None)
    with pytest.raises(DdesTypeError, match="only use args OR keywords, not both"):
        Point(1.0, 2.0, 3.0, w=1.0)


def test_unknown_keyword_is_named_first_in_call_order() -> None:
    with pytest.raises(DdesAttributeError, match=r"^q is not an attribute of Point; its fields "
                                                 r"are x, y, z$"):
        Point(x=1.0, q=2, r=3)


def test_wrong_count_of_positional_values_shows_them() -> None:
    with pytest.raises(DdesTypeError, match=r"args are\(1, 2, 3, 4\); pass all 3 fields"):
        Point(1, 2, 3, 4)


def test_fields_named_like_builtins_and_parameters() -> None:
    text = ("int32 len\nint32 next\nint32 iter\nint32 range\nstring args\nstring kwds\n"
            "int32 self\na/In[2] pair\ntime t\nduration[2] ds\n"
            f"{SEP}\nMSG: a/In\nint32 range\n")
    cls = message_class_from_definition("a/Names", text)
    default = cls()
    assert (default.len, default.args, default.self_) == (0, "", 0)
    assert [p.range for p in default.pair] == [0, 0] and default.pair[0] is not default.pair[1]
    assert default.t == Time() and default.ds == [Duration(), Duration()]
    kw = cls(len=1, next=2, iter=3, range=4, args="a", kwds="k", self_=5)
    assert (kw.len, kw.next, kw.iter, kw.range, kw.args, kw.kwds, kw.self_) == \
        (1, 2, 3, 4, "a", "k", 5)
    pos = cls(1, 2, 3, 4, "a", "k", 5, None, None, None)
    assert serialize_message(pos) == serialize_message(kw)
    assert deserialize_message(cls, serialize_message(kw)) == kw


def test_fields_that_collide_once_renamed_still_construct() -> None:
    cls = message_class_from_definition("a/Twice", "int32 from\nint32 from_\n")
    assert cls.__slots__ == ("from_", "from_")
    assert cls(1, 2).from_ == 2 and cls(from_=3).from_ == 3 and cls().from_ == 0
    with pytest.raises(DdesAttributeError, match="is not an attribute"):
        cls(x=1)


def test_nested_defaults_are_fresh_and_equal_to_constructed_ones() -> None:
    a, b = Odometry(), Odometry()
    assert a == b and a.header is not b.header and a.header.stamp is not b.header.stamp
    assert a.pose.covariance is not b.pose.covariance
    assert type(a.header.stamp) is Time and (a.header.stamp.secs, a.header.stamp.nsecs) == (0, 0)
    assert type(a.header.stamp.secs) is int and type(a.header.stamp.nsecs) is int
    fresh = Odometry._ddes_fresh()
    assert type(fresh) is Odometry and fresh == a
    assert serialize_message(fresh) == serialize_message(a)
    assert Odometry(header=None, pose=None) == a


# --- reading -----------------------------------------------------------------------------


def test_invalid_utf8_in_any_string_is_replaced_everywhere() -> None:
    msg = JointState(name=["ok", "x"], position=[1.0, 2.0])
    msg.header.frame_id = "frame"
    data = bytearray(serialize_message(msg))
    bad = data.index(b"frame")
    data[bad] = 0xFF  # the header's frame_id
    data[data.rindex(b"x")] = 0xC3  # a truncated two-byte sequence in name[1]
    back = deserialize_message(JointState, bytes(data))
    assert back.header.frame_id == "\ufffdrame"
    assert back.name == ["ok", "\ufffd"]
    assert back.position == (1.0, 2.0)
    assert deserialize_message(JointState, bytes(data)) == back  # the rerun is cached


def test_invalid_utf8_before_a_truncation_still_reports_the_truncation() -> None:
    data = bytearray(serialize_message(TFMessage(transforms=[TransformStamped(
        child_frame_id="child")])))
    data[data.index(b"child")] = 0xFF
    with pytest.raises(DeserializationError, match="truncated"):
        deserialize_message(TFMessage, bytes(data[:-3]))


def test_float_arrays_read_bit_exact() -> None:
    Floats = get_message_class("std_msgs/Float64MultiArray")
    values = [0.0, -0.0, 1e-310, -1.5, math.inf, -math.inf, 1.7976931348623157e308]
    nan_payload = struct.unpack("<d", bytes.fromhex("0100000000f87f7f"))[0]
    data = serialize_message(Floats(data=values + [nan_payload]))
    back = deserialize_message(Floats, data)
    assert [struct.pack("<d", v) for v in back.data] == \
        [struct.pack("<d", v) for v in values + [nan_payload]]
    assert serialize_message(back) == data
    raw32 = bytes.fromhex("0100807f" "0000c0ff" "00000080" "01000000" "ffff7f7f")
    scan = bytearray(serialize_message(LaserScan()))
    scan[-8:-4] = struct.pack("<I", 5)  # ranges: the 5 float32 values above
    scan[-4:-4] = raw32
    read = deserialize_message(LaserScan, bytes(scan))
    assert struct.pack("<5f", *read.ranges) == struct.pack("<5f", *struct.unpack("<5f", raw32))
    assert type(read.ranges) is tuple and read.ranges[3] == 1.401298464324817e-45


def test_times_read_from_the_wire_are_canonical_in_arrays_too() -> None:
    cls = message_class_from_definition("a/Times", "time[] ts\nduration d\n")
    data = struct.pack("<IIIii", 1, 1, 1_000_000_000, 0, 0)  # one time, nsecs = 1e9
    back = deserialize_message(cls, data)
    assert back.ts == [Time(2, 0)] and type(back.ts[0]) is Time
    neg = deserialize_message(cls, struct.pack("<Iii", 0, 1, -1))
    assert (neg.d.secs, neg.d.nsecs) == (0, 999_999_999) and type(neg.d) is Duration


# --- writing -----------------------------------------------------------------------------


def test_float32_overflow_still_raises_and_infinities_still_pass() -> None:
    with pytest.raises(ROSSerializationException, match=r"ranges\[1\] \(float32\).*too large"):
        serialize_message(LaserScan(ranges=[1.0, 1e39]))
    ok = serialize_message(LaserScan(ranges=[math.inf, -math.inf, math.nan, 3.4e38]))
    assert deserialize_message(LaserScan, ok).ranges[:2] == (math.inf, -math.inf)


def test_string_fields_holding_other_bytes_like_values() -> None:
    assert serialize_message(String(data=bytearray(b"ab"))) == b"\x02\x00\x00\x00ab"
    assert serialize_message(String(data=b"ab")) == b"\x02\x00\x00\x00ab"

    class Text(str):
        pass

    with pytest.raises(ROSSerializationException, match="sequence item 1"):
        serialize_message(String(data=Text("ab")))  # join's own error, as before


def test_writers_with_loops_and_without_agree_with_struct() -> None:
    tf = TFMessage(transforms=[TransformStamped(child_frame_id=f"c{i}") for i in range(3)])
    tf.transforms[1].header.stamp = Time(3, 4)
    tf.transforms[2].transform.rotation.w = 1.0
    data = serialize_message(tf)
    assert data[:4] == struct.pack("<I", 3)
    assert deserialize_message(TFMessage, data) == tf
    odom = Odometry(child_frame_id="base")
    odom.pose.covariance = [float(i) for i in range(36)]
    layout = struct.pack("<4I", 0, 0, 0, 0) + struct.pack("<I", 4) + b"base" + \
        struct.pack("<7d36d6d36d", *([0.0] * 7), *range(36), *([0.0] * 42))
    assert serialize_message(odom) == layout
