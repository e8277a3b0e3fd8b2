"""ddes.compat.roslib: load_manifest, roslib.packages and roslib.message on the world's path."""

from __future__ import annotations

import json
import os
import textwrap
from pathlib import Path

import pytest

import ddes
from ddes.compat import roslib
from ddes.compat.roslib import message, packages
from ddes.compat.scripts import run_script
from ddes.errors import DdesError, DdesValueError
from ddes.rospack import BUNDLED_PATH, PackageNotFound


def _package(root: Path) -> Path:
    pkg = root / "src" / "my_pkg"
    for sub in ("scripts", "config", "sub/config", ".hidden", "msg"):
        (pkg / sub).mkdir(parents=True)
    (pkg / "package.xml").write_text("<package format='2'><name>my_pkg</name></package>")
    (pkg / "msg" / "Thing.msg").write_text("int32 value\n")
    for rel in ("config/params.yaml", "sub/config/params.yaml", ".hidden/params.yaml"):
        (pkg / rel).write_text("a: 1\n")
    tool = pkg / "scripts" / "tool.py"
    tool.write_text("print('tool')\n")
    tool.chmod(0o755)
    (pkg / "config" / "tool.py").write_text("# not executable\n")
    return pkg


def _run(tmp_path: Path, body: str) -> tuple[list[str], Path]:
    pkg = _package(tmp_path)
    path = tmp_path / "node.py"
    path.write_text(textwrap.dedent(body))
    out: list[str] = []
    world = ddes.World(seed=13, package_path=[tmp_path / "src"])
    done, _ = run_script(world, path, print_line=lambda text, _err: out.append(text))
    world.run(until=1.0)
    assert done.triggered and done.ok and done.value == 0
    return out, pkg


def test_a_script_loads_its_manifest_and_finds_its_files(tmp_path: Path) -> None:
    out, pkg = _run(tmp_path, """
        import roslib
        roslib.load_manifest("my_pkg")
        import roslib.packages
        from roslib import message
        import rospy

        rospy.init_node("finder")
        print(roslib.load_manifest("rospy_tutorials"))
        print(roslib.packages.get_pkg_dir("my_pkg"))
        print(roslib.packages.find_resource("my_pkg", "params.yaml"))
        print(roslib.packages.find_node("my_pkg", "tool.py"))
        print(roslib.packages.get_pkg_dir("nope", required=False))
        Thing = message.get_message_class("my_pkg/Thing")
        from my_pkg.msg import Thing as Direct
        print(Thing is Direct, Thing._type, message.get_message_class("my_pkg/Other"))
        print(message.get_service_class("rospy_tutorials/AddTwoInts")._type)
        try:
            roslib.load_manifest("nope")
        except Exception as exc:
            print(type(exc).__name__, str(exc).splitlines()[0])
        try:
            roslib.packages.get_pkg_dir("nope")
        except roslib.packages.InvalidROSPkgException as exc:
            print(str(exc).split(". ROS_ROOT")[0])
    """)
    assert out == [
        "None",
        str(pkg),
        str([str(pkg / "config" / "params.yaml"), str(pkg / "sub" / "config" / "params.yaml")]),
        str([str(pkg / "scripts" / "tool.py")]),
        "None",
        "True my_pkg/Thing None",
        "rospy_tutorials/AddTwoInts",
        "ResourceNotFound nope",
        "Cannot locate installation of package nope: "
        "b\"[rospack] Error: package 'nope' not found\"",
    ]


def test_errors_are_rospy_shaped_and_in_the_ddes_tree() -> None:
    with pytest.raises(packages.ResourceNotFound) as info:
        roslib.load_manifest("no_such_package")
    assert isinstance(info.value, PackageNotFound) and isinstance(info.value, DdesError)
    assert str(info.value) == f"no_such_package\nROS path [0]={BUNDLED_PATH}"
    with pytest.raises(packages.InvalidROSPkgException) as bad:
        packages.get_pkg_dir("no_such_package")
    assert isinstance(bad.value, packages.ROSPkgException)
    assert isinstance(bad.value, PackageNotFound)
    assert str(bad.value).endswith(f"ROS_ROOT[None] ROS_PACKAGE_PATH[{BUNDLED_PATH}]")
    with pytest.raises(packages.ResourceNotFound):
        packages.find_resource("no_such_package", "x")
    assert roslib.load_manifest("std_msgs") is None
    assert packages.get_pkg_dir("std_msgs") == os.path.normpath(BUNDLED_PATH / "std_msgs")
    assert str(packages.ResourceNotFound("x")) == "x"


def test_message_names_as_genpy_splits_them() -> None:
    assert message.get_message_class("Header")._type == "std_msgs/Header"
    assert message.get_message_class("std_msgs/String")._type == "std_msgs/String"
    assert message.get_message_class("std_msgs/Nope") is None
    assert message.get_message_class("std_msgs/") is None
    assert message.get_service_class("std_srvs/Empty")._type == "std_srvs/Empty"
    assert message.get_service_class("std_srvs/Nope") is None
    with pytest.raises(DdesValueError, match="message type is missing package name: String"):
        message.get_message_class("String")
    with pytest.raises(ValueError, match=r"invalid name \[a/b/c\]"):
        message.get_message_class("a/b/c")
    assert message.Time is ddes.Time and message.Duration is ddes.Duration


_REFERENCE = r"""
import json
import roslib
import roslib.message
import roslib.packages
out = {"load": repr(roslib.load_manifest("std_msgs")),
       "none": repr(roslib.packages.get_pkg_dir("no_such_package_x", required=False))}
try:
    roslib.load_manifest("no_such_package_x")
except Exception as exc:
    out["load_missing"] = [type(exc).__name__, str(exc).splitlines()[0],
                           str(exc).splitlines()[1].split("=")[0]]
try:
    roslib.packages.get_pkg_dir("no_such_package_x")
except Exception as exc:
    out["dir_missing"] = [type(exc).__name__, str(exc).split(". ROS_ROOT[")[0]]
try:
    roslib.packages.find_resource("no_such_package_x", "a")
except Exception as exc:
    out["find_missing"] = [type(exc).__name__, str(exc).splitlines()[0]]
out["find_none"] = roslib.packages.find_resource("std_msgs", "no_such_file.txt")
names = []
for name in ["std_msgs/String", "Header", "std_msgs/Nope", "std_msgs/", "nopkg_x/Nope",
             "String", "/String", "a/b/c", "geometry_msgs/PoseStamped"]:
    try:
        cls = roslib.message.get_message_class(name)
        names.append(cls._type if cls is not None else None)
    except ValueError as exc:
        names.append("ValueError: " + str(exc))
for name in ["std_srvs/Empty", "std_srvs/Nope", "std_msgs/String"]:
    cls = roslib.message.get_service_class(name)
    names.append(cls._type if cls is not None else None)
out["names"] = names
print(json.dumps(out))
"""


@pytest.mark.ros
def test_answers_and_texts_match_noetic(ros_python, tmp_path: Path) -> None:
    expected = ros_python(_REFERENCE, as_json=True)
    out, _ = _run(tmp_path, "import rospy\nrospy.init_node('rl')\n" + _REFERENCE)
    got = json.loads(out[0])
    assert expected["load_missing"] == ["ResourceNotFound", "no_such_package_x", "ROS path [0]"]
    assert got == expected
