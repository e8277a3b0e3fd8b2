"""``rosbag record`` and ``rosbag play`` as launch-file nodes (the bundled ``rosbag`` package).

The course's launch files run them as ``<node pkg="rosbag" type="record" .../>`` and
``<node pkg="rosbag" type="play" args="--clock -r 0.5 $(find pkg)/data/x.bag"/>``: the node
is named as the launch file names it, the recording is written when the launch ends (or the
node is killed), and a ``required`` player ends the launch when the bag is done.
"""

from __future__ import annotations

import textwrap
from pathlib import Path

import pytest

from ddes import Time
from ddes.console.tooling import ToolContext, run_command_result
from ddes.console.toolkit import node_pid
from ddes.graph.world import World
from ddes.launch import load_launch
from ddes.launch.runtime import LaunchRunner, start_core
from ddes.msg import get_message_class
from ddes.nodes import start_node
from ddes.rosbag import Bag
from ddes.rospack import RosPack

String = get_message_class("std_msgs/String")
Clock = get_message_class("rosgraph_msgs/Clock")


@pytest.fixture
def pkg(tmp_path: Path) -> Path:
    """A package ``demo`` (launch/ and data/) next to ddes's bundled packages."""
    folder = tmp_path / "src" / "demo"
    (folder / "launch").mkdir(parents=True)
    (folder / "data").mkdir()
    (folder / "package.xml").write_text("<package><name>demo</name></package>\n")
    return folder


def launch(pkg: Path, xml: str, world: World | None = None) -> tuple[LaunchRunner, list[str]]:
    """Start ``xml`` (the body of a <launch>) on a world with a roscore; returns runner, lines."""
    path = pkg / "launch" / "test.launch"
    path.write_text("<launch>\n" + textwrap.dedent(xml).strip("\n") + "\n</launch>\n")
    rospack = RosPack([pkg.parent], use_env=False)
    world = world or World(seed=0, package_path=[pkg.parent])
    start_core(world)
    lines: list[str] = []
    runner = LaunchRunner(world, load_launch(path, {}, rospack, anon_seed=0), rospack=rospack,
                          out=lines.append)
    runner.start(print_summary=False)
    return runner, lines


def after(lines: list[str], marker: str) -> list[str]:
    """The lines after the first one equal to ``marker``."""
    return lines[lines.index(marker) + 1:]


def chatter_bag(path: Path, n: int = 5) -> None:
    """``n`` messages on /chatter, 0.1 s apart from t = 100 s (as a 10 Hz talker leaves them)."""
    with Bag(str(path), "w") as bag:
        for i in range(n):
            bag.write("/chatter", String(data=f"hello world {i}"), Time(100, i * 100_000_000))


# -- record -------------------------------------------------------------------------------------

def test_a_launch_records_the_talker_and_writes_the_bag_when_it_ends(pkg: Path) -> None:
    out = pkg / "out.bag"
    runner, lines = launch(pkg, f"""
        <node pkg="roscpp_tutorials" type="talker" name="talker"/>
        <node pkg="rosbag" type="record" name="rec" args="-O {out} /chatter" output="screen"/>
        """)
    world = runner.world
    assert "/rec" in world.nodes  # named as the launch file names it
    world.run(until=1.05)
    assert not out.exists() and (pkg / "out.bag.active").exists()
    runner.shutdown()  # Ctrl+C on roslaunch
    assert after(lines, f"process[rec-2]: started with pid [{node_pid('/rec')}]") == [
        "[ INFO] [0.000000000]: Subscribing to /chatter",
        f"[ INFO] [0.000000000]: Recording to '{out}'.",
        "[rec-2] killing on exit",
        "[talker-1] killing on exit",
        "shutting down processing monitor...",
        "... shutting down processing monitor complete",
        "done",
    ]
    bag = Bag(str(out))
    # hello world 0 went out at 0 s, before the connection was up (1 ms later), as in ROS
    assert [(m.message.data, m.timestamp) for m in bag.read_messages()] == [
        (f"hello world {i}", Time(0, i * 100_000_000)) for i in range(1, 11)]
    (conn,) = bag.get_connections()
    assert conn.header == {"callerid": "/talker", "latching": "0",
                           "md5sum": String._md5sum, "message_definition": String._full_text,
                           "topic": "/chatter", "type": "std_msgs/String"}


def test_record_all_with_a_relative_name_writes_in_the_working_directory(
        pkg: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(tmp_path)
    runner, _lines = launch(pkg, """
        <node pkg="roscpp_tutorials" type="talker" name="talker"/>
        <node pkg="rosbag" type="record" name="rec" args="-a -O out.bag"/>
        """)
    runner.world.run(until=2.5)
    runner.shutdown()
    bag = Bag(str(tmp_path / "out.bag"))
    assert sorted(bag.get_type_and_topic_info().topics) == ["/chatter", "/rosout", "/rosout_agg"]
    assert bag.get_message_count("/chatter") == 24  # 0.1 .. 2.4 s


def test_record_with_a_duration_ends_by_itself(pkg: Path) -> None:
    out = pkg / "d.bag"
    runner, lines = launch(pkg, f"""
        <node pkg="roscpp_tutorials" type="talker" name="talker"/>
        <node pkg="rosbag" type="record" name="rec" args="--duration 0.5 -O {out} /chatter"/>
        """)
    runner.world.run(until=1)
    assert lines[-1] == "[rec-2] process has finished cleanly"
    assert Bag(str(out)).get_message_count() == 5
    assert not runner.done


def test_rosnode_kill_writes_the_bag(pkg: Path) -> None:
    out = pkg / "k.bag"
    runner, lines = launch(pkg, f"""
        <node pkg="roscpp_tutorials" type="talker" name="talker"/>
        <node pkg="rosbag" type="record" name="rec" args="-O {out} /chatter"/>
        """)
    world = runner.world
    world.run(until=0.55)
    killed = run_command_result(ToolContext(world), "rosnode kill /rec")
    assert killed.out == "killing /rec\nkilled\n"
    assert lines[-1] == "[rec-2] process has finished cleanly"
    assert Bag(str(out)).get_message_count() == 5
    assert "/rec" not in world.nodes and "/talker" in world.nodes


def test_rosrun_rosbag_record_is_anonymous_and_logs_as_roscpp() -> None:
    world = World(seed=0)
    logged: list[str] = []
    world.log_output = lambda line, level: logged.append(line)
    node = start_node(world, "rosbag", "record", argv=["-a", "-l", "3"])
    world.run(until=0.1)
    assert node.name.startswith("/record_") and node.is_shutdown()
    assert logged == ["Specifying a count is not valid with automatic topic subscription."]
    assert world.trace.filter(kind="node.exit")[-1].details == {"code": 1}


@pytest.mark.parametrize(("args", "expected"), [
    ("--bogus /chatter", "[ERROR] [0.000000000]: Error reading options: unrecognised option "
                         "'--bogus'"),
    ("-O", "[ERROR] [0.000000000]: Error reading options: the required argument for option "
           "'--output-name' is missing"),
    ("-l x /chatter", "[ERROR] [0.000000000]: Error reading options: the argument ('x') for "
                      "option '--limit' is invalid"),
    ("--duration 5x /chatter", "[ERROR] [0.000000000]: Error reading options: Duration unit "
                               "must be s, m, or h (got 'x' in '5x')"),
    ("--split --duration 5 /chatter", "[ERROR] [0.000000000]: Error reading options: ddes does "
                                      "not model --split (see docs/bags.md)"),
    ("", "No topics specified."),
])
def test_bad_record_command_lines_exit_1(pkg: Path, args: str, expected: str) -> None:
    runner, lines = launch(pkg, f"""
        <node pkg="rosbag" type="record" name="rec" args="{args}"/>
        """)
    runner.world.run(until=0.001)
    assert after(lines, f"process[rec-1]: started with pid [{node_pid('/rec')}]")[:3] == [
        expected,
        f"[rec-1] process has died [pid {node_pid('/rec')}, exit code 1, cmd rosbag/record "
        + (f"{args} " if args else "") + "__name:=rec].",
        "all processes on machine have died, roslaunch will exit",
    ]


def test_the_date_of_default_names_comes_from_the_world(pkg: Path, tmp_path: Path,
                                                        monkeypatch: pytest.MonkeyPatch) -> None:
    from ddes.rosbag.recorder import set_record_date

    monkeypatch.chdir(tmp_path)
    monkeypatch.setenv("DDES_BAG_DATE", "1999-12-31-23-59-59")  # the world's own date wins
    world = World(seed=0, package_path=[pkg.parent])
    set_record_date(world, "2024-03-01T12:00:00")
    world.run(until=61.5)
    runner, lines = launch(pkg, """
        <node pkg="rosbag" type="record" name="rec" args="-a -o course"/>
        """, world)
    world.run(until=62)
    runner.shutdown()
    assert (tmp_path / "course_2024-03-01-12-01-01.bag").exists()


def test_ddes_bag_date_names_default_recordings(pkg: Path, tmp_path: Path,
                                                monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(tmp_path)
    monkeypatch.setenv("DDES_BAG_DATE", "2024-03-01-12-00-00")
    runner, lines = launch(pkg, """
        <node pkg="rosbag" type="record" name="rec" args="-a" output="screen"/>
        """)
    runner.world.run(until=2)
    runner.shutdown()
    assert "[ INFO] [0.000000000]: Recording to '2024-03-01-12-00-00.bag'." in lines
    assert (tmp_path / "2024-03-01-12-00-00.bag").exists()
    monkeypatch.setenv("DDES_BAG_DATE", "March the first")
    runner, lines = launch(pkg, """
        <node pkg="rosbag" type="record" name="rec" args="-a"/>
        """)
    runner.world.run(until=0.001)
    assert after(lines, f"process[rec-1]: started with pid [{node_pid('/rec')}]")[0].startswith(
        "[ERROR] [0.000000000]: Error reading options: recording date 'March the first' is not "
        "a date")


# -- play ---------------------------------------------------------------------------------------

def test_a_required_player_with_clock_ends_the_launch(pkg: Path) -> None:
    chatter_bag(pkg / "data" / "x.bag")
    runner, lines = launch(pkg, """
        <param name="use_sim_time" value="true"/>
        <node pkg="rosbag" type="play" name="player" output="screen" required="true"
              args="--clock -r 0.5 $(find demo)/data/x.bag"/>
        """)
    world = runner.world
    heard: list[tuple[float, str]] = []
    clock: list[float] = []
    listener = world.create_node("listener")  # on simulated time: /use_sim_time is set
    listener.subscribe("chatter", String,
                       lambda m: heard.append((listener.get_time(), m.data)))
    listener.subscribe("/clock", Clock, lambda m: clock.append(m.clock.to_sec()))
    world.run(runner.finished)
    # 0.2 s delay, then 0.4 bag seconds at half speed
    assert world.now == 1_000_000_000
    assert heard == [(100 + i / 10, f"hello world {i}") for i in range(5)]
    assert clock[0] == 100.0 and clock[-1] == 100.4 and len(clock) > 50  # --hz 100
    data = str(pkg / "data" / "x.bag")
    assert after(lines, f"process[player-1]: started with pid [{node_pid('/player')}]") == [
        f"[ INFO] [0.000000000]: Opening {data}",
        "",
        "Waiting 0.2 seconds after advertising topics... done.",
        "",
        "Hit space to toggle paused, or 's' to step.",
        " [RUNNING]  Bag Time:    100.350000   Duration: 0.350000 / 0.400000",
        "Done.",
        "=" * 80 + "REQUIRED process [player-1] has died!\nprocess has finished cleanly\n"
        "Initiating shutdown!\n" + "=" * 80,
        "shutting down processing monitor...",
        "... shutting down processing monitor complete",
        "done",
    ]


def test_a_player_without_output_screen_prints_only_its_errors(pkg: Path) -> None:
    chatter_bag(pkg / "data" / "x.bag")
    runner, lines = launch(pkg, """
        <node pkg="rosbag" type="play" name="player" args="$(find demo)/data/x.bag"/>
        <node pkg="rosbag" type="play" name="broken" args="$(find demo)/data/none.bag"/>
        """)
    runner.world.run(runner.finished)
    none = pkg / "data" / "none.bag"
    assert after(lines, f"process[broken-2]: started with pid [{node_pid('/broken')}]") == [
        f"[FATAL] [0.000000000]: {none}: no such bag file",  # play.cpp: ROS_FATAL, exit 1
        f"[broken-2] process has died [pid {node_pid('/broken')}, exit code 1, cmd rosbag/play "
        f"{none} __name:=broken].",
        "[player-1] process has finished cleanly",  # its standard output went to the log
        "all processes on machine have died, roslaunch will exit",
        "shutting down processing monitor...",
        "... shutting down processing monitor complete",
        "done",
    ]


def test_loop_plays_until_the_launch_ends(pkg: Path) -> None:
    chatter_bag(pkg / "data" / "x.bag")
    runner, lines = launch(pkg, """
        <node pkg="rosbag" type="play" name="player" output="screen"
              args="--loop -q $(find demo)/data/x.bag"/>
        """)
    world = runner.world
    heard: list[str] = []
    listener = world.create_node("listener")
    listener.subscribe("chatter", String, lambda m: heard.append(m.data))
    world.run(until=2.05)
    assert heard[:6] == [f"hello world {i}" for i in (0, 1, 2, 3, 4, 0)]
    assert len(heard) >= 20 and not runner.done
    runner.shutdown()
    assert "Done." not in lines


def test_play_command_line_errors(pkg: Path) -> None:
    runner, lines = launch(pkg, """
        <node pkg="rosbag" type="play" name="p1" args="--clock"/>
        <node pkg="rosbag" type="play" name="p2" args="--topics /a"/>
        """)
    runner.world.run(until=0.001)
    assert "[ERROR] [0.000000000]: Error reading options: You must specify at least one bag to " \
           "play back." in lines
    assert "[ERROR] [0.000000000]: Error reading options: When using --topics or " \
           "--pause-topics, --bags should be specified to list bags." in lines


def test_rosrun_rosbag_play_ends_with_the_bag(tmp_path: Path) -> None:
    chatter_bag(tmp_path / "x.bag", 2)
    world = World(seed=0)
    logged: list[str] = []
    world.log_output = lambda line, level: logged.append(line)
    node = start_node(world, "rosbag", "play", argv=["x.bag"], cwd=str(tmp_path))
    world.run(until=1)
    assert node.name.startswith("/play_") and node.is_shutdown()
    assert logged == ["[ INFO] [0.000000000]: Opening x.bag", "",
                      "Waiting 0.2 seconds after advertising topics... done.", "",
                      "Hit space to toggle paused, or 's' to step.",
                      " [RUNNING]  Bag Time:    100.000000   Duration: 0.000000 / 0.100000",
                      "Done."]
    assert world.trace.filter(kind="node.exit")[-1].details == {"code": 0}


def test_exclude_alone_records_all_with_record_cpps_warning(pkg: Path, tmp_path: Path,
                                                            monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(tmp_path)
    runner, lines = launch(pkg, """
        <node pkg="roscpp_tutorials" type="talker" name="talker"/>
        <node pkg="rosbag" type="record" name="rec" args="-x /rosout.* -O out.bag"/>
        """)
    runner.world.run(until=1.05)
    runner.shutdown()
    # standard error reaches the screen without output="screen", as in roslaunch
    assert after(lines, f"process[rec-2]: started with pid [{node_pid('/rec')}]")[:2] == [
        "Warning: Exclusion regex given, but no topics to subscribe to.",
        "Adding implicit 'record all'."]
    assert sorted(Bag(str(tmp_path / "out.bag")).get_type_and_topic_info().topics) == ["/chatter"]


def test_rosrun_rosbag_record_and_play_in_the_console(tmp_path: Path,
                                                      monkeypatch: pytest.MonkeyPatch) -> None:
    from ddes.console.shell import Console

    monkeypatch.chdir(tmp_path)
    console = Console(seed=0, out=lambda _line: None)
    console.run("rostopic pub -r 10 /chatter std_msgs/String 'data: hi' &")
    started = console.run("rosrun rosbag record -O c.bag /chatter &")
    assert "[ INFO] [0.000000000]: Subscribing to /chatter\n" in started
    console.run("sleep 1.05")
    (recorder,) = [n for n in console.world.nodes if n.startswith("/record_")]
    console.run(f"rosnode kill {recorder}")
    assert Bag(str(tmp_path / "c.bag")).get_message_count() == 10
    console.run("rosrun rosbag play c.bag &")
    played = console.run("sleep 2")
    assert played == ("Waiting 0.2 seconds after advertising topics... done.\n\n"
                      "Hit space to toggle paused, or 's' to step.\n"
                      " [RUNNING]  Bag Time:      0.900000   Duration: 0.800000 / 0.900000\n"
                      "Done.\n")
    assert not [n for n in console.world.nodes if n.startswith("/play_")]
