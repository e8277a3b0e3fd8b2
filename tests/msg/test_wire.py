"""Wire format: known byte layouts, round trips, typed errors."""

from __future__ import annotations

import io

import pytest

from ddes import Duration, Time
from ddes.errors import DeserializationError, ROSMessageException, ROSSerializationException
from ddes.msg import deserialize_message, get_message_class, serialize_message

String = get_message_class("std_msgs/String")
Header = get_message_class("std_msgs/Header")
LaserScan = get_message_class("sensor_msgs/LaserScan")


def test_string_layout_is_length_prefixed_utf8() -> None:
    assert serialize_message(String(data="héllo")) == bytes.fromhex("0600000068c3a96c6c6f")


def test_serialize_writes_to_buffer_like_genpy() -> None:
    buff = io.BytesIO()
    String(data="hi").serialize(buff)
    assert buff.getvalue() == b"\x02\x00\x00\x00hi"


def test_header_layout() -> None:
    data = serialize_message(Header(seq=3, stamp=Time(5, 7), frame_id="laser"))
    assert data == bytes.fromhex("03000000" "05000000" "07000000" "05000000") + b"laser"


def test_laserscan_round_trip_gives_tuples_like_genpy() -> None:
    msg = LaserScan(angle_min=-1.5, ranges=[1.0, 2.5], intensities=[0.5])
    back = deserialize_message(LaserScan, serialize_message(msg))
    assert back == msg
    assert back.ranges == (1.0, 2.5)
    assert LaserScan().deserialize(serialize_message(msg)) == msg


def test_duration_is_signed() -> None:
    Dur = get_message_class("std_msgs/Duration")
    data = serialize_message(Dur(data=Duration(-1, 500)))
    assert data == bytes.fromhex("ffffffff" "f4010000")
    assert deserialize_message(Dur, data).data == Duration(-1, 500)


@pytest.mark.parametrize("cut", [0, 3, 4, 12, 15, 19])
def test_truncated_data_raises_deserialization_error(cut: int) -> None:
    data = serialize_message(Header(seq=3, stamp=Time(5, 7), frame_id="laser"))
    with pytest.raises(DeserializationError, match="truncated") as info:
        deserialize_message(Header, data[:cut])
    assert isinstance(info.value, ROSMessageException)


def test_bad_value_names_field_type_and_value() -> None:
    with pytest.raises(ROSSerializationException, match=r"header\.seq \(uint32\).*-1"):
        serialize_message(LaserScan(header=Header(seq=-1)))
    with pytest.raises(ROSSerializationException, match=r"data \(string\).*42"):
        serialize_message(String(data=42))


@pytest.mark.parametrize(("make", "match"), [
    (lambda: get_message_class("nav_msgs/Odometry")(header=get_message_class("geometry_msgs/Point")()),
     r"field header \(std_msgs/Header\) has invalid value <geometry_msgs/Point message>: must be "
     r"a std_msgs/Header message, not a geometry_msgs/Point"),
    (lambda: get_message_class("sensor_msgs/CameraInfo")(K=[1.0]),
     r"field K \(float64\[9\]\) has invalid value \[1.0\]: has 1 elements; this fixed-size array "
     r"needs exactly 9"),
    (lambda: get_message_class("std_msgs/Float32")(data=1e39),
     r"field data \(float32\) has invalid value 1e\+39: is too large for a float32"),
    (lambda: get_message_class("std_msgs/Duration")(data=Duration(2**31)),
     r"field data \(duration\) .*secs=2147483648 outside the duration range"),
    (lambda: get_message_class("sensor_msgs/Image")(data=[1, 300]),
     r"field data \(uint8\[\]\) .*element \[1\] = 300, not a byte"),
    (lambda: get_message_class("sensor_msgs/Image")(data="abc"),
     r"field data \(uint8\[\]\) has invalid value 'abc': must be bytes or a list of ints"),
    (lambda: get_message_class("sensor_msgs/JointState")(name=["a", 3]),
     r"field name\[1\] \(string\) has invalid value 3: must be a str"),
    (lambda: String(data="\udc80"), r"field data \(string\) .*cannot be encoded as UTF-8"),
    (lambda: get_message_class("std_msgs/Int8")(data=128),
     r"field data \(int8\) has invalid value 128: is out of range for int8 \[-128, 127\]"),
    (lambda: get_message_class("std_msgs/Float64")(data="1.0"),
     r"field data \(float64\) has invalid value '1.0': must be a float, not str"),
    (lambda: get_message_class("rosgraph_msgs/Clock")(clock=Duration(-1)),
     r"field clock \(time\) .*must be a ddes.Time, not Duration"),
    (lambda: get_message_class("actionlib_msgs/GoalStatusArray")(status_list=[None]),
     r"field status_list\[0\] \(actionlib_msgs/GoalStatus\) has invalid value None"),
])
def test_serialization_errors_name_the_field(make: object, match: str) -> None:
    msg = make()  # type: ignore[operator]
    with pytest.raises(ROSSerializationException, match=match):
        serialize_message(msg)
    with pytest.raises(ROSSerializationException, match=match):
        msg.serialize(io.BytesIO())


def test_unset_field_is_reported() -> None:
    msg = object.__new__(String)
    with pytest.raises(ROSSerializationException, match=r"field data \(string\) is not set"):
        serialize_message(msg)


def test_bytes_and_lists_for_uint8_arrays_serialize_alike() -> None:
    Image = get_message_class("sensor_msgs/Image")
    assert serialize_message(Image(data=[1, 2, 255])) == serialize_message(
        Image(data=b"\x01\x02\xff")) == serialize_message(Image(data=bytearray(b"\x01\x02\xff")))


def test_memoryview_and_bytearray_input() -> None:
    data = serialize_message(String(data="x"))
    assert deserialize_message(String, memoryview(data)).data == "x"
    assert String().deserialize(bytearray(data)).data == "x"


def test_invalid_utf8_is_replaced_like_genpy() -> None:
    assert deserialize_message(String, b"\x02\x00\x00\x00\xff\xfe").data == "\ufffd\ufffd"


def test_non_canonical_wire_time_is_canonicalised() -> None:
    data = bytes.fromhex("00000000" "01000000" "00ca9a3b" "00000000")  # nsecs = 1e9
    assert deserialize_message(Header, data).stamp == Time(2, 0)


def test_trailing_bytes_are_ignored_like_genpy() -> None:
    data = serialize_message(String(data="x")) + b"junk"
    assert deserialize_message(String, data).data == "x"


def test_huge_length_prefix_is_a_truncation_not_a_memory_error() -> None:
    Floats = get_message_class("std_msgs/Float64MultiArray")
    data = serialize_message(Floats())[:-4] + b"\xff\xff\xff\x7f"
    with pytest.raises(DeserializationError, match="truncated"):
        deserialize_message(Floats, data)
