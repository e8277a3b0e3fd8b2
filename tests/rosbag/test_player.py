"""rosbag play on simulated time: timing, the clock, loops, pausing, and faithful replay."""

from __future__ import annotations

from collections.abc import Generator
from typing import Any

import pytest

from ddes import ROSTimeMovedBackwardsException, Time, World
from ddes.errors import DdesValueError, ROSBagException
from ddes.msg import get_message_class
from ddes.rosbag import Bag, Player, Recorder

from .conftest import Int32, String

Clock = get_message_class("rosgraph_msgs/Clock")
Header = get_message_class("std_msgs/Header")


def bag_at(*times: float, topic: str = "/n", start: int = 0) -> Bag:
    bag = Bag()
    for i, t in enumerate(times):
        bag.write(topic, Int32(data=start + i), Time.from_sec(t))
    return bag


def listen(world: World, topic: str = "/n", cls: Any = Int32, sim: bool = False) -> list[Any]:
    """(kernel s, ROS s, data) of every message the listener gets."""
    node = world.create_node(f"listener{world.next_id('test')}", use_sim_time=sim)
    got: list[Any] = []
    node.subscribe(topic, cls, lambda m: got.append(
        (round(world.now / 1e9, 9), node.get_rostime().to_sec(), getattr(m, "data", m))),
        queue_size=1000)
    return got


def test_bag_time_maps_onto_kernel_time_scaled_by_rate(world: World) -> None:
    got = listen(world)
    player = Player(world, bag_at(100.0, 100.5, 102.0), rate=2.0)
    world.run(player.done)
    assert [(k, d) for k, _, d in got] == [(0.2, 0), (0.45, 1), (1.2, 2)]
    assert player.published == 3 and player.node.is_shutdown()
    assert player.node.name == "/play_1"
    marks = [(e.kind, e.t) for e in world.trace if e.kind.startswith("rosbag.")]
    assert marks == [("rosbag.play", 200_000_000), ("rosbag.loop", 1_200_000_000),
                     ("rosbag.done", 1_200_000_000)]


def test_clock_ticks_at_hz_and_equals_the_message_time_on_delivery(world: World) -> None:
    clock: list[tuple[float, float]] = []
    probe = world.create_node("probe")
    probe.subscribe("/clock", Clock, lambda m: clock.append((round(world.now / 1e9, 9),
                                                            m.clock.to_sec())), queue_size=100)
    sim = listen(world, sim=True)
    player = Player(world, bag_at(50.0, 50.35, 51.0), clock=True, hz=10)
    world.run(player.done)
    assert [(ros, d) for _, ros, d in sim] == [(50.0, 0), (50.35, 1), (51.0, 2)]
    values = [v for _, v in clock]
    assert values == sorted(values)
    assert clock[0] == (0.2, 50.0)
    ticks = [k for k, _ in clock]
    assert all(round(b - a, 9) <= 0.1 for a, b in zip(ticks, ticks[1:]))
    assert (0.3, 50.1) in clock and (0.55, 50.35) in clock
    assert all(v == pytest.approx(50.0 + (k - 0.2)) for k, v in clock)


def test_start_duration_and_topics_select_the_view(world: World) -> None:
    bag = bag_at(10, 11, 12, 13, 14)
    for i in range(5):
        bag.write("/other", String(data=str(i)), Time(10 + i))
    got = listen(world)
    other = listen(world, "/other", String)
    player = Player(world, bag, start=1.0, duration=2.0, topics=["/n"])
    world.run(player.done)
    assert [d for _, _, d in got] == [1, 2, 3]  # bag times 11..13, both ends inclusive
    assert other == []
    with pytest.raises(ROSBagException, match="No messages to play"):
        Player(World(), bag, topics=["/missing"])


def test_immediate_and_skip_empty(world: World) -> None:
    got = listen(world)
    player = Player(world, bag_at(0.0, 0.1, 10.1, 10.2, 30.0), immediate=True)
    world.run(player.done)
    assert {k for k, _, _ in got} == {0.2}
    skipped = World()
    got2 = listen(skipped)
    player2 = Player(skipped, bag_at(0.0, 0.1, 10.1, 10.2, 30.0), skip_empty=1.0)
    skipped.run(player2.done)
    assert [k for k, _, _ in got2] == [0.2, 0.3, 0.3, 0.4, 0.4]


def test_pause_step_resume(world: World) -> None:
    got = listen(world)
    player = Player(world, bag_at(1.0, 2.0, 3.0, 4.0), pause=True, clock=True, hz=4)
    world.run(5.0)
    assert got == [] and player.is_paused
    assert player.bag_time == Time(1)
    assert player.step()
    world.run(5.5)
    assert [(k, d) for k, _, d in got] == [(5.0, 0)]
    player.step()
    world.run(6.0)
    assert [(k, d) for k, _, d in got] == [(5.0, 0), (5.5, 1)]
    player.resume()
    assert not player.step()
    world.run(player.done)
    assert [(k, d) for k, _, d in got] == [(5.0, 0), (5.5, 1), (7.0, 2), (8.0, 3)]
    player.toggle_pause()  # after the end: harmless


def test_pause_mid_play_freezes_the_bag_clock(world: World) -> None:
    got = listen(world)
    player = Player(world, bag_at(0.0, 1.0, 2.0), delay=0.0)
    world.run(0.5)
    player.pause()
    world.run(3.0)
    assert player.bag_time == Time.from_sec(0.5)
    player.toggle_pause()
    world.run(player.done)
    # with no delay the first message goes out before the listener is connected (ROS's
    # reason for --delay 0.2): it is lost
    assert [(k, d) for k, _, d in got] == [(3.5, 1), (4.5, 2)]


def test_loop_with_clock_jumps_back_and_sim_time_nodes_see_it_as_ros_defines(
        world: World) -> None:
    world.use_sim_time = True
    bag = bag_at(*[100 + 0.1 * i for i in range(20)])  # 100.0 .. 101.9
    node = world.create_node("controller")
    events: list[Any] = []

    def strict() -> Generator[Any, Any, None]:
        rate = node.create_rate(5)
        try:
            while True:
                yield rate.sleep()
                events.append(("strict", node.get_time()))
        except ROSTimeMovedBackwardsException as exc:
            events.append(("raised", round(exc.time, 6)))

    def forgiving() -> Generator[Any, Any, None]:
        rate = node.create_rate(5, reset=True)
        while True:
            yield rate.sleep()
            events.append(("reset", node.get_time()))

    timer_fires: list[float] = []
    node.create_timer(0.5, lambda ev: timer_fires.append(node.get_time()))
    node.process(strict())
    node.process(forgiving())
    player = Player(world, bag, clock=True, loop=True)
    world.run(6.5)
    assert player.loops == 3
    raised = [e for e in events if e[0] == "raised"]
    assert len(raised) == 1 and raised[0][1] > 1.0  # the first jump back kills a plain Rate
    strict_times = [t for kind, t in events if kind == "strict"]
    assert strict_times and max(strict_times) < 102.0
    reset_times = [t for kind, t in events if kind == "reset"]
    assert sum(1 for a, b in zip(reset_times, reset_times[1:]) if b < a) >= 2  # survived loops
    assert reset_times[-1] > 100.0
    backs = sum(1 for a, b in zip(timer_fires, timer_fires[1:]) if b < a)
    assert backs >= 2 and len(timer_fires) > 8  # the timer keeps firing in every pass
    player.stop()
    assert player.done.triggered


def test_replay_with_clock_reproduces_the_recording_exactly() -> None:
    original = World(seed=7)
    original.set_link("/odom", latency=lambda rng: rng.uniform(0.0, 0.01))
    robot = original.create_node("robot")
    odom = robot.advertise("odom", Header, queue_size=100)
    status = robot.advertise("status", String, queue_size=1, latch=True)

    def drive() -> Generator[Any, Any, None]:
        status.publish(String(data="ready"))
        rate = robot.create_rate(30)
        for i in range(90):
            odom.publish(Header(seq=0, stamp=robot.get_rostime(), frame_id=f"f{i}"))
            if i % 40 == 0:
                status.publish(String(data=f"leg {i}"))
            yield rate.sleep()

    robot.process(drive())
    rec = Recorder(original, ["/odom", "/status"], in_memory=True)
    original.run(4.0)
    rec.stop()
    recorded = rec.bag

    replay = World(seed=1)
    replay.use_sim_time = True
    again = Recorder(replay, ["/odom", "/status"], in_memory=True)
    seen = listen(replay, "/odom", Header, sim=True)
    player = Player(replay, recorded, clock=True)
    replay.run(player.done)
    again.stop()

    def seq(bag: Bag) -> list[tuple[str, int, bytes]]:
        return [(m.topic, m.timestamp.to_nsec(), m.message[1]) for m in bag.read_messages(raw=True)]

    assert seq(again.bag) == seq(recorded)
    assert len(seq(recorded)) == 92
    odom_times = [m.timestamp.to_sec() for m in recorded.read_messages("/odom")]
    assert [ros for _, ros, _ in seen] == odom_times
    latched = [c for c in again.bag.get_connections() if c.topic == "/status"]
    assert [c.latching for c in latched] == [True]


def test_publishers_keep_types_latching_and_bytes(world: World) -> None:
    bag = Bag()
    header = {"topic": "/h", "type": Header._type, "md5sum": Header._md5sum,
              "message_definition": Header._full_text, "callerid": "/src", "latching": "1"}
    bag.write("/h", Header(seq=42, frame_id="x"), Time(1), connection_header=header)
    player = Player(world, bag, keep_alive=True, prefix="/replay")
    world.run(1.0)
    entry = world.master.topics["/replay/h"]
    (pub,) = entry.publishers
    assert (entry.type, entry.md5sum, pub.latch) == (Header._type, Header._md5sum, True)
    assert pub.data_class._full_text == Header._full_text
    late = world.create_node("late")
    got: list[Any] = []
    late.subscribe("/replay/h", Header, got.append, queue_size=1)
    world.run(2.0)
    assert [m.seq for m in got] == [42]  # recorded bytes, seq not rewritten; latched
    assert not player.done.triggered
    player.stop()
    assert player.done.triggered and world.master.topics["/replay/h"].publishers == []


def test_latched_messages_before_start_are_republished(world: World) -> None:
    bag = Bag()
    header = {"topic": "/map", "type": String._type, "md5sum": String._md5sum,
              "message_definition": String._full_text, "callerid": "/map_server",
              "latching": "1"}
    bag.write("/map", String(data="old"), Time(0), connection_header=header)
    bag.write("/map", String(data="new"), Time(1), connection_header=header)
    for i in range(5):
        bag.write("/n", Int32(data=i), Time(i))
    maps = listen(world, "/map", String)
    nums = listen(world)
    player = Player(world, bag, start=2.0)
    world.run(player.done)
    # /map is advertised only now, so the latched message reaches the listener when it
    # connects, 1 ms later
    assert [(k, d) for k, _, d in maps] == [(0.201, "new")]
    assert [(k, d) for k, _, d in nums] == [(0.2, 2), (1.2, 3), (2.2, 4)]


def test_wait_for_subscribers(world: World) -> None:
    player = Player(world, bag_at(0.0, 0.5), wait_for_subscribers=True)
    world.run(3.0)
    assert player.published == 0
    got = listen(world)
    world.run(player.done)
    assert [d for _, _, d in got] == [0, 1]
    assert got[0][0] == pytest.approx(3.1)  # the next 0.1 s poll after connecting


def test_multiple_bags_merge_by_time(world: World) -> None:
    got = listen(world)
    player = Player(world, [bag_at(1.0, 3.0), bag_at(2.0, 4.0, start=10)])
    world.run(player.done)
    assert [d for _, _, d in got] == [0, 10, 1, 11]


def test_loops_that_take_no_time_are_refused() -> None:
    with pytest.raises(ROSBagException, match="--immediate"):
        Player(World(), bag_at(1.0, 2.0), loop=True, immediate=True)
    with pytest.raises(ROSBagException, match="spanning no time"):
        Player(World(), bag_at(1.0, 1.0), loop=True)
    world = World()
    player = Player(world, bag_at(0.0, 10.0, 20.0), loop=True, skip_empty=1.0)
    player.done.callbacks.append(lambda ev: setattr(ev, "defused", True))
    world.run(5.0)
    assert player.done.triggered and not player.done.ok
    assert "took no simulated time" in str(player.done.value)


def test_option_validation() -> None:
    world = World()
    bag = bag_at(1.0)
    cases: list[tuple[dict[str, Any], str]] = [
        ({"rate": 0}, "rate"), ({"hz": -1}, "hz"), ({"delay": -1}, "delay"),
        ({"duration": 0}, "Invalid duration"), ({"skip_empty": 0}, "skip_empty")]
    for kwargs, words in cases:
        with pytest.raises(DdesValueError, match=words):
            Player(world, bag, **kwargs)
    with pytest.raises(DdesValueError, match="at least one bag"):
        Player(world, [])
    with pytest.raises(ROSBagException, match="No messages"):
        Player(world, Bag())


def test_set_rate_and_interrupt(world: World) -> None:
    got = listen(world)
    player = Player(world, bag_at(0.0, 1.0, 2.0, 3.0), delay=0.01)
    world.run(1.51)
    player.set_rate(2.0)
    world.run(2.6)
    assert [(k, d) for k, _, d in got] == [(0.01, 0), (1.01, 1), (1.76, 2), (2.26, 3)]
    other = World()
    p2 = Player(other, bag_at(0.0, 5.0))
    other.run(1.0)
    p2.process.interrupt("kill")
    other.run(2.0)
    assert p2.done.triggered and p2.node.is_shutdown() and p2.published == 1


def test_seconds_and_hz_are_taken_as_rosbag_cpp_takes_them() -> None:
    """Seconds round to the nearest ns (ros::Duration(double)); the /clock tick is
    WallDuration(1.0 / hz), rounded half away from zero."""
    world = World()
    player = Player(world, bag_at(0.0, 2.0, 3.0, 5.0), delay=1.2, start=1.2, duration=1.2,
                    skip_empty=1.2, hz=1024.0)
    assert player._delay_ns == player._skip_ns == 1_200_000_000
    assert player._initial - player._full_begin == 1_200_000_000
    assert player._finish is not None and player._finish - player._initial == 1_200_000_000
    assert player._tick_ns == 976_563  # 976562.5 ns, rounded up as roscpp does
