"""rosbag record on simulated time: what is recorded, when, under which name."""

from __future__ import annotations

import datetime
import os
from collections.abc import Generator
from pathlib import Path
from typing import Any

import pytest

from ddes import Duration, Time, World
from ddes.errors import DdesValueError, ROSBagException, ROSBagUnindexedException
from ddes.msg import get_message_class
from ddes.rosbag import Bag, Recorder, bag_filename
from ddes.rosbag.recorder import parse_duration

from .conftest import Int32, String

PointStamped = get_message_class("geometry_msgs/PointStamped")
Clock = get_message_class("rosgraph_msgs/Clock")


def talker(world: World, topic: str = "chatter", hz: float = 10.0, name: str = "talker",
           start: float = 0.0, latch: bool = False) -> Any:
    """A node advertising ``topic`` at ``start`` and publishing Int32 counts at ``hz``."""
    node = world.create_node(name)
    pubs = []

    def loop() -> Generator[Any, Any, None]:
        if start:
            yield node.sleep(start)
        pub = node.advertise(topic, Int32, queue_size=10, latch=latch)
        pubs.append(pub)
        rate = node.create_rate(hz)
        i = 0
        while True:
            pub.publish(Int32(data=i))
            i += 1
            yield rate.sleep()

    node.process(loop())
    return node


def data_times(bag: Bag, topic: str | None = None) -> list[tuple[int, float]]:
    return [(m.message.data, m.timestamp.to_sec()) for m in bag.read_messages(topic)]


def test_record_time_is_the_recorders_ros_time_at_receipt(world: World) -> None:
    world.set_link("/p", latency=0.05)
    node = world.create_node("sensor")
    pub = node.advertise("p", PointStamped, queue_size=10)
    rec = Recorder(world, ["/p"], in_memory=True)

    def send() -> Generator[Any, Any, None]:
        yield node.sleep(1.0)
        msg = PointStamped()
        msg.header.stamp = node.get_rostime()
        pub.publish(msg)

    node.process(send())
    world.run(2.0)
    (m,) = rec.bag.read_messages()
    assert m.message.header.stamp == Time(1)
    assert m.timestamp == Time(1, 50_000_000)  # receipt, not the header stamp
    assert rec.node.name == "/record_1"


def test_sim_time_records_clock_time_and_zero_before_the_first_clock(world: World) -> None:
    world.use_sim_time = True
    clock_node = world.create_node("clock", use_sim_time=False)
    clock_pub = clock_node.advertise("/clock", Clock, queue_size=1)
    node = talker(world, hz=10.0)
    rec = Recorder(world, ["/chatter"], in_memory=True)

    def clock() -> Generator[Any, Any, None]:
        yield clock_node.wall_sleep(0.25)
        for i in range(20):
            clock_pub.publish(Clock(clock=Time(1000 + i)))
            yield clock_node.wall_sleep(0.1)

    clock_node.process(clock())
    world.run(1.0)
    rec.stop()
    assert node.use_sim_time
    times = [m.timestamp.to_sec() for m in rec.bag.read_messages()]
    assert rec.start_time == 1000.0
    assert times[0] == 0.0 or times[0] >= 1000.0
    assert set(times) <= {0.0} | {float(1000 + i) for i in range(20)}
    assert times == sorted(times)


def test_limit_records_n_per_topic_then_stops(tmp_path: Path, world: World) -> None:
    talker(world, "a", hz=10.0, name="ta")
    talker(world, "b", hz=3.0, name="tb")
    out = str(tmp_path / "lim")
    rec = Recorder(world, ["/b", "/a", "/a"], limit=3, output_name=out)
    assert rec.topics == ["/a", "/b"]
    world.run(rec.done)
    assert rec.stop_reason == "limit" and not rec.is_recording
    assert rec.node.is_shutdown()
    assert [d for d, _ in data_times(rec.bag, "/a")] == [1, 2, 3]
    assert [d for d, _ in data_times(rec.bag, "/b")] == [1, 2, 3]
    assert world.now == pytest.approx(1e9, abs=1e6)  # /b's third message at ~1.0 s
    assert Bag(out + ".bag").get_message_count() == 6
    marks = [(e.kind, e.details) for e in world.trace if e.kind.startswith("rosbag.")]
    assert marks == [("rosbag.record", {"path": out + ".bag", "topics": ["/a", "/b"]}),
                     ("rosbag.stop", {"reason": "limit", "messages": 6})]
    assert not os.path.exists(out + ".bag.active")


def test_duration_stops_once_ros_time_is_past_start_plus_duration(world: World) -> None:
    talker(world, hz=10.0, start=0.05)
    rec = Recorder(world, ["/chatter"], duration="1", in_memory=True)
    world.run(5.0)
    assert rec.stop_reason == "duration"
    times = [t for _, t in data_times(rec.bag)]
    # advertised at 0.05 s: its first message goes out before the connection exists
    assert times[0] == pytest.approx(0.15) and times[-1] == pytest.approx(0.95)
    exact = World()
    talker(exact, hz=10.0)
    rec2 = Recorder(exact, ["/chatter"], duration=1.0, in_memory=True)
    exact.run(3.0)
    # a message exactly 1.0 s after the start is kept (rosbag compares with '>')
    assert [round(t, 3) for _, t in data_times(rec2.bag)][-1] == 1.0
    assert rec2.stop_reason == "duration"


def test_all_picks_up_topics_at_each_one_second_check(world: World) -> None:
    talker(world, "early", hz=10.0, name="e")
    talker(world, "late", hz=10.0, name="l", start=2.3)
    rec = Recorder(world, all=True, exclude="/rosout", in_memory=True)
    world.run(4.0)
    assert rec.recording == ["/early"] + ["/late"]
    late = data_times(rec.bag, "/late")
    # advertised at 2.3 s, subscribed at the 3 s check and connected 1 ms later: the
    # messages before that are not recorded
    assert late[0] == (8, pytest.approx(3.1))
    early = data_times(rec.bag, "/early")
    assert early[0] == (1, pytest.approx(0.1))  # subscribed at start; message 0 beat the link
    assert "/rosout" not in rec.recording


def test_regex_and_exclude(world: World) -> None:
    for topic in ("/sensor/a", "/sensor/b", "/other"):
        talker(world, topic, name="t" + topic.replace("/", "_"))
    rec = Recorder(world, ["/sensor/.*"], regex=True, exclude=".*/b", in_memory=True)
    world.run(1.5)
    assert rec.recording == ["/sensor/a"]
    implied = World()
    for topic in ("/x", "/y"):
        talker(implied, topic, name="t" + topic[1:])
    rec2 = Recorder(implied, exclude="/y|/rosout", in_memory=True)  # implies all
    implied.run(1.5)
    assert rec2.recording == ["/x"]


def test_node_option_records_what_a_node_subscribes_to(world: World) -> None:
    talker(world, "a", name="ta")
    talker(world, "b", name="tb")
    listener = world.create_node("listener")
    listener.subscribe("b", Int32, lambda m: None, queue_size=1)
    rec = Recorder(world, node="/listener", in_memory=True)
    world.run(1.5)
    assert rec.recording == ["/b"]


def test_latched_and_multiple_publishers_keep_their_headers(world: World) -> None:
    talker(world, "t", name="one", latch=True)
    talker(world, "t", name="two")
    rec = Recorder(world, ["/t"], in_memory=True)
    world.run(0.55)
    conns = rec.bag.get_connections()
    assert sorted((c.callerid, c.header["latching"]) for c in conns) == [("/one", "1"),
                                                                         ("/two", "0")]
    for c in conns:
        assert list(c.header) == sorted(c.header)
        assert c.header["topic"] == "/t" and c.header["type"] == "std_msgs/Int32"
    assert rec.bag.get_type_and_topic_info().topics["/t"].connections == 2


def test_latched_message_published_before_recording_is_recorded(world: World) -> None:
    node = world.create_node("map")
    pub = node.advertise("map_name", String, queue_size=1, latch=True)
    pub.publish(String(data="lab"))
    world.run(5.0)
    rec = Recorder(world, ["/map_name"], in_memory=True)
    world.run(6.0)
    (m,) = rec.bag.read_messages(return_connection_header=True)
    assert m.message.data == "lab" and m.connection_header["latching"] == "1"
    assert m.timestamp == Time(5, 1_000_000)


def test_file_names_follow_rosbag_rules() -> None:
    utc = datetime.timezone.utc
    assert bag_filename(None, "run", 0, utc) == "run.bag"
    assert bag_filename(None, "run.bag", 0, utc) == "run.bag"
    assert bag_filename("pre", None, 0, utc) == "pre_1970-01-01-00-00-00.bag"
    assert bag_filename("pre.bag", None, 86_400 * 10**9 + 5, utc) == "pre_1970-01-02-00-00-00.bag"
    assert bag_filename(None, None, 61 * 10**9, utc) == "1970-01-01-00-01-01.bag"
    two = datetime.timezone(datetime.timedelta(hours=2))
    assert bag_filename(None, None, 0, two) == "1970-01-01-02-00-00.bag"
    with pytest.raises(DdesValueError, match="Can't set both"):
        bag_filename("a", "b")
    with pytest.raises(ROSBagException, match="filename is empty"):
        bag_filename(None, "", 0)


def test_active_file_while_recording_then_renamed(tmp_path: Path, world: World) -> None:
    talker(world)
    prefix = str(tmp_path / "run")
    rec = Recorder(world, ["/chatter"], output_prefix=prefix, tz=datetime.timezone.utc,
                   compression="bz2", publish=True)
    assert rec.path == prefix + "_1970-01-01-00-00-00.bag"
    world.run(1.0)
    assert os.path.exists(rec.path + ".active") and not os.path.exists(rec.path)
    with pytest.raises(ROSBagUnindexedException):
        Bag(rec.path + ".active")
    begin = world.create_node("probe")
    got: list[str] = []
    begin.subscribe("/begin_write", String, lambda m: got.append(m.data), queue_size=1)
    world.run(1.1)
    rec.process.interrupt("stop")
    world.run(1.2)
    assert rec.stop_reason == "interrupted"
    assert got == [rec.path]
    saved = Bag(rec.path)
    assert saved.get_compression_info().compression == "bz2"
    assert saved.get_message_count() == rec.bag.get_message_count() == 10


def test_validation() -> None:
    world = World()
    with pytest.raises(DdesValueError, match="No topics specified"):
        Recorder(world, in_memory=True)
    with pytest.raises(DdesValueError, match="count is not valid"):
        Recorder(world, all=True, limit=2, in_memory=True)
    with pytest.raises(DdesValueError, match="regular expression"):
        Recorder(world, ["("], regex=True, in_memory=True)
    with pytest.raises(DdesValueError, match="limit"):
        Recorder(world, ["/a"], limit=-1, in_memory=True)
    with pytest.raises(ROSBagException, match="Error writing"):
        Recorder(world, ["/a"], output_name="/nonexistent/dir/x")


@pytest.mark.parametrize("text,ns", [("30", 30 * 10**9), ("1.5s", 1_500_000_000),
                                     ("2m", 120 * 10**9), ("1h", 3600 * 10**9),
                                     (0.25, 250_000_000)])
def test_parse_duration(text: Any, ns: int) -> None:
    assert parse_duration(text) == ns


@pytest.mark.parametrize("text,words", [("abc", "floating point"), ("5d", "unit must be"),
                                        ("0", "positive"), ("-1", "positive")])
def test_parse_duration_errors(text: str, words: str) -> None:
    with pytest.raises(DdesValueError, match=words):
        parse_duration(text)


def test_recording_is_deterministic() -> None:
    def run() -> tuple[bytes, str]:
        world = World(seed=3)
        world.set_link("/chatter", latency=lambda rng: rng.uniform(0.0, 0.02))
        talker(world, hz=20.0)
        rec = Recorder(world, ["/chatter"], in_memory=True, duration=2.0)
        world.run(3.0)
        return rec.bag.to_bytes(), world.digest()

    assert run() == run()


def test_stopping_before_the_start_is_clean(tmp_path: Path) -> None:
    world = World()
    rec = Recorder(world, all=True, output_name=str(tmp_path / "early"))
    rec.stop()
    world.run(3.0)
    assert rec.stop_reason == "stopped" and rec.start_time is None
    assert Bag(str(tmp_path / "early.bag")).get_message_count() == 0
    assert not rec.process.is_alive


def test_durations_are_taken_as_rosbag_cpp_takes_them() -> None:
    """ros::Duration(double) rounds to the nearest ns (ddes.time.units truncates, as genpy)."""
    assert parse_duration("1.2") == parse_duration(1.2) == parse_duration("0.02m") == 1_200_000_000
    assert parse_duration(Duration(1, 200_000_000)) == 1_200_000_000
    world = World()
    talker(world, hz=10.0)
    rec = Recorder(world, ["/chatter"], duration=1.2, in_memory=True)
    world.run(3.0)
    # the message exactly 1.2 s after the start is kept, as rosbag record keeps it
    assert [round(t, 3) for _, t in data_times(rec.bag)][-1] == 1.2
