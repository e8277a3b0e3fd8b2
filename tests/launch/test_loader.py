"""Loading launch files: args, includes, groups, remaps, params, rosparam, nodes."""

from __future__ import annotations

import math

import pytest

from ddes.errors import ROSLaunchException
from ddes.launch import LaunchPlan, NodeSpec, RosparamCommand, load_launch

from .scenario import build
from .workspace import CountingRandom, Workspace


def test_minimal_plan_from_text(ws: Workspace) -> None:
    plan = ws.load('<launch><node pkg="rospy_tutorials" type="talker" name="talker"/></launch>')
    assert plan.params == {} and plan.files == []
    assert plan.nodes == [NodeSpec("rospy_tutorials", "talker", "talker", "/",
                                   source="<string>:1")]
    assert plan.nodes[0].full_name == "/talker"


def test_path_objects_and_strings_both_load(ws: Workspace) -> None:
    path = ws.write("a.launch", "<launch><param name='x' value='1'/></launch>")
    assert ws.load(path).params == {"/x": 1}
    plan = load_launch(str(path), {}, ws.rospack)
    assert plan.params == {"/x": 1} and plan.files == [str(path)]


# -- args ------------------------------------------------------------------------------------

def test_arg_default_value_and_command_line(ws: Workspace) -> None:
    body = """
        <arg name="a" default="1"/>
        <arg name="b" value="fixed"/>
        <arg name="c"/>
        <param name="a" value="$(arg a)"/>
        <param name="b" value="$(arg b)"/>
        <param name="c" value="$(arg c)"/>
    """
    plan = ws.launch("x.launch", body, c="given")
    assert plan.params == {"/a": 1, "/b": "fixed", "/c": "given"}
    assert plan.args == {"a": "1", "b": "fixed", "c": "given"}
    assert ws.launch("x.launch", body, a="2.5", c="z").params["/a"] == 2.5


def test_arg_in_group_is_scoped(ws: Workspace) -> None:
    with pytest.raises(ROSLaunchException, match="arg 'inner' is not defined"):
        ws.launch("x.launch", """
            <group><arg name="inner" default="1"/><param name="ok" value="$(arg inner)"/></group>
            <param name="bad" value="$(arg inner)"/>
        """)


def test_args_may_use_earlier_args_and_eval(ws: Workspace) -> None:
    plan = ws.launch("x.launch", """
        <arg name="n" default="4"/>
        <arg name="twice" default="$(eval n * 2)"/>
        <arg name="label" default="n$(arg n)_$(arg twice)"/>
        <param name="label" value="$(arg label)"/>
    """)
    assert plan.params == {"/label": "n4_8"}


def test_undeclared_command_line_arg_is_an_error(ws: Workspace) -> None:
    with pytest.raises(ROSLaunchException, match=r"unused args \[robto\] for \[.*x.launch\]"):
        ws.launch("x.launch", '<arg name="robot" default="a"/>', robto="b")
    # __special args (e.g. __ns) are not launch args
    assert ws.launch("x.launch", '<param name="p" value="1"/>', __ns="/r").params == {"/r/p": 1}


# -- if / unless ---------------------------------------------------------------------------

@pytest.mark.parametrize(("cond", "kept"), [
    ('if="true"', True), ('if="1"', True), ('if="TRUE"', True), ('if="false"', False),
    ('if="0"', False), ('unless="true"', False), ('unless="0"', True),
    ('if="$(arg on)"', True), ('unless="$(arg on)"', False),
    ('if="$(eval on and 2 > 1)"', True), ('if="$(eval not on)"', False),
])
def test_if_unless(ws: Workspace, cond: str, kept: bool) -> None:
    plan = ws.launch("x.launch", f"""
        <arg name="on" default="true"/>
        <param name="p" value="1" {cond}/>
        <group {cond}><node pkg="p" type="t" name="n"/></group>
        <node pkg="p" type="t" name="m"><param name="q" value="1" {cond}/></node>
    """)
    assert ("/p" in plan.params) is kept
    assert ([n.name for n in plan.nodes] == ["n", "m"]) is kept
    assert ("/m/q" in plan.params) is kept


def test_false_if_skips_the_tag_entirely(ws: Workspace) -> None:
    plan = ws.launch("x.launch", """
        <include if="false" file="/does/not/exist.launch"/>
        <param if="false" name="p" value="$(arg undefined)"/>
        <arg if="false" name="skipped" value="1"/>
        <arg name="skipped" default="2"/>
        <param name="skipped" value="$(arg skipped)"/>
    """)
    assert plan.params == {"/skipped": 2}


# -- groups, namespaces, remaps ------------------------------------------------------------

def test_group_namespaces(ws: Workspace) -> None:
    plan = ws.launch("x.launch", """
        <group ns="a">
          <param name="p" value="1"/>
          <group ns="b/c"><node pkg="p" type="t" name="n1"/></group>
          <group ns="/abs"><node pkg="p" type="t" name="n2" ns="x"/></group>
          <node pkg="p" type="t" name="n3" ns="/g"/>
          <param name="/global" value="2"/>
        </group>
    """)
    assert plan.params == {"/a/p": 1, "/global": 2}
    assert [n.full_name for n in plan.nodes] == ["/a/b/c/n1", "/abs/x/n2", "/g/n3"]
    assert [n.namespace for n in plan.nodes] == ["/a/b/c/", "/abs/x/", "/g/"]


def test_remaps_compose_by_scope(ws: Workspace) -> None:
    plan = ws.launch("x.launch", """
        <node pkg="p" type="t" name="before"/>
        <remap from="chatter" to="/loud"/>
        <remap from="a" to="b"/>
        <group>
          <remap from="chatter" to="quiet"/>
          <node pkg="p" type="t" name="inner">
            <remap from="a" to="c"/>
            <remap from="x//y/" to="z"/>
          </node>
        </group>
        <node pkg="p" type="t" name="outer"/>
    """)
    by = {n.name: n.remappings for n in plan.nodes}
    assert by["before"] == []
    assert by["inner"] == [("chatter", "quiet"), ("a", "c"), ("x/y", "z")]
    assert by["outer"] == [("chatter", "/loud"), ("a", "b")]


def test_env_is_recorded_per_node(ws: Workspace) -> None:
    plan = ws.launch("x.launch", """
        <env name="A" value="1"/>
        <group><env name="B" value="$(env DDES_TEST_VAR)"/><node pkg="p" type="t" name="n1"/></group>
        <node pkg="p" type="t" name="n2"><env name="C" value="3"/></node>
    """)
    assert plan.node("/n1").env == [("A", "1"), ("B", "hello")]
    assert plan.node("/n2").env == [("A", "1"), ("C", "3")]


# -- params --------------------------------------------------------------------------------

def test_param_types_and_files(ws: Workspace) -> None:
    ws.write("cfg/robot.urdf", "<robot name='r'/>\n")
    ws.write("cfg/blob.bin", b"\x00\xffdata")
    ws.write("cfg/n.txt", "41\n")
    plan = ws.launch("x.launch", f"""
        <param name="i" value="1"/>
        <param name="f" value="1.5"/>
        <param name="b" value="false"/>
        <param name="s" value=" padded "/>
        <param name="si" type="str" value="1"/>
        <param name="y" type="yaml" value="[1, {{a: b}}]"/>
        <param name="urdf" textfile="{ws.root}/cfg/robot.urdf"/>
        <param name="n" type="int" textfile="{ws.root}/cfg/n.txt"/>
        <param name="blob" binfile="{ws.root}/cfg/blob.bin"/>
    """)
    assert plan.params == {"/i": 1, "/f": 1.5, "/b": False, "/s": "padded", "/si": "1",
                           "/y": [1, {"a": "b"}], "/urdf": "<robot name='r'/>\n", "/n": 41,
                           "/blob": b"\x00\xffdata"}


def test_private_params_reach_later_nodes_only(ws: Workspace) -> None:
    plan = ws.launch("x.launch", """
        <node pkg="p" type="t" name="early"/>
        <param name="~rate" value="10"/>
        <group ns="g">
          <param name="~only_in_group" value="1"/>
          <node pkg="p" type="t" name="n1"><param name="~rate" value="20"/></node>
        </group>
        <node pkg="p" type="t" name="n2"/>
    """)
    assert plan.params == {"/g/n1/rate": 20, "/g/n1/only_in_group": 1, "/n2/rate": 10}
    assert plan.node("/early").params == {}
    assert plan.node("/g/n1").params == {"/g/n1/rate": 20, "/g/n1/only_in_group": 1}


def test_node_params_are_private_even_when_global(ws: Workspace) -> None:
    plan = ws.launch("x.launch", """
        <node pkg="p" type="t" name="n" ns="robot">
          <param name="rel" value="1"/>
          <param name="~tilde" value="2"/>
          <param name="/abs" value="3"/>
          <rosparam param="/really_global">4</rosparam>
          <rosparam>yaml: {a: 5}</rosparam>
        </node>
    """)
    assert plan.params == {"/really_global": 4, "/robot/n/yaml/a": 5, "/robot/n/rel": 1,
                           "/robot/n/tilde": 2, "/robot/n/abs": 3}


def test_later_values_override_but_keep_their_place(ws: Workspace) -> None:
    plan = ws.launch("x.launch", """
        <param name="a" value="1"/>
        <param name="b" value="2"/>
        <param name="a" value="3"/>
    """)
    assert list(plan.params.items()) == [("/a", 3), ("/b", 2)]


def test_parent_conflict_is_a_warning(ws: Workspace) -> None:
    plan = ws.launch("x.launch", '<param name="a" value="1"/><param name="a/b" value="2"/>')
    assert plan.params == {"/a": 1, "/a/b": 2}
    assert plan.warnings == ["parameter [/a/b] conflicts with parent parameter [/a]"]


def test_rosparam_load_unrolls_dicts(ws: Workspace) -> None:
    ws.write("cfg/gains.yaml", """
        pid: {p: 1.0, i: 0.1}
        topics: [/scan, /odom]
        empty: {}
    """)
    plan = ws.launch("x.launch", f"""
        <group ns="ctl">
          <rosparam command="load" file="{ws.root}/cfg/gains.yaml"/>
          <rosparam file="{ws.root}/cfg/gains.yaml" ns="copy"/>
          <rosparam param="scalar">3</rosparam>
          <rosparam ns="a" param="b">{{c: deg(180)}}</rosparam>
          <rosparam>pid: {{d: 0.5}}</rosparam>
        </group>
    """)
    assert plan.params == {
        "/ctl/pid/p": 1.0, "/ctl/pid/i": 0.1, "/ctl/topics": ["/scan", "/odom"],
        "/ctl/copy/pid/p": 1.0, "/ctl/copy/pid/i": 0.1, "/ctl/copy/topics": ["/scan", "/odom"],
        "/ctl/scalar": 3, "/ctl/a/b/c": math.pi, "/ctl/pid/d": 0.5,
    }
    assert plan.rosparam_loads[2] == ("/ctl/scalar", 3)
    assert plan.rosparam_loads[0][0] == "/ctl"


def test_rosparam_subst_value(ws: Workspace) -> None:
    body = """
        <arg name="topic" default="/scan"/>
        <rosparam subst_value="true">t: $(arg topic)</rosparam>
        <rosparam subst_value="false">u: $(arg topic)</rosparam>
    """
    assert ws.launch("x.launch", body).params == {"/t": "/scan", "/u": "$(arg topic)"}


def test_rosparam_delete_and_dump_are_commands(ws: Workspace) -> None:
    plan = ws.launch("x.launch", """
        <group ns="g">
          <rosparam command="delete" param="old"/>
          <rosparam command="dump" file="out.yaml"/>
        </group>
    """)
    assert plan.rosparam_commands == [
        RosparamCommand("delete", "/g/old", None, f"{ws.root}/x.launch:3"),
        RosparamCommand("dump", "/g", "out.yaml", f"{ws.root}/x.launch:4"),
    ]
    assert plan.deletions == ["/g/old"] and plan.params == {}


def test_clear_params(ws: Workspace) -> None:
    plan = ws.launch("x.launch", """
        <group ns="g" clear_params="true"><node pkg="p" type="t" name="n" clear_params="true"/></group>
        <group ns="h" clear_params="false"/>
        <group ns="k" clear_params=""/>
    """)
    assert plan.clear_params == ["/g/", "/g/n/"]


# -- nodes -----------------------------------------------------------------------------------

def test_node_attributes(ws: Workspace) -> None:
    plan = ws.launch("x.launch", """
        <arg name="hz" default="5"/>
        <node pkg="p" type="t.py" name="n" args="--hz $(arg hz) 'a b' &quot;c&quot;"
              output="screen" respawn="true" respawn_delay="1.5" cwd="ROS_HOME"
              launch-prefix="gdb -ex run"/>
        <node pkg="p" type="t.py" name="m" required="true" output="log" cwd="node"/>
    """)
    n, m = plan.nodes
    assert (n.args, n.output, n.respawn, n.respawn_delay, n.required, n.cwd) == (
        ["--hz", "5", "a b", "c"], "screen", True, 1.5, False, "ROS_HOME")
    assert (m.required, m.output, m.cwd, m.respawn) == (True, "log", "node", False)
    assert n.launch_prefix == "gdb -ex run"
    assert any("launch-prefix" in w for w in plan.warnings)


def test_anon_node_names_depend_on_the_seed_only(ws: Workspace) -> None:
    body = '<node pkg="p" type="t" name="$(anon rviz)"/><node pkg="p" type="t" name="$(anon rviz_2)"/>'
    a = [n.name for n in ws.launch("x.launch", body, anon=3).nodes]
    b = [n.name for n in ws.launch("x.launch", body, anon=3).nodes]
    c = [n.name for n in ws.launch("x.launch", body, anon=4).nodes]
    assert a == b != c
    assert a[0].startswith("rviz_") and a[1].startswith("rviz_2_")


def test_test_master_and_machine_tags_are_ignored_with_warnings(ws: Workspace) -> None:
    plan = ws.launch("x.launch", """
        <master auto="start"/>
        <machine name="robot" address="10.0.0.2" user="u"/>
        <node pkg="p" type="t" name="n" machine="robot"/>
        <test test-name="check" pkg="p" type="t" time-limit="10"><param name="x" value="1"/></test>
    """)
    assert [n.name for n in plan.nodes] == ["n"] and plan.nodes[0].machine == "robot"
    assert plan.params == {"/check/x": 1}  # roslaunch sets a <test>'s params too
    assert len(plan.warnings) == 3


# -- includes --------------------------------------------------------------------------------

def test_include_with_args_ns_and_find(ws: Workspace) -> None:
    pkg = ws.package("robot_bringup")
    ws.write("src/robot_bringup/launch/base.launch", """
        <launch>
          <arg name="name"/>
          <arg name="speed" default="1.0"/>
          <param name="speed" value="$(arg speed)"/>
          <node pkg="robot_bringup" type="base" name="$(arg name)"/>
        </launch>
    """)
    plan = ws.launch("top.launch", """
        <include file="$(find robot_bringup)/launch/base.launch" ns="r1">
          <arg name="name" value="driver"/>
        </include>
        <include file="$(find robot_bringup)/launch/base.launch">
          <arg name="name" value="driver2"/>
          <arg name="speed" value="2.5"/>
        </include>
    """)
    assert plan.params == {"/r1/speed": 1.0, "/speed": 2.5}
    assert [n.full_name for n in plan.nodes] == ["/r1/driver", "/driver2"]
    base = str(pkg / "launch" / "base.launch")
    assert plan.files == [str(ws.root / "top.launch"), base, base]
    assert plan.nodes[0].include_chain == (f"{ws.root}/top.launch:2",)
    assert plan.nodes[0].source == f"{base}:5"


def test_include_sees_only_passed_args(ws: Workspace) -> None:
    ws.write("inc.launch", '<launch><param name="p" value="$(arg secret)"/></launch>')
    with pytest.raises(ROSLaunchException, match="arg 'secret' is not defined"):
        ws.launch("top.launch", f'<arg name="secret" default="s"/><include file="{ws.root}/inc.launch"/>')


def test_pass_all_args(ws: Workspace) -> None:
    ws.write("inc.launch", """
        <launch>
          <arg name="a" default="inner"/>
          <param name="a" value="$(arg a)"/>
          <param name="b" value="$(arg b)"/>
        </launch>
    """)
    plan = ws.launch("top.launch", f"""
        <arg name="a" default="outer"/>
        <arg name="b" default="B"/>
        <include file="{ws.root}/inc.launch" pass_all_args="true"/>
        <include file="{ws.root}/inc.launch" pass_all_args="true" ns="o">
          <arg name="b" value="overridden"/>
        </include>
    """)
    assert plan.params == {"/a": "outer", "/b": "B", "/o/a": "outer", "/o/b": "overridden"}


def test_include_dirname_is_relative_to_each_file(ws: Workspace) -> None:
    ws.write("sub/inner.launch", '<launch><param name="d" value="$(dirname)"/></launch>')
    plan = ws.launch("top.launch", """
        <param name="top" value="$(dirname)"/>
        <include file="$(dirname)/sub/inner.launch"/>
    """)
    assert plan.params == {"/top": str(ws.root), "/d": str(ws.root / "sub")}


def test_demo_package_loads(ws: Workspace) -> None:
    build(ws)
    plan = ws.load(ws.src / "demo_pkg" / "launch" / "main.launch", CountingRandom())
    assert isinstance(plan, LaunchPlan)
    assert plan.params["/talker/nested/a"] == "overrides rosparam"
    assert plan.params["/r1/sub/who"] == "r1_sub" and plan.params["/who"] == "all"
    assert plan.params["/bin"] == b"\x00\x01binary\xff"
    assert plan.params["/found"] == f"{ws.src}/demo_pkg/config"
    assert plan.params["/env"] == "hello-fall back"
    assert plan.clear_params == ["/r1/", "/r1/listener/", "/r1/sub/"]
    assert "/never" not in [n.full_name for n in plan.nodes]


def test_default_environment_is_os_environ(ws: Workspace, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("DDES_LAUNCH_TEST_ENV", "from-os")
    plan = load_launch('<launch><param name="e" value="$(env DDES_LAUNCH_TEST_ENV)"/></launch>',
                       rospack=ws.rospack)
    assert plan.params == {"/e": "from-os"}


def test_loading_twice_gives_equal_plans(ws: Workspace) -> None:
    build(ws)
    path = ws.src / "demo_pkg" / "launch" / "main.launch"
    assert ws.load(path, 11) == ws.load(path, 11)


def test_test_tag_name_defaults_to_test_name(ws: Workspace) -> None:
    plan = ws.launch("x.launch", """
        <test test-name="t1" pkg="p" type="t"><param name="a" value="1"/></test>
        <test test-name="t2" name="named" pkg="p" type="t"><param name="b" value="2"/></test>
    """)
    assert plan.params == {"/t1/a": 1, "/named/b": 2} and plan.nodes == []


def test_param_name_is_stripped_before_substitution(ws: Workspace) -> None:
    plan = ws.launch("x.launch", """
        <arg name="n" default="p"/>
        <param name=" $(arg n) " value="1"/>
    """)
    assert plan.params == {"/p": 1}
