"""roslaunch input against hostile files: bombs, deep nesting, recursion, endless files (issue 13)."""

from __future__ import annotations

import os
import tracemalloc
from collections.abc import Callable
from pathlib import Path

import pytest

from ddes.errors import ROSLaunchException
from ddes.launch import load_launch
from ddes.launch.loader import MAX_NESTING

BILLION_LAUGHS_YAML = "\n".join(
    ["a0: &a0 [x,x,x,x,x,x,x,x,x]"]
    + [f"a{i}: &a{i} [" + ",".join([f"*a{i - 1}"] * 9) + "]" for i in range(1, 10)])


def _peak(fn: Callable[[], object]) -> int:
    """Peak bytes allocated while ``fn()`` runs (tracemalloc): memory, not CPU time, shows
    hostile input refused before it is expanded or read, and holds on a loaded machine."""
    tracemalloc.start()
    try:
        fn()
        return tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()


def _groups(n: int, inner: str = "") -> str:
    return "<launch>" + "<group>" * n + inner + "</group>" * n + "</launch>"


def test_a_yaml_alias_bomb_in_rosparam_is_refused() -> None:
    def hostile() -> None:
        with pytest.raises(ROSLaunchException, match=r"<string>:1: <rosparam>: .*alias bomb"):
            load_launch(f"<launch><rosparam><![CDATA[{BILLION_LAUGHS_YAML}]]></rosparam></launch>")
        value = BILLION_LAUGHS_YAML.replace("&", "&amp;").replace("\n", "&#10;")
        with pytest.raises(ROSLaunchException, match="alias bomb"):
            load_launch(f'<launch><param name="p" type="yaml" value="{value}"/></launch>')
    assert _peak(hostile) < 8 * 2**20


def test_a_hostile_angle_expression_in_rosparam_is_refused() -> None:
    def hostile() -> None:
        with pytest.raises(ROSLaunchException, match="invalid radian expression"):
            load_launch("<launch><rosparam>x: !radians 9**9**9</rosparam></launch>")
        with pytest.raises(ROSLaunchException, match="invalid degree value"):
            load_launch("<launch><rosparam>x: !degrees 9**9**9</rosparam></launch>")
    assert _peak(hostile) < 8 * 2**20


def test_an_xml_entity_bomb_is_refused_with_its_doctype() -> None:
    ents = '<!ENTITY a "lollollollollol">' + "".join(
        f'<!ENTITY {chr(98 + i)} "' + f"&{chr(97 + i)};" * 10 + '">' for i in range(8))
    bomb = f'<?xml version="1.0"?><!DOCTYPE launch [{ents}]><launch><arg name="x" default="&i;"/></launch>'
    def hostile() -> None:
        with pytest.raises(ROSLaunchException, match="DOCTYPE launch.*not allowed"):
            load_launch(bomb)
        with pytest.raises(ROSLaunchException, match="DOCTYPE"):
            load_launch('<!DOCTYPE launch SYSTEM "file:///etc/passwd"><launch/>')
    assert _peak(hostile) < 8 * 2**20


def test_deep_groups_are_refused_not_a_recursion_error() -> None:
    with pytest.raises(ROSLaunchException, match="nested more than 128 elements deep"):
        load_launch(_groups(450))
    with pytest.raises(ROSLaunchException, match="nested more than 128 elements deep"):
        load_launch(_groups(100_000))
    plan = load_launch(_groups(120, "<param name=\"p\" value=\"1\"/>"))
    assert plan.params == {"/p": 1}


def test_a_file_including_itself_is_refused_naming_the_chain(tmp_path: Path) -> None:
    f = tmp_path / "self.launch"
    f.write_text(f'<launch><group><include file="{f}"/></group></launch>')
    with pytest.raises(ROSLaunchException, match=r"nested more than 40 deep") as info:
        load_launch(f)
    assert f"included from {f}:1" in str(info.value)


def test_groups_and_includes_together_are_bounded(tmp_path: Path) -> None:
    for i in range(40):
        nxt = f'<include file="{tmp_path}/f{i + 1}.launch"/>' if i < 39 else ""
        (tmp_path / f"f{i}.launch").write_text(_groups(4, nxt))
    with pytest.raises(ROSLaunchException, match=f"nest more than {MAX_NESTING} deep in all"):
        load_launch(tmp_path / "f0.launch")


@pytest.mark.parametrize("attr", ["textfile", "binfile"])
def test_devices_fifos_and_directories_are_refused_before_reading(tmp_path: Path,
                                                                   attr: str) -> None:
    fifo = tmp_path / "fifo"
    os.mkfifo(fifo)
    for path, kind in [("/dev/zero", "a device"), (fifo, "a FIFO"), (tmp_path, "a directory")]:
        with pytest.raises(ROSLaunchException, match=f"{attr} {path} is {kind}"):
            load_launch(f'<launch><param name="p" {attr}="{path}"/></launch>')
    with pytest.raises(ROSLaunchException, match="a device"):
        load_launch('<launch><rosparam file="/dev/zero"/></launch>')
    with pytest.raises(ROSLaunchException, match="launch file /dev/zero is a device"):
        load_launch("/dev/zero")
    with pytest.raises(ROSLaunchException, match="is a FIFO"):
        load_launch(f'<launch><include file="{fifo}"/></launch>')


def test_files_over_16_mib_are_refused_before_reading(tmp_path: Path) -> None:
    big = tmp_path / "big.yaml"
    with open(big, "wb") as f:  # sparse: no 16 MiB written
        f.truncate(16 * 1024 * 1024 + 1)
    def hostile() -> None:
        with pytest.raises(ROSLaunchException, match="larger than 16777216 bytes"):
            load_launch(f'<launch><rosparam file="{big}"/></launch>')
        with pytest.raises(ROSLaunchException, match="larger than 16777216 bytes"):
            load_launch(big)
    assert _peak(hostile) < 4 * 2**20  # neither 16 MiB file was read
    # text: refused by its size (the message names the limit), before any XML is parsed
    with pytest.raises(ROSLaunchException, match="larger than 16777216"):
        load_launch("<launch>" + " " * (16 * 1024 * 1024) + "</launch>")
