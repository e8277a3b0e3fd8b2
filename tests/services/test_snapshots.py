"""The trace's copies of requests and responses: held as wire bytes, read when looked at."""

from __future__ import annotations

import copy
import gc
import pickle
from collections.abc import Generator
from typing import Any

import ddes
from ddes.kernel.trace import Trace
from ddes.msg import get_message_class, get_service_class
from ddes.services import Service, ServiceProxy
from ddes.services.transport import _CALL_KEYS, _wire_keys

Odometry = get_message_class("nav_msgs/Odometry")
AddTwoInts = get_service_class("rospy_tutorials/AddTwoInts")


def odometry() -> Any:
    msg = Odometry()
    msg.header.seq = 7
    msg.header.frame_id = "odom"
    msg.pose.pose.position.x = 1.5
    msg.twist.covariance = tuple(float(i) for i in range(36))
    return msg


def traced(msg: Any) -> Trace:
    """A trace with one service.call row holding ``msg`` as its wire bytes."""
    trace = Trace()
    trace.append_row((5, "service.call", "/c", _wire_keys(_CALL_KEYS, "request", Odometry), "/s",
                      1, False, msg._serialize_to_bytes()))
    return trace


def test_the_trace_holds_the_message_it_was_taken_of_and_it_stays_so() -> None:
    msg = odometry()
    trace = traced(msg)
    msg.header.frame_id = "changed"  # the original changes after the call: the copy does not
    want = odometry()
    got = trace[0].details["request"]
    assert got == want and want == got
    assert type(got) is Odometry
    assert repr(got) == repr(want)
    got.header.frame_id = "mutated by a reader"  # every read is an independent copy
    assert trace[0].details["request"] == want


def test_a_wire_row_reads_as_the_row_that_held_the_message() -> None:
    msg = odometry()
    wire = traced(msg)
    plain = Trace()
    plain.append_row((5, "service.call", "/c", _CALL_KEYS, "/s", 1, False, odometry()))
    assert list(wire.lines()) == list(plain.lines())
    assert wire.digest() == plain.digest()
    assert wire.events == plain.events
    assert wire.select("service.call", request=odometry()) == plain.select("service.call",
                                                                           request=odometry())
    assert len(wire.select("service.call", request=Odometry())) == 0
    assert wire.format() == plain.format()


def test_a_wire_row_is_not_tracked_by_the_garbage_collector() -> None:
    trace = traced(odometry())
    gc.collect()  # untracks the key tuple (all strs), a row once its elements are untracked:
    gc.collect()  # the next pass (a key tuple is made once per class; its rows come after)
    assert not gc.is_tracked(trace._raw[0])


def test_an_equal_key_tuple_of_ones_own_holds_what_it_holds() -> None:
    trace = Trace()
    data = odometry()._serialize_to_bytes()
    trace.append_row((5, "service.call", "/c", tuple(list(_CALL_KEYS)), "/s", 1, False, data))
    assert trace[0].details["request"] == data


def test_copies_and_pickles_keep_the_events_and_the_digest() -> None:
    trace = traced(odometry())
    want = trace.digest()
    for other in (copy.copy(trace), copy.deepcopy(trace), pickle.loads(pickle.dumps(trace))):
        assert other.digest() == want
        assert other[0].details["request"] == odometry()
        assert type(other[0].details["request"]) is Odometry


def _calls(node: ddes.Node) -> Generator[Any, Any, None]:
    proxy = ServiceProxy(node, "add", AddTwoInts)
    for i in range(3):
        yield proxy(i, 10)


def test_a_worlds_trace_copied_after_a_run_digests_as_the_original() -> None:
    world = ddes.World(3)
    Service(world.create_node("server"), "add", AddTwoInts, lambda req: req.a + req.b)
    client = world.create_node("client")
    client.process(_calls(client))
    world.run()
    responses = [ev.details["response"].sum for ev in world.trace.select("service.response")]
    assert responses == [10, 11, 12]
    for other in (copy.deepcopy(world.trace), pickle.loads(pickle.dumps(world.trace))):
        assert other.digest() == world.digest()
        assert other.events == world.trace.events
