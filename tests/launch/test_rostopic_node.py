"""``rostopic`` as a launch-file node (the bundled ``rostopic`` package), against real roslaunch.

``<node pkg="rostopic" type="rostopic" name="pub" args="pub /chatter std_msgs/String 'data: hi'
-r 2"/>`` runs rostopic in a process of the launch: the node registers under the launch's name
(roslaunch passes ``__name:=pub``, which turns rostopic's ``anonymous=True`` off), publishes
under that caller id, logs nothing on ``/rosout`` (``disable_rosout=True``), and exits as
rostopic does (``-1`` after 3 seconds, ``echo -n N`` after N messages, a bad command line
with rostopic's exit code).
"""

from __future__ import annotations

import re
import textwrap
from collections.abc import Callable
from pathlib import Path
from typing import Any

import pytest

from ddes.console.shell import Console
from ddes.graph.world import World
from ddes.launch import load_launch
from ddes.launch.runtime import LaunchRunner, node_pid, start_core
from ddes.msg import get_message_class
from ddes.rospack import RosPack

String = get_message_class("std_msgs/String")
Int32 = get_message_class("std_msgs/Int32")
Point = get_message_class("geometry_msgs/Point")

Runner = Callable[..., Any]


def launch(body: str, world: World | None = None, *, core: bool = True
           ) -> tuple[World, LaunchRunner, list[str]]:
    """Start ``<launch>body</launch>`` on a world; returns the world, runner and its lines."""
    world = world or World(seed=0)
    if core:
        start_core(world)
    lines: list[str] = []
    xml = "<launch>\n" + textwrap.dedent(body).strip("\n") + "\n</launch>\n"
    runner = LaunchRunner(world, load_launch(xml, {}, RosPack(), anon_seed=0), out=lines.append)
    runner.start(print_summary=False)
    return world, runner, lines


def listen(world: World, topic: str, cls: type, name: str = "probe") -> list[tuple[Any, ...]]:
    """Messages on ``topic`` as (time, value, callerid, latching)."""
    got: list[tuple[Any, ...]] = []
    node = world.lookup_node("/" + name) or world.create_node(name)

    def cb(m: Any) -> None:
        h = m._connection_header
        value = m.data if hasattr(m, "data") else (m.x, m.y, m.z)
        got.append((world.now / 1e9, value, h["callerid"], h["latching"]))

    node.subscribe(topic, cls, cb)
    return got


def printed(lines: list[str]) -> list[str]:
    """What the nodes printed: the lines that are not roslaunch's own."""
    own = ("process[", "ROS_MASTER_URI=", "shutting down", "... shutting down", "done",
           "all processes")
    after = lines[lines.index("") + 1:]  # roslaunch's blank line after ROS_MASTER_URI
    return [ln for ln in after if not ln.startswith(own) and not re.match(r"\[[\w/]+-\d+\] ", ln)]


def died(lines: list[str], label: str) -> str:
    """The text after ``[label] `` of the process's exit line."""
    (line,) = [ln for ln in lines if ln.startswith(f"[{label}] process has")]
    return line[len(label) + 3:]


# -- pub ------------------------------------------------------------------------------------------

def test_pub_at_a_rate_registers_under_the_launch_name() -> None:
    world, runner, lines = launch("""
        <node pkg="rostopic" type="rostopic" name="pub"
              args="pub /chatter std_msgs/String 'data: hi' -r 2"/>
        """)
    got = listen(world, "/chatter", String)
    world.run(until=2.1)
    assert "/pub" in world.nodes and not any(n.startswith("/rostopic") for n in world.nodes)
    assert world.master.topics["/chatter"].publisher_nodes() == ["/pub"]
    # the first message goes out at 0, before the probe's connection is up, as in ROS
    assert got == [(t, "hi", "/pub", "0") for t in (0.5, 1.0, 1.5, 2.0)]
    # rostopic pub: init_node(disable_rosout=True)
    assert "/pub" not in world.master.topics["/rosout"].publisher_nodes()
    runner.shutdown()
    assert "[pub-1] killing on exit" in lines


def test_a_latched_message_stays_and_the_node_spins() -> None:
    world, _runner, lines = launch("""
        <node pkg="rostopic" type="rostopic" name="latched" output="screen"
              args="pub /latched std_msgs/String '{data: once}'"/>
        <node pkg="rostopic" type="rostopic" name="quiet" args="pub /q std_msgs/Int32 3"/>
        """)
    world.run(until=5)
    got = listen(world, "/latched", String)  # subscribing late: the latched message arrives
    world.run(until=6)
    assert [g[1:] for g in got] == [("once", "/latched", "1")]
    assert {"/latched", "/quiet"} <= set(world.nodes)
    # stdout shows with output="screen" only
    assert lines.count("publishing and latching message. Press ctrl-C to terminate") == 1


def test_once_publishes_and_exits_after_three_seconds() -> None:
    world, _runner, lines = launch("""
        <node pkg="rostopic" type="rostopic" name="one" output="screen"
              args="pub -1 /one geometry_msgs/Point 1 2 3"/>
        <node pkg="rostopic" type="rostopic" name="two" args="pub --once /two std_msgs/Int32 2"/>
        """)
    got = listen(world, "/one", Point)
    world.run(until=2.9)
    assert [g[1:] for g in got] == [((1.0, 2.0, 3.0), "/one", "1")]
    assert {"/one", "/two"} <= set(world.nodes)
    world.run(until=3.001)
    assert "/one" not in world.nodes and "/two" not in world.nodes
    assert "publishing and latching message for 3.0 seconds" in lines
    assert died(lines, "one-1") == "process has finished cleanly"
    assert died(lines, "two-2") == "process has finished cleanly"


def test_latch_with_a_rate_keeps_the_last_message_for_late_subscribers() -> None:
    world, _runner, _lines = launch("""
        <node pkg="rostopic" type="rostopic" name="rel"
              args="pub -l /r std_msgs/Int32 -r 2 -- -5"/>
        """)
    world.run(until=1.2)
    got = listen(world, "/r", Int32)
    world.run(until=1.6)
    # the latched message on connecting (1 ms later), then the next one
    assert [(round(t, 3), *rest) for t, *rest in got] == [(1.201, -5, "/rel", "1"),
                                                          (1.5, -5, "/rel", "1")]


@pytest.mark.parametrize("args, value", [
    ("/p std_msgs/String 'data: hi'", "hi"),
    ("/p std_msgs/String '{data: hi}'", "hi"),
    ("/p std_msgs/String hi", "hi"),
    ("/p std_msgs/String -- '-r'", "-r"),
    ("/p std_msgs/Int32 '{data: 7}'", 7),
    ("/p std_msgs/Int32 -- -7", -7),
    ("/p geometry_msgs/Point '{x: 1.5, y: 2}'", (1.5, 2.0, 0.0)),
    ("/p geometry_msgs/Point 1 2 3", (1.0, 2.0, 3.0)),
    ("/p geometry_msgs/Point '[1, 2, 3]' 4 5", None),  # a list fills the first field: an error
])
def test_the_yaml_forms_of_the_values(args: str, value: Any) -> None:
    cls = Int32 if "Int32" in args else Point if "Point" in args else String
    world, _runner, lines = launch(f"""
        <node pkg="rostopic" type="rostopic" name="p" args="pub -1 {args}"/>
        """)
    got = listen(world, "/p", cls)
    world.run(until=1)
    if value is None:
        assert got == [] and "exit code 1" in died(lines, "p-1")
        return
    assert [g[1] for g in got] == [value]


def test_a_list_for_all_fields_fails_as_rostopic_fails() -> None:
    world, _runner, lines = launch("""
        <node pkg="rostopic" type="rostopic" name="one"
              args="pub -1 /one geometry_msgs/Point '[1, 2, 3]'"/>
        """)
    world.run(until=1)
    # standard error shows without output="screen"; rostopic exits 1
    start = lines.index("ERROR: Not enough arguments:")
    assert lines[start:start + 6] == [
        "ERROR: Not enough arguments:", " * Given: [[1, 2, 3]]", " * Expected: ['x', 'y', 'z']",
        "", "Args are: [x y z]",
        f"[one-1] process has died [pid {node_pid('/one')}, exit code 1, cmd rostopic/rostopic "
        "pub -1 /one geometry_msgs/Point [1, 2, 3] __name:=one]."]


def test_names_resolve_in_the_node_namespace_and_remaps_apply() -> None:
    world, _runner, _lines = launch("""
        <group ns="g">
          <remap from="renamed" to="/elsewhere"/>
          <node pkg="rostopic" type="rostopic" name="rel" args="pub rel std_msgs/Int32 1"/>
          <node pkg="rostopic" type="rostopic" name="priv" args="pub ~priv std_msgs/Int32 2"/>
          <node pkg="rostopic" type="rostopic" name="re" args="pub renamed std_msgs/Int32 3"/>
        </group>
        """)
    world.run(until=0.5)
    pubs = {t: e.publisher_nodes() for t, e in world.master.topics.items() if e.publishers}
    # rosgraph's script_resolve_name: ~priv is under <ns>/rostopic, not the node's name
    assert pubs["/g/rel"] == ["/g/rel"]
    assert pubs["/g/rostopic/priv"] == ["/g/priv"]
    assert pubs["/elsewhere"] == ["/g/re"]


def test_substitute_keywords_stamps_every_message() -> None:
    Header = get_message_class("std_msgs/Header")
    world, _runner, _lines = launch("""
        <node pkg="rostopic" type="rostopic" name="h"
              args="pub -s -r 1 /h std_msgs/Header '{stamp: now, frame_id: base}'"/>
        """)
    stamps: list[float] = []
    world.create_node("probe").subscribe(
        "/h", Header, lambda m: stamps.append(m.stamp.to_sec()))
    world.run(until=3.5)
    assert stamps == [1.0, 2.0, 3.0]


def test_pub_runs_on_the_wall_clock_unless_use_rostime() -> None:
    world = World(seed=0)
    world.master.params.set_param("/use_sim_time", True)  # and nobody publishes /clock
    world, _runner, _lines = launch("""
        <node pkg="rostopic" type="rostopic" name="wall" args="pub -r 1 /w std_msgs/Int32 1"/>
        <node pkg="rostopic" type="rostopic" name="ros"
              args="pub -r 1 --use-rostime /r std_msgs/Int32 2"/>
        """, world)
    wall, ros = listen(world, "/w", Int32), listen(world, "/r", Int32)
    world.run(until=3.5)
    assert [g[0] for g in wall] == [1.0, 2.0, 3.0]
    assert [g[0] for g in ros] == []  # its Rate waits for /clock, as rospy's would
    assert not world.nodes["/wall"].use_sim_time and world.nodes["/ros"].use_sim_time


def test_pub_file_publishes_each_document(tmp_path: Path) -> None:
    data = tmp_path / "msgs.yaml"
    data.write_text("data: 1\n---\ndata: 2\n---\ndata: 3\n")
    world, _runner, lines = launch(f"""
        <node pkg="rostopic" type="rostopic" name="f" args="pub /f std_msgs/Int32 -f {data}"/>
        """)
    got = listen(world, "/f", Int32)
    world.run(until=2)
    # it waits for a subscriber (up to 5 s), then 10 Hz by default, then exits
    assert [(round(t, 2), v) for t, v, _, _ in got] == [(0.01, 1), (0.1, 2), (0.2, 3)]
    assert died(lines, "f-1") == "process has finished cleanly"


@pytest.mark.parametrize("args, code, err", [
    ("pub /x", 2, ["Usage: rostopic pub /topic type [args...]", "",
                   "rostopic: error: topic type must be specified"]),
    ("pub /x std_msgs/String", 2, ["Usage: rostopic pub /topic type [args...]", "",
                                   "rostopic: error: Please specify message values"]),
    ("pub -1 -r 2 /x std_msgs/String hi", 2,
     ["Usage: rostopic pub /topic type [args...]", "",
      "rostopic: error: You cannot select both -r and -1 (--once)"]),
    ("pub /x std_msgs/Nope 'data: 1'", 1,
     ["ERROR: invalid message type: std_msgs/Nope.",
      "If this is a valid message type, perhaps you need to type 'rosmake std_msgs'"]),
    ("pub /x std_msgs/String '{data: [}'", 2, None),
    ("info /x", 1, None),
    ("", 64, None),
    ("nope", 64, None),
    ("echo", 2, ["Usage: rostopic echo [options] /topic", "",
                 "rostopic: error: topic must be specified"]),
    ("echo -b x.bag /t", 1, None),
])
def test_bad_command_lines_exit_as_rostopic(args: str, code: int, err: list[str] | None) -> None:
    world, _runner, lines = launch(f"""
        <node pkg="rostopic" type="rostopic" name="x" args="{args}"/>
        """)
    world.run(until=1)
    end = died(lines, "x-1")
    assert f"exit code {code}," in end
    if err is not None:
        assert printed(lines) == err


def test_rosrun_rostopic_pub_is_anonymous_unless_named() -> None:
    con = Console(seed=0, out=lambda _line: None)
    out = con.run("rosrun rostopic rostopic pub /chatter std_msgs/String hello &")
    assert out.endswith("publishing and latching message. Press ctrl-C to terminate\n")
    con.run("rosrun rostopic rostopic pub /bye std_msgs/String bye __name:=named &")
    nodes = con.run("rosnode list").split()
    assert "/named" in nodes
    assert [n for n in nodes if n.startswith("/rostopic_")] != []  # rostopic's anonymous name
    assert con.run("rosrun rostopic rostopic echo -n 1 /bye") == 'data: "bye"\n---\n'


# -- echo, list, type, find ---------------------------------------------------------------------

def test_echo_waits_for_the_topic_prints_n_messages_and_exits() -> None:
    world, _runner, lines = launch("""
        <group ns="g">
          <node pkg="rostopic" type="rostopic" name="echo" output="screen"
                args="echo -n 2 /chatter"/>
        </group>
        <node pkg="rostopic" type="rostopic" name="pub"
              args="pub /chatter std_msgs/String 'data: hi' -r 2"/>
        """)
    world.run(until=2)
    assert "/g/echo" not in world.nodes
    assert printed(lines) == ["WARNING: topic [/chatter] does not appear to be published yet",
                              'data: "hi"', "---", 'data: "hi"', "---"]
    assert died(lines, "g/echo-1") == "process has finished cleanly"  # roslaunch's label


def test_echo_fields_and_options() -> None:
    world, _runner, lines = launch("""
        <node pkg="rostopic" type="rostopic" name="pt"
              args="pub -r 10 /pt geometry_msgs/Point '{x: 1.5, y: 2, z: 3}'"/>
        <node pkg="rostopic" type="rostopic" name="s" args="pub -r 10 /s std_msgs/String abc"/>
        <node pkg="rostopic" type="rostopic" name="y" output="screen" args="echo -n 1 /pt/y"/>
        <node pkg="rostopic" type="rostopic" name="f" output="screen"
              args="echo -n 1 --filter 'm.x > 1' /pt"/>
        <node pkg="rostopic" type="rostopic" name="n" output="screen" args="echo -n 1 --nostr /s"/>
        """)
    world.run(until=1)
    assert printed(lines) == ["2.0", "---", "x: 1.5", "y: 2.0", "z: 3.0", "---",
                              'data: "<string length: 3>"', "---"]


def test_list_type_and_find_print_and_exit() -> None:
    world, _runner, lines = launch("""
        <node pkg="rostopic" type="rostopic" name="pt" args="pub /pt geometry_msgs/Point 1 2 3"/>
        <node pkg="rostopic" type="rostopic" name="l" output="screen" args="list"/>
        <node pkg="rostopic" type="rostopic" name="t" output="screen" args="type /pt/x"/>
        <node pkg="rostopic" type="rostopic" name="fi" output="screen"
              args="find geometry_msgs/Point"/>
        """)
    world.run(until=1)
    assert printed(lines) == ["/pt", "/rosout", "/rosout_agg", "geometry_msgs/Point x float64",
                              "/pt"]
    assert all(died(lines, f"{n}-{i}") == "process has finished cleanly"
               for i, n in enumerate(["l", "t", "fi"], start=2))


# -- against real roslaunch ----------------------------------------------------------------------

LAUNCH = """\
<launch>
  <node pkg="rostopic" type="rostopic" name="pub" args="pub /chatter std_msgs/String 'data: hi' -r 2"/>
  <node pkg="rostopic" type="rostopic" name="latched" output="screen" args="pub /latched std_msgs/String '{data: once}'"/>
  <node pkg="rostopic" type="rostopic" name="one" output="screen" args="pub -1 /one geometry_msgs/Point 1 2 3"/>
  <group ns="g">
    <node pkg="rostopic" type="rostopic" name="rel" args="pub rel std_msgs/Int32 -r 2 -l -- -5"/>
  </group>
</launch>
"""

REAL_LAUNCH = r'''
import json, os, re, signal, socket, subprocess, sys, tempfile, time
folder = tempfile.mkdtemp()
launch = os.path.join(folder, "pub.launch")
with open(launch, "w") as f:
    f.write(sys.stdin.read())
with socket.socket() as s:
    s.bind(("127.0.0.1", 0))
    port = s.getsockname()[1]
uri = f"http://localhost:{port}"
env = {k: v for k, v in os.environ.items() if not k.startswith("PYTHON")}
# rostopic's script starts "#!/usr/bin/env python3": Debian's python, not a virtualenv's
env.update(ROS_MASTER_URI=uri, ROS_HOME=folder, PATH="/usr/bin:/bin:" + env.get("PATH", ""))
os.environ["ROS_MASTER_URI"] = uri
proc = subprocess.Popen(["roslaunch", "-p", str(port), launch], env=env, cwd=folder,
                        stdin=subprocess.DEVNULL, stdout=subprocess.PIPE,
                        stderr=subprocess.STDOUT, text=True, start_new_session=True)
out = {"messages": {}}
try:
    import rosgraph, rosnode, rospy
    from std_msgs.msg import Int32, String
    master = rosgraph.Master("/probe", master_uri=uri)
    deadline = time.time() + 60
    def published():
        try:
            return {t for t, _ in master.getPublishedTopics("/")}
        except Exception:
            return set()
    while not {"/chatter", "/g/rel", "/latched", "/one"} <= published():
        assert time.time() < deadline, "the launch did not start"
        time.sleep(0.1)
    out["nodes"] = sorted(rosnode.get_node_names())  # `pub -1` has 3 s left at most
    rospy.init_node("probe", disable_signals=True)
    def keep(topic):
        got = out["messages"].setdefault(topic, [])
        def cb(m):
            h = m._connection_header
            got.append([m.data, h["callerid"], h.get("latching", "0")])
        return cb
    subs = [rospy.Subscriber(t, c, keep(t)) for t, c in
            [("/chatter", String), ("/latched", String), ("/g/rel", Int32)]]
    time.sleep(1.5)
    state = master.getSystemState()
    out["publishers"] = {t: sorted(ns) for t, ns in state[0]}
    time.sleep(3.5)
    out["nodes_later"] = sorted(n for n in rosnode.get_node_names() if n != "/probe")
finally:
    os.killpg(proc.pid, signal.SIGINT)
    try:
        text, _ = proc.communicate(timeout=30)
    except subprocess.TimeoutExpired:
        os.killpg(proc.pid, signal.SIGKILL)
        text, _ = proc.communicate()
out["lines"] = [re.sub(r"\x1b\[[0-9;]*m|\x1b\]2;[^\x07]*\x07", "", line)
                for line in text.splitlines()]
print(json.dumps(out))
'''


_COMPARED = re.compile(
    r"process\[(?:pub|latched|one|g/rel)-\d\]: started with pid \[\d+\]"
    r"|\[(?:pub|latched|one|g/rel)-\d\] (?:process has died \[[^\]]*\]\.|process has finished cleanly"
    r"|killing on exit)"
    r"|publishing and latching message[^\n]*?(?:terminate|seconds)|ERROR: [^\n]*")


def _compared(lines: list[str]) -> list[str]:
    """roslaunch's lines about the rostopic processes and what they printed, in a stable order
    (the processes share roslaunch's pipe: their output interleaves with roslaunch's, even
    inside a line, as a print's newline is a write of its own).  Left out: the core's
    ``[rosout-1] killing on exit`` and ``[master] ...`` (ddes's runner leaves the core
    running)."""
    found = _COMPARED.findall("\n".join(lines))
    return sorted(re.sub(r"pid \[\d+\]", "pid [N]", f) for f in found)


@pytest.mark.ros
def test_launch_nodes_match_real_roslaunch(ros_python: Runner) -> None:
    real = ros_python(REAL_LAUNCH, stdin=LAUNCH, as_json=True, timeout=180)
    world = World(seed=0)
    lines: list[str] = []
    runner = LaunchRunner(world, load_launch(LAUNCH, {}, RosPack(), anon_seed=0),
                          out=lines.append)
    runner.start(print_summary=False)  # starts its own core: rosout-1, as real roslaunch
    world.run(until=0.2)  # the probe starts once every topic is published
    nodes = sorted(world.nodes)
    got = {t: listen(world, t, c) for t, c in
           [("/chatter", String), ("/latched", String), ("/g/rel", Int32)]}
    world.run(until=1.7)
    publishers = {t: sorted(e.publisher_nodes()) for t, e in world.master.topics.items()
                  if e.publishers}
    world.run(until=5.2)
    nodes_later = sorted(n for n in world.nodes if n != "/probe")
    runner.shutdown()
    # the same nodes, under the launch names, before and after `pub -1` has exited
    assert nodes == real["nodes"] == ["/g/rel", "/latched", "/one", "/pub", "/rosout"]
    assert nodes_later == real["nodes_later"] == ["/g/rel", "/latched", "/pub", "/rosout"]
    # the same publishers; rostopic pub does not log on /rosout
    for topic in ("/chatter", "/latched", "/g/rel", "/one", "/rosout"):
        assert publishers.get(topic) == real["publishers"].get(topic), topic
    # what arrives: data, caller id and latching, for each topic
    for topic, msgs in got.items():
        assert {tuple(m[1:]) for m in msgs} == {tuple(m) for m in real["messages"][topic]}
    assert len(real["messages"]["/latched"]) == len(got["/latched"]) == 1
    # what roslaunch and rostopic print about these processes
    assert _compared(lines) == _compared(real["lines"])
