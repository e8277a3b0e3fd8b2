"""Topics on the kernel: ordering, lost-before-connect, latching, queues, latency, loss."""

from __future__ import annotations

from collections.abc import Generator
from typing import Any

import pytest

import ddes
from ddes.errors import ROSException, ROSSerializationException, ROSTopicException
from ddes.graph.topics import AnyMsg
from ddes.msg import get_message_class

String = get_message_class("std_msgs/String")
Int32 = get_message_class("std_msgs/Int32")
Header = get_message_class("std_msgs/Header")
PoseStamped = get_message_class("geometry_msgs/PoseStamped")
MS = 1_000_000


def talker(world: ddes.World, hz: float = 10, n: int = 5, topic: str = "chatter",
           latch: bool = False) -> Any:
    node = world.create_node("talker")
    pub = node.advertise(topic, Int32, queue_size=10, latch=latch)

    def main() -> Generator[Any, Any, None]:
        rate = node.create_rate(hz)
        for i in range(n):
            pub.publish(Int32(i))
            yield rate.sleep()

    node.process(main())
    return pub


def test_messages_before_the_connection_are_lost(world: ddes.World) -> None:
    got: list[tuple[int, int]] = []
    talker(world)
    world.create_node("listener").subscribe("chatter", Int32, lambda m: got.append((world.now // MS, m.data)))
    world.run()
    assert got == [(100, 1), (200, 2), (300, 3), (400, 4)]  # 0 was sent before the 1 ms handshake
    drops = world.trace.filter(kind="topic.publish")
    assert [e.details["connections"] for e in drops if e.details["topic"] == "/chatter"] == [0, 1, 1, 1, 1]


def test_connect_delay_is_configurable(world: ddes.World) -> None:
    world.connect_delay = 250 * MS
    got: list[int] = []
    world.create_node("listener").subscribe("chatter", Int32, lambda m: got.append(m.data))
    talker(world)
    world.run()
    assert got == [3, 4]  # published at 0, 100 and 200 ms: before the connection


def test_zero_connect_delay_still_connects_after_this_instant(world: ddes.World) -> None:
    # Same-time order: the talker's process starts (urgent) before the
    # connection event scheduled at the same instant.
    world.connect_delay = 0
    got: list[int] = []
    world.create_node("listener").subscribe("chatter", Int32, lambda m: got.append(m.data))
    talker(world)
    world.run()
    assert got == [1, 2, 3, 4]


def test_latched_topic_reaches_late_subscribers(world: ddes.World) -> None:
    talker(world, n=3, latch=True)
    got: list[tuple[int, int]] = []

    def late() -> Generator[Any, Any, None]:
        yield world.timeout(1.0)
        world.create_node("late").subscribe("chatter", Int32, lambda m: got.append((world.now // MS, m.data)))

    world.process(late())
    world.run()
    assert got == [(1001, 2)]  # the last message, on connect


def test_slow_callback_fills_queue_and_drops_oldest(world: ddes.World) -> None:
    talker(world, hz=10, n=12)
    listener = world.create_node("listener")
    got: list[int] = []

    def slow(msg: Any) -> Generator[Any, Any, None]:
        got.append(msg.data)
        yield listener.sleep(0.35)

    listener.subscribe("chatter", Int32, slow, queue_size=2)
    world.run()
    drops = [e.details["seq"] for e in world.trace.filter(kind="topic.drop")]
    # seq = data: message 0 goes out before the connection exists, so rospy does not
    # count it.  1 runs 100-450 ms while 2, 3, 4 arrive: 2 is dropped;
    # 3 runs 450-800 while 5, 6, 7 arrive: 4 and 5 dropped; 6 runs 800-1150
    # while 8-11 arrive: 7, 8, 9 dropped; then 10 and 11.
    assert got == [1, 3, 6, 10, 11]
    assert drops == [2, 4, 5, 7, 8, 9]
    stats = world.topic_stats("/chatter")
    assert stats["dropped"] == 6 and stats["delivered"] == 5 and stats["received"] == 11
    assert stats["published"] == 12 and stats["sent"] == 11


def test_publisher_mutation_after_publish_changes_nothing(world: ddes.World) -> None:
    world.connect_delay = 0
    node = world.create_node("pub")
    pub = node.advertise("s", String, queue_size=1)
    got: list[str] = []
    world.create_node("sub").subscribe("s", String, lambda m: got.append(m.data))
    world.run(until=0.01)
    msg = String("first")
    pub.publish(msg)
    msg.data = "mutated"
    world.run()
    assert got == ["first"]


def test_header_seq_is_set_like_rospy(world: ddes.World) -> None:
    world.connect_delay = 0
    node = world.create_node("pub")
    pub = node.advertise("pose", PoseStamped, queue_size=1)
    seqs: list[int] = []
    world.create_node("sub").subscribe("pose", PoseStamped, lambda m: seqs.append(m.header.seq))
    world.run(until=0.01)
    m = PoseStamped()
    pub.publish(m)
    pub.publish(m)
    world.run()
    assert seqs == [1, 2] and m.header.seq == 2


def test_publish_forms_and_wrong_types(world: ddes.World) -> None:
    world.connect_delay = 0
    node = world.create_node("pub")
    pub = node.advertise("s", String, queue_size=1)
    got: list[str] = []
    world.create_node("sub").subscribe("s", String, lambda m: got.append(m.data))
    world.run(until=0.01)
    pub.publish("positional")
    pub.publish(data="keyword")
    with pytest.raises(TypeError, match=r"expected \[std_msgs/String\] but got \[std_msgs/Int32\]"):
        pub.publish(Int32(3))
    with pytest.raises(ROSSerializationException, match="data"):
        pub.publish(String(data=42))
    world.run()
    assert got == ["positional", "keyword"]


def test_type_mismatch_on_a_topic_is_an_error(world: ddes.World) -> None:
    a = world.create_node("a")
    a.advertise("x", String, queue_size=1)
    with pytest.raises(ROSTopicException, match="std_msgs/Int32.*std_msgs/String"):
        world.create_node("b").subscribe("x", Int32, lambda m: None)
    with pytest.raises(ROSTopicException):
        world.create_node("c").advertise("x", Int32, queue_size=1)
    world.create_node("d").subscribe("x", AnyMsg, lambda m: None)  # AnyMsg matches all


@pytest.mark.parametrize("qs, ok", [(None, True), (-1, True), (5, True), (0, False), (2.5, False),
                                    ("3", False)])
def test_subscriber_queue_size_rules(world: ddes.World, qs: Any, ok: bool) -> None:
    node = world.create_node("n")
    if ok:
        node.subscribe("t", String, lambda m: None, queue_size=qs)
    else:
        with pytest.raises(ROSException, match="queue size"):
            node.subscribe("t", String, lambda m: None, queue_size=qs)


def test_bad_data_class_and_callback(world: ddes.World) -> None:
    node = world.create_node("n")
    with pytest.raises(TypeError, match="data_class"):
        node.advertise("t", "std_msgs/String", queue_size=1)
    with pytest.raises(TypeError, match="callable"):
        node.subscribe("t", String, "not callable")


def test_latency_fifo_and_loss_are_seeded(world: ddes.World) -> None:
    def run(seed: int) -> tuple[list[tuple[int, int]], str]:
        w = ddes.World(seed=seed)
        w.set_link("/chatter", latency=lambda rng: rng.uniform(0.0, 0.25), loss=0.2)
        got: list[tuple[int, int]] = []
        w.create_node("listener").subscribe("chatter", Int32, lambda m: got.append((w.now, m.data)))
        talker(w, hz=20, n=40)
        w.run()
        return got, w.digest()

    got, digest = run(7)
    assert [d for _, d in got] == sorted(d for _, d in got)  # FIFO despite random latency
    assert [t for t, _ in got] == sorted(t for t, _ in got)
    assert 20 < len(got) < 40  # some lost
    assert run(7) == (got, digest)
    assert run(8)[1] != digest
    lost = [e for e in ddes.World(seed=7).trace.filter(kind="topic.drop")]
    assert lost == []


def test_set_link_per_subscriber(world: ddes.World) -> None:
    world.set_link("/chatter", subscriber="/far", latency=0.05)
    near: list[int] = []
    far: list[int] = []
    world.create_node("near").subscribe("chatter", Int32, lambda m: near.append(world.now // MS))
    world.create_node("far").subscribe("chatter", Int32, lambda m: far.append(world.now // MS))
    talker(world, n=3)
    world.run()
    assert near == [100, 200] and far == [150, 250]


def test_anymsg_receives_bytes_and_header(world: ddes.World) -> None:
    world.connect_delay = 0
    got: list[Any] = []
    world.create_node("rec").subscribe("chatter", AnyMsg, got.append)
    talker(world, n=2)
    world.run()
    assert got[0]._buff == b"\x01\x00\x00\x00"
    assert got[0]._connection_header["type"] == "std_msgs/Int32"
    assert got[0]._connection_header["callerid"] == "/talker"


def test_unregister_and_node_shutdown_close_connections(world: ddes.World) -> None:
    got: list[int] = []
    sub = world.create_node("listener").subscribe("chatter", Int32, lambda m: got.append(m.data))
    pub = talker(world, n=10)
    world.run(until=0.25)
    sub.unregister()
    world.run()
    assert got == [1, 2] and pub.get_num_connections() == 0
    pub.node.shutdown()
    # rospy's _PublisherImpl.publish: a topic the shutdown closed drops the message quietly
    pub.publish(Int32(1))
    assert pub.get_num_connections() == 0
    other = world.create_node("other").advertise("other", Int32, queue_size=1)
    other.unregister()
    with pytest.raises(ROSException, match="unregistered"):  # the user's unregister: an error
        other.publish(Int32(1))


def test_wait_for_message(world: ddes.World) -> None:
    talker(world, n=5)
    node = world.create_node("waiter")
    out: list[Any] = []

    def main() -> Generator[Any, Any, None]:
        msg = yield node.wait_for_message("chatter", Int32)
        out.append((world.now // MS, msg.data))
        try:
            yield node.wait_for_message("silent", Int32, timeout=0.5)
        except ROSException as exc:
            out.append((world.now // MS, str(exc)))

    node.process(main())
    world.run()
    assert out == [(100, 1), (600, "timeout exceeded while waiting for message on topic silent")]


@pytest.mark.parametrize("kind", ["typed", "args", "any", "busy"])
def test_a_lone_connection_arrives_as_a_batch_of_one_would(kind: str) -> None:
    """Publisher._fanout hands a group of one connection to Subscriber._arrive_one, a larger
    group to _arrive_batch, and a connection with a drawn latency sends on its own
    (Connection.send, then _arrive_one): the listener's deliveries, drops and trace rows are
    the same on every path."""
    def run(twin: bool, drawn: bool = False) -> tuple[list[Any], list[Any], Any,
                                                      list[tuple[int, ...]]]:
        world = ddes.World(5)
        world.connect_delay = 0
        got: list[Any] = []
        node = world.create_node("listener")

        def busy(m: Any) -> Generator[Any, Any, None]:
            got.append((world.now, m.data))
            yield node.sleep(0.25)  # the spinner is taken: later messages queue, some drop

        if kind == "typed":
            node.subscribe("chatter", Int32, lambda m: got.append((world.now, m.data)))
        elif kind == "args":
            node.subscribe("chatter", Int32, lambda m, a: got.append((world.now, m.data, a)),
                           callback_args="x")
        elif kind == "any":
            node.subscribe("chatter", AnyMsg, lambda m: got.append((world.now, m._buff)))
        else:
            node.subscribe("chatter", Int32, busy, queue_size=2)
        if twin:
            world.create_node("twin").subscribe("chatter", Int32, lambda m: None)
        if drawn:  # a latency drawn per message (always 0): the connection is not batchable
            world.set_link("/chatter", subscriber="/listener", latency=lambda rng: 0.0)
        pub = talker(world, hz=10, n=8)
        world.run()
        rows = [ev for ev in world.trace if ev.source == "/listener"]
        stats = [(c.sent, c.received, c.delivered, c.dropped, c.lost) for c in pub.connections
                 if c.sub.node.name == "/listener"]
        return got, rows, pub._fanout[0][2] if pub._fanout else pub._single, stats

    alone, rows_alone, path_alone, stats_alone = run(False)
    batched, rows_batched, path_batched, stats_batched = run(True)
    single, rows_single, path_single, stats_single = run(False, drawn=True)
    assert stats_alone == stats_batched == stats_single
    assert getattr(path_alone, "__func__", None) is ddes.graph.topics.Subscriber._arrive_one
    assert path_batched is ddes.graph.topics._arrive_batch
    assert len(path_single) == 1 and not path_single[0].batchable
    assert alone == batched == single and len(alone) >= 3
    assert rows_alone == rows_batched == rows_single
    if kind == "busy":
        assert any(ev.kind == "topic.drop" for ev in rows_alone)


def test_the_per_message_handles_are_slotted_with_every_attribute_they_use() -> None:
    """Publisher, Subscriber and Timer keep their state in slots (compact objects: a world of a
    thousand nodes touches one per message); a handle that used an attribute outside its
    __slots__ would raise AttributeError here, on a run that exercises publish, deliver,
    latching, a queue and a timer."""
    world = ddes.World()
    a, b = world.create_node("a"), world.create_node("b")
    pub = a.advertise("x", String, queue_size=1, latch=True)
    got: list[str] = []
    sub = b.subscribe("x", String, lambda m, arg: got.append(m.data + arg), callback_args="!",
                      queue_size=1)
    timer = a.create_timer(0.1, lambda _e: pub.publish(String("tick")))
    world.run(until=0.35)
    for handle in (pub, sub, timer):
        assert not hasattr(handle, "__dict__"), type(handle).__name__
        with pytest.raises(AttributeError):
            handle.not_an_attribute = 1  # type: ignore[union-attr]
    assert got == ["tick!"] * 3
    assert (pub.published, timer.fires, sub.get_num_connections()) == (3, 3, 1)
    timer.shutdown()
    sub.unregister()
    pub.unregister()
