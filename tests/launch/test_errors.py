"""Bad launch files: each raises ROSLaunchException naming file, line, element and the fix.

Each case is a list of lines inside ``<launch>``; the innermost element of
the *last* line is the offending one, so the expected location is
``file:len(lines)+1`` and that element.
"""

from __future__ import annotations

import re

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from ddes.errors import ROSLaunchException
from ddes.launch import load_launch
from ddes.rospack import RosPack

from .workspace import Workspace

CASES: list[tuple[list[str], str]] = [
    # XML vocabulary
    (["<bogus/>"], "unrecognized tag <bogus>"),
    (['<param name="a" value="1" bogus="2"/>'], "unknown <param> attribute 'bogus'"),
    (['<node pkg="p" type="t" name="n" colour="red"/>'], "unknown <node> attribute 'colour'"),
    (['<node pkg="p" type="t" name="n"><include file="x"/></node>'],
     "unrecognized <include> child tag in <node>"),
    # missing attributes
    (['<param value="1"/>'], "<param> tag is missing required attribute: 'name'"),
    (['<node pkg="p" type="t"/>'], "<node> tag is missing required attribute: 'name'"),
    (['<node name="n" type="t"/>'], "<node> tag is missing required attribute: 'pkg'"),
    (['<remap from="a"/>'], "<remap> tag is missing required attribute: 'to'"),
    (['<include/>'], "<include> tag is missing required attribute: 'file'"),
    (['<arg default="1"/>'], "<arg> tag is missing required attribute: 'name'"),
    (['<env name="A"/>'], "<env> tag is missing required attribute: 'value'"),
    # if / unless
    (['<param name="a" value="1" if="yes"/>'], "yes is not a 'bool' type; use true, false, 1 or 0"),
    (['<group unless="$(eval 2)"/>'], "2 is not a 'bool' type"),
    (['<param name="a" value="1" if="1" unless="0"/>'],
     "cannot set both 'if' and 'unless' on the same tag"),
    # args
    (['<arg name="x" value="1" default="2"/>'], "must have one and only one of value/default"),
    (['<arg name="x" default="1"/>', '<arg name="x" default="2"/>'],
     "arg 'x' has already been declared"),
    (['<arg name="x" value="1"/>', '<group><arg name="x" value="2"/></group>'],
     "arg 'x' has already been declared"),
    (['<param name="a" value="$(arg x)"/>'], r"arg 'x' is not defined\. Declare it with"),
    (['<arg name="x"/>', '<param name="a" value="$(arg x)"/>'], "arg 'x' is not defined"),
    # substitutions
    (['<param name="a" value="$(foo x)"/>'], r"Unknown substitution command \[foo x\]"),
    (['<param name="a" value="v=$(eval 1)"/>'], r"must be the whole attribute value"),
    (['<param name="a" value="$(find $(arg p))"/>'], "roslaunch does not nest substitutions"),
    (['<param name="a" value="$(find missing_pkg)/x"/>'], "package 'missing_pkg' not found"),
    (['<param name="a" value="$(env DDES_SURELY_UNSET_42)"/>'],
     "environment variable 'DDES_SURELY_UNSET_42' is not set"),
    (['<param name="a" value="$(eval 1 +* 2)"/>'], r"\$\(eval 1 \+\* 2\) failed: SyntaxError"),
    (['<param name="a" value="$(eval __class__)"/>'], "may not contain double underscore"),
    # params
    (['<param name="a" type="int" value="x"/>'], "invalid literal for int"),
    (['<param name="a" type="float" value="1"/>'], "Unknown type 'float'"),
    (['<param name="a" value="1" textfile="f.txt"/>'],
     "must have one and only one of value/textfile/binfile"),
    (['<param name="a" command="xacro robot.xacro"/>'], "ddes runs no external processes"),
    (['<param name="a" textfile="/nonexistent/f.txt"/>'], r"cannot read textfile \[/nonexistent"),
    (['<param name="a" binfile="/nonexistent/f.bin"/>'], r"cannot read binfile \[/nonexistent"),
    (['<param name="" value="1"/>'], "parameter name must be non-empty"),
    # rosparam
    (["<rosparam>5</rosparam>"], "'param' attribute must be set for non-dictionary values"),
    (["<rosparam>a: [1</rosparam>"], "Error within YAML block"),
    (["<rosparam>1: a</rosparam>"], "YAML key 1 under"),
    (['<rosparam command="reload">a: 1</rosparam>'], "command must be 'load', 'dump', or 'delete'"),
    (['<rosparam command="load" file="/nonexistent/p.yaml"/>'],
     r"file does not exist \[/nonexistent/p.yaml\]"),
    (['<rosparam command="delete" file="p.yaml"/>'], "'file' attribute is invalid with 'delete'"),
    (['<rosparam command="dump"/>'], 'needs file="..."'),
    (['<rosparam subst_value="1">a: 1</rosparam>'], "invalid bool value for subst_value: 1"),
    (['<rosparam param="/">7</rosparam>'], "Cannot load non-dictionary types into global"),
    # remap / env / groups
    (['<remap from="a" to=""/>'], "remap from/to attributes cannot be empty"),
    (['<remap from="1a" to="b"/>'], r"remap from \[1a\] is not a valid ROS name"),
    (['<env name="" value="v"/>'], "'name' attribute must be non-empty"),
    (['<group clear_params="true"/>'], "'ns' attribute must be set in order to use 'clear_params'"),
    (['<group ns=""/>'], "<group> tag has an empty 'ns' attribute"),
    (['<group ns="~"/>'], "cannot turn"),
    # nodes
    (['<node pkg="p" type="t" name="a/b"/>'], "node name cannot contain a namespace"),
    (['<node pkg="p" type="t" name=""/>'], "node name must be non-empty"),
    (['<node pkg=" " type="t" name="n"/>'], "package must be non-empty"),
    (['<node pkg="p" type="t" name="n" respawn="true" required="true"/>'],
     "respawn and required cannot both be set to true"),
    (['<node pkg="p" type="t" name="n" respawn="1"/>'], "invalid bool value for respawn: 1"),
    (['<node pkg="p" type="t" name="n" respawn_delay="x"/>'],
     "invalid float value for respawn_delay: x"),
    (['<node pkg="p" type="t" name="n" output="file"/>'], "output must be one of 'log', 'screen'"),
    (['<node pkg="p" type="t" name="n" cwd="tmp"/>'], "cwd must be one of 'ROS_HOME', 'node'"),
    (['<node pkg="p" type="t" name="n" args="&quot;unclosed"/>'], "cannot split args"),
    (['<node pkg="p" type="t" name="n" machine="nowhere"/>'], r"unknown machine \[nowhere\]"),
    (['<node pkg="p" type="t" name="n" clear_params="maybe"/>'],
     "invalid bool value for clear_params: maybe"),
    (['<node pkg="p" type="t" name="n"/>', '<group><node pkg="p" type="t" name="n"/></group>'],
     r"multiple nodes named \[/n\]"),
    (['<test pkg="p" type="t" test-name="x" output="screen"/>'],
     "<test> tags cannot have 'output' attribute"),
    (['<test pkg="p" type="t" test-name="x" time-limit="0"/>'],
     "'time-limit' must be a positive number"),
    (['<machine name="m" address="a" ros-root="/opt"/>'], "ros-\\* attributes are not supported"),
    # includes
    (['<include file="/nonexistent/x.launch"/>'], "launch file not found: /nonexistent/x.launch"),
    (['<include file="INC"><arg name="typo" value="1"/></include>'],
     r"unused args \[typo\] for include of"),
    (['<include file="INC"><arg name="a"/></include>'], "include args must have declared values"),
    (['<include file="INC"><node pkg="p" type="t" name="n"/></include>'],
     "unrecognized <node> tag in <include>"),
    (['<include file="INC" pass_all_args="yes"/>'], "invalid bool value for pass_all_args: yes"),
]


@pytest.mark.parametrize(("lines", "message"), CASES, ids=[c[1][:40] for c in CASES])
def test_bad_input(ws: Workspace, lines: list[str], message: str) -> None:
    inc = ws.write("inc.launch", "<launch/>")
    body = "\n".join(line.replace('"INC"', f'"{inc}"') for line in lines)
    path = ws.write("bad.launch", f"<launch>\n{body}\n</launch>\n")
    with pytest.raises(ROSLaunchException) as info:
        ws.load(path)
    text = str(info.value)
    tag = re.findall(r"<([\w-]+)", lines[-1])[-1]  # the innermost element of the last line
    assert text.startswith(f"{path}:{len(lines) + 1}: <{tag}"), text
    assert re.search(message, text), text


def test_error_inside_nested_include_names_the_chain(ws: Workspace) -> None:
    leaf = ws.write("leaf.launch", '<launch>\n\n<param name="p" value="$(arg missing)"/>\n</launch>')
    mid = ws.write("mid.launch", f'<launch>\n<include file="{leaf}"/>\n</launch>')
    top = ws.write("top.launch", f'<launch>\n\n\n<group ns="g">\n<include file="{mid}"/>\n</group>\n</launch>')
    with pytest.raises(ROSLaunchException) as info:
        ws.load(top)
    assert str(info.value).splitlines() == [
        f'{leaf}:3: <param name="p" value="$(arg missing)">: arg \'missing\' is not defined. '
        'Declare it with <arg name="missing" default="..."/> or pass missing:=VALUE (an <arg> '
        'declared without value or default must be given a value)',
        f"  included from {mid}:2",
        f"  included from {top}:5",
    ]


def test_malformed_included_file_names_the_chain(ws: Workspace) -> None:
    bad = ws.write("bad.launch", "<launch>\n<param name='a' value='1'>\n</launch>")
    top = ws.write("top.launch", f'<launch>\n<include file="{bad}"/>\n</launch>')
    with pytest.raises(ROSLaunchException) as info:
        ws.load(top)
    lines = str(info.value).splitlines()
    assert lines[0].startswith(f"{bad}:3: Invalid roslaunch XML syntax: mismatched tag")
    assert lines[1] == f"  included from {top}:2"


@pytest.mark.parametrize(("text", "message"), [
    ("<launch>", "no element found"),
    ("<launch><param name='a' value='1' value='2'/></launch>", "duplicate attribute"),
    ("<launch>&bogus;</launch>", "undefined entity"),
    ("<robot/>", r"no root <launch> tag \(found <robot>\)"),
    ("", "no element found"),
])
def test_malformed_xml(ws: Workspace, text: str, message: str) -> None:
    path = ws.write("x.launch", text)
    with pytest.raises(ROSLaunchException, match=f"^{re.escape(str(path))}:1: .*{message}"):
        ws.load(path)


def test_if_on_launch_is_rejected(ws: Workspace) -> None:
    with pytest.raises(ROSLaunchException, match="if/unless on <launch> has no effect"):
        ws.load('<launch if="false"><param name="a" value="1"/></launch>')


def test_missing_top_level_file(ws: Workspace) -> None:
    with pytest.raises(ROSLaunchException, match="launch file not found: .*nope.launch"):
        load_launch(ws.root / "nope.launch", {}, ws.rospack)


def test_string_launch_has_no_dirname(ws: Workspace) -> None:
    with pytest.raises(ROSLaunchException, match=r"^<string>:1: <param .*Cannot substitute"):
        ws.load('<launch><param name="d" value="$(dirname)"/></launch>')


def test_self_include_is_stopped(ws: Workspace) -> None:
    path = ws.write("self.launch", '<launch>\n<include file="$(dirname)/self.launch"/>\n</launch>')
    with pytest.raises(ROSLaunchException, match="includes nested more than 1000 deep") as info:
        ws.load(path)
    # the 10 innermost and 10 outermost of the 1000 files, around the count of the rest
    assert str(info.value).count("included from") == 20
    assert "\n  ... 980 more includes ...\n" in str(info.value)


def test_guarded_recursive_include_terminates(ws: Workspace) -> None:
    ws.write("count.launch", """
        <launch>
          <arg name="n"/>
          <node pkg="p" type="t" name="n$(arg n)"/>
          <include file="$(dirname)/count.launch" if="$(eval n > 0)">
            <arg name="n" value="$(eval n - 1)"/>
          </include>
        </launch>
    """)
    assert [n.name for n in ws.load("count.launch", n="3").nodes] == ["n3", "n2", "n1", "n0"]


def test_arg_values_must_be_strings(ws: Workspace) -> None:
    with pytest.raises(ROSLaunchException, match="launch args are strings"):
        load_launch("<launch/>", {"n": 3}, ws.rospack)  # type: ignore[dict-item]


_TAGS = ["group", "node", "param", "remap", "arg", "rosparam", "env", "include", "test",
         "machine", "bogus"]
_ATTRS = ['ns="g"', 'ns=""', 'ns="/abs"', 'if="$(arg a)"', 'unless="1"', 'if="maybe"',
          'pkg="p"', 'type="t"', 'name="n"', 'name="$(anon x)"', 'name="~p"', 'value="1"',
          'value="$(eval a * 2)"', 'value="$(arg b)"', 'default="2"', 'type="int"',
          'from="a"', 'to="b"', 'file="/nonexistent"', 'clear_params="true"', 'args="a \'b"',
          'param="q"', 'command="delete"', 'subst_value="true"', 'respawn="true"',
          'required="true"', 'test-name="t"', 'address="h"', 'textfile="/nonexistent"']
_TEXTS = ["", "a: 1", "[1, 2]", "$(arg a)", "{b: {c: deg(90)}}", "x: [", "&amp;"]


def _elements(depth: int = 0) -> st.SearchStrategy[str]:
    children = st.lists(_elements(depth + 1), max_size=3).map("".join) if depth < 3 \
        else st.just("")
    return st.builds(
        lambda tag, attrs, text, kids:
            f"<{tag} {' '.join({a.split('=')[0]: a for a in attrs}.values())}>{text}{kids}</{tag}>",
        st.sampled_from(_TAGS), st.lists(st.sampled_from(_ATTRS), max_size=4),
        st.sampled_from(_TEXTS), children)


@settings(max_examples=150, deadline=None)
@given(st.lists(_elements(), max_size=6))
def test_random_input_loads_or_raises_roslaunchexception(elements: list[str]) -> None:
    text = '<launch><arg name="a" default="true"/>' + "".join(elements) + "</launch>"
    try:
        plan = load_launch(text, {}, RosPack([], use_env=False, bundled=False), environ={})
    except ROSLaunchException as exc:
        assert re.match(r"<string>:1: <[\w-]+", str(exc)), str(exc)
    else:
        assert plan.to_text().startswith("SUMMARY\n")
