"""``roscore`` in the console: already running (the console is a roscore), or started by it."""

from __future__ import annotations

import os
import re
import select
import signal
import socket
import subprocess
import time
from pathlib import Path
from typing import Any

import pytest

from ddes.console.shell import Console
from ddes.launch.runtime import node_pid, run_id
from ddes.world import World

from .rostools import real_tool, ros_env

HEADER = """\
ros_comm version 1.16.0


SUMMARY
========

PARAMETERS
 * /rosdistro: noetic
 * /rosversion: 1.16.0

NODES

"""

REFUSAL = ("RLException: roscore cannot run as another roscore/master is already running. \n"
           "Please kill other roscore/master processes before relaunching.\n"
           "The ROS_MASTER_URI is http://localhost:11311/\n")
#: What ddes adds after roscore's own refusal (a documented deviation, issue 42).
NOTE = ("[ddes] this console is the roscore: the master, the parameter server and /rosout already "
        "run here, until you exit the console; type the next command (rosrun, rostopic, ...) at "
        "this prompt, no other terminal is needed\n")
RUNNING = REFUSAL + NOTE


def test_already_running(console: Console) -> None:
    result = console.execute("roscore")
    assert (result.code, result.out, result.err) == (1, HEADER, RUNNING)


def test_starts_the_core_without_one() -> None:
    console = Console(seed=3, core=False, out=lambda _line: None)
    assert console.run("rosnode list") == "\n"
    code, text = console.transcript(["roscore", "rosnode list", "rosparam get /run_id",
                                     "roscore"])
    uuid = run_id(World(seed=3))  # drawn from the world's seed: the same on every run
    assert text == ("$ roscore\n" + HEADER + f"""\
auto-starting new master
process[master]: started with pid [{node_pid('master')}]
ROS_MASTER_URI=http://localhost:11311/

setting /run_id to {uuid}
process[rosout-1]: started with pid [{node_pid('/rosout')}]
started core service [/rosout]
$ rosnode list
/rosout
$ rosparam get /run_id
{uuid}
$ roscore
""" + HEADER + RUNNING)
    assert code == 1
    assert console.world.master.params.get_param("/run_id") == uuid
    assert re.fullmatch(r"[0-9a-f]{8}-[0-9a-f]{4}-1[0-9a-f]{3}-[0-9a-f]{4}-[0-9a-f]{12}", uuid)


def test_the_core_started_by_roscore_works() -> None:
    console = Console(core=False, out=lambda _line: None)
    console.run("roscore")
    console.run("rosrun --quiet rospy_tutorials talker &")
    assert console.run("rostopic list") == "/chatter\n/rosout\n/rosout_agg\n"
    assert console.run("rostopic echo -n 1 /rosout_agg/msg") == '"hello world 0.0"\n---\n'


@pytest.mark.parametrize("line, text", [
    ("roscore extra", "roscore does not take arguments (usage: roscore [options])"),
    ("roscore -p 11312", "roscore -p 11312: the console has one master, at "
                         "http://localhost:11311/"),
])
def test_errors(console: Console, line: str, text: str) -> None:
    result = console.execute(line)
    assert result.code == 1
    assert result.err.startswith(f"ERROR: {text}") and result.err.count("\n") == 1


def test_options_and_help(console: Console) -> None:
    assert console.execute("roscore -p 11311 -w 4 --sigint-timeout 2").err == RUNNING
    assert console.run("roscore -h").startswith("Usage: roscore [options]\n\nOptions:\n")


# -- real roscore -------------------------------------------------------------------------------------

_LOG_LINES = ("... logging to ", "Checking log directory for disk usage", "Press Ctrl-C to interrupt",
              "Done checking log file disk usage", "started roslaunch server ",
              "The traceback for the exception was written to the log file")


def _plain(text: str, port: int, version: tuple[str, str]) -> str:
    """Real roscore's text as ddes prints it: no escape codes, log-file or server lines, the
    console's port and ddes's Noetic version strings instead of Debian's."""
    # the terminal titles: the first with its line, the second (after ROS_MASTER_URI) leaves
    # its empty line, as in ddes roslaunch
    text = re.sub(r"\x1b\]2;[^\x07]*\x07", "", text.replace("\x1b]2;roscore\x07\n", "", 1))
    text = re.sub(r"\x1b\[[0-9;]*m", "", text)           # bold and red
    lines = [x for x in text.split("\n") if not x.startswith(_LOG_LINES)]
    text = "\n".join(lines).replace(f"localhost:{port}/", "localhost:11311/")
    distro, ros_version = version
    return (text.replace(f"/rosdistro: {distro}", "/rosdistro: noetic")
            .replace(f"ros_comm version {ros_version}", "ros_comm version 1.16.0")
            .replace(f"/rosversion: {ros_version}", "/rosversion: 1.16.0"))


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


def _read_until(proc: subprocess.Popen[bytes], marker: str, limit: float = 60.0) -> str:
    """What ``proc`` prints up to the line holding ``marker`` (read from the pipe unbuffered)."""
    assert proc.stdout is not None
    fd = proc.stdout.fileno()
    seen = b""
    deadline = time.monotonic() + limit
    key = marker.encode()
    while key not in seen or b"\n" not in seen[seen.index(key):]:
        left = deadline - time.monotonic()
        if left <= 0 or not select.select([fd], [], [], left)[0]:
            raise AssertionError(f"real roscore did not print {marker!r}; it printed:\n{seen!r}")
        chunk = os.read(fd, 65536)
        if not chunk:
            raise AssertionError(f"real roscore ended before {marker!r}:\n{seen!r}")
        seen += chunk
    text = seen.decode()
    return text[:text.index("\n", text.index(marker)) + 1]


@pytest.mark.ros
def test_same_text_as_real_roscore(ros_python: Any, tmp_path: Path) -> None:
    exe = real_tool("roscore")
    port = _free_port()
    env = ros_env(tmp_path / "home", ROS_HOSTNAME="localhost",
                  ROS_MASTER_URI=f"http://localhost:{port}/", PYTHONUNBUFFERED="1")
    first = subprocess.Popen([exe, "-p", str(port)], stdout=subprocess.PIPE,
                             stderr=subprocess.STDOUT, env=env)
    try:
        started = _read_until(first, "started core service [/rosout]")
        second = subprocess.run([exe, "-p", str(port)], capture_output=True, text=True, env=env,
                                timeout=120)
    finally:
        first.send_signal(signal.SIGINT)
        try:
            first.communicate(timeout=60)
        except subprocess.TimeoutExpired:
            first.kill()
            first.communicate()
    found = re.search(r"\* /rosdistro: (\S+)\n \* /rosversion: (\S+)\n", started)
    assert found is not None
    version = (found.group(1), found.group(2))
    # a second roscore: the header on stdout, the refusal on stderr, exit code 1
    console = Console(out=lambda _line: None)
    result = console.execute("roscore")
    assert result.code == second.returncode == 1
    assert result.out == _plain(second.stdout, port, version)
    assert result.err == _plain(second.stderr, port, version) + NOTE  # ddes's line after it
    # the first one, started where no master ran: the same lines, with its own pids and run id
    console = Console(core=False, out=lambda _line: None)
    ours = console.run("roscore")
    theirs = _plain(started, port, version)
    theirs = re.sub(r"started with pid \[\d+\]", "started with pid [PID]", theirs)
    theirs = re.sub(r"setting /run_id to \S+", "setting /run_id to RUN_ID", theirs)
    ours = re.sub(r"started with pid \[\d+\]", "started with pid [PID]", ours)
    ours = ours.replace(str(console.world.master.params.get_param("/run_id")), "RUN_ID")
    assert ours == theirs
