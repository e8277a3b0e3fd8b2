"""Bag's Python API: rosbag's semantics for writing, reading, counting and times."""

from __future__ import annotations

import io
import os
from typing import Any

import pytest

from ddes import Time, World
from ddes.errors import DdesTypeError, DdesValueError, ROSBagException
from ddes.graph.topics import AnyMsg
from ddes.msg import message_class_from_definition
from ddes.rosbag import Bag, BagMessage, TopicTuple

from .conftest import Int32, String, contents, sample_bag


def test_messages_come_in_time_order_ties_in_connection_order() -> None:
    bag = sample_bag()
    got = [(m.topic, m.message.data, m.timestamp) for m in bag.read_messages()]
    assert got == [("/chatter", "ho", Time(0, 5)), ("/chatter", "hi", Time(1, 5)),
                   ("/n", 3, Time(1, 5))]
    first = next(iter(bag))
    assert isinstance(first, BagMessage) and first.topic == "/chatter"


def test_equal_stamps_on_one_connection_keep_write_order() -> None:
    bag = Bag()
    for i in range(5):
        bag.write("/a", Int32(data=i), Time(2))
    bag.write("/a", Int32(data=-1), Time(1))
    assert [m.message.data for m in bag.read_messages()] == [-1, 0, 1, 2, 3, 4]


def test_bounds_are_inclusive_and_zero_time_is_no_bound() -> None:
    bag = Bag()
    for s in range(5):
        bag.write("/a", Int32(data=s), Time(s))
    def data(**kw: Any) -> list[int]:
        return [m.message.data for m in bag.read_messages(**kw)]
    assert data(start_time=Time(1), end_time=Time(3)) == [1, 2, 3]
    assert data(start_time=Time(0), end_time=Time(0)) == [0, 1, 2, 3, 4]
    assert data(end_time=Time(2)) == [0, 1, 2]
    assert data(start_time=Time(3, 1)) == [4]
    with pytest.raises(DdesTypeError):
        data(start_time=1.0)


def test_topic_selection_by_string_list_canonical_name_and_filter() -> None:
    bag = sample_bag()
    assert [m.topic for m in bag.read_messages("/n")] == ["/n"]
    assert [m.topic for m in bag.read_messages(["/n", "/chatter"])] == ["/chatter", "/chatter", "/n"]
    assert [m.topic for m in bag.read_messages("//n/")] == ["/n"]
    assert [m.topic for m in bag.read_messages([])] == ["/chatter", "/chatter", "/n"]
    only_int = bag.read_messages(connection_filter=lambda topic, datatype, md5, d, h:
                                 datatype == "std_msgs/Int32")
    assert [m.topic for m in only_int] == ["/n"]


def test_raw_and_connection_header() -> None:
    bag = sample_bag()
    topic, raw, t, header = next(bag.read_messages(raw=True, return_connection_header=True))
    datatype, data, md5, pos, pytype = raw
    assert (datatype, data, md5, pos) == ("std_msgs/String", b"\x02\x00\x00\x00ho",
                                          String._md5sum, None)
    assert pytype is String
    assert header == {"topic": "/chatter", "type": "std_msgs/String", "md5sum": String._md5sum,
                      "message_definition": String._full_text}
    copy = Bag()
    copy.write(topic, raw, t, raw=True)
    copy.write("/other", raw[:2] + raw[2:3] + raw[4:], t, raw=True)  # the 4-tuple form
    assert [m.message.data for m in copy.read_messages()] == ["ho", "ho"]
    with pytest.raises(DdesValueError, match="length 4 or 5"):
        copy.write("/x", ("a", b""), t, raw=True)


def test_one_connection_per_topic_and_given_header_kept() -> None:
    bag = Bag()
    header = {"topic": "/t", "type": String._type, "md5sum": String._md5sum,
              "message_definition": String._full_text, "callerid": "/me", "latching": "1"}
    bag.write("/t", String(data="a"), Time(1), connection_header=header)
    bag.write("/t", String(data="b"), Time(2), connection_header={**header, "callerid": "/you"})
    conns = bag.get_connections()
    assert len(conns) == 1 and conns[0].header == header and conns[0].latching
    assert conns[0].callerid == "/me"


def test_write_raw_gives_one_connection_per_distinct_header() -> None:
    bag = Bag()
    base = {"topic": "/t", "type": String._type, "md5sum": String._md5sum,
            "message_definition": String._full_text, "latching": "0"}
    data = String(data="x")._serialize_to_bytes()
    bag._write_raw("/t", {**base, "callerid": "/a"}, data, 1)
    bag._write_raw("/t", {**base, "callerid": "/b"}, data, 2)
    bag._write_raw("/t", {**base, "callerid": "/a"}, data, 3)
    info = bag.get_type_and_topic_info()
    assert info.topics["/t"][:3] == ("std_msgs/String", 3, 2)
    assert info.topics["/t"].frequency == pytest.approx(1e9)
    assert list(bag.get_connections()[0].header) == sorted(base | {"callerid": ""})


def test_counts_times_and_type_topic_info() -> None:
    bag = sample_bag()
    assert bag.get_message_count() == 3
    assert bag.get_message_count("/chatter") == 2
    assert bag.get_message_count(["/n", "/missing"]) == 1
    assert bag.get_start_time() == 5e-09
    assert bag.get_end_time() == 1.000000005
    info = bag.get_type_and_topic_info()
    assert info.msg_types == {"std_msgs/Int32": Int32._md5sum, "std_msgs/String": String._md5sum}
    assert list(info.msg_types) == sorted(info.msg_types)
    assert info.topics == {"/chatter": TopicTuple("std_msgs/String", 2, 1, 1.0),
                           "/n": TopicTuple("std_msgs/Int32", 1, 1, None)}
    assert list(bag.get_type_and_topic_info("/n").topics) == ["/n"]


def test_frequency_is_one_over_median_period_and_absent_with_skip_index() -> None:
    bag = Bag()
    for t in (0.0, 0.1, 0.2, 0.3, 1.3):
        bag.write("/a", Int32(data=0), Time.from_sec(t))
    bag.write("/b", Int32(data=0), Time(1))
    bag.write("/b", Int32(data=0), Time(1))
    topics = bag.get_type_and_topic_info().topics
    assert topics["/a"].frequency == pytest.approx(10.0)
    assert topics["/b"].frequency is None  # median period 0
    data = bag.to_bytes()
    assert Bag(io.BytesIO(data), skip_index=True).get_type_and_topic_info().topics["/a"] \
        .frequency is None


def test_empty_bag() -> None:
    bag = Bag()
    for fn in (bag.get_start_time, bag.get_end_time):
        with pytest.raises(ROSBagException, match="Bag contains no message"):
            fn()
    assert bag.get_message_count() == 0
    assert list(bag.read_messages()) == []
    assert bag.get_type_and_topic_info().topics == {}
    back = Bag.from_bytes(bag.to_bytes())
    assert back.get_message_count() == 0


def test_write_needs_a_time_or_a_clock() -> None:
    bag = Bag()
    with pytest.raises(DdesValueError, match="no wall clock"):
        bag.write("/a", Int32(data=1))
    with pytest.raises(DdesTypeError, match="must be a Time"):
        bag.write("/a", Int32(data=1), 1.5)
    with pytest.raises(DdesValueError, match="time range"):
        bag.write("/a", Int32(data=1), Time(2**32))
    world = World()
    node = world.create_node("n")
    world.run(2.5)
    for clock in (node, world, node.clock, lambda: Time(7)):
        bound = Bag(clock=clock)
        bound.write("/a", Int32(data=1))
        expected = 7.0 if callable(clock) and not hasattr(clock, "time") \
            and not hasattr(clock, "get_rostime") else 2.5
        assert bound.get_start_time() == expected


def test_write_rejects_bad_arguments_and_closed_or_read_only_bags(tmp_path: object) -> None:
    bag = Bag()
    with pytest.raises(DdesValueError, match="topic is invalid"):
        bag.write("", Int32(data=1), Time(1))
    with pytest.raises(DdesValueError, match="msg is invalid"):
        bag.write("/a", None, Time(1))
    with pytest.raises(DdesTypeError, match="must be a ROS message"):
        bag.write("/a", {"data": 1}, Time(1))
    bag.close()
    bag.close()
    for call in (lambda: bag.write("/a", Int32(data=1), Time(1)), lambda: bag.read_messages(),
                 bag.get_message_count, bag.flush, lambda: str(bag)):
        with pytest.raises(ValueError, match="closed bag"):
            call()
    path = os.path.join(str(tmp_path), "r.bag")
    sample_bag().save(path)
    with Bag(path) as reader, pytest.raises(DdesValueError, match="open it with mode 'a'"):
        reader.write("/a", Int32(data=1), Time(1))


def test_anymsg_is_written_raw_with_its_header() -> None:
    header = {"callerid": "/talker", "latching": "1", "md5sum": String._md5sum,
              "message_definition": String._full_text, "topic": "/t", "type": String._type}
    bag = Bag()
    bag.write("/t", AnyMsg(String(data="z")._serialize_to_bytes(), header), Time(3))
    (m,) = bag.read_messages(return_connection_header=True)
    assert m.message.data == "z" and m.connection_header == header


def test_unknown_types_are_rebuilt_from_the_definition() -> None:
    Bar = message_class_from_definition("foo_msgs/Bar", "int32 x\nstring name")
    bag = Bag()
    bag.write("/bar", Bar(x=4, name="q"), Time(1))
    back = Bag.from_bytes(bag.to_bytes())
    (m,) = back.read_messages()
    assert (m.message._type, m.message.x, m.message.name) == ("foo_msgs/Bar", 4, "q")
    assert m.message._md5sum == Bar._md5sum


def test_known_types_come_back_as_the_registry_classes() -> None:
    back = Bag.from_bytes(sample_bag().to_bytes())
    assert [type(m.message) for m in back.read_messages()] == [String, String, Int32]


def test_file_modes_write_via_active_then_rename(tmp_path: object) -> None:
    path = os.path.join(str(tmp_path), "x.bag")
    bag = Bag(path, "w")
    assert os.path.exists(path + ".active") and not os.path.exists(path)
    bag.write("/a", Int32(data=1), Time(1))
    bag.close()
    assert os.path.exists(path) and not os.path.exists(path + ".active")
    with Bag(path, "a") as more:
        assert more.get_message_count() == 1
        more.write("/a", Int32(data=2), Time(2))
        more.write("/b", String(data="s"), Time(0))
    with Bag(path) as final:
        assert [m.message.data for m in final.read_messages()] == ["s", 1, 2]
        assert final.filename == path and final.mode == "r" and final.version == 200
    new = os.path.join(str(tmp_path), "new.bag")
    with Bag(new, "a") as created:
        created.write("/a", Int32(data=5), Time(5))
    assert Bag(new).get_message_count() == 1


def test_file_objects_are_read_and_written_in_place() -> None:
    buf = io.BytesIO(b"prefix")
    buf.seek(6)
    with Bag(buf, "w") as bag:
        bag.write("/a", Int32(data=1), Time(1))
    assert buf.getvalue().startswith(b"prefix#ROSBAG V2.0\n") and not buf.closed
    buf.seek(6)
    with Bag(buf, "a") as bag:
        bag.write("/a", Int32(data=2), Time(2))
    buf.seek(6)
    reread = Bag(buf)
    assert [m.message.data for m in reread.read_messages()] == [1, 2]
    assert reread.filename is None


def test_constructor_validation() -> None:
    with pytest.raises(DdesValueError, match="mode"):
        Bag(None, "x")
    with pytest.raises(DdesValueError, match="in-memory"):
        Bag(None, "r")
    with pytest.raises(DdesValueError, match="compression must be one of"):
        Bag(compression="zstd")
    with pytest.raises(DdesValueError, match="chunk_threshold"):
        Bag(chunk_threshold=-1)
    bag = Bag(options={"compression": "bz2", "chunk_threshold": 10})
    assert bag.options == {"compression": "bz2", "chunk_threshold": 10}
    with pytest.raises(DdesValueError, match="format"):
        Bag(format="zip")


def test_mcap_paths_write_and_read_mcap(tmp_path: object) -> None:
    path = os.path.join(str(tmp_path), "x.mcap")
    with Bag(path, "w") as bag:
        bag.write("/a", Int32(data=1), Time(1))
    with open(path, "rb") as f:
        assert f.read(8) == b"\x89MCAP0\r\n"
    assert contents(Bag(path)) == contents(sample_bag().__class__.from_bytes(
        Bag(path).to_bytes()))
    assert [m.message.data for m in Bag(path).read_messages()] == [1]


def test_repr_and_compression_info() -> None:
    bag = sample_bag(compression="bz2")
    assert repr(bag) == "<Bag memory (w) 2 connections 3 messages>"
    info = bag.get_compression_info()
    assert info.compression == "bz2" and info.uncompressed > info.compressed > 0
    assert list(bag.reindex()) == [4117]
