"""MCAP in the ros1 profile: what Foxglove's libraries read of ddes files, and ddes reading
files other tools wrote."""

from __future__ import annotations

import io
import warnings
from pathlib import Path

from mcap.reader import make_reader
from mcap_ros1.decoder import DecoderFactory

from ddes import Time
from ddes.msg import get_message_class
from ddes.rosbag import Bag

from .conftest import Int32, String, contents

Pose = get_message_class("geometry_msgs/PoseStamped")


def _bag() -> Bag:
    bag = Bag()
    latched = {"topic": "/map_name", "type": String._type, "md5sum": String._md5sum,
               "message_definition": String._full_text, "callerid": "/map_server",
               "latching": "1"}
    bag.write("/map_name", String(data="lab"), Time(10), connection_header=latched)
    for i in range(5):
        pose = Pose()
        pose.header.frame_id = "map"
        pose.header.stamp = Time(10 + i)
        pose.pose.position.x = i * 0.5
        bag.write("/pose", pose, Time(10 + i, 1))
        bag.write("/count", Int32(data=i), Time(10 + i, 1))
    return bag


def test_ddes_mcap_is_ros1_profile_and_decodes_with_mcap_ros1() -> None:
    bag = _bag()
    reader = make_reader(io.BytesIO(bag.to_bytes("mcap")), decoder_factories=[DecoderFactory()])
    header = reader.get_header()
    assert header.profile == "ros1" and header.library.startswith("ddes/")
    summary = reader.get_summary()
    assert summary is not None
    channels = {c.topic: c for c in summary.channels.values()}
    assert {c.message_encoding for c in channels.values()} == {"ros1"}
    assert {s.encoding for s in summary.schemas.values()} == {"ros1msg"}
    assert channels["/map_name"].metadata["latching"] == "true"
    assert channels["/map_name"].metadata["callerid"] == "/map_server"
    assert summary.statistics is not None
    assert summary.statistics.message_count == bag.get_message_count()
    got = [(ch.topic, msg.log_time, decoded) for _s, ch, msg, decoded
           in reader.iter_decoded_messages(log_time_order=True)]
    want = list(bag.read_messages())
    assert [(t, n) for t, n, _ in got] == [(m.topic, m.timestamp.to_nsec()) for m in want]
    for (_topic, _t, decoded), m in zip(got, want):
        if m.topic == "/pose":
            assert decoded.pose.position.x == m.message.pose.position.x
            assert decoded.header.frame_id == "map"
        else:
            assert decoded.data == m.message.data


def test_ddes_reads_mcap_written_by_mcap_ros1(tmp_path: Path) -> None:
    from mcap_ros1.writer import Writer

    path = tmp_path / "foreign.mcap"
    with open(path, "wb") as f:
        writer = Writer(f)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            writer.write_message("/chatter", String(data="a"), log_time=5)
            writer.write_message("/chatter", String(data="b"), log_time=7)
            writer.write_message("/n", Int32(data=1), log_time=6)
        writer.finish()
    bag = Bag(str(path))
    assert [(m.topic, m.message, m.timestamp.to_nsec()) for m in bag.read_messages()] == \
        [("/chatter", String(data="a"), 5), ("/n", Int32(data=1), 6),
         ("/chatter", String(data="b"), 7)]
    conn = bag.get_connections("/chatter")[0]
    assert conn.header == {"topic": "/chatter", "type": "std_msgs/String",
                           "md5sum": String._md5sum, "message_definition": String._full_text}
    assert bag.filename == str(path)
    bag.info()  # summarised as the .bag it would become


def test_mcap_file_round_trip_and_conversion_to_bag(tmp_path: Path) -> None:
    bag = _bag()
    mcap_path = str(tmp_path / "x.mcap")
    bag_path = str(tmp_path / "x.bag")
    bag.save(mcap_path)
    Bag(mcap_path).save(bag_path)
    assert contents(Bag(bag_path)) == contents(bag)  # MCAP keeps time order, not write order
    assert Bag(mcap_path, "r").get_message_count() == 11
    with Bag(mcap_path, "a") as more:
        more.write("/count", Int32(data=99), Time(99))
    assert Bag(mcap_path).get_end_time() == 99.0
