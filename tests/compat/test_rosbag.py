"""ddes.compat.rosbag: the same plain scripts under real rosbag and under ddes.

A writer script writes a bag with ``rosbag.Bag(path, "w", compression=...)``; a reader script
prints everything rosbag's API says about a bag (messages with their fields and stamps, filtered
reads, counts, start/end, type and topic info, compression info).  Under real ROS (Debian's
python3 with rosbag, marker ``ros``) and as a ddes script node the writer writes one bag each;
each reader reads both files, and all four readings agree.  The error script prints the type
and text of rosbag's errors in both.
"""

from __future__ import annotations

import json
import re
from collections.abc import Callable
from pathlib import Path
from typing import Any

import pytest

import ddes
from ddes.compat import rosbag
from ddes.compat.scripts import run_script
from ddes.errors import BagNotFoundError, DdesError, ROSInitException

WRITER = r'''
import sys
import rosbag
import rospy
from std_msgs.msg import Int32, String
from geometry_msgs.msg import Point

path, compression, late = sys.argv[1], sys.argv[2], sys.argv[3:] != ["in-order"]
with rosbag.Bag(path, "w", compression=compression, chunk_threshold=300) as bag:
    for i in range(20):
        t = rospy.Time(1000 + i // 3, (i * 37000000) % 1000000000)
        bag.write("/chatter", String(data="hello %d" % i), t)
        if i % 2 == 0:
            bag.write("/count", Int32(data=i * i), t + rospy.Duration(0, 500))
        if i % 5 == 0:
            bag.write("points", Point(x=float(i), y=-i / 2.0, z=0.25), t)
    if late:
        bag.write("/chatter", String(data="late"), rospy.Time(999, 1))
    bag.write("/count", Int32(data=-1), rospy.Time(1010))
print("wrote", path)
'''

APPENDER = r'''
import sys
import rosbag
import rospy
from std_msgs.msg import Int32, String

with rosbag.Bag(sys.argv[1], "a") as bag:
    bag.write("/count", Int32(data=7), rospy.Time(1020))
    bag.write("/new", String(data="new"), rospy.Time(1021))
'''

READER = r'''
import json
import re
import sys
import rosbag
import rospy


def plain(v):
    if hasattr(v, "_type") and hasattr(v, "__slots__"):
        return {s: plain(getattr(v, s)) for s in v.__slots__}
    if isinstance(v, (list, tuple)):
        return [plain(x) for x in v]
    return v


def stamp(t):
    return [t.secs, t.nsecs]


out = {}
with rosbag.Bag(sys.argv[1]) as bag:
    out["messages"] = [[m.topic, m.message._type, plain(m.message), stamp(m.timestamp)]
                       for m in bag.read_messages()]
    out["window"] = [[topic, stamp(t)] for topic, msg, t in bag.read_messages(
        topics=["/count", "points"], start_time=rospy.Time(1002), end_time=rospy.Time(1004))]
    out["one_topic"] = [plain(m) for _, m, _ in bag.read_messages("/count")]
    out["counts"] = [bag.get_message_count(), bag.get_message_count("/chatter"),
                     bag.get_message_count(["/count", "points"]), bag.get_message_count("/x")]
    out["span"] = [bag.get_start_time(), bag.get_end_time()]
    info = bag.get_type_and_topic_info()
    out["types"] = info.msg_types
    out["topics"] = {k: list(v) for k, v in info.topics.items()}
    out["topic_fields"] = list(type(next(iter(info.topics.values())))._fields)
    out["filtered"] = {k: list(v) for k, v in
                       bag.get_type_and_topic_info(topic_filters="/count").topics.items()}
    out["compression"] = list(bag.get_compression_info())
    out["mode"] = bag.mode
    out["info_head"] = [line for line in str(bag).splitlines()
                        if line.split(":")[0] in ("version", "duration", "messages",
                                                  "compression", "types", "topics")]
print(json.dumps(out))
'''

ERRORS = r'''
import io
import json
import re
import os
import sys
import rosbag
import rospy
from std_msgs.msg import String

os.chdir(sys.argv[1])
out = []


def probe(what, f):
    try:
        f()
        out.append([what, "ok"])
    except Exception as e:
        kinds = [k for k, c in (("ValueError", ValueError), ("FileNotFoundError", FileNotFoundError),
                                ("UnsupportedOperation", io.UnsupportedOperation),
                                ("ROSBagException", rosbag.ROSBagException),
                                ("ROSBagUnindexedException", rosbag.ROSBagUnindexedException))
                 if isinstance(e, c)]
        text = str(e) if not isinstance(e, io.UnsupportedOperation) else "-"
        out.append([what, kinds, text])


probe("bad mode", lambda: rosbag.Bag("x.bag", "x"))
probe("missing", lambda: rosbag.Bag("missing.bag"))
probe("no name", lambda: rosbag.Bag(""))
probe("options", lambda: rosbag.Bag("x.bag", "w", options=[1]))
probe("compression", lambda: rosbag.Bag("x.bag", "w", compression="zip"))
probe("threshold", lambda: rosbag.Bag("x.bag", "w", chunk_threshold=-1))
writing = rosbag.Bag("w.bag", "w")
writing.write("/a", String(data="x"), rospy.Time(1))
probe("read while written", lambda: rosbag.Bag("w.bag"))
probe("empty topic", lambda: writing.write("", String(data="x"), rospy.Time(1)))
probe("no msg", lambda: writing.write("/a", None, rospy.Time(1)))
writing.close()
probe("write closed", lambda: writing.write("/a", String(data="x"), rospy.Time(2)))
probe("read closed", lambda: list(writing.read_messages()))
probe("size closed", lambda: writing.size)
probe("str closed", lambda: str(writing))
out.append(["count closed", writing.get_message_count(), writing.get_start_time(),
            writing.get_end_time()])
reading = rosbag.Bag("w.bag")
probe("write read-only", lambda: reading.write("/a", String(data="x"), rospy.Time(2)))
out.append(["names", reading.filename, reading.mode])
reading.close()
probe("close twice", reading.close)
empty = rosbag.Bag("e.bag", "w")
empty.close()
empty = rosbag.Bag("e.bag")
probe("start of empty", empty.get_start_time)
out.append(["empty", empty.get_message_count(), list(empty.get_type_and_topic_info())])
print(json.dumps(out))
'''

DRIVER = r'''
import runpy, sys
sys.argv = [{path!r}] + {args!r}
runpy.run_path({path!r}, run_name="__main__")
'''


def _files(tmp_path: Path) -> dict[str, Path]:
    out = {}
    for name, text in (("writer", WRITER), ("appender", APPENDER), ("reader", READER), ("errors", ERRORS)):
        out[name] = tmp_path / f"{name}.py"
        out[name].write_text(text, encoding="utf-8")
    return out


def _ddes(script: Path, *args: str, until: float = 1.0) -> str:
    """Run ``script`` as a ddes script node; what it printed."""
    lines: list[str] = []
    world = ddes.World()
    done, _ = run_script(world, script, list(args), print_line=lambda t, _e: lines.append(t))
    world.run(until=until)
    assert done.processed and done.ok, done.value
    return "\n".join(lines)


def _real(ros_python: Callable[..., Any], script: Path, *args: str) -> str:
    return str(ros_python(DRIVER.format(path=str(script), args=list(args))))


@pytest.mark.parametrize("compression", ["none", "bz2", "lz4"])
def test_a_bag_written_by_ddes_reads_in_ddes(tmp_path: Path, compression: str) -> None:
    files = _files(tmp_path)
    _ddes(files["writer"], str(tmp_path / "d.bag"), compression)
    seen = json.loads(_ddes(files["reader"], str(tmp_path / "d.bag")))
    assert seen["counts"] == [36, 21, 15, 0]
    # rosbag's order: a message written out of time order into a later chunk is read there
    late = ["/chatter", "std_msgs/String", {"data": "late"}, [999, 1]]
    assert seen["messages"][0] == ["/chatter", "std_msgs/String", {"data": "hello 0"}, [1000, 0]]
    assert seen["messages"].index(late) == 32
    assert seen["messages"][-1] == ["/count", "std_msgs/Int32", {"data": -1}, [1010, 0]]
    assert seen["span"] == [1000.0, 1010.0]  # the first chunk's start, as rosbag
    assert seen["compression"][0] == compression
    assert seen["topics"]["points"] == ["geometry_msgs/Point", 4, 1, seen["topics"]["points"][3]]


@pytest.mark.ros
@pytest.mark.parametrize("compression", ["none", "bz2", "lz4"])
def test_each_reads_the_others_bag_the_same(ros_python: Callable[..., Any], tmp_path: Path,
                                            compression: str) -> None:
    files = _files(tmp_path)
    _ddes(files["writer"], str(tmp_path / "d.bag"), compression)
    _real(ros_python, files["writer"], str(tmp_path / "r.bag"), compression)
    readings = {
        (who, bag): json.loads(run(files["reader"], str(tmp_path / bag)))
        for who, run in (("ddes", _ddes),
                         ("ros", lambda s, *a: _real(ros_python, s, *a)))
        for bag in ("d.bag", "r.bag")
    }
    reference = readings[("ros", "r.bag")]
    assert len(reference["messages"]) == 36
    for key, seen in readings.items():
        assert seen == reference, key
    if compression != "lz4":  # the same bytes (LZ4 compressors differ in their output bytes)
        assert (tmp_path / "d.bag").read_bytes() == (tmp_path / "r.bag").read_bytes()


@pytest.mark.ros
def test_errors_have_rosbags_types_and_texts(ros_python: Callable[..., Any],
                                             tmp_path: Path) -> None:
    files = _files(tmp_path)
    (tmp_path / "ros").mkdir()
    (tmp_path / "ddes").mkdir()
    theirs = json.loads(_real(ros_python, files["errors"], str(tmp_path / "ros")))
    ours = json.loads(_ddes(files["errors"], str(tmp_path / "ddes")))
    assert ours == theirs
    assert ["bad mode", ["ValueError"], 'mode "x" is invalid'] in ours


def test_errors_are_ddes_errors_under_rosbags_names(tmp_path: Path) -> None:
    with pytest.raises(BagNotFoundError) as missing:
        rosbag.Bag(str(tmp_path / "missing.bag"))
    assert isinstance(missing.value, (DdesError, FileNotFoundError))
    assert str(missing.value) == f"[Errno 2] No such file or directory: '{tmp_path}/missing.bag'"
    with pytest.raises(rosbag.ROSBagUnindexedException, match="^Unindexed bag$"):
        writing = rosbag.Bag(str(tmp_path / "w.bag"), "w")
        rosbag.Bag(str(tmp_path / "w.bag"))
    assert rosbag.Bag(str(tmp_path / "w.bag"), allow_unindexed=True).get_message_count() == 0
    writing.close()
    assert issubclass(rosbag.ROSBagException, DdesError)


def test_write_without_t_takes_the_nodes_ros_time(tmp_path: Path) -> None:
    script = tmp_path / "rec.py"
    script.write_text(
        "import rospy, rosbag\n"
        "from std_msgs.msg import String\n"
        "import sys\n"
        "rospy.init_node('rec')\n"
        "rospy.sleep(2.5)\n"
        "with rosbag.Bag(sys.argv[1], 'w') as bag:\n"
        "    bag.write('/s', String(data='now'))\n", encoding="utf-8")
    _ddes(script, str(tmp_path / "t.bag"), until=5.0)
    with rosbag.Bag(str(tmp_path / "t.bag")) as bag:
        assert [(t.secs, t.nsecs) for _, _, t in bag.read_messages()] == [(2, 500_000_000)]


def test_write_without_t_outside_a_node_says_so(tmp_path: Path) -> None:
    from ddes.msg import get_message_class

    with rosbag.Bag(str(tmp_path / "n.bag"), "w") as bag, \
            pytest.raises(ROSInitException, match="time is not initialized"):
        bag.write("/s", get_message_class("std_msgs/String")(data="x"))


@pytest.mark.ros
def test_appending_to_the_others_bag(ros_python: Callable[..., Any], tmp_path: Path) -> None:
    """Appending starts a new connection per topic, as rosbag does. ddes rewrites the whole file
    on close (its chunks then follow the appending bag's threshold), so chunk counts and
    compression sizes are not compared."""
    files = _files(tmp_path)
    _ddes(files["writer"], str(tmp_path / "d.bag"), "none", "in-order")
    _real(ros_python, files["writer"], str(tmp_path / "r.bag"), "none", "in-order")
    _real(ros_python, files["appender"], str(tmp_path / "d.bag"))
    _ddes(files["appender"], str(tmp_path / "r.bag"))
    readings = [json.loads(run(files["reader"], str(tmp_path / bag)))
                for run in (_ddes, lambda s, *a: _real(ros_python, s, *a))
                for bag in ("d.bag", "r.bag")]
    for seen in readings:
        del seen["compression"], seen["info_head"]
        assert seen == readings[0]
    assert readings[0]["topics"]["/count"][:3] == ["std_msgs/Int32", 12, 2]
    assert readings[0]["messages"][-1] == ["/new", "std_msgs/String", {"data": "new"},
                                           [1021, 0]]


def _doc_section(title: str) -> str:
    doc = (Path(__file__).resolve().parents[2] / "docs" / "rospy.md").read_text(encoding="utf-8")
    return doc.split(f"\n## {title}\n", 1)[1].split("\n## ", 1)[0]


def test_the_script_in_docs_rospy_md_prints_what_it_shows(tmp_path: Path,
                                                          monkeypatch: pytest.MonkeyPatch) -> None:
    section = _doc_section("rosbag")
    script = re.findall(r"```python\n(.*?)```", section, re.S)[0]
    shown = re.findall(r"```text\n(.*?)```", section, re.S)[0]
    (tmp_path / "recorder.py").write_text(script, encoding="utf-8")
    monkeypatch.chdir(tmp_path)
    assert _ddes(tmp_path / "recorder.py", until=5.0) == shown.rstrip("\n")
