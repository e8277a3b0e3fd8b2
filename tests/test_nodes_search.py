"""rosrun and roslaunch find a package's executables where ROS finds them: anywhere below the
package (rospy_tutorials keeps its scripts in ``001_talker_listener/`` …), executable files
only outside ``scripts/``/``nodes/``, several of one name refused with roslaunch's text."""

from __future__ import annotations

import os
import stat
from pathlib import Path

import pytest

import ddes
from ddes.errors import DdesError
from ddes.launch.runtime import ROSLaunchException
from ddes.nodes import AmbiguousNodeType, find_executables, find_script, start_node

UPSTREAM = Path(__file__).resolve().parents[2] / "shared" / "upstream"
RT = UPSTREAM / "ros_tutorials" / "rospy_tutorials"
needs_upstream = pytest.mark.skipif(not RT.is_dir(), reason="no ../shared/upstream here")


def _scripts(pkg: Path) -> list[Path]:
    return sorted(p for p in pkg.rglob("*") if p.is_file() and not p.name.startswith(".")
                  and os.stat(p).st_mode & stat.S_IXUSR)


@needs_upstream
def test_every_executable_of_rospy_tutorials_is_found() -> None:
    found = {p.name: p for p in _scripts(RT)}
    assert len([p for p in found.values() if "test" not in p.parts[-2]]) >= 17
    for name, path in found.items():
        assert find_script(RT, name) == path, name


@needs_upstream
def test_rosrun_starts_a_tutorial_script_from_its_numbered_folder() -> None:
    world = ddes.World(seed=1, package_path=[UPSTREAM / "ros_tutorials"], strict=False)
    world.log_output = False
    node = start_node(world, "rospy_tutorials", "talker.py")
    world.run(until=1.05)
    said = [e for e in world.trace.select(kind="topic.publish", source=node.name)
            if e.details["topic"] == "/chatter"]
    assert len(said) == 11  # 0.0, 0.1, …, 1.0 at 10 Hz


def _package(tmp_path: Path, files: dict[str, bool]) -> Path:
    pkg = tmp_path / "pkg"
    for rel, executable in files.items():
        path = pkg / rel
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text("#!/usr/bin/env python3\n")
        path.chmod(0o755 if executable else 0o644)
    return pkg


def test_an_executable_anywhere_below_the_package_is_found(tmp_path: Path) -> None:
    pkg = _package(tmp_path, {"test/node_a.py": True, "src/lib/tool": True,
                              "doc/readme.py": False, ".hidden/node_b.py": True})
    assert find_script(pkg, "node_a.py") == pkg / "test" / "node_a.py"
    assert find_script(pkg, "tool") == pkg / "src" / "lib" / "tool"
    assert find_script(pkg, "readme.py") is None  # not executable
    assert find_script(pkg, "node_b.py") is None  # hidden folders are skipped, as ROS does


def test_scripts_and_nodes_need_no_executable_bit(tmp_path: Path) -> None:
    """ddes's convenience (a zip drops the bit): scripts/ and nodes/ are searched first."""
    pkg = _package(tmp_path, {"scripts/talker.py": False, "test/talker.py": True})
    assert find_script(pkg, "talker.py") == pkg / "scripts" / "talker.py"


def test_several_executables_of_one_name_are_refused_with_roslaunchs_text(tmp_path: Path) -> None:
    pkg = _package(tmp_path, {"a/node.py": True, "b/node.py": True})
    with pytest.raises(AmbiguousNodeType) as err:
        find_script(pkg, "node.py", "pkg")
    assert str(err.value) == (f"multiple files named [node.py] in package [pkg]:\n- {pkg}/a/node.py"
                              f"\n- {pkg}/b/node.py\nPlease specify full path instead")
    assert isinstance(err.value, DdesError)


def test_a_link_loop_ends_the_search(tmp_path: Path) -> None:
    pkg = _package(tmp_path, {"a/x.py": True})
    (pkg / "a" / "loop").symlink_to(pkg)
    assert find_executables(pkg, "x.py") == [pkg / "a" / "x.py"]


def test_roslaunch_names_several_matches(tmp_path: Path) -> None:
    pkg = _package(tmp_path, {"a/node.py": True, "b/node.py": True})
    (pkg / "package.xml").write_text("<package format='2'><name>pkg</name><version>0.0.0</version>"
                                     "<description>x</description><maintainer email='a@b.c'>a"
                                     "</maintainer><license>BSD</license></package>")
    launch = tmp_path / "x.launch"
    launch.write_text('<launch><node pkg="pkg" type="node.py" name="n"/></launch>')
    from ddes.launch import load_launch
    from ddes.launch.runtime import LaunchRunner
    from ddes.rospack import RosPack

    rospack = RosPack([tmp_path], use_env=False)
    world = ddes.World(seed=1)
    runner = LaunchRunner(world, load_launch(launch, {}, rospack, anon_seed=0), rospack=rospack,
                          out=lambda line: None)
    with pytest.raises(ROSLaunchException, match=r"multiple files named \[node.py\] in package "
                                                 r"\[pkg\]"):
        runner.validate()


@pytest.mark.ros
@needs_upstream
def test_the_same_files_as_roslibs_find_node(ros_python, tmp_path: Path) -> None:  # type: ignore[no-untyped-def]
    names = sorted({p.name for p in _scripts(RT)} | {"talker", "missing.py"})
    real = ros_python(f"""
import json, os
from roslib.packages import _find_resource, _executable_filter
names = {names!r}
print(json.dumps({{n: _find_resource({str(RT)!r}, n, filter_fn=_executable_filter)
                  for n in names}}))
""", as_json=True)
    for name in names:
        ours = find_executables(RT, name)
        assert sorted(str(p) for p in ours) == sorted(real[name]), name
