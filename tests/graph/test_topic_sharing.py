"""One topic, one set of connections per node: the Publishers (Subscribers) a node makes on one
topic share them, as rospy's topic manager keeps one impl per node and topic.  The scripts of
tests/compat/test_rospy_behaviours.py compare the same with real rospy."""

from __future__ import annotations

from typing import Any

import ddes
from ddes.graph.statistics import handshake_size
from ddes.msg import get_message_class

String = get_message_class("std_msgs/String")
MS = 1_000_000


def _pair(world: ddes.World) -> tuple[Any, Any, list[str], Any]:
    talker, listener = world.create_node("talker"), world.create_node("listener")
    heard: list[str] = []
    sub = listener.subscribe("chatter", String, lambda m: heard.append(m.data))
    first = talker.advertise("chatter", String, queue_size=10)
    world.run(until=0.01)
    return talker, listener, heard, (first, sub)


def test_a_second_publisher_sends_on_the_connections_at_once() -> None:
    world = ddes.World()
    talker, _listener, heard, (first, _sub) = _pair(world)
    for i in range(20):
        talker.advertise("chatter", String, queue_size=10).publish(f"m{i}")
    world.run(until=0.02)
    assert heard == [f"m{i}" for i in range(20)]
    entry = world.master.topics["/chatter"]
    assert entry.publishers == [first] and first.get_num_connections() == 1
    assert len(world.topic_stats("/chatter")["connections"]) == 1


def test_the_connections_outlive_the_first_publisher_until_the_last_goes() -> None:
    world = ddes.World()
    talker, _listener, heard, (first, sub) = _pair(world)
    second = talker.advertise("chatter", String, queue_size=10)
    first.unregister()
    second.publish("still here")
    world.run(until=0.02)
    assert heard == ["still here"] and world.master.topics["/chatter"].publishers == [second]
    assert sub.get_num_connections() == 1 and second.seq == 1
    second.publish("sent before the close")
    second.unregister()
    world.run(until=0.03)
    assert heard[-1] == "sent before the close"  # TCP delivers what was written
    assert sub.get_num_connections() == 0 and not world.master.topics["/chatter"].publishers


def test_subscribers_share_one_connection_and_a_latched_message() -> None:
    world = ddes.World()
    talker, listener = world.create_node("talker"), world.create_node("listener")
    pub = talker.advertise("latched", String, queue_size=1, latch=True)
    pub.publish("L")
    got: dict[int, list[str]] = {1: [], 2: []}
    first = listener.subscribe("latched", String, lambda m: got[1].append(m.data))
    world.run(until=0.01)
    second = listener.subscribe("latched", String, lambda m: got[2].append(m.data))
    world.run(until=0.02)
    assert got == {1: ["L"], 2: ["L"]} and second.get_num_connections() == 1
    pub.publish("next")
    world.run(until=0.03)
    assert got == {1: ["L", "next"], 2: ["L", "next"]}
    assert world.master.topics["/latched"].subscribers == [first]
    first.unregister()
    pub.publish("after")
    world.run(until=0.04)
    assert got[2][-1] == "after" and world.master.topics["/latched"].subscribers == [second]


def test_a_subscribe_listener_hears_each_connection() -> None:
    world = ddes.World()
    talker, listener = world.create_node("talker"), world.create_node("listener")
    events: list[Any] = []

    class Listener:
        def peer_subscribe(self, topic: str, topic_publish: Any, peer_publish: Any) -> None:
            events.append(("subscribe", topic))
            peer_publish(String("to you"))
            topic_publish(String("to all"))

        def peer_unsubscribe(self, topic: str, num_peers: int) -> None:
            events.append(("unsubscribe", topic, num_peers))

    talker.advertise("news", String, queue_size=1, subscriber_listener=Listener())
    heard: list[str] = []
    sub = listener.subscribe("news", String, lambda m: heard.append(m.data))
    world.run(until=0.01)
    sub.unregister()
    world.run(until=0.02)
    assert heard == ["to you", "to all"]
    assert events == [("subscribe", "/news"), ("unsubscribe", "/news", 0)]


def test_custom_headers_reach_the_subscriber() -> None:
    world = ddes.World()
    talker, listener = world.create_node("talker"), world.create_node("listener")
    talker.advertise("hdr", String, queue_size=1, headers={"cookies": "yum"}).publish("x")
    headers: list[dict[str, str]] = []
    listener.subscribe("hdr", String, lambda m: headers.append(m._connection_header))
    pub = talker.advertise("hdr", String, queue_size=1, latch=True)
    pub.publish("y")
    world.run(until=0.01)
    assert headers and headers[0]["cookies"] == "yum" and headers[0]["latching"] == "1"


def test_statistics_count_what_rospy_counts() -> None:
    world = ddes.World()
    world.params.set_param("/enable_statistics", True)
    Stats = get_message_class("rosgraph_msgs/TopicStatistics")  # noqa: N806
    talker, listener = world.create_node("talker"), world.create_node("listener")
    reports: list[Any] = []
    listener.subscribe("/statistics", Stats, reports.append)
    listener.subscribe("a", String, lambda m: None)
    listener.subscribe("b", String, lambda m: None)
    a = talker.advertise("a", String, queue_size=1)
    b = talker.advertise("b", String, queue_size=1)

    def main() -> Any:
        yield talker.sleep(1.5)
        for i in range(30):
            a.publish(f"a{i:02d}")
            if i == 10:
                b.publish("b")
            yield talker.sleep(0.1)

    talker.process(main())
    world.run(until=5.0)
    (first_b,) = [r for r in reports if r.topic == "/b"]
    header = handshake_size({"topic": "/b", "message_definition": String._full_text,
                             "tcp_nodelay": "0", "md5sum": String._md5sum,
                             "type": "std_msgs/String", "callerid": "/listener"})
    assert (first_b.node_pub, first_b.node_sub, first_b.delivered_msgs, first_b.traffic) == \
        ("/talker", "/listener", 1, header + 4 + 5)
    # the first /a report is lost (its /statistics Publisher had no connection yet), as in rospy
    a_reports = [r for r in reports if r.topic == "/a"]
    assert a_reports and all(r.traffic == r.delivered_msgs * 11 for r in a_reports)
    assert a_reports[0].window_start.to_sec() == 1.5  # the lost first report started it
