"""roslaunch input against hostile files: bombs, deep nesting, recursion, endless files (issue 13)."""

from __future__ import annotations

import os
import time
import tracemalloc
from collections.abc import Callable
from pathlib import Path
from typing import Any

import pytest

from ddes.errors import ResourceLimitError, ROSLaunchException
from ddes.launch import load_launch
from ddes.launch.loader import MAX_LOAD_FILES, MAX_NESTING
from ddes.launch.substitution import (
    MAX_EXPANSION_CHARS,
    MAX_VALUE_CHARS,
    CostlyLaunchExpression,
    LaunchLimitError,
)
from ddes.launch.xmltree import MAX_XML_DEPTH, MAX_XML_ELEMENTS

from .test_interop import ddes_json, run_roslaunch
from .workspace import Workspace

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


def _named_groups(n: int, inner: str = "") -> str:
    return ("<launch>" + "".join(f'<group ns="g{i}">' for i in range(n)) + inner
            + "</group>" * n + "</launch>")


def test_600_nested_groups_load_and_the_node_inside_gets_their_namespace() -> None:
    # roslaunch recurses once per <group> and once per level again for a node's remaps: it
    # dies with RecursionError near 490 groups with a node inside (990 without); ddes keeps
    # its own stack
    inner = ('<remap from="a" to="b"/><node pkg="p" type="t" name="n">'
             '<param name="rate" value="5"/></node>')
    xml = _named_groups(600, inner).replace('<group ns="g0">',
                                           '<group ns="g0"><remap from="x" to="y"/>', 1)
    plan = load_launch(xml)
    ns = "/" + "/".join(f"g{i}" for i in range(600)) + "/"
    (node,) = plan.nodes
    assert (node.namespace, node.full_name) == (ns, ns + "n")
    assert node.remappings == [("x", "y"), ("a", "b")]
    assert plan.params == {ns + "n/rate": 5}


def test_groups_nest_as_deep_as_the_budget_allows_not_a_recursion_error() -> None:
    plan = load_launch(_groups(4000, '<param name="p" value="1"/>'))
    assert plan.params == {"/p": 1}
    plan = load_launch(_named_groups(2000, '<node pkg="p" type="t" name="n"/>'))
    assert plan.nodes[0].namespace.count("/") == 2001


@pytest.mark.parametrize("n", [MAX_XML_DEPTH + 1, 100_000, 1_000_000])
def test_deep_groups_are_refused_not_a_recursion_error(n: int) -> None:
    """Past MAX_XML_DEPTH (five times roslaunch's limit), quickly, with a typed error."""
    start = time.process_time()
    with pytest.raises(LaunchLimitError, match=f"nested more than {MAX_XML_DEPTH} elements "
                                               r"deep \(ddes.launch.xmltree.MAX_XML_DEPTH\)"):
        load_launch(_groups(n))
    assert time.process_time() - start < 2  # expat stops at the limit


def test_deep_long_namespaces_are_bounded_by_the_work_not_the_depth() -> None:
    # 3000 levels of 100-character namespaces: each level's namespace is up to 300 KB, 450 MB
    # in all if built; the work budget refuses it (typed, naming the file and line) early
    name = "n" * 100
    xml = "<launch>" + f'<group ns="{name}">' * 3000 + "</group>" * 3000 + "</launch>"
    start = time.process_time()
    with pytest.raises(LaunchLimitError, match=r"^<string>:1: <group ns=\"n+\">: this launch "
                                               r"does more work than ddes allows") as info:
        load_launch(xml)
    assert "flatten the groups, use shorter namespaces, or split the launch" in str(info.value)
    assert isinstance(info.value, ResourceLimitError)
    assert time.process_time() - start < 10
    # a few deep params each: 2000 levels of names, 200 nodes inside
    inner = "".join(f'<node pkg="p" type="t" name="n{i}"><param name="a" value="1"/></node>'
                    for i in range(2000))
    with pytest.raises(LaunchLimitError, match="does more work than ddes allows"):
        load_launch(_named_groups(2000, inner))


def test_a_huge_flat_file_is_refused_by_its_element_count() -> None:
    start = time.process_time()
    with pytest.raises(LaunchLimitError, match=f"more than {MAX_XML_ELEMENTS} elements in one "
                                               "load"):
        load_launch("<launch>" + "<arg name='a' value='1'/>" * (MAX_XML_ELEMENTS + 1)
                    + "</launch>")
    assert time.process_time() - start < 5


def test_text_with_many_entities_is_read_in_linear_time() -> None:
    # expat delivers "a", "&", "a", "&" ... one by one; adding each to the text was quadratic
    body = "a&amp;" * 1_000_000
    start = time.process_time()
    plan = load_launch(f'<launch><param name="p" type="str" value="x"/><rosparam param="q">'
                       f'"{body}"</rosparam></launch>')
    assert plan.params["/q"] == "a&" * 1_000_000
    assert time.process_time() - start < 5


def test_a_file_including_itself_is_refused_naming_the_chain(tmp_path: Path) -> None:
    f = tmp_path / "self.launch"
    f.write_text(f'<launch><group><include file="{f}"/></group></launch>')
    with pytest.raises(LaunchLimitError, match=r"nested more than 1000 deep") as info:
        load_launch(f)
    assert f"included from {f}:1" in str(info.value)


def test_includes_nest_deeper_than_roslaunch_reads(tmp_path: Path) -> None:
    # roslaunch dies with RecursionError near 330 nested includes
    for i in range(400):
        nxt = f'<include file="{tmp_path}/f{i + 1}.launch"/>' if i < 399 else ""
        (tmp_path / f"f{i}.launch").write_text(f'<launch><group ns="i{i}">{nxt}'
                                               '<param name="p" value="1"/></group></launch>')
    plan = load_launch(tmp_path / "f0.launch")
    assert len(plan.files) == 400 and len(plan.params) == 400


def test_groups_and_includes_together_are_bounded(tmp_path: Path) -> None:
    for i in range(10):
        nxt = f'<include file="{tmp_path}/f{i + 1}.launch"/>' if i < 9 else ""
        (tmp_path / f"f{i}.launch").write_text(_groups(600, nxt))
    with pytest.raises(LaunchLimitError, match=f"nest more than {MAX_NESTING} deep in all") as info:
        load_launch(tmp_path / "f0.launch")
    assert f"included from {tmp_path}/f7.launch:1" in str(info.value)


def test_a_file_included_again_and_again_is_bounded(tmp_path: Path) -> None:
    # each level includes the next 20 times: 20**5 files to read, 3.2 million
    for i in range(6):
        nxt = f'<include file="{tmp_path}/w{i + 1}.launch"/>' * 20 if i < 5 else \
            '<param name="p" value="1"/>'
        (tmp_path / f"w{i}.launch").write_text(f"<launch>{nxt}</launch>")
    start = time.process_time()
    with pytest.raises(LaunchLimitError, match=f"more than {MAX_LOAD_FILES} launch files read "
                                               "in one load"):
        load_launch(tmp_path / "w0.launch")
    assert time.process_time() - start < 10
    # and when each read holds many elements, the element budget ends it first
    (tmp_path / "w5.launch").write_text("<launch>" + "".join(f"<arg name='a{i}' value='1'/>"
                                                         for i in range(1000)) + "</launch>")
    with pytest.raises(LaunchLimitError, match="elements in one load"):
        load_launch(tmp_path / "w0.launch")


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


def _doubling(levels: int, extra: str = "") -> str:
    """``a{i}`` defined as ``$(arg a{i-1})$(arg a{i-1})``: 8 * 2**(levels-1) characters at the top."""
    args = ['<arg name="a0" default="xxxxxxxx"/>'] + [
        f'<arg name="a{i}" default="$(arg a{i - 1})$(arg a{i - 1})"/>' for i in range(1, levels)]
    return "<launch>" + "".join(args) + extra + "</launch>"


def test_args_doubling_each_other_are_refused_before_the_value_is_built() -> None:
    hostile = _doubling(40, '<param name="p" value="$(arg a39)"/>')
    assert len(hostile) < 2000  # 8 TiB once expanded; roslaunch (and ddes before) hung on it
    def load() -> None:
        with pytest.raises(LaunchLimitError) as info:
            load_launch(hostile)
        text = str(info.value)
        # the first value past 1 MiB, named with its file and line, before it is built
        assert '<arg name="a18" default="$(arg a17)$(arg a17)">' in text
        assert f"a value of 2097152 characters, more than the {MAX_VALUE_CHARS}" in text
        assert "MAX_VALUE_CHARS" in text and "write the value out instead" in text
    assert _peak(load) < 8 * 2**20  # the largest value kept is 1 MiB, not the 2 MiB refused
    assert isinstance(load_launch(_doubling(17)).args["a16"], str)  # 512 KiB: allowed


def test_substitutions_are_bounded_in_all_across_includes(tmp_path: Path) -> None:
    # 512 KiB values, each repeated once: 32 of them reach the 16 MiB every load may add
    inner = tmp_path / "inner.launch"
    inner.write_text('<launch><arg name="v"/>' + "".join(
        f'<param name="p{i}" value="$(arg v)"/>' for i in range(20)) + "</launch>")
    include = f'<group><include file="{inner}"><arg name="v" value="$(arg a16)"/></include></group>'
    top = _doubling(17, include * 3)
    with pytest.raises(LaunchLimitError) as info:
        load_launch(top)
    text = str(info.value)
    assert f"more than the {MAX_EXPANSION_CHARS} ddes allows in all" in text
    assert "MAX_EXPANSION_CHARS" in text and "included from <string>:1" in text
    assert isinstance(info.value, ResourceLimitError)


def test_a_rosparam_body_longer_than_the_value_limit_still_substitutes() -> None:
    body = "x: $(arg a)\ny: " + "z" * MAX_VALUE_CHARS  # more than 1 MiB of text already
    plan = load_launch(f'<launch><arg name="a" default="1"/><rosparam subst_value="true">'
                       f"{body}</rosparam></launch>")
    assert plan.params["/x"] == 1 and len(plan.params["/y"]) == MAX_VALUE_CHARS


def test_eval_results_are_bounded_like_any_value() -> None:
    with pytest.raises(CostlyLaunchExpression, match=r"str\.join \(1499001500 items\)"):
        load_launch('<launch><param name="p" value="$(eval (\'a\'*10**6).join(\'b\'*1500))"/>'
                    "</launch>")


def test_the_evals_of_one_load_share_a_budget(monkeypatch: pytest.MonkeyPatch) -> None:
    """Each $(eval) may touch 5,000,000 items (about a second); a file of thousands of them is
    bounded in all by MAX_EVAL_WORK, shared across the load."""
    from ddes.launch import substitution

    monkeypatch.setattr(substitution, "MAX_EVAL_WORK", 20_000)  # stands in for 20,000,000
    one = '<param name="p{i}" value="$(eval len(sorted(range(1500))))"/>'  # 7511 items
    assert load_launch("<launch>" + one.format(i=0) + one.format(i=1) + "</launch>"
                       ).params["/p1"] == 1500
    with pytest.raises(CostlyLaunchExpression) as info:
        load_launch("<launch>" + "".join(one.format(i=i) for i in range(10)) + "</launch>")
    text = str(info.value)
    assert '<param name="p2"' in text  # the third would pass 20,000 in all
    assert "may touch 20000 items in all, ddes.launch.substitution.MAX_EVAL_WORK" in text


@pytest.mark.ros
def test_deep_files_load_as_in_roslaunch_and_past_its_recursion_limit(ros_python: Any,
                                                                      ws: Workspace) -> None:
    inner = ('<remap from="a" to="b"/><node pkg="p" type="t" name="n" args="-x 1">'
             '<param name="rate" value="5"/><remap from="c" to="d"/></node>'
             '<param name="~priv" value="2"/><node pkg="p" type="t" name="m"/>')
    deep = _named_groups(400, inner).replace('<group ns="g0">',
                                             '<group ns="g0"><remap from="x" to="y"/>', 1)
    for i in range(120):  # includes 120 deep, a group in each (roslaunch dies near 160)
        nxt = f'<include file="{ws.root}/f{i + 1}.launch"/>' if i < 119 else \
            '<node pkg="p" type="t" name="leaf"/>'
        ws.write(f"f{i}.launch", f'<launch><group ns="i{i}"><param name="p" value="{i}"/>'
                                 f'{nxt}</group></launch>')
    cases = [{"text": deep}, {"text": _groups(950, '<param name="q" value="2"/>')},
             {"file": str(ws.root / "f0.launch"), "argv": []},
             {"text": _named_groups(600, inner)}]
    theirs = run_roslaunch(ros_python, ws, cases)
    for case, their in zip(cases[:3], theirs):
        assert "error" not in their, (case.get("file"), their)
        ours = ddes_json(ws, case.get("text") or Path(case["file"]), {})
        for key in ("params", "nodes", "clear", "summary"):
            assert ours[key] == their[key], key
    # 600 groups with a node inside: roslaunch's own limit, not ddes's
    assert "RecursionError" in theirs[3]["error"] or "recursion" in theirs[3]["error"]
    ours = ddes_json(ws, cases[3]["text"], {})
    assert [n["name"] for n in ours["nodes"]] == ["n", "m"]
    assert ours["nodes"][0]["namespace"].count("/") == 601
