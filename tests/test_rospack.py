"""``RosPack.depends1``: a package's run-time dependencies, read from package.xml as rospack."""

from __future__ import annotations

import tempfile
from pathlib import Path

import pytest
from hypothesis import given
from hypothesis import strategies as st

from ddes.errors import DdesError, ResourceLimitError
from ddes.rospack import (
    DEPEND_TAGS,
    MAX_MANIFEST_BYTES,
    InvalidManifest,
    PackageNotFound,
    RosPack,
)

_HEAD = '<?xml version="1.0"?>\n<package format="2">\n  <name>{0}</name>\n'


def _write(root: Path, name: str, body: str) -> Path:
    folder = root / name
    folder.mkdir(parents=True, exist_ok=True)
    (folder / "package.xml").write_text(_HEAD.format(name) + body + "</package>\n")
    return folder


def test_rospack_order_and_tags(tmp_path: Path) -> None:
    _write(tmp_path, "p", "<depend>d1</depend><build_depend>b</build_depend>"
                          "<exec_depend> e1 </exec_depend><test_depend>t</test_depend>"
                          "<run_depend>r1</run_depend><doc_depend>doc</doc_depend>"
                          "<buildtool_depend>catkin</buildtool_depend><depend>e1</depend>"
                          "<build_export_depend>x</build_export_depend>"
                          "<export><depend>nested</depend></export>")
    assert RosPack([tmp_path]).depends1("p") == ["r1", "e1", "d1"]


def test_bundled_manifests() -> None:
    rp = RosPack()
    assert rp.depends1("lecture4_actions") == ["message_runtime", "actionlib_msgs", "nav_msgs"]
    assert rp.depends1("std_msgs") == []


def test_folder_of_definitions_has_none(tmp_path: Path) -> None:
    (tmp_path / "defs" / "msg").mkdir(parents=True)
    assert RosPack([tmp_path]).depends1("defs") == []


def test_errors(tmp_path: Path) -> None:
    rp = RosPack([tmp_path], bundled=False)
    with pytest.raises(PackageNotFound, match="package 'nope' not found"):
        rp.depends1("nope")
    _write(tmp_path, "me", "<depend>me</depend>")
    with pytest.raises(InvalidManifest, match="package 'me' depends on itself") as info:
        rp.refresh()
        rp.depends1("me")
    assert info.value.rospack_text == "package 'me' depends on itself"
    (tmp_path / "bad").mkdir()
    (tmp_path / "bad" / "package.xml").write_text("<package><name>bad</name><depend>")
    rp.refresh()
    with pytest.raises(InvalidManifest, match=r"error parsing manifest of package bad at .*: "
                                              r"no element found \(line 1, column 33\); fix the XML") as info:
        rp.depends1("bad")
    assert info.value.rospack_text == \
        f"error parsing manifest of package bad at {tmp_path}/bad/package.xml"
    assert isinstance(info.value, DdesError)


def test_doctype_and_size_are_refused(tmp_path: Path) -> None:
    (tmp_path / "dtd").mkdir()
    (tmp_path / "dtd" / "package.xml").write_text(
        '<?xml version="1.0"?>\n<!DOCTYPE package [<!ENTITY a "aaaaaaaaaa">]>\n'
        "<package><name>dtd</name><depend>&a;</depend></package>\n")
    (tmp_path / "big").mkdir()
    (tmp_path / "big" / "package.xml").write_text(
        "<package><name>big</name>" + " " * MAX_MANIFEST_BYTES + "</package>")
    rp = RosPack([tmp_path], bundled=False)
    with pytest.raises(InvalidManifest, match=r"<!DOCTYPE package> is not allowed"):
        rp.depends1("dtd")
    with pytest.raises(ResourceLimitError, match="more than 1048576"):
        rp.depends1("big")


_NAMES = st.sampled_from(["a", "b", "c", "std_msgs", "nav_msgs", "roscpp"])
_ELEMENTS = st.lists(st.tuples(st.sampled_from([*DEPEND_TAGS, "build_depend", "test_depend",
                                                "doc_depend", "license"]), _NAMES), max_size=12)


@given(_ELEMENTS)
def test_depends1_is_rospacks_rule(elements: list[tuple[str, str]]) -> None:
    body = "".join(f"  <{tag}>{name}</{tag}>\n" for tag, name in elements)
    expected: list[str] = []
    for tag in DEPEND_TAGS:  # every <run_depend>, then <exec_depend>, then <depend>
        for t, name in elements:
            if t == tag and name not in expected:
                expected.append(name)
    with tempfile.TemporaryDirectory() as tmp:
        _write(Path(tmp), "pkg", body)
        assert RosPack([tmp], bundled=False).depends1("pkg") == expected


def test_a_package_is_named_by_its_package_xml_not_its_folder(tmp_path: Path) -> None:
    folder = tmp_path / "src" / "folder_name"
    folder.mkdir(parents=True)
    (folder / "package.xml").write_text(_HEAD.format("real_name") + "</package>\n")
    (tmp_path / "defs" / "msg").mkdir(parents=True)  # no package.xml: the folder's name
    rp = RosPack([tmp_path])
    assert rp.get_path("real_name") == folder
    assert "folder_name" not in rp
    assert rp.get_path("defs") == tmp_path / "defs"
    with pytest.raises(PackageNotFound):
        rp.get_path("folder_name")


def _pkg(folder: Path, name: str) -> Path:
    folder.mkdir(parents=True, exist_ok=True)
    (folder / "package.xml").write_text(f"<package><name>{name}</name></package>")
    return folder


def test_a_catkin_workspace_is_found_from_anywhere_inside_it(tmp_path: Path) -> None:
    from ddes.rospack import command_package_path, working_folder_paths, workspace_of

    ws = tmp_path / "catkin_ws"
    pkg = _pkg(ws / "src" / "smb_highlevel_controller", "smb_highlevel_controller")
    (ws / "devel").mkdir()
    for start in (ws, ws / "src", pkg, ws / "devel"):
        assert workspace_of(start) == ws.absolute(), start
        assert working_folder_paths(start)[0] == (ws / "src").absolute()
    rospack = RosPack(command_package_path({}, pkg))
    assert rospack.get_path("smb_highlevel_controller") == pkg.absolute()


def test_an_exercise_folder_holding_a_package_is_on_the_path(tmp_path: Path) -> None:
    from ddes.rospack import command_package_path

    exercise = tmp_path / "ex4b"
    _pkg(exercise / "smb_follow_path", "smb_follow_path")
    paths = command_package_path({"DDES_PACKAGE_PATH": "/elsewhere"}, exercise)
    assert paths == [Path("/elsewhere"), exercise.absolute()]  # the variable first
    assert RosPack(paths).get_path("smb_follow_path") == (exercise / "smb_follow_path").absolute()
    # a package folder itself
    assert command_package_path({}, exercise / "smb_follow_path") == [
        (exercise / "smb_follow_path").absolute()]


def test_a_folder_without_packages_adds_nothing_and_a_big_one_is_not_searched(
        tmp_path: Path) -> None:
    from ddes.rospack import LOOK_BELOW_ENTRIES, command_package_path

    assert command_package_path({}, tmp_path) == []
    home = tmp_path / "home"
    for i in range(LOOK_BELOW_ENTRIES + 5):
        (home / f"d{i:05d}").mkdir(parents=True)
    _pkg(home / "zzz" / "pkg", "pkg")  # sorted after the first entries looked at
    assert command_package_path({}, home) == []


def test_package_not_found_says_where_it_looked_and_what_to_do(tmp_path: Path) -> None:
    with pytest.raises(PackageNotFound) as info:
        RosPack([tmp_path], bundled=False).get_path("smb_follow_path")
    text = str(info.value)
    assert f"searched: {tmp_path}" in text
    assert "Start ddes in the folder that holds the package" in text
    assert "DDES_PACKAGE_PATH=/path/to/parent" in text
