"""The typed public contracts of the graph behave at run time as their annotations say."""

from __future__ import annotations

import random
from typing import Any

import ddes
from ddes.graph.topics import LinkModel, Publisher, Subscriber, link_latency_ns
from ddes.kernel.events import Posted, post
from ddes.msg import get_message_class
from ddes.msg.anymsg import AnyMsg
from ddes.msg.message import Message, MessageClass

String = get_message_class("std_msgs/String")


def test_publisher_and_subscriber_are_generic_in_their_data_class() -> None:
    # Publisher[type[String]] is what node.advertise(..., String) gives a type checker.
    assert Publisher[type[Message]] is not Publisher
    assert Subscriber[MessageClass] is not Subscriber
    world = ddes.World(seed=1)
    node = world.create_node("n", disable_rosout=True)
    pub = node.advertise("chatter", String, queue_size=1)
    sub = node.subscribe("chatter", AnyMsg, lambda m: None, queue_size=1)
    assert isinstance(pub, Publisher) and pub.data_class is String
    assert isinstance(sub, Subscriber) and sub.data_class is AnyMsg


def test_topic_stats_has_the_typed_keys() -> None:
    world = ddes.World(seed=1)
    world.connect_delay_ns = 0
    talker = world.create_node("talker", disable_rosout=True)
    listener = world.create_node("listener", disable_rosout=True)
    pub = talker.advertise("chatter", String, queue_size=10)
    listener.subscribe("chatter", String, lambda m: None, queue_size=10)
    world.run_for(0.001)
    pub.publish(String("hi"))
    world.run_for(0.001)
    stats = world.topic_stats("/chatter")
    assert list(stats) == ["topic", "type", "published", "sent", "lost", "received", "dropped",
                           "delivered", "connections"]
    assert stats["published"] == stats["sent"] == stats["delivered"] == 1
    (conn,) = stats["connections"]
    assert list(conn) == ["id", "publisher", "subscriber", "sent", "lost", "received",
                          "dropped", "delivered"]
    assert all(type(stats[k]) is int for k in ("sent", "lost", "received", "dropped", "delivered"))


def test_link_latency_may_be_drawn_from_the_connection_stream() -> None:
    def draw(rng: random.Random) -> float:
        return rng.uniform(0.001, 0.002)

    link = LinkModel(draw, 0.0)
    assert link.latency is draw
    assert link_latency_ns(ddes.Duration(0, 5)) == 5
    assert link_latency_ns(0.5) == 500_000_000


def test_post_callbacks_get_the_posted_value() -> None:
    world = ddes.World(seed=1)
    seen: list[tuple[int, Any]] = []

    def cb(ev: Posted[tuple[str, int]]) -> None:
        seen.append((ev.at_ns, ev.payload))

    ev = post(world.env, 7, ("x", 1), cb)
    assert isinstance(ev, Posted) and ev.value == ev.payload == ("x", 1)
    world.run()
    assert seen == [(7, ("x", 1))]


def test_sleep_and_rates_take_a_node_or_a_clock() -> None:
    world = ddes.World(seed=1)
    node = world.create_node("n", disable_rosout=True)
    times: list[int] = []

    def main() -> Any:
        yield ddes.sleep(node, 0.5)
        times.append(world.now)
        yield ddes.sleep(node.clock, 0.5)
        times.append(world.now)
        yield ddes.Rate(node.clock, 10).sleep()
        times.append(world.now)
        yield ddes.WallRate(node, 10).sleep()
        times.append(world.now)
        yield ddes.WallRate(world, 10).sleep()
        times.append(world.now)

    node.process(main())
    world.run()
    assert times == [500_000_000, 1_000_000_000, 1_100_000_000, 1_200_000_000, 1_300_000_000]
