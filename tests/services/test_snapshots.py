"""The trace's copies of requests and responses: read from the wire bytes when first looked at."""

from __future__ import annotations

import copy
import pickle
from typing import Any

from ddes.msg import get_message_class
from ddes.services.transport import _snapshot

Odometry = get_message_class("nav_msgs/Odometry")


def odometry() -> Any:
    msg = Odometry()
    msg.header.seq = 7
    msg.header.frame_id = "odom"
    msg.pose.pose.position.x = 1.5
    msg.twist.covariance = tuple(float(i) for i in range(36))
    return msg


def test_a_snapshot_is_the_message_it_was_taken_of_and_stays_so() -> None:
    msg = odometry()
    snap = _snapshot(msg, msg._serialize_to_bytes())
    msg.header.frame_id = "changed"  # the original changes after the call: the copy does not
    want = odometry()
    assert snap == want and want == snap
    assert isinstance(snap, Odometry)
    assert type(snap).__name__ == "Odometry" and snap._type == Odometry._type
    assert snap.__slots__ == Odometry.__slots__
    assert repr(snap) == repr(want)
    assert snap.header.frame_id == "odom" and snap.pose.pose.position.x == 1.5


def test_writing_a_field_first_reads_the_others_from_the_wire() -> None:
    msg = odometry()
    snap = _snapshot(msg, msg._serialize_to_bytes())
    snap.child_frame_id = "base"  # before anything was read
    assert snap.child_frame_id == "base"
    assert snap.header.seq == 7  # not overwritten by a later read
    assert snap._serialize_to_bytes() != msg._serialize_to_bytes()


def test_missing_attributes_raise_as_on_the_message() -> None:
    msg = odometry()
    snap = _snapshot(msg, msg._serialize_to_bytes())
    for obj in (msg, snap):
        try:
            obj.no_such_field  # noqa: B018 - the read is the test
        except AttributeError as exc:
            assert "no_such_field" in str(exc)
        else:  # pragma: no cover - a failure
            raise AssertionError("no AttributeError")
    assert getattr(snap, "to_nsec", None) is None


def test_copies_and_pickles_are_plain_equal_messages() -> None:
    msg = odometry()
    for snap in (_snapshot(msg, msg._serialize_to_bytes()) for _ in range(3)):
        assert copy.copy(snap) == msg
    snap = _snapshot(msg, msg._serialize_to_bytes())
    deep = copy.deepcopy(snap)
    assert deep == msg and deep.header is not snap.header
    back = pickle.loads(pickle.dumps(_snapshot(msg, msg._serialize_to_bytes())))
    assert type(back) is Odometry and back == msg
