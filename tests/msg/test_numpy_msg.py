"""numpy_msg: opt-in numpy arrays, same wire bytes as the plain class."""

from __future__ import annotations

import pytest

from ddes import Time
from ddes.errors import DdesTypeError, ROSSerializationException
from ddes.msg import deserialize_message, get_message_class, serialize_message
from ddes.msg.numpy_msg import numpy_msg

np = pytest.importorskip("numpy")


def _scan():  # type: ignore[no-untyped-def]
    scan = get_message_class("sensor_msgs/LaserScan")(
        angle_min=-1.5, angle_max=1.5, range_max=30.0,
        ranges=[1.0 + 0.01 * i for i in range(361)], intensities=[])
    scan.header.stamp = Time(3, 4)
    scan.header.frame_id = "laser"
    return scan


def test_laser_scan_reads_numpy_and_writes_the_same_bytes() -> None:
    scan = _scan()
    data = serialize_message(scan)
    cls = numpy_msg(type(scan))
    assert cls is numpy_msg(type(scan)) and cls._md5sum == type(scan)._md5sum
    got = deserialize_message(cls, data)
    assert isinstance(got.ranges, np.ndarray) and got.ranges.dtype == np.dtype("<f4")
    assert got.ranges.tolist() == list(deserialize_message(type(scan), data).ranges)
    assert serialize_message(got) == data
    got.ranges = np.asarray(scan.ranges, dtype=np.float32)
    assert serialize_message(got) == data


def test_fixed_arrays_and_nested_messages() -> None:
    odom_cls = get_message_class("nav_msgs/Odometry")
    odom = odom_cls(child_frame_id="base")
    odom.pose.covariance = [0.5 * i for i in range(36)]
    data = serialize_message(odom)
    got = deserialize_message(numpy_msg(odom_cls), data)
    assert isinstance(got.pose.covariance, np.ndarray) and got.pose.covariance.shape == (36,)
    assert serialize_message(got) == data
    got.pose.covariance = np.zeros(35)
    with pytest.raises(ROSSerializationException, match="exactly 36"):
        serialize_message(got)


def test_rejects_a_non_message() -> None:
    with pytest.raises(DdesTypeError, match="message class"):
        numpy_msg(int)  # type: ignore[type-var]
