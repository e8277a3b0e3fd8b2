"""``roscd``, ``pwd``, ``cd``, ``ls``: the console's own working directory, as rosbash's roscd."""

from __future__ import annotations

import os
import subprocess
from pathlib import Path
from typing import Any

import pytest

from ddes.console.roscd import NO_WORKSPACE
from ddes.console.shell import Console
from ddes.console.tooling import ToolContext, run_command
from ddes.graph.world import World
from ddes.rospack import BUNDLED_PATH

from .rostools import ROSBASH, ros_env

PKG = f"{BUNDLED_PATH}/rospy_tutorials"


def _listing(folder: str) -> str:
    """What ``ls`` prints for ``folder`` (other work adds files to the bundled packages)."""
    return "\n".join(sorted(n for n in os.listdir(folder) if not n.startswith(".")))


def test_transcript(console: Console) -> None:
    start = os.getcwd()
    code, text = console.transcript([
        "roscd", "roscd nope", "roscd rospy_tutorials", "pwd", "ls", "roscd rospy_tutorials/launch",
        "pwd", "ls", "roscd rospy_tutorials/nope", "pwd", "roscd std_msgs/msg/../", "pwd",
        "cd ..", "pwd", "cd rospy_tutorials/config", "pwd", "cd nope", "roscd a b"],
        keep_going=True)
    assert text == f"""\
$ roscd
{NO_WORKSPACE}
$ roscd nope
roscd: No such package/stack 'nope'
$ roscd rospy_tutorials
$ pwd
{PKG}
$ ls
{_listing(PKG)}
$ roscd rospy_tutorials/launch
$ pwd
{PKG}/launch
$ ls
{_listing(PKG + "/launch")}
$ roscd rospy_tutorials/nope
bash: cd: {PKG}/nope: No such file or directory
$ pwd
{PKG}/launch
$ roscd std_msgs/msg/../
$ pwd
{BUNDLED_PATH}/std_msgs
$ cd ..
$ pwd
{BUNDLED_PATH}
$ cd rospy_tutorials/config
$ pwd
{PKG}/config
$ cd nope
bash: cd: nope: No such file or directory
$ roscd a b
usage: roscd package

Jump to target package.
"""
    assert code == 1
    assert os.getcwd() == start  # the process's own directory never moves


def test_no_argument_message(console: Console) -> None:
    assert NO_WORKSPACE == (
        "Neither ROS_WORKSPACE is set nor a catkin workspace is listed in CMAKE_PREFIX_PATH.  "
        "Please set ROS_WORKSPACE or source a catkin workspace to use roscd with no arguments.")
    result = console.execute("roscd")
    assert (result.code, result.out, result.err) == (1, NO_WORKSPACE + "\n", "")


def test_failed_cd_keeps_the_directory(console: Console, tmp_path: Path) -> None:
    (tmp_path / "file.txt").write_text("x")
    console.run(f"cd {tmp_path}")
    result = console.execute("cd file.txt")
    assert (result.code, result.err) == (1, "bash: cd: file.txt: Not a directory\n")
    assert console.run("pwd") == f"{tmp_path}\n"
    assert console.execute("cd a b").err == "bash: cd: too many arguments\n"
    console.run("cd")
    assert console.run("pwd") == os.path.expanduser("~") + "\n"


def test_ls(console: Console, tmp_path: Path) -> None:
    (tmp_path / "b").mkdir()
    (tmp_path / "a.yaml").write_text("x: 1\n")
    (tmp_path / ".hidden").write_text("")
    console.run(f"cd {tmp_path}")
    assert console.run("ls") == "a.yaml\nb\n"
    assert console.run("ls a.yaml") == "a.yaml\n"
    assert console.run("ls b") == ""
    result = console.execute("ls missing")
    assert (result.code, result.err) == (2, "ls: cannot access 'missing': No such file or "
                                            "directory\n")
    assert console.execute("ls -l").err.startswith("ERROR: ls takes no options")


def test_files_open_from_the_console_directory(console: Console, tmp_path: Path) -> None:
    console.run("roscd rospy_tutorials/config")
    console.run("rosparam load param_talker.yaml /loaded")
    assert console.run("rosparam get /loaded/utterance") == "Hello World\n"
    console.run(f"cd {tmp_path}")
    console.run("rosparam dump out.yaml /loaded/gains")
    assert (tmp_path / "out.yaml").read_text() == "D: 3.0\nI: 2.0\nP: 1.0\n"
    (tmp_path / "note.txt").write_text("a note")
    console.run("rosparam set -t note.txt /note")
    assert console.run("rosparam get /note") == "a note\n"
    console.run("roscd rospy_tutorials/launch")
    assert console.run("roslaunch --nodes talker_listener.launch") == "/talker\n/listener\n"
    console.run("cd ..")
    assert console.run("roslaunch --nodes launch/talker_listener.launch") == \
        "/talker\n/listener\n"
    assert console.run("roslaunch --nodes rospy_tutorials talker_listener.launch") == \
        "/talker\n/listener\n"


def test_tool_context_from_python() -> None:
    ctx = ToolContext(World())
    run_command(ctx.world, "roscd roscpp_tutorials", ctx)
    assert ctx.cwd == f"{BUNDLED_PATH}/roscpp_tutorials"
    assert ctx.resolve_path("srv/TwoInts.srv") == f"{ctx.cwd}/srv/TwoInts.srv"
    assert run_command(ctx.world, "pwd", ctx) == ctx.cwd + "\n"


# -- real roscd (rosbash) ----------------------------------------------------------------------------

@pytest.mark.ros
@pytest.mark.parametrize("arg", ["", "nope", "rospy_tutorials", "rospy_tutorials/launch",
                                 "rospy_tutorials/nope", "rospy_tutorials//launch/",
                                 "std_msgs/msg/../", "nope/x", "a b", "--help",
                                 "rospy_tutorials/launch/talker.launch"])
def test_same_as_real_roscd(console: Console, ros_python: Any, tmp_path: Path, arg: str) -> None:
    if not os.path.isfile(ROSBASH):
        pytest.skip("rosbash's roscd is not installed")
    script = f'source {ROSBASH}\ncd {tmp_path}\nroscd {arg}\necho "rc=$?"\npwd\n'
    proc = subprocess.run(["bash", "-c", script], capture_output=True, text=True, timeout=120,
                          env=ros_env(tmp_path / "home"))
    lines = proc.stdout.split("\n")  # ..., "rc=N", pwd, ""
    out, rc_line, real_pwd = "\n".join(lines[:-3]), lines[-3], lines[-2]
    console.run(f"cd {tmp_path}")
    result = console.execute(f"roscd {arg}".strip())
    assert result.out == (out + "\n" if out else "")
    assert console.run("pwd") == real_pwd + "\n"
    # bash names its script in the message ("bash: line 3: cd: ..."); an interactive bash says
    # "bash: cd: ..."; rosbash's roscd returns 0 after a failed cd, ddes 1
    if proc.stderr:
        assert result.err == "bash: cd: " + proc.stderr.split(" cd: ", 1)[1]
        assert (rc_line, result.code) == ("rc=0", 1)
    else:
        assert (result.err, result.code) == ("", int(rc_line[3:]))
