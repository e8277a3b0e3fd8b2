"""How long a console command runs: foreground until it ends, a script's --until, the background,
and what Python scheduled before the command (issue 14, items 2-4)."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

from ddes.console.shell import Console
from ddes.errors import ROSConsoleError


def test_a_foreground_rosrun_runs_until_its_node_exits(console: Console) -> None:
    """The slides: the client after the server prints Sum: 42 and the prompt comes back."""
    assert console.run("rosrun roscpp_tutorials add_two_ints_server &") == \
        "[1] rosrun roscpp_tutorials add_two_ints_server\n"
    assert console.run("rosrun roscpp_tutorials add_two_ints_client 20 22") == (
        "[ INFO] [0.000300000]: request: x=20, y=22\n"
        "[ INFO] [0.000300000]:   sending back response: [42]\n"
        "[ INFO] [0.000400000]: Sum: 42\n")
    assert console.world.now == 400_000  # it ran exactly until the client exited
    assert console.run("rosnode list") == "/add_two_ints_server\n/rosout\n"


def test_rosrun_returns_its_nodes_exit_code(console: Console) -> None:
    result = console.execute("rosrun roscpp_tutorials add_two_ints_client 3")
    assert result.code == 1
    assert result.out == "[ INFO] [0.000000000]: usage: add_two_ints_client X Y\n"


def test_a_never_ending_command_in_a_script_says_so(console: Console) -> None:
    result = console.execute("rostopic echo /chatter")
    assert result.code == 1
    assert result.err == (
        "ERROR: 'rostopic echo' runs until Ctrl+C in ROS and would never end here: give a count "
        "(-n), --duration SECONDS (simulated), end the line with & to keep it running in the "
        "background, or give the script a time limit (ddes console --until SECONDS)\n")


def test_a_script_time_limit_ends_what_runs_until_ctrl_c() -> None:
    console = Console(seed=0, until=0.35, out=lambda _line: None)
    code, text = console.transcript([
        "rosrun --quiet roscpp_tutorials talker &",
        "rostopic echo /chatter/data",
        "time",
        "rosrun roscpp_tutorials listener",  # at the limit: it starts, and ends as on Ctrl+C
        "rosnode list",
        "sleep 1",
        "time",
    ])
    assert code == 0
    assert text == (
        "$ rosrun --quiet roscpp_tutorials talker &\n"
        "[1] rosrun --quiet roscpp_tutorials talker\n"
        "$ rostopic echo /chatter/data\n"
        '"hello world 1"\n---\n"hello world 2"\n---\n"hello world 3"\n---\n'
        "$ time\nsimulated time: 0.350000000 s\n"
        "$ rosrun roscpp_tutorials listener\n"
        "$ rosnode list\n/rosout\n/talker\n"
        "$ sleep 1\n"
        "$ time\nsimulated time: 1.350000000 s\n")


def test_a_foreground_node_that_never_exits_in_a_script_without_a_limit() -> None:
    console = Console(seed=0, out=lambda _line: None)
    result = console.execute("rosrun --quiet rospy_tutorials listener")
    assert result.code == 1
    assert result.err.startswith("ERROR: rosrun --quiet rospy_tutorials listener: still waiting "
                                 "for /listener_1 to exit after 600 simulated seconds; "
                                 "/listener_1 runs until Ctrl+C in ROS; end the line with &")
    assert console.run("rosnode list") == "/rosout\n"  # stopped, as Ctrl+C would


def test_a_background_job_honours_its_own_duration(console: Console) -> None:
    console.run('rostopic pub -r 20 --duration 0.3 /t std_msgs/String "data: x" &')
    console.run("rostopic echo /t/data &")
    out = console.run("sleep 1")
    # 0.05 .. 0.25 s at 20 Hz (the message at 0 s left before the echo was connected), then the
    # job ended by itself at 0.3 s
    assert out.count('"x"') == 5
    assert console.run("jobs") == (
        "[1]  Done                    rostopic pub -r 20 --duration 0.3 /t std_msgs/String "
        "'data: x'\n"
        "[2]  Running                 rostopic echo /t/data &\n")


def test_what_python_scheduled_starts_before_the_command(console: Console) -> None:
    world = console.world
    string = world.messages.get_message_class("std_msgs/String")

    def late_start():  # type: ignore[no-untyped-def]
        node = world.create_node("from_python")
        node.advertise("/py", string)
        yield world.env.timeout(0)

    world.env.process(late_start())  # no run, no `sleep 0`
    assert "/py\n" in console.run("rostopic list")
    assert "/from_python\n" in console.run("rosnode list")


def test_rtf_shows_and_sets_the_pacing(console: Console) -> None:
    assert console.run("rtf") == (
        "real-time factor: off (commands run as fast as possible; one that runs until Ctrl+C "
        "in ROS needs -n, --duration or &)\n")
    assert console.run("rtf 2.5").startswith("real-time factor: 2.5 ")
    assert console.rtf == 2.5
    with pytest.raises(ROSConsoleError, match="invalid real-time factor '0'"):
        console.run("rtf 0")
    console.run("rtf off")
    assert console.rtf is None


def test_the_command_line_takes_until_and_checks_rtf(tmp_path: Path) -> None:
    script = tmp_path / "s.txt"
    script.write_text("rosrun --quiet roscpp_tutorials talker &\nrostopic hz /chatter\ntime\n")
    cmd = [sys.executable, "-m", "ddes.cli.main", "console", "--script", str(script)]
    done = subprocess.run([*cmd, "--until", "2.5"], capture_output=True, text=True, check=False)
    assert done.returncode == 0, done.stderr
    assert done.stdout.endswith("$ time\nsimulated time: 2.500000000 s\n")
    assert done.stdout.count("average rate: 10.000") == 2
    bad = subprocess.run([*cmd, "--until", "soon"], capture_output=True, text=True, check=False)
    assert bad.returncode == 2 and "invalid time limit 'soon'" in bad.stderr
    bad = subprocess.run([*cmd, "--rtf", "-1"], capture_output=True, text=True, check=False)
    assert bad.returncode == 2 and "invalid real-time factor '-1'" in bad.stderr
