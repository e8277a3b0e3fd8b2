"""``header.seq`` as rospy (and roscpp) count it, checked against real rospy.

rospy's ``_PublisherImpl.publish`` returns before counting when no subscriber
is connected, leaving ``header.seq`` as the user set it; with a subscriber the
per-topic counter (shared by every Publisher of the topic in the node) counts
up and overwrites ``header.seq``.  A latched message is published again on a
new connection, with a new seq.  roscpp counts every publish and writes the
count only into the sent bytes.
"""

from __future__ import annotations

import json
from collections.abc import Callable
from typing import Any

import pytest

import ddes
from ddes.errors import ROSSerializationException

from .rosmaster_script import MASTER

PointStamped = ddes.get_message_class("geometry_msgs/PointStamped")
Int32 = ddes.get_message_class("std_msgs/Int32")
STEP = ddes.Duration(0, 10_000_000)  # 10 ms more of simulated time (connections take 1 ms)


def _stamped(seq: int = 77) -> Any:
    m = PointStamped()
    m.header.seq = seq
    return m


def scenario_in_ddes() -> dict[str, list[int]]:
    """The steps of ``ROSPY_SCENARIO`` in a ddes world (simulated time, 1 ms connections)."""
    world = ddes.World(seed=0)
    node = world.create_node("seq_talker")
    got: list[int] = []
    latched: list[int] = []
    out: dict[str, list[int]] = {}

    def publish_all(pub: Any, n: int) -> list[int]:
        after = []
        for _ in range(n):
            m = _stamped()
            pub.publish(m)
            after.append(m.header.seq)
        return after

    pub = ddes.Publisher(node, "/pt", PointStamped, queue_size=10)
    out["no_subscriber_after"] = publish_all(pub, 3)
    ddes.Subscriber(node, "/pt", PointStamped, lambda m: got.append(m.header.seq))
    world.run(until=STEP)
    out["subscribed_after"] = publish_all(pub, 3)
    pub2 = ddes.Publisher(node, "/pt", PointStamped, queue_size=10)
    world.run(until=STEP)
    out["second_publisher_after"] = publish_all(pub2, 1) + publish_all(pub, 1)
    world.run(until=STEP)
    out["received"] = list(got)

    lpub = ddes.Publisher(node, "/latched", PointStamped, latch=True, queue_size=1)
    out["latched_no_subscriber_after"] = publish_all(lpub, 2)
    ddes.Subscriber(node, "/latched", PointStamped, lambda m: latched.append(m.header.seq))
    world.run(until=STEP)
    out["latched_subscribed_after"] = publish_all(lpub, 1)
    world.run(until=STEP)
    out["latched_received"] = list(latched)

    pub.unregister()
    pub2.unregister()
    got.clear()
    pub3 = ddes.Publisher(node, "/pt", PointStamped, queue_size=10)
    world.run(until=STEP)
    out["republished_after"] = publish_all(pub3, 2)
    world.run(until=STEP)
    out["republished_received"] = list(got)
    return out


ROSPY_SCENARIO = MASTER + r'''
import json, threading, time
import rospy
from geometry_msgs.msg import PointStamped

rospy.init_node("seq_talker", disable_signals=True)
got, latched = [], []
lock = threading.Condition()

def wait_for(cond, what):
    deadline = time.time() + 30
    while not cond():
        if time.time() > deadline:
            raise SystemExit("timed out waiting for " + what)
        time.sleep(0.01)

def stamped():
    m = PointStamped()
    m.header.seq = 77
    return m

def publish_all(pub, n):
    after = []
    for _ in range(n):
        m = stamped()
        pub.publish(m)
        after.append(m.header.seq)
    return after

out = {}
pub = rospy.Publisher("/pt", PointStamped, queue_size=10)
out["no_subscriber_after"] = publish_all(pub, 3)
sub = rospy.Subscriber("/pt", PointStamped, lambda m: got.append(m.header.seq))
wait_for(lambda: pub.get_num_connections() == 1, "the /pt connection")
out["subscribed_after"] = publish_all(pub, 3)
pub2 = rospy.Publisher("/pt", PointStamped, queue_size=10)
out["second_publisher_after"] = publish_all(pub2, 1) + publish_all(pub, 1)
wait_for(lambda: len(got) == 5, "5 messages")
out["received"] = list(got)

lpub = rospy.Publisher("/latched", PointStamped, latch=True, queue_size=1)
out["latched_no_subscriber_after"] = publish_all(lpub, 2)
rospy.Subscriber("/latched", PointStamped, lambda m: latched.append(m.header.seq))
wait_for(lambda: lpub.get_num_connections() == 1 and len(latched) == 1, "the latched message")
out["latched_subscribed_after"] = publish_all(lpub, 1)
wait_for(lambda: len(latched) == 2, "2 latched-topic messages")
out["latched_received"] = list(latched)

pub.unregister()
pub2.unregister()
time.sleep(0.5)
del got[:]
pub3 = rospy.Publisher("/pt", PointStamped, queue_size=10)
wait_for(lambda: pub3.get_num_connections() == 1, "the new /pt connection")
out["republished_after"] = publish_all(pub3, 2)
wait_for(lambda: len(got) == 2, "2 messages")
out["republished_received"] = list(got)
print(json.dumps(out))
'''


def test_ddes_counts_seq_as_rospy() -> None:
    assert scenario_in_ddes() == {
        "no_subscriber_after": [77, 77, 77],        # not sent: not counted, header untouched
        "subscribed_after": [1, 2, 3],
        "second_publisher_after": [4, 5],           # one counter per topic and node
        "received": [1, 2, 3, 4, 5],
        "latched_no_subscriber_after": [77, 77],
        "latched_subscribed_after": [2],            # the latched resend took seq 1
        "latched_received": [1, 2],
        "republished_after": [1, 2],                # the topic's last publisher went: restart
        "republished_received": [1, 2],
    }


@pytest.mark.ros
def test_seq_agrees_with_rospy(ros_python: Callable[..., Any]) -> None:
    theirs = ros_python(ROSPY_SCENARIO, as_json=True, timeout=120)
    assert json.loads(json.dumps(scenario_in_ddes())) == theirs


def test_trace_records_seq_zero_for_a_publish_nobody_receives(world: ddes.World) -> None:
    node = world.create_node("talker")
    pub = node.advertise("/n", Int32, queue_size=1)
    pub.publish(1)
    node.subscribe("/n", Int32, lambda m: None)
    world.run(until=0.01)
    pub.publish(2)
    seqs = [e.details["seq"] for e in world.trace.filter(kind="topic.publish")]
    assert seqs == [0, 1] and pub.seq == 1 and pub.published == 2
    stats = world.topic_stats("/n")
    assert stats["published"] == 2 and stats["sent"] == 1


def test_publishers_of_one_topic_in_two_nodes_count_apart(world: ddes.World) -> None:
    a, b = world.create_node("a"), world.create_node("b")
    got: list[tuple[str, int]] = []
    world.create_node("l").subscribe(
        "/p", PointStamped, lambda m: got.append((m.header.frame_id, m.header.seq)))
    pa, pb = a.advertise("/p", PointStamped, queue_size=5), b.advertise("/p", PointStamped,
                                                                        queue_size=5)
    world.run(until=0.01)
    for pub, name in [(pa, "a"), (pb, "b"), (pa, "a")]:
        m = PointStamped()
        m.header.frame_id = name
        pub.publish(m)
    world.run(until=0.02)
    assert got == [("a", 1), ("b", 1), ("a", 2)]


def test_roscpp_nodes_count_every_publish_into_the_bytes(world: ddes.World) -> None:
    node = world.create_node("cpp", log_style="roscpp")
    assert node.client_library == "roscpp" and world.create_node("py").client_library == "rospy"
    got: list[int] = []
    pub = node.advertise("/c", PointStamped, queue_size=5)
    m = _stamped()
    pub.publish(m)  # no subscriber: roscpp counts it anyway
    assert m.header.seq == 77  # roscpp never writes into the message object
    world.create_node("l").subscribe("/c", PointStamped, lambda msg: got.append(msg.header.seq))
    world.run(until=0.01)
    pub.publish(m)
    pub.publish(m)
    world.run(until=0.02)
    assert got == [2, 3] and m.header.seq == 77


def test_roscpp_latched_resend_keeps_its_seq(world: ddes.World) -> None:
    node = world.create_node("cpp", log_style="roscpp")
    pub = node.advertise("/c", PointStamped, queue_size=1, latch=True)
    pub.publish(_stamped())
    pub.publish(_stamped())
    got: list[int] = []
    world.create_node("l").subscribe("/c", PointStamped, lambda msg: got.append(msg.header.seq))
    world.run(until=0.01)
    pub.publish(_stamped())
    world.run(until=0.02)
    assert got == [2, 3]


def test_a_bad_field_raises_even_without_subscribers(world: ddes.World) -> None:
    # A deliberate deviation (docs/graph.md): rospy would only fail once someone subscribes.
    pub = world.create_node("t").advertise("/i", Int32, queue_size=1)
    with pytest.raises(ROSSerializationException):
        pub.publish(Int32(data="not an int"))
