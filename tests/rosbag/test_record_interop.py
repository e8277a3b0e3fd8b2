"""Recordings of ddes against recordings of real ``rosbag record`` (Noetic, system Python).

A real roscore (on a free port), a rospy talker named ``/talker`` logging and publishing
``hello world N`` at 10 Hz, and real ``rosbag record`` (``/chatter -l 5`` and ``-a
--duration 2``), against the same talker and the ``rosbag/record`` node type in a ddes launch:

* the connection records hold the same headers (callerid, topic, type, md5sum,
  message_definition, latching) for every publisher the two recorders share;
* record prints the same lines (times aside), and ``-a`` subscribes to the same topics;
* real rosbag reads what the ddes launch node recorded, message for message.
"""

from __future__ import annotations

import re
import textwrap
from collections.abc import Callable
from pathlib import Path
from typing import Any

import pytest

from ddes.graph.world import World
from ddes.launch import load_launch
from ddes.launch.runtime import LaunchRunner, start_core
from ddes.rosbag import Bag
from ddes.rospack import RosPack

pytestmark = pytest.mark.ros

Runner = Callable[..., Any]

REAL_RECORD = r'''
import json, os, re, signal, socket, subprocess, sys, tempfile, time
import rosbag

folder = tempfile.mkdtemp()
with socket.socket() as s:
    s.bind(("127.0.0.1", 0))
    port = s.getsockname()[1]
env = dict(os.environ, ROS_MASTER_URI=f"http://localhost:{port}", ROS_HOME=folder)
env = {k: v for k, v in env.items() if not k.startswith("PYTHON")}
TALKER = """
import rospy
from std_msgs.msg import String
rospy.init_node('talker')
pub = rospy.Publisher('chatter', String, queue_size=10)
rate = rospy.Rate(10)
i = 0
while not rospy.is_shutdown():
    text = 'hello world %d' % i
    rospy.loginfo(text)
    pub.publish(text)
    i += 1
    rate.sleep()
"""
procs = []
def start(*cmd):
    p = subprocess.Popen(cmd, env=env, cwd=folder, stdout=subprocess.DEVNULL,
                         stderr=subprocess.DEVNULL, start_new_session=True)
    procs.append(p)
    return p
def record(*args):
    p = subprocess.run(["rosbag", "record", *args], env=env, cwd=folder, capture_output=True,
                       text=True, timeout=60)
    return re.sub(r"\x1b\[[0-9;]*m", "", p.stdout).splitlines()
try:
    start("roscore", "-p", str(port))
    import rosgraph
    deadline = time.time() + 30
    master = rosgraph.Master("/probe", master_uri=env["ROS_MASTER_URI"])
    while not master.is_online():
        assert time.time() < deadline, "roscore did not start"
        time.sleep(0.1)
    start(sys.executable, "-c", TALKER)
    while "/chatter" not in [t for t, _ in master.getPublishedTopics("/")]:
        assert time.time() < deadline, "the talker did not start"
        time.sleep(0.1)
    out = {"limit": record("-O", "limit.bag", "-l", "5", "/chatter"),
           "all": record("-a", "--duration", "2", "-O", "all.bag")}
finally:
    for p in reversed(procs):
        os.killpg(p.pid, signal.SIGINT)
    for p in procs:
        try:
            p.wait(timeout=20)
        except subprocess.TimeoutExpired:
            os.killpg(p.pid, signal.SIGKILL)
def conns(name):
    bag = rosbag.Bag(os.path.join(folder, name))
    found = [{k: v.decode() if isinstance(v, bytes) else v for k, v in c.header.items()}
             for c in bag._connections.values()]
    data = [(topic, msg.data) for topic, msg, _ in bag.read_messages(topics=["/chatter"])]
    return {"connections": found, "chatter": data}
out["limit_bag"] = conns("limit.bag")
out["all_bag"] = conns("all.bag")
print(json.dumps(out))
'''

REAL_READ = r'''
import json, sys
import rosbag
bag = rosbag.Bag(sys.argv[1] if len(sys.argv) > 1 else sys.stdin.read().strip())
info = bag.get_type_and_topic_info()
print(json.dumps({
    "messages": [(topic, getattr(msg, "data", None), t.to_nsec())
                 for topic, msg, t in bag.read_messages(topics=["/chatter"])],
    "count": bag.get_message_count(),
    "topics": {k: [v.msg_type, v.message_count] for k, v in info.topics.items()},
    "headers": sorted([{k: v.decode() for k, v in c.header.items()}
                       for c in bag._connections.values()], key=lambda h: sorted(h.items())),
}))
'''


def normalize(lines: list[str]) -> list[str]:
    """Record's lines with the times and anonymous suffixes replaced."""
    return [re.sub(r"\[ ?(\w+)\] \[[\d.]+\]", r"[\1] [T]", line) for line in lines]


def ddes_record(tmp_path: Path, args: str, until: float) -> tuple[list[str], Bag]:
    """The same session in ddes: a launch with the rospy talker and rosbag/record as ``/rec``."""
    tmp_path.mkdir(parents=True, exist_ok=True)
    launch = tmp_path / "rec.launch"
    out = tmp_path / "ddes.bag"
    launch.write_text(textwrap.dedent(f"""\
        <launch>
          <node pkg="rospy_tutorials" type="talker" name="talker"/>
          <node pkg="rosbag" type="record" name="rec" output="screen" args="{args} -O {out}"/>
        </launch>
        """))
    world = World(seed=0)
    start_core(world)
    lines: list[str] = []
    runner = LaunchRunner(world, load_launch(launch, {}, RosPack(), anon_seed=0), out=lines.append)
    runner.start(print_summary=False)
    world.run(until=until)
    runner.shutdown()
    logged = [line for line in lines if line.startswith("[ INFO]")]
    return logged, Bag(str(out))


def shared(headers: list[dict[str, str]]) -> list[dict[str, str]]:
    """The connections both recorders see: the talker's, rosout's (not the recorder's own)."""
    return sorted((h for h in headers if not h["callerid"].startswith(("/record", "/rec"))),
                  key=lambda h: (h["topic"], h["callerid"]))


def test_record_stores_and_prints_as_the_real_recorder(ros_python: Runner,
                                                        tmp_path: Path) -> None:
    real = ros_python(REAL_RECORD, as_json=True, timeout=180)
    # rosbag record /chatter -l 5 -O limit.bag
    logged, bag = ddes_record(tmp_path / "limit", "-l 5 /chatter", until=3)
    assert normalize(real["limit"]) == ["[INFO] [T]: Subscribing to /chatter",
                                        "[INFO] [T]: Recording to 'limit.bag'."]
    assert normalize(logged) == ["[INFO] [T]: Subscribing to /chatter",
                                 f"[INFO] [T]: Recording to '{tmp_path / 'limit' / 'ddes.bag'}'."]
    assert [dict(c.header) for c in bag.get_connections()] == real["limit_bag"]["connections"]
    assert bag.get_message_count() == 5 == len(real["limit_bag"]["chatter"])
    assert all(re.fullmatch(r"hello world [\d.]+", m.message.data) for m in bag.read_messages())
    # rosbag record -a --duration 2
    logged, bag = ddes_record(tmp_path / "all", "-a --duration 2", until=3)
    subscribed = sorted(line for line in normalize(real["all"]) if "Subscribing" in line)
    assert subscribed == sorted(line for line in normalize(logged) if "Subscribing" in line)
    assert subscribed == ["[INFO] [T]: Subscribing to /chatter",
                          "[INFO] [T]: Subscribing to /rosout",
                          "[INFO] [T]: Subscribing to /rosout_agg"]
    ours = shared([dict(c.header) for c in bag.get_connections()])
    assert [h["topic"] for h in ours] == ["/chatter", "/rosout", "/rosout_agg"]
    # callerid, topic, type, md5sum, message_definition, latching: the same
    assert ours == shared(real["all_bag"]["connections"])


def test_real_rosbag_reads_what_the_launch_node_recorded(ros_python: Runner,
                                                         tmp_path: Path) -> None:
    _logged, bag = ddes_record(tmp_path, "-a", until=2.5)
    read = ros_python(REAL_READ, stdin=str(tmp_path / "ddes.bag"), as_json=True)
    ours = [(m.topic, m.message.data, m.timestamp.to_nsec())
            for m in bag.read_messages(topics=["/chatter"])]
    assert [tuple(m) for m in read["messages"]] == ours and len(ours) == 24
    assert read["count"] == bag.get_message_count()
    info = bag.get_type_and_topic_info()
    assert read["topics"] == {k: [v.msg_type, v.message_count] for k, v in info.topics.items()}
    assert read["headers"] == sorted([dict(c.header) for c in bag.get_connections()],
                                     key=lambda h: sorted(h.items()))
