"""rosrun, sleep, time, jobs, kill, and the tutorial nodes' log lines."""

from __future__ import annotations

import textwrap
from pathlib import Path

import pytest

from ddes.console.shell import Console
from ddes.rospack import RosPack


def test_rospy_talker_and_listener_log_as_rospy(console: Console) -> None:
    assert console.run("rosrun rospy_tutorials talker &") == (
        "[1] rosrun rospy_tutorials talker\n[INFO] [0.000000]: hello world 0.0\n")
    assert console.run("rosrun rospy_tutorials listener &") == "[2] rosrun rospy_tutorials listener\n"
    assert console.run("sleep 0.2") == (
        "[INFO] [0.100000]: hello world 0.1\n"
        "[INFO] [0.100000]: /listener_2I heard hello world 0.1\n"
        "[INFO] [0.200000]: hello world 0.2\n"
        "[INFO] [0.200000]: /listener_2I heard hello world 0.2\n"
    )


def test_roscpp_talker_and_listener_log_as_roscpp(console: Console) -> None:
    console.run("rosrun roscpp_tutorials listener &")
    assert console.run("rosrun roscpp_tutorials talker &") == (
        "[2] rosrun roscpp_tutorials talker\n[ INFO] [0.000000000]: hello world 0\n")
    assert console.run("sleep 0.1") == (
        "[ INFO] [0.100000000]: hello world 1\n"
        "[ INFO] [0.100000000]: I heard: [hello world 1]\n"
    )
    assert console.run("rosnode list") == "/listener\n/rosout\n/talker\n"


def test_rosrun_arguments_rename_and_remap(console: Console) -> None:
    console.run("rosrun --quiet rospy_tutorials talker __name:=speaker chatter:=/talk _rate:=5 &")
    console.run("sleep 0.01")
    assert console.run("rosnode list") == "/rosout\n/speaker\n"
    assert "/talk\n" in console.run("rostopic list")
    assert console.run("rosparam get /speaker/rate") == "5\n"
    console.run("rosrun --quiet rospy_tutorials talker.py __ns:=/robot &")
    assert "/robot/talker_1\n" in console.run("rosnode list")


def test_quiet_hides_info_but_not_warnings(console: Console) -> None:
    console.run("rosrun --quiet rospy_tutorials talker &")
    assert console.run("sleep 1") == ""


def test_sleep_is_inclusive_and_time(console: Console) -> None:
    console.run("rostopic pub -r 1 /tick std_msgs/Empty &")
    console.run("rostopic echo /tick &")
    # Empty prints as an empty line; the tick at 0 s went out before echo's connection existed
    assert console.run("sleep 2") == "\n---\n" * 2  # at 1 and 2 s
    assert console.run("time") == "simulated time: 2.000000000 s\n"
    assert console.run("sleep 0.5s") == ""
    assert console.run("time") == "simulated time: 2.500000000 s\n"


def test_jobs_and_kill(console: Console) -> None:
    console.run("rosrun --quiet rospy_tutorials talker &")
    console.run("rostopic hz /chatter &")
    assert console.run("jobs") == (
        "[1]  Running                 rosrun --quiet rospy_tutorials talker &\n"
        "[2]  Running                 rostopic hz /chatter &\n")
    assert console.run("kill %1 %2") == (
        "[1]  Terminated              rosrun --quiet rospy_tutorials talker\n"
        "[2]  Terminated              rostopic hz /chatter\n")
    assert console.run("jobs") == ""
    assert console.run("rosnode list") == "/rosout\n"


def test_finished_background_job_is_reported_once(console: Console) -> None:
    console.run("rostopic pub -1 /x std_msgs/Empty &")
    console.run("sleep 4")
    assert console.run("jobs") == "[1]  Done                    rostopic pub -1 /x std_msgs/Empty\n"
    assert console.run("jobs") == ""


@pytest.mark.parametrize("line, text", [
    ("rosrun no_such_pkg talker &", "package 'no_such_pkg' not found"),
    ("rosrun rospy_tutorials no_such_node", "Couldn't find executable named no_such_node"),
    ("rosrun rospy_tutorials", "rosrun needs a package and a node type"),
    ("rosrun rospy_tutorials talker a:=b:=c &", "':='"),
    ("sleep", "sleep needs one argument"),
    ("sleep soon", "invalid time interval 'soon'"),
    ("sleep -1", "invalid time interval '-1'"),
    ("kill 12", "give a job as %N"),
    ("kill %7", "%7: no such job"),
    ("kill", "usage: kill %N"),
    ("time now", "time takes no arguments"),
    ("jobs -l", "jobs takes no arguments"),
])
def test_errors(console: Console, line: str, text: str) -> None:
    result = console.execute(line)
    assert result.code == 1
    assert result.err.startswith("ERROR: ") and text in result.err
    assert result.err.count("\n") == 1


def test_foreign_background_processes_are_jobs(console: Console) -> None:
    """Later tools (rosbag record ...) leave plain SimPy processes or nodes as jobs."""
    world = console.world
    ticks: list[int] = []

    def recorder():  # type: ignore[no-untyped-def]
        while True:
            yield world.env.timeout(500_000_000)
            ticks.append(world.now)

    console.ctx.background("rosbag record -a", world.env.process(recorder()))
    node = world.create_node("watcher")
    console.ctx.background("watcher", node)
    assert console.run("jobs") == ("[1]  Running                 rosbag record -a &\n"
                                   "[2]  Running                 watcher &\n")
    console.run("sleep 1")
    assert console.run("kill %1 %2") == ("[1]  Terminated              rosbag record -a\n"
                                         "[2]  Terminated              watcher\n")
    console.run("sleep 1")
    assert ticks == [500_000_000, 1_000_000_000]
    assert node.is_shutdown()


def test_log_router_without_a_trace(console: Console) -> None:
    console.world.trace.enabled = False
    console.run("rosrun --quiet rospy_tutorials talker &")
    # without the trace the router cannot tell nodes apart: everything prints
    assert console.run("sleep 0.1") == "[INFO] [0.100000]: hello world 0.1\n"


def test_foreign_job_done_is_reported_once(console: Console) -> None:
    world = console.world

    def short():  # type: ignore[no-untyped-def]
        yield world.env.timeout(1)

    console.ctx.background("short", world.env.process(short()))
    console.run("sleep 0.1")
    assert console.run("jobs") == "[1]  Done                    short\n"
    assert console.run("jobs") == ""


def _package(root: Path, scripts: dict[str, str]) -> RosPack:
    pkg = root / "mypkg"
    (pkg / "scripts").mkdir(parents=True)
    (pkg / "package.xml").write_text(
        '<?xml version="1.0"?><package format="2"><name>mypkg</name><version>0.0.0</version>'
        '<description>d</description><maintainer email="a@b.c">a</maintainer>'
        "<license>BSD</license></package>\n")
    for name, text in scripts.items():
        (pkg / "scripts" / name).write_text(textwrap.dedent(text))
    return RosPack([root])


def test_a_script_dying_before_init_node_shows_its_traceback(tmp_path: Path) -> None:
    rospack = _package(tmp_path, {
        "bad.py": """
            import rospy

            def load():
                raise ValueError("broken config")

            load()
            rospy.init_node("bad")
        """,
        "usage.py": """
            import sys
            print("usage: usage.py N")
            print("  N: how many", file=sys.stderr)
            sys.exit(2)
        """})
    console = Console(seed=0, rospack=rospack, out=lambda _line: None)
    result = console.execute("rosrun mypkg bad.py")
    assert (result.code, result.out) == (1, "")
    assert result.err == (
        "Traceback (most recent call last):\n"
        '  File "bad.py", line 7, in <module>\n'
        "    load()\n"
        '  File "bad.py", line 5, in load\n'
        '    raise ValueError("broken config")\n'
        "ValueError: broken config\n"
        "ERROR: mypkg/bad.py exited with code 1 before rospy.init_node: there is no node (check "
        "its arguments)\n")
    result = console.execute("rosrun mypkg usage.py")
    assert (result.out, result.err.splitlines()[0]) == ("usage: usage.py N\n", "  N: how many")
    code, text = console.transcript(["rosrun mypkg bad.py"])
    assert code == 1 and "ValueError: broken config\nERROR: mypkg/bad.py exited" in text
