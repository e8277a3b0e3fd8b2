"""``rospack`` in the console: find, list, depends, depends-on, as real rospack prints them."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import pytest

from ddes.console.rospack import depends, depends_on
from ddes.console.shell import Console
from ddes.graph.world import World
from ddes.rospack import BUNDLED_PATH, RosPack

from .rostools import real_tool, ros_env, run_real

_META = ('<version>1.0.0</version><description>{0}</description>'
         '<maintainer email="x@example.invalid">x</maintainer><license>BSD</license>')


def _package(root: Path, name: str, deps: str = "", folder: str | None = None) -> Path:
    path = root / (folder or name)
    path.mkdir(parents=True)
    (path / "package.xml").write_text(
        f'<?xml version="1.0"?>\n<package format="2">\n  <name>{name}</name>\n  '
        + _META.format(name) + f"\n  {deps}\n</package>\n")
    return path


@pytest.fixture
def workspace(tmp_path: Path) -> Path:
    """Packages a, b, c (a -> b -> c -> std_msgs, a -> c) and d (definitions only)."""
    ws = tmp_path / "ws"
    _package(ws, "a", "<build_depend>c</build_depend><depend>b</depend><exec_depend>c"
                      "</exec_depend>\n  <run_depend>b</run_depend><test_depend>c</test_depend>"
                      "<doc_depend>b</doc_depend><depend>std_msgs</depend>")
    _package(ws, "b", "<depend>c</depend>", folder="group/b")
    _package(ws, "c", "<depend>\n    std_msgs\n  </depend><build_export_depend>b"
                      "</build_export_depend>")
    (ws / "d" / "msg").mkdir(parents=True)
    (ws / "d" / "msg" / "Num.msg").write_text("int64 num\n")
    return ws


def _without_plain_folders(ws: Path) -> Path:
    """``ws`` without ``d``: rospack needs a package.xml, ddes also counts a folder of
    definitions as a package (docs/console.md)."""
    (ws / "d" / "msg" / "Num.msg").unlink()
    (ws / "d" / "msg").rmdir()
    (ws / "d").rmdir()
    return ws


def _console(ws: Path, bundled: bool = True) -> Console:
    return Console(World(package_path=[ws]), rospack=RosPack([ws], bundled=bundled),
                   out=lambda _line: None)


def test_transcript(workspace: Path) -> None:
    console = _console(workspace, bundled=False)
    code, text = console.transcript([
        "rospack find b", "rospack list", "rospack list-names", "rospack depends1 a",
        "rospack depends a", "rospack deps1 c", "rospack depends-on c", "rospack depends-on1 c",
        "rospack find nope", "rospack depends nope", "rospack depends-on nope", "rospack find",
        "rospack", "rospack bogus", "rospack list x", "rospack find a b",
        "rospack -q find nope"], keep_going=True)
    ws = str(workspace)
    assert text == f"""\
$ rospack find b
{ws}/group/b
$ rospack list
a {ws}/a
b {ws}/group/b
c {ws}/c
d {ws}/d
$ rospack list-names
a
b
c
d
$ rospack depends1 a
b
c
$ rospack depends a
c
b
$ rospack deps1 c
$ rospack depends-on c
a
b
$ rospack depends-on1 c
a
b
$ rospack find nope
[rospack] Error: package 'nope' not found
$ rospack depends nope
[rospack] Error: no such package nope
$ rospack depends-on nope
[rospack] Error: no such package nope
$ rospack find
[rospack] Error: no package given
$ rospack
[rospack] Error: no command given.  Try 'rospack help'
$ rospack bogus
[rospack] Error: command bogus not implemented
$ rospack list x
[rospack] Error: invalid option(s) given
$ rospack find a b
[rospack] Error: failed to parse command-line options: too many positional options have been \
specified on the command line
$ rospack -q find nope
"""
    assert code == 1


def test_bundled_packages(console: Console) -> None:
    assert console.run("rospack find roscpp_tutorials") == f"{BUNDLED_PATH}/roscpp_tutorials\n"
    assert console.run("rospack depends1 lecture4_actions") == "actionlib_msgs\nnav_msgs\n"
    assert console.run("rospack depends lecture4_actions") == "actionlib_msgs\nnav_msgs\n"
    assert console.run("rospack depends-on1 nav_msgs") == "lecture4_actions\n"
    listing = console.run("rospack list").splitlines()
    assert listing == sorted(listing)
    assert f"std_msgs {BUNDLED_PATH}/std_msgs" in listing
    assert console.run("rospack list-names").split() == [x.split()[0] for x in listing]


def test_exit_codes(console: Console) -> None:
    assert console.execute("rospack find nope").code == 1
    assert console.execute("rospack").code == 0  # rospack exits 0 without a command
    assert console.execute("rospack help").out.startswith(
        "USAGE: rospack <command> [options] [package]\n  Allowed commands:\n    help\n")
    assert console.execute("rospack help").out.endswith(
        " is used (if it contains a package.xml or manifest.xml).\n\n")
    assert console.run("rospack -h") == console.run("rospack help")


def test_package_of_the_working_directory(workspace: Path) -> None:
    console = _console(workspace)
    console.run(f"cd {workspace}/group/b")
    assert console.run("rospack find") == f"{workspace}/group/b\n"
    assert console.run("rospack depends1") == "c\n"
    console.run("roscd a")
    assert console.run("rospack depends1") == "b\nc\nstd_msgs\n"
    console.run("cd ..")
    assert console.execute("rospack find").err == "[rospack] Error: no package given\n"


def test_missing_dependencies_are_skipped(workspace: Path) -> None:
    _package(workspace, "e", "<exec_depend>message_runtime</exec_depend><depend>a</depend>")
    rp = RosPack([workspace])
    assert rp.depends1("e") == ["message_runtime", "a"]
    assert depends(rp, "e", direct=True) == ["a"]
    assert depends(rp, "e") == ["std_msgs", "c", "b", "a"]
    assert depends_on(rp, "a") == ["e"]
    assert depends_on(rp, "std_msgs") == ["a", "b", "c", "e"]


@pytest.fixture
def tangled(tmp_path: Path) -> Path:
    """x and y depend on each other, z on x, self on itself, broken has malformed XML."""
    root = tmp_path / "tangled"
    _package(root, "x", "<depend>y</depend>")
    _package(root, "y", "<depend>x</depend>")
    _package(root, "z", "<depend>x</depend>")
    _package(root, "self", "<depend>self</depend>")
    (root / "broken").mkdir()
    (root / "broken" / "package.xml").write_text("<package><name>broken</name>\n<depend>")
    return root


def test_cycles_and_bad_manifests(tangled: Path) -> None:
    console = _console(tangled)
    cycle = "[rospack] Error: maximum dependency depth exceeded (likely circular dependency: x, y)\n"
    assert (console.execute("rospack depends z").code, console.execute("rospack depends z").err) \
        == (1, cycle)
    assert console.execute("rospack depends-on x").err == cycle  # a cycle anywhere stops it
    assert console.run("rospack depends-on1 x") == "y\nz\n"
    result = console.execute("rospack depends1 self")
    assert (result.code, result.err) == (1, "[rospack] Error: package 'self' depends on itself\n")
    result = console.execute("rospack depends broken")
    assert (result.code, result.err) == (
        1, f"[rospack] Error: error parsing manifest of package broken at {tangled}/broken/"
           "package.xml\n")
    assert console.run("rospack depends-on1 std_msgs") == ""  # unreadable ones are skipped


@pytest.mark.parametrize("line, text", [
    ("rospack export --lang=cpp --attrib=cflags std_msgs", "rospack export is not offered by "
                                                            "ddes"),
    ("rospack profile", "rospack profile is not offered by ddes"),
])
def test_commands_not_offered(console: Console, line: str, text: str) -> None:
    result = console.execute(line)
    assert result.code == 1 and result.err.startswith("ERROR: ") and text in result.err


def test_option_errors(console: Console) -> None:
    assert console.execute("rospack find --deps-only std_msgs").err == \
        "[rospack] Error: invalid option(s) given\n"
    assert console.execute("rospack find --foo std_msgs").err == \
        "[rospack] Error: failed to parse command-line options: unrecognised option '--foo'\n"
    assert console.execute("rospack depends --lang").err.startswith(
        "[rospack] Error: failed to parse command-line options: the required argument")


# -- real rospack -----------------------------------------------------------------------------------

def _real_lines(text: str) -> list[str]:
    """The lines of a real rospack's output, without the complaints about this machine's rosdep."""
    return [x for x in text.splitlines()
            if x not in ("could not find rosdep cache, continuing without it",
                         "the rosdep view is empty: call 'sudo rosdep init' and 'rosdep update'")]


@pytest.mark.ros
@pytest.mark.parametrize("args", [
    "find a", "find b", "find nope", "depends1 a", "deps1 a", "depends a", "depends b",
    "depends1 c", "depends c", "depends nope", "depends1 nope",
    "depends-on nope", "depends-on1 nope", "find", "", "bogus", "list x",
    "list-names x", "help", "-q find nope", "find --deps-only a",
    "find roscpp_tutorials", "depends-on1 nav_msgs", "depends1 nav_msgs",
])
def test_same_text_as_real_rospack(workspace: Path, ros_python: Any, tmp_path: Path,
                                   args: str) -> None:
    # not 'find a b': rospack prints its "too many positional options" error only sometimes
    # (the quiet flag it checks is not yet set when the command line fails to parse)
    exe = real_tool("rospack")
    env = ros_env(tmp_path / "home", [_without_plain_folders(workspace)])
    code, out, err = run_real([exe, *args.split()], env, cwd=tmp_path)
    result = _console(workspace).execute(f"rospack {args}")
    assert result.out.splitlines() == _real_lines(out)
    assert result.err.splitlines() == _real_lines(err)
    assert result.code == code


@pytest.mark.ros
@pytest.mark.parametrize("args", ["depends z", "depends1 self", "depends self", "depends-on1 x",
                                  "depends1 z", "find x"])
def test_cycles_like_real_rospack(tangled: Path, ros_python: Any, tmp_path: Path,
                                  args: str) -> None:
    exe = real_tool("rospack")
    (tangled / "broken" / "package.xml").unlink()  # real rospack aborts on it (SIGABRT)
    code, out, err = run_real([exe, *args.split()], ros_env(tmp_path / "home", [tangled]))
    result = _console(tangled).execute(f"rospack {args}")
    assert (result.out.splitlines(), result.err.splitlines()) == \
        (_real_lines(out), _real_lines(err))
    assert result.code == code


@pytest.mark.ros
@pytest.mark.parametrize("args", ["depends-on c", "depends-on1 c", "depends-on b",
                                  "depends-on1 a"])
def test_depends_on_matches_real_rospack(workspace: Path, ros_python: Any, tmp_path: Path,
                                         args: str) -> None:
    exe = real_tool("rospack")
    code, out, _err = run_real([exe, *args.split()],
                               ros_env(tmp_path / "home", [_without_plain_folders(workspace)]))
    result = _console(workspace).execute(f"rospack {args}")
    assert result.code == code == 0
    assert result.out.splitlines() == sorted(_real_lines(out))  # rospack: hash-table order


@pytest.mark.ros
def test_list_matches_real_rospack(workspace: Path, ros_python: Any, tmp_path: Path) -> None:
    exe = real_tool("rospack")
    env = ros_env(tmp_path / "home", [_without_plain_folders(workspace)])
    ours = _console(workspace).run("rospack list").splitlines()
    # the machine's own ROS packages are listed too: keep those on ddes's package path
    theirs = [x for x in _real_lines(run_real([exe, "list"], env)[1])
              if x.split()[1].startswith((str(workspace), str(BUNDLED_PATH)))]
    assert ours == theirs
    names = _real_lines(run_real([exe, "list-names"], env)[1])
    assert _console(workspace).run("rospack list-names").splitlines() == \
        [n for n in names if n in {x.split()[0] for x in theirs}]


@pytest.mark.ros
def test_package_of_the_directory_like_real_rospack(workspace: Path, ros_python: Any,
                                                    tmp_path: Path) -> None:
    exe = real_tool("rospack")
    env = ros_env(tmp_path / "home", [_without_plain_folders(workspace)])
    here = workspace / "group" / "b"
    console = _console(workspace)
    console.run(f"cd {here}")
    for args in (["find"], ["depends1"], ["depends"]):
        code, out, _err = run_real([exe, *args], env, cwd=here)
        assert console.run(" ".join(["rospack", *args])).splitlines() == _real_lines(out)
        assert code == 0
