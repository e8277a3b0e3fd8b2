"""Shared helpers of the bag tests: a UTC time zone, message classes, small bags."""

from __future__ import annotations

import os
import time
from collections.abc import Iterator
from typing import Any

import pytest

from ddes import Time
from ddes.msg import get_message_class
from ddes.rosbag import Bag

String = get_message_class("std_msgs/String")
Int32 = get_message_class("std_msgs/Int32")


@pytest.fixture
def utc() -> Iterator[None]:
    """Run with TZ=UTC (rosbag info prints local time), restoring the zone afterwards."""
    old = os.environ.get("TZ")
    os.environ["TZ"] = "UTC"
    time.tzset()
    yield
    if old is None:
        del os.environ["TZ"]
    else:
        os.environ["TZ"] = old
    time.tzset()


def sample_bag(**kwargs: Any) -> Bag:
    """Three messages on two topics, one written out of order (as in the docs)."""
    bag = Bag(**kwargs)
    bag.write("/chatter", String(data="hi"), Time(1, 5))
    bag.write("/n", Int32(data=3), Time(1, 5))
    bag.write("/chatter", String(data="ho"), Time(0, 5))
    return bag


def contents(bag: Bag, **kwargs: Any) -> list[tuple[Any, ...]]:
    """Everything observable of a bag's messages: topic, time, bytes, connection header."""
    return [(m.topic, m.timestamp.to_nsec(), m.message[1], dict(m.connection_header))
            for m in bag.read_messages(raw=True, return_connection_header=True, **kwargs)]
