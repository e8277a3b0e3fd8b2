"""``rosmsg`` in the console: the world's types, ``ddes rosmsg``'s output, real rosmsg's text."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import pytest

from ddes.cli.main import main
from ddes.console.rosmsg import rossrv
from ddes.console.shell import Console
from ddes.console.tooling import ToolContext
from ddes.graph.world import World

from .rostools import real_python_tool, ros_env, run_real

SESSION = """\
rosmsg show rospy_tutorials/HeaderString
rosmsg info -r rospy_tutorials/Floats
rosmsg md5 HeaderString
rosmsg package -s rospy_tutorials
rosmsg show Nope
rosmsg md5 std_msgs/Nope
rosmsg show std_msgs::String
"""

TRANSCRIPT = """\
$ rosmsg show rospy_tutorials/HeaderString
std_msgs/Header header
  uint32 seq
  time stamp
  string frame_id
string data

$ rosmsg info -r rospy_tutorials/Floats
float32[] data

$ rosmsg md5 HeaderString
[rospy_tutorials/HeaderString]: c99a9440709e4d4a9716d55b8270d5e7
$ rosmsg package -s rospy_tutorials
rospy_tutorials/Floats rospy_tutorials/HeaderString
$ rosmsg show Nope
Could not find msg 'Nope'
$ rosmsg md5 std_msgs/Nope
Cannot locate [std_msgs/Nope]
$ rosmsg show std_msgs::String
ERROR: rosmsg does not understand C++-style namespaces (i.e. '::'). Please refer to msg/srv \
types as 'package_name/Type'. (usage: rosmsg show [options] <message type>)
"""


def test_transcript() -> None:
    code, text = Console(seed=0).transcript(SESSION.splitlines(), keep_going=True)
    assert code == 1  # 'show Nope' and the '::' usage error fail; md5 exits 0 as rosmsg does
    assert text == TRANSCRIPT


@pytest.mark.parametrize("line", [
    "rosmsg show geometry_msgs/PoseStamped",
    "rosmsg info sensor_msgs/NavSatStatus",
    "rosmsg show -r std_msgs/Header",
    "rosmsg show String",
    "rosmsg show std_msgs/String.msg",
    "rosmsg md5 String",
    "rosmsg md5 std_msgs/Nope",
    "rosmsg md5 Nope",
    "rosmsg list",
    "rosmsg package actionlib_msgs",
    "rosmsg package -s std_msgs",
    "rosmsg packages",
    "rosmsg packages -s",
    "rosmsg show NoSuchType",
    "rosmsg show std_msgs/Nope",
    "rosmsg",
])
def test_same_output_as_ddes_rosmsg(console: Console, capsys: pytest.CaptureFixture[str],
                                    line: str) -> None:
    code = main(line.split())
    out, err = capsys.readouterr()
    result = console.execute(line)
    assert (result.code, result.out, result.err) == (code, out, err)


def test_unknown_package_is_ex_usage(console: Console) -> None:
    result = console.execute("rosmsg package nope_pkg")
    assert result.code == 64
    assert result.err.startswith("Invalid package: package 'nope_pkg' not found")


def test_uses_the_world_types(tmp_path: Path) -> None:
    (tmp_path / "my_pkg" / "msg").mkdir(parents=True)
    (tmp_path / "my_pkg" / "msg" / "Num.msg").write_text("int64 num  # a number\nint8 ONE=1\n")
    console = Console(World(package_path=[tmp_path]), out=lambda _line: None)
    assert console.run("rosmsg show Num") == "[my_pkg/Num]:\nint8 ONE=1\nint64 num\n\n"
    assert console.run("rosmsg package my_pkg") == "my_pkg/Num\n"
    assert "my_pkg" in console.run("rosmsg packages").split()
    assert "my_pkg" not in Console(out=lambda _line: None).run("rosmsg packages").split()


@pytest.mark.parametrize("line, text", [
    ("rosmsg show", "give the message type: the console reads no message type from standard "
                    "input (usage: rosmsg show [options] <message type>)"),
    ("rosmsg show a/B c/D", "you may only specify one message type"),
    ("rosmsg show std.msgs/String", "invalid message type 'std.msgs/String'. Please refer to "
                                    "msg/srv types as 'package_name/Type'."),
    ("rosmsg show -b x.bag std_msgs/String", "rosmsg show -b is not offered by ddes"),
    ("rosmsg md5", "give the message type"),
    ("rosmsg package", "give the package"),
    ("rosmsg frob", "unknown command 'rosmsg frob'; rosmsg commands: info, list, md5, package, "
                    "packages, show"),
])
def test_usage_errors_are_one_line(console: Console, line: str, text: str) -> None:
    result = console.execute(line)
    assert result.code == 1
    assert result.err.startswith("ERROR: ") and text in result.err
    assert result.err.count("\n") == 1


def test_help_and_usage(console: Console) -> None:
    assert console.run("rosmsg show -h").startswith(
        "Usage: rosmsg show [options] <message type>\n\nOptions:\n")
    usage = console.run("rosmsg")
    assert usage.startswith("rosmsg is a command-line tool for displaying information about ROS "
                            "Message types.\n\nCommands:\n\trosmsg show\tShow message description")
    assert console.run("rosmsg -h") == usage


def test_rossrv_on_the_world_types(tmp_path: Path) -> None:
    (tmp_path / "my_srvs" / "srv").mkdir(parents=True)
    (tmp_path / "my_srvs" / "srv" / "Add.srv").write_text("int32 a\n---\nint32 sum\n")
    ours: list[str] = []
    ctx = ToolContext(World(package_path=[tmp_path]), out=ours.append, err=ours.append)
    assert rossrv(ctx, ["show", "my_srvs/Add"]) == 0
    assert ours == ["int32 a\n---\nint32 sum\n"]
    ours.clear()
    assert rossrv(ctx, ["md5", "std_srvs/SetBool"]) == 0
    assert ours == ["09fb03525b03e7ea1fd3992bafd87e16"]


# -- real rosmsg ------------------------------------------------------------------------------------

@pytest.mark.ros
@pytest.mark.parametrize("line", [
    "rosmsg show geometry_msgs/PoseStamped",
    "rosmsg show rospy_tutorials/HeaderString",
    "rosmsg info -r std_msgs/Header",
    "rosmsg show --raw visualization_msgs/Marker",
    "rosmsg show sensor_msgs/NavSatStatus",
    "rosmsg show HeaderString",
    "rosmsg show Floats",
    "rosmsg show String",
    "rosmsg show Nope",
    "rosmsg show rospy_tutorials/Floats.msg",
    "rosmsg md5 geometry_msgs/Twist",
    "rosmsg md5 std_msgs/Header",
    "rosmsg md5 Twist",
    "rosmsg md5 rospy_tutorials/Nope",
    "rosmsg md5 Nope",
    "rosmsg package rospy_tutorials",
    "rosmsg package -s geometry_msgs",
    "rosmsg",
])
def test_same_text_as_real_rosmsg(console: Console, ros_python: Any, tmp_path: Path,
                                  line: str) -> None:
    code, out, err = run_real([*real_python_tool("rosmsg"), *line.split()[1:]], ros_env(tmp_path))
    # rospack's complaint about this machine's rosdep set-up is not rosmsg's output
    err = "".join(x for x in err.splitlines(keepends=True) if "rosdep" not in x)
    result = console.execute(line)
    assert (result.out, result.err) == (out, err)
    assert result.code == code


@pytest.mark.ros
def test_unknown_type_reads_as_real_rosmsg(console: Console, ros_python: Any,
                                           tmp_path: Path) -> None:
    code, _out, err = run_real([*real_python_tool("rosmsg"), "show", "rospy_tutorials/Nope"],
                               ros_env(tmp_path))
    result = console.execute("rosmsg show rospy_tutorials/Nope")
    assert result.code == code == 1
    # the same sentence up to where rosmsg prints its search path (a Python dict of folders)
    assert err.startswith("Unable to load msg [rospy_tutorials/Nope]: Cannot locate message "
                          "[Nope] in package [rospy_tutorials]")
    assert result.err.startswith("Unable to load msg [rospy_tutorials/Nope]: Cannot locate "
                                 "message [Nope] in package [rospy_tutorials]")
