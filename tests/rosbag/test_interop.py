"""ddes against real ROS 1 rosbag (Noetic, under the system Python).

* ``rosbag info`` (plain, ``--freq``, ``-y``, ``-k``) of ddes equals real ``rosbag info``
  on the same files — files real rosbag wrote and files ddes wrote — with ``TZ`` fixed;
* for the same writes, ddes writes the same bytes as ``rosbag.Bag`` (no compression, bz2);
* real ``rosbag.Bag`` reads what ddes writes (none/bz2/lz4, several connections per
  topic, latching headers, types it must rebuild) with identical content, and ddes
  reads what real rosbag writes;
* ``rosbag filter`` of ddes and of ROS give the same bag.
"""

from __future__ import annotations

import json
import os
import time
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

import pytest

from ddes import Time
from ddes.console.tooling import ToolContext, run_command_result
from ddes.graph.world import World
from ddes.msg import get_message_class, message_class_from_definition
from ddes.rosbag import Bag

pytestmark = pytest.mark.ros

Runner = Callable[..., Any]
TZ = "Asia/Kolkata"  # a zone with a half-hour offset: local time really is used

String = get_message_class("std_msgs/String")
Int32 = get_message_class("std_msgs/Int32")
Odometry = get_message_class("nav_msgs/Odometry")
Imu = get_message_class("sensor_msgs/Imu")


@pytest.fixture
def zone() -> Iterator[None]:
    old = os.environ.get("TZ")
    os.environ["TZ"] = TZ
    time.tzset()
    yield
    if old is None:
        del os.environ["TZ"]
    else:
        os.environ["TZ"] = old
    time.tzset()


def writes(n: int = 40) -> list[dict[str, Any]]:
    """A spec of raw writes (topic, type, bytes, time, optional connection header)."""
    out: list[dict[str, Any]] = []
    latched = {"callerid": "/map_server", "latching": "1"}
    for i in range(n):
        t = 1486033546 * 10**9 + i * 73_000_000 + (i % 3)
        odom = Odometry()
        odom.header.seq = i
        odom.header.frame_id = "odom"
        odom.pose.pose.position.x = i / 7
        out.append({"topic": "/odom", "cls": Odometry, "data": odom._serialize_to_bytes(), "t": t})
        if i % 2:
            out.append({"topic": "/imu/data", "cls": Imu,
                        "data": Imu()._serialize_to_bytes(), "t": t + 5_000_000})
        if i % 15 == 0:
            out.append({"topic": "/map_name", "cls": String,
                        "data": String(data=f"map {i}")._serialize_to_bytes(), "t": t,
                        "extra": latched})
    out.append({"topic": "/late", "cls": Int32, "data": Int32(data=1)._serialize_to_bytes(),
                "t": 1486033546 * 10**9 - 4_000_000_000})  # out of order
    return out


def spec_json(spec: list[dict[str, Any]]) -> str:
    return json.dumps([{"topic": w["topic"], "type": w["cls"]._type, "md5": w["cls"]._md5sum,
                        "def": w["cls"]._full_text, "data": w["data"].hex(), "t": w["t"],
                        "extra": w.get("extra")} for w in spec])


def ddes_write(spec: list[dict[str, Any]], path: str, compression: str = "none",
               chunk_threshold: int = 768 * 1024) -> None:
    bag = Bag(path, "w", compression=compression, chunk_threshold=chunk_threshold)
    for w in spec:
        cls = w["cls"]
        header = None
        if w.get("extra"):
            header = {"topic": w["topic"], "type": cls._type, "md5sum": cls._md5sum,
                      "message_definition": cls._full_text, **w["extra"]}
        bag.write(w["topic"], (cls._type, w["data"], cls._md5sum, cls), Time._from_ns(w["t"]),
                  raw=True, connection_header=header)
    bag.close()


_WRITE = r"""
import json, sys, rosbag, genpy, roslib.message
req = json.load(sys.stdin)
with rosbag.Bag(req["path"], "w", compression=req["compression"],
                chunk_threshold=req["chunk_threshold"]) as bag:
    for w in req["spec"]:
        cls = roslib.message.get_message_class(w["type"])
        header = None
        if w["extra"]:
            header = dict(topic=w["topic"], type=w["type"], md5sum=w["md5"],
                          message_definition=cls._full_text, **w["extra"])
        t = genpy.Time(w["t"] // 10**9, w["t"] % 10**9)
        bag.write(w["topic"], (w["type"], bytes.fromhex(w["data"]), w["md5"], cls), t, raw=True,
                  connection_header=header)
"""


def ros_write(ros_python: Runner, spec: list[dict[str, Any]], path: str,
              compression: str = "none", chunk_threshold: int = 768 * 1024) -> None:
    request = {"path": path, "compression": compression, "chunk_threshold": chunk_threshold,
               "spec": json.loads(spec_json(spec))}
    ros_python(_WRITE, stdin=json.dumps(request))


_INFO = r"""
import json, os, subprocess, sys
req = json.load(sys.stdin)
env = dict(os.environ, TZ=req["tz"])
out = []
for args in req["runs"]:
    p = subprocess.run(["rosbag", "info"] + args, env=env, capture_output=True, text=True)
    out.append([p.returncode, p.stdout, p.stderr])
print(json.dumps(out))
"""

INFO_ARGS = [[], ["--freq"], ["-y"], ["-y", "--freq"], ["-y", "-k", "topics"],
             ["-y", "-k", "types"], ["-y", "-k", "duration"], ["-y", "-k", "compression"],
             ["-y", "-k", "messages"]]


def compare_info(ros_python: Runner, paths: list[str]) -> None:
    runs = [args + [p] for p in paths for args in INFO_ARGS] + [list(paths)]
    real = ros_python(_INFO, stdin=json.dumps({"tz": TZ, "runs": runs}), as_json=True)
    ctx = ToolContext(World())
    for args, (code, out, _err) in zip(runs, real):
        mine = run_command_result(ctx, "rosbag info " + " ".join(args))
        assert (mine.code, mine.out) == (code, out), args


@pytest.mark.parametrize("compression,threshold", [("none", 768 * 1024), ("bz2", 2000),
                                                   ("lz4", 3000)])
def test_info_of_bags_real_rosbag_wrote(ros_python: Runner, zone: None, tmp_path: Path,
                                        compression: str, threshold: int) -> None:
    path = str(tmp_path / "ros.bag")
    ros_write(ros_python, writes(), path, compression, threshold)
    compare_info(ros_python, [path])


def test_info_of_bags_ddes_wrote(ros_python: Runner, zone: None, tmp_path: Path) -> None:
    multi = Bag()
    header = {"type": String._type, "md5sum": String._md5sum,
              "message_definition": String._full_text, "topic": "/chatter", "latching": "0"}
    for i in range(200):
        multi._write_raw("/chatter", {**header, "callerid": f"/talker{i % 3}"},
                         String(data="x" * (i % 17))._serialize_to_bytes(),
                         10**12 + i * 250_000_000)
    multi.write("/slow", Int32(data=0), Time(10**3))
    multi.write("/slow", Int32(data=1), Time(10**3 + 4000))  # over an hour long
    paths = [str(tmp_path / "multi.bag"), str(tmp_path / "short.bag"), str(tmp_path / "e.bag")]
    multi.save(paths[0], compression="bz2")
    short = Bag()
    short.write("/a", Int32(data=1), Time(5, 999_000_000))
    short.write("/a", Int32(data=1), Time(100, 1))
    short.save(paths[1])
    Bag().save(paths[2])
    compare_info(ros_python, paths)


@pytest.mark.parametrize("compression,threshold", [("none", 768 * 1024), ("none", 500),
                                                   ("bz2", 768 * 1024), ("bz2", 1500)])
def test_same_writes_same_bytes(ros_python: Runner, tmp_path: Path, compression: str,
                                threshold: int) -> None:
    spec = writes(30)
    ros_write(ros_python, spec, str(tmp_path / "ros.bag"), compression, threshold)
    ddes_write(spec, str(tmp_path / "ddes.bag"), compression, threshold)
    assert (tmp_path / "ddes.bag").read_bytes() == (tmp_path / "ros.bag").read_bytes()


_READ = r"""
import json, sys, rosbag
out = []
with rosbag.Bag(json.load(sys.stdin)["path"]) as bag:
    for topic, raw, t, header in bag.read_messages(raw=True, return_connection_header=True):
        datatype, data, md5, pos, pytype = raw
        msg = pytype()
        msg.deserialize(data)
        out.append([topic, t.to_nsec(), data.hex(), datatype, md5,
                    {k: v.decode() for k, v in header.items()}, len(str(msg)) > 0])
    info = bag.get_type_and_topic_info()
    topics = {k: [v.msg_type, v.message_count, v.connections] for k, v in info.topics.items()}
    span = [bag.get_start_time(), bag.get_end_time()]
print(json.dumps({"messages": out, "types": info.msg_types, "topics": topics, "span": span}))
"""


def ddes_view(bag: Bag) -> dict[str, Any]:
    messages = [[m.topic, m.timestamp.to_nsec(), m.message[1].hex(), m.message[0], m.message[2],
                 dict(m.connection_header), True]
                for m in bag.read_messages(raw=True, return_connection_header=True)]
    info = bag.get_type_and_topic_info()
    topics = {k: [v.msg_type, v.message_count, v.connections] for k, v in info.topics.items()}
    return {"messages": messages, "types": info.msg_types, "topics": topics,
            "span": [bag.get_start_time(), bag.get_end_time()]}


@pytest.mark.parametrize("compression", ["none", "bz2", "lz4"])
def test_real_rosbag_reads_what_ddes_writes(ros_python: Runner, tmp_path: Path,
                                            compression: str) -> None:
    path = str(tmp_path / "d.bag")
    bag = Bag(chunk_threshold=4000)
    for w in writes(25):
        cls = w["cls"]
        header = {"topic": w["topic"], "type": cls._type, "md5sum": cls._md5sum,
                  "message_definition": cls._full_text, "callerid": "/rec", "latching": "0",
                  **(w.get("extra") or {})}
        bag._write_raw(w["topic"], header, w["data"], w["t"])
    definition = ("int32 x\nstring[] names\ngeometry_msgs/Point p\n" + "=" * 80 +
                  "\nMSG: geometry_msgs/Point\nfloat64 x\nfloat64 y\nfloat64 z")
    Custom = message_class_from_definition("ddes_test_msgs/Custom", definition)
    custom = Custom(x=3, names=["a", "b"])
    bag.write("/custom", custom, Time(1486033550))
    bag.save(path, compression=compression)
    real = ros_python(_READ, stdin=json.dumps({"path": path}), as_json=True)
    assert real == ddes_view(Bag(path))
    assert len(real["messages"]) == bag.get_message_count()
    assert real["topics"]["/map_name"][2] == 1


def test_ddes_reads_what_real_rosbag_writes(ros_python: Runner, tmp_path: Path) -> None:
    path = str(tmp_path / "r.bag")
    ros_write(ros_python, writes(30), path, "lz4", 2500)
    real = ros_python(_READ, stdin=json.dumps({"path": path}), as_json=True)
    assert ddes_view(Bag(path)) == real


_FILTER = r"""
import json, subprocess, sys
req = json.load(sys.stdin)
p = subprocess.run(["rosbag", "filter", req["in"], req["out"], req["expr"]], capture_output=True,
                   text=True)
print(json.dumps([p.returncode, p.stderr]))
"""


def test_filter_gives_the_same_bag_as_rosbag_filter(ros_python: Runner, tmp_path: Path) -> None:
    source = str(tmp_path / "in.bag")
    ddes_write(writes(20), source)
    expr = "topic != '/imu/data' and t.to_sec() < 1486033547.2"
    code, err = ros_python(_FILTER, stdin=json.dumps(
        {"in": source, "out": str(tmp_path / "ros.bag"), "expr": expr}), as_json=True)
    assert code == 0, err
    mine = run_command_result(ToolContext(World()),
                              f"rosbag filter {source} {tmp_path / 'ddes.bag'} \"{expr}\"")
    assert mine.code == 0, mine.err
    assert (tmp_path / "ddes.bag").read_bytes() == (tmp_path / "ros.bag").read_bytes()
