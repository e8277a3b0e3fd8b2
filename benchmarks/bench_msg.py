"""Message serialize+deserialize round trips per second against rosbags' ROS 1 serializer.

Each row measures one ddes round trip (``serialize_message`` then
``deserialize_message``) against the same round trip through the rosbags
typestore (``serialize_ros1`` / ``deserialize_ros1``) on the same message,
in the same run.  The rosbags message is read from ddes's bytes, and the
bytes rosbags writes back are checked to be identical before timing.
"""

from __future__ import annotations

import sys
from collections.abc import Callable
from pathlib import Path
from typing import Any

from rosbags.typesys import Stores, get_typestore

sys.path.insert(0, str(Path(__file__).resolve().parent))

from common import compare, result, size  # noqa: E402

from ddes import Time  # noqa: E402
from ddes.msg import (  # noqa: E402
    Message,
    deserialize_message,
    get_message_class,
    serialize_message,
)
from ddes.msg.numpy_msg import numpy_msg  # noqa: E402

_STORE = get_typestore(Stores.ROS1_NOETIC)


def _string() -> Message:
    return get_message_class("std_msgs/String")(data="hello world, this is a ROS message")


def _odometry() -> Message:
    odom = get_message_class("nav_msgs/Odometry")(child_frame_id="base_link")
    odom.header.stamp = Time(1234, 5678)
    odom.header.frame_id = "odom"
    odom.pose.pose.position.x = 1.5
    odom.pose.pose.orientation.w = 1.0
    odom.pose.covariance = [0.01 * i for i in range(36)]
    odom.twist.twist.linear.x = 0.3
    return odom


def _laser_scan() -> Message:
    scan = get_message_class("sensor_msgs/LaserScan")(
        angle_min=-3.14159, angle_max=3.14159, angle_increment=0.00872664,
        range_min=0.1, range_max=30.0,
        ranges=[1.0 + 0.01 * i for i in range(720)],
        intensities=[float(i % 100) for i in range(720)],
    )
    scan.header.stamp = Time(99, 1)
    scan.header.frame_id = "laser"
    return scan


def _loop(fn: Callable[[], None], n: int) -> Callable[[], int]:
    def run() -> int:
        for _ in range(n):
            fn()
        return n

    return run


def round_trips(msg: Message, numpy: bool = False) -> tuple[Callable[[], None],
                                                              Callable[[], None], bytes]:
    """ddes's and rosbags' serialize + deserialize of ``msg`` (in rospy's numpy_msg form with
    ``numpy``), and its bytes; raises if the two disagree on the bytes."""
    cls = type(msg)
    if numpy:  # rospy's numpy_msg form: numeric arrays as numpy arrays, both sides
        cls = numpy_msg(cls)
        msg = deserialize_message(cls, serialize_message(msg))
    rb_type = msg._type.replace("/", "/msg/", 1)
    data = serialize_message(msg)
    rb_msg = _STORE.deserialize_ros1(data, rb_type)
    if bytes(_STORE.serialize_ros1(rb_msg, rb_type)) != data:
        raise AssertionError(f"rosbags and ddes disagree on the bytes of {msg._type}")

    def ddes_round_trip() -> None:
        deserialize_message(cls, serialize_message(msg))

    def rosbags_round_trip() -> None:
        _STORE.deserialize_ros1(_STORE.serialize_ros1(rb_msg, rb_type), rb_type)

    return ddes_round_trip, rosbags_round_trip, data


def _pair(name: str, msg: Message, n: int, numpy: bool = False) -> dict[str, Any]:
    ddes_round_trip, rosbags_round_trip, data = round_trips(msg, numpy)
    c = compare(_loop(ddes_round_trip, n), _loop(rosbags_round_trip, n), repeat=7)
    return result(name, c, "msgs/s", "rosbags serialize_ros1+deserialize_ros1",
                  n=n, bytes=len(data))


def benchmarks() -> list[dict[str, Any]]:
    return [
        _pair("msg_roundtrip_string", _string(), size(20_000)),
        _pair("msg_roundtrip_odometry", _odometry(), size(10_000)),
        _pair("msg_roundtrip_laserscan720", _laser_scan(), size(3_000)),
        _pair("msg_roundtrip_laserscan720_numpy", _laser_scan(), size(3_000), numpy=True),
    ]


if __name__ == "__main__":
    import json

    for r in benchmarks():
        print(json.dumps(r))
