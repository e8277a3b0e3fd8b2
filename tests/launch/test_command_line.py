"""``roslaunch PKG FILE.launch arg:=value`` and ``roslaunch PATH arg:=value``."""

from __future__ import annotations

import pytest

from ddes.errors import ROSLaunchException
from ddes.launch import load_launch, resolve_launch_args

from .workspace import Workspace


def test_package_form_finds_the_file_anywhere_in_the_package(ws: Workspace) -> None:
    pkg = ws.package("bringup")
    ws.write("src/bringup/launch/robots/robot.launch", '<launch><arg name="n" default="1"/></launch>')
    path, args = resolve_launch_args(["bringup", "robot.launch", "n:=2", "_priv:=3"], ws.rospack)
    assert path == str(pkg / "launch" / "robots" / "robot.launch")
    assert args == {"n": "2"}  # _private:=value assignments are not launch args (rosgraph)
    assert load_launch(path, args, ws.rospack).args == {"n": "2"}


def test_path_form(ws: Workspace) -> None:
    f = ws.write("x.launch", "<launch/>")
    assert resolve_launch_args([str(f), "a:=1", "__ns:=/r"], ws.rospack) == (
        str(f), {"a": "1", "__ns": "/r"})


def test_hidden_folders_are_not_searched(ws: Workspace) -> None:
    ws.package("p")
    ws.write("src/p/.git/x.launch", "<launch/>")
    with pytest.raises(ROSLaunchException, match=r"\[x.launch\] is neither a launch file in "
                                                  r"package \[p\] nor is \[p\] a launch file name"):
        resolve_launch_args(["p", "x.launch"], ws.rospack)


def test_ambiguous_file_name(ws: Workspace) -> None:
    ws.package("p")
    ws.write("src/p/a/x.launch", "<launch/>")
    ws.write("src/p/b/x.launch", "<launch/>")
    with pytest.raises(ROSLaunchException, match=r"multiple files named \[x.launch\] in package "
                                                  r"\[p\]:\n- .*/a/x.launch\n- .*/b/x.launch"):
        resolve_launch_args(["p", "x.launch"], ws.rospack)


@pytest.mark.parametrize(("argv", "message"), [
    ([], "no launch file given"),
    (["a:=1"], "no launch file given"),
    (["/nonexistent.launch"], r"\[/nonexistent.launch\] is not a launch file name"),
    (["nopkg", "x.launch"], r"\[x.launch\] is neither a launch file in package \[nopkg\]"),
    (["a:=b:=c", "x.launch"], "':=' separators"),
])
def test_errors(ws: Workspace, argv: list[str], message: str) -> None:
    with pytest.raises(ROSLaunchException, match=message):
        resolve_launch_args(argv, ws.rospack)


def test_extra_words_after_a_path(ws: Workspace) -> None:
    f = ws.write("x.launch", "<launch/>")
    with pytest.raises(ROSLaunchException, match="unexpected arguments"):
        resolve_launch_args([str(f), "other.launch"], ws.rospack)
