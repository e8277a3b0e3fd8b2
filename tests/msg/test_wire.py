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
