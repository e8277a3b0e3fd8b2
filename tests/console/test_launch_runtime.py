"""Launch files at runtime: parameters first, nodes, remaps, respawn, required, output."""

from __future__ import annotations

import textwrap
from pathlib import Path

import pytest

from ddes.console.shell import Console
from ddes.console.toolkit import node_pid
from ddes.graph.world import World
from ddes.launch import load_launch
from ddes.launch.runtime import LaunchRunner, start_core
from ddes.rospack import RosPack

NODES_PY = '''
from ddes.nodes import NodeType


def blink(node):
    """Log, warn, then exit after ~param seconds (exit code from ~code)."""
    node.loginfo("blink up")
    node.logwarn("blink warns")
    yield node.sleep(node.get_param("~life", 0.5))
    return node.get_param("~code", 0)


def steady(node):
    """Log once and keep running (a plain main: the node spins)."""
    node.loginfo("steady up, greeting=%s", node.get_param("greeting", "none"))


def broken(node):
    """Fail at start-up, as a script with a bad import would."""
    raise RuntimeError("cannot start")


NODES = {
    "blink": NodeType(blink, name="blink"),
    "steady": NodeType(steady, name="steady"),
    "broken": NodeType(broken, name="broken"),
}
'''


@pytest.fixture
def pkg(tmp_path: Path) -> Path:
    """A package ``demo`` with node types blink, steady and broken."""
    folder = tmp_path / "src" / "demo"
    (folder / "launch").mkdir(parents=True)
    (folder / "package.xml").write_text("<package><name>demo</name></package>\n")
    (folder / "nodes.py").write_text(NODES_PY)
    return folder


@pytest.fixture
def con(pkg: Path) -> Console:
    return Console(rospack=RosPack([pkg.parent], use_env=False), out=lambda _line: None)


def write(pkg: Path, name: str, xml: str) -> Path:
    path = pkg / "launch" / name
    path.write_text(textwrap.dedent(xml))
    return path


def test_bundled_launch_with_include_remap_and_yaml(console: Console) -> None:
    out = console.run("roslaunch rospy_tutorials param_talker.launch &")
    assert out.startswith("[1] roslaunch rospy_tutorials param_talker.launch\n\nSUMMARY\n========\n\nPARAMETERS\n * /foo/gains/D: 3.0\n")
    assert "NODES\n  /\n    listener (roscpp_tutorials/listener)\n  /foo/\n" \
           "    param_talker (rospy_tutorials/param_talker)\n\n" in out
    assert ("ROS_MASTER_URI=http://localhost:11311\n\n"
            f"process[foo/param_talker-1]: started with pid [{node_pid('/foo/param_talker')}]\n"
            f"process[listener-2]: started with pid [{node_pid('/listener')}]\n") in out
    # the parameters were all set before the node read them
    assert "[INFO] [0.000000]: gains are 1.0, 2.0, 3.0\n" in out
    assert "[INFO] [0.000000]: /foo/param_talker/topic_name is chatter\n" in out
    assert console.run("sleep 1") == ("[INFO] [1.000000]: Hello World\n"
                                      "[ INFO] [1.000000000]: I heard: [Hello World]\n")
    info = console.run("rostopic info /foo/chatter")
    assert " * /foo/param_talker (" in info and " * /listener (" in info
    assert console.run("rosparam get /foo/gains") == "D: 3.0\nI: 2.0\nP: 1.0\n\n"


def test_launch_args_and_duration(console: Console) -> None:
    out = console.run("roslaunch --duration 1.5 rospy_tutorials param_talker.launch ns:=bar")
    assert "/bar/utterance is Hello World" in out
    assert out.endswith("[listener-2] killing on exit\n[bar/param_talker-1] killing on exit\n"
                        "shutting down processing monitor...\n"
                        "... shutting down processing monitor complete\ndone\n")
    assert console.world.now == 1_500_000_000
    assert console.run("rosnode list") == "/rosout\n"
    assert console.run("jobs") == ""


def test_roslaunch_by_path_and_kill(console: Console) -> None:
    from ddes.rospack import BUNDLED_PATH

    path = BUNDLED_PATH / "rospy_tutorials" / "launch" / "talker_listener.launch"
    console.run(f"roslaunch {path} &")
    assert console.run("rosnode list") == "/listener\n/rosout\n/talker\n"
    assert console.run("rosparam get /chatter/rate_hz") == "10\n"
    assert console.run("kill %1").endswith("done\n[1]  Terminated              "
                                           f"roslaunch {path}\n")
    assert console.run("rosnode list") == "/rosout\n"


def test_output_screen_and_log(con: Console, pkg: Path) -> None:
    write(pkg, "out.launch", """\
        <launch>
          <node pkg="demo" type="blink" name="shown" output="screen"><param name="life" value="9"/></node>
          <node pkg="demo" type="blink" name="hidden"><param name="life" value="9"/></node>
        </launch>
        """)
    out = con.run("roslaunch demo out.launch")
    assert "[INFO] [0.000000]: blink up\n[WARN] [0.000000]: blink warns\n" \
           "[WARN] [0.000000]: blink warns\n" in out
    assert out.count("blink up") == 1


def test_respawn_after_delay(con: Console, pkg: Path) -> None:
    write(pkg, "respawn.launch", """\
        <launch>
          <node pkg="demo" type="blink" name="b" respawn="true" respawn_delay="1">
            <param name="life" value="0.5"/>
          </node>
        </launch>
        """)
    con.run("roslaunch demo respawn.launch &")
    out = con.run("sleep 1.6")
    pid = node_pid("/b")
    assert out == ("[b-1] process has finished cleanly\n"  # at 0.5 s
                   "[b-1] restarting process\n"  # at 1.5 s
                   f"process[b-1]: started with pid [{pid}]\n"
                   "[WARN] [1.500000]: blink warns\n")
    assert con.run("rosnode list") == "/b\n/rosout\n"
    # killed nodes respawn too, as in roslaunch
    assert con.run("rosnode kill /b") == "killing /b\n[b-1] process has finished cleanly\nkilled\n"
    assert con.run("rosnode list") == "/rosout\n"
    assert con.run("sleep 1").startswith("[b-1] restarting process\n")
    assert con.run("rosnode list") == "/b\n/rosout\n"


def test_required_node_shuts_the_launch_down(con: Console, pkg: Path) -> None:
    write(pkg, "req.launch", """\
        <launch>
          <node pkg="demo" type="steady" name="s"/>
          <node pkg="demo" type="blink" name="r" required="true">
            <param name="life" value="0.25"/><param name="code" value="3"/>
          </node>
        </launch>
        """)
    con.run("roslaunch demo req.launch &")
    out = con.run("sleep 1")
    assert out == (
        "=" * 80 + "REQUIRED process [r-2] has died!\n"
        f"process has died [pid {node_pid('/r')}, exit code 3, cmd demo/blink __name:=r].\n"
        "Initiating shutdown!\n" + "=" * 80 + "\n"
        "[s-1] killing on exit\n"
        "shutting down processing monitor...\n"
        "... shutting down processing monitor complete\n"
        "done\n")
    assert con.run("rosnode list") == "/rosout\n"
    assert con.run("jobs").startswith("[1]  Done ")


def test_all_processes_died(con: Console, pkg: Path) -> None:
    write(pkg, "short.launch", """\
        <launch>
          <node pkg="demo" type="blink" name="x"><param name="life" value="0.1"/></node>
        </launch>
        """)
    # in the foreground, roslaunch returns when its last node has ended, as in ROS
    out = con.run("roslaunch demo short.launch")
    assert out.endswith("[x-1] process has finished cleanly\n"
                        "all processes on machine have died, roslaunch will exit\n"
                        "shutting down processing monitor...\n"
                        "... shutting down processing monitor complete\ndone\n")
    assert con.world.now == 100_000_000
    assert con.run("jobs") == ""


def test_start_up_failure_is_a_dead_process(con: Console, pkg: Path) -> None:
    write(pkg, "broken.launch", """\
        <launch>
          <node pkg="demo" type="steady" name="s"/>
          <node pkg="demo" type="broken" name="x"/>
        </launch>
        """)
    out = con.run("roslaunch demo broken.launch &")
    assert "RuntimeError: cannot start\n[x-2] process has died [pid " in out
    assert con.run("rosnode list") == "/rosout\n/s\n"


def test_params_only_and_rosparam_commands(con: Console, pkg: Path, tmp_path: Path) -> None:
    dump = tmp_path / "before.yaml"
    con.run("rosparam set /old/a 1")
    con.run("rosparam set /keep 2")
    write(pkg, "params.launch", f"""\
        <launch>
          <rosparam command="dump" file="{dump}" param="/old"/>
          <rosparam command="delete" param="/old"/>
          <param name="greeting" value="hi"/>
        </launch>
        """)
    out = con.run("roslaunch demo params.launch")
    assert out.endswith("No processes to monitor\nshutting down processing monitor...\n"
                        "... shutting down processing monitor complete\n")
    assert dump.read_text() == "a: 1\n"
    assert con.run("rosparam list") == "/greeting\n/keep\n/rosdistro\n/rosversion\n/run_id\n"


def test_runner_starts_a_core_when_there_is_none(pkg: Path) -> None:
    world = World(seed=3)
    lines: list[str] = []
    plan = load_launch('<launch><node pkg="demo" type="steady" name="s"/></launch>', {},
                       RosPack([pkg.parent], use_env=False))
    runner = LaunchRunner(world, plan, rospack=RosPack([pkg.parent], use_env=False),
                          out=lines.append)
    runner.start(print_summary=False)
    assert lines[:4] == ["auto-starting new master",
                         f"process[master]: started with pid [{node_pid('master')}]",
                         "ROS_MASTER_URI=http://localhost:11311", ""]
    assert lines[4].startswith("setting /run_id to ")
    assert lines[5:] == [f"process[rosout-1]: started with pid [{node_pid('/rosout')}]",
                         "started core service [/rosout]",
                         f"process[s-2]: started with pid [{node_pid('/s')}]"]
    assert start_core(world) is world.nodes["/rosout"]


@pytest.mark.parametrize("xml, args, text", [
    ("<launch><node pkg='demo' type='blink'/>\n</launch>", "",
     "bad.launch:1: <node pkg=\"demo\" type=\"blink\">"),
    ("<launch>\n  <arg name='robot'/>\n  <param name='r' value='$(arg robot)'/>\n</launch>", "",
     "bad.launch:3"),
    ("<launch><param name='p' value='$(find no_such_pkg)'/></launch>", "",
     "no_such_pkg"),
    ("<launch><node pkg='demo' type='nope' name='n'/></launch>", "",
     "cannot launch node of type [demo/nope]"),
    ("<launch><node pkg='gone' type='x' name='n'/></launch>", "",
     "package 'gone' not found"),
    ("<launch><arg name='a' default='1'/></launch>", "b:=2", "unused args [b]"),
    ("<launch><nodes/></launch>", "", "unrecognized tag <nodes>"),
    ("<launch><node pkg='demo'", "", "bad.launch"),
])
def test_launch_errors_are_one_line(con: Console, pkg: Path, xml: str, args: str,
                                    text: str) -> None:
    path = pkg / "launch" / "bad.launch"
    path.write_text(xml)
    result = con.execute(f"roslaunch demo bad.launch {args}")
    assert result.code == 1 and result.out == ""
    assert result.err.startswith("ERROR: ") and text in result.err
    assert result.err.count("\n") == 1
    assert con.world.nodes.keys() == {"/rosout"}


def test_roslaunch_introspection(console: Console) -> None:
    assert console.run("roslaunch --nodes rospy_tutorials param_talker.launch") == \
        "/foo/param_talker\n/listener\n"
    assert console.run("roslaunch --args /listener rospy_tutorials param_talker.launch") == \
        "roscpp_tutorials/listener chatter:=/foo/chatter __name:=listener\n"
    assert console.run("roslaunch --files rospy_tutorials talker_listener.launch").endswith(
        "rospy_tutorials/launch/talker_listener.launch\n")
    assert console.run("rosnode list") == "/rosout\n"


def test_rosrun_of_a_node_failing_at_start_up(con: Console) -> None:
    result = con.execute("rosrun demo broken")
    assert (result.code, result.err) == (
        1, "ERROR: demo/broken died at start-up: RuntimeError: cannot start\n")
    assert con.run("rosnode list") == "/rosout\n"
