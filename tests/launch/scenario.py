"""A demo package exercising most of roslaunch, shared by loader and interop tests."""

from __future__ import annotations

from .workspace import Workspace

MAIN = """
<launch>
  <arg name="robot" default="r1"/>
  <arg name="rate" default="10"/>
  <arg name="use_sim" default="true"/>
  <arg name="fixed" value="const"/>
  <arg name="documented" default="x" doc="only documented"/>
  <param name="use_sim_time" value="$(arg use_sim)"/>
  <param name="rate" value="$(arg rate)"/>
  <param name="half_rate" value="$(eval arg('rate') / 2)"/>
  <param name="bare" value="$(eval rate * 3 + floor(pi))"/>
  <param name="s" type="str" value="42"/>
  <param name="i" type="int" value=" 7 "/>
  <param name="d" type="double" value="3"/>
  <param name="b" type="bool" value="1"/>
  <param name="bs" type="boolean" value="FALSE"/>
  <param name="y" type="yaml" value="{a: 1, b: [x, 2.5]}"/>
  <param name="auto_underscore" value="1_000"/>
  <param name="auto_exp" value="1e3"/>
  <param name="auto_float" value="-0.5"/>
  <param name="auto_bool" value="True"/>
  <param name="t" textfile="$(find demo_pkg)/config/text.txt"/>
  <param name="tint" type="int" textfile="$(find demo_pkg)/config/number.txt"/>
  <param name="bin" binfile="$(find demo_pkg)/config/blob.bin"/>
  <param name="found" value="$(find demo_pkg)/config"/>
  <param name="found_bare" value="$(find demo_pkg) tail"/>
  <param name="dir" value="$(dirname)/x"/>
  <param name="env" value="$(env DDES_TEST_VAR)-$(optenv DDES_SURELY_UNSET_42 fall  back)"/>
  <param name="multi" value="$(arg robot)/$(arg robot)/$(arg fixed)"/>
  <param name="~launch_private" value="lp"/>
  <param name="/global/abs" value="g"/>
  <param name="nothing" value="keep $ (this) and $() and $$ as is"/>
  <remap from="chatter" to="/shared/chatter"/>
  <remap from="cmd" to="cmd_vel"/>
  <env name="LAUNCH_ENV" value="1"/>
  <rosparam command="load" file="$(find demo_pkg)/config/params.yaml"/>
  <rosparam param="list_param">[1, 2, 3]</rosparam>
  <rosparam ns="nsattr" param="p">{x: deg(180), y: rad(pi/4), z: !degrees 90}</rosparam>
  <rosparam subst_value="true">subst: $(arg robot)</rosparam>
  <rosparam>
    # a comment
    plain: {q: 1}
  </rosparam>
  <rosparam command="delete" param="old"/>
  <rosparam command="dump" file="$(dirname)/dump.yaml" param="dumped"/>
  <node pkg="demo_pkg" type="talker.py" name="talker"
        args="--rate $(arg rate) 'two words' &quot;q&quot;" output="screen"
        respawn="true" respawn_delay="2.5" cwd="node">
    <remap from="cmd" to="override"/>
    <param name="p1" value="1"/>
    <param name="~p2" value="2"/>
    <param name="/p3" value="3"/>
    <rosparam>nested: {a: 1, b: {c: 2}}</rosparam>
    <rosparam param="/global_from_node">5</rosparam>
    <param name="nested/a" value="overrides rosparam"/>
    <env name="NODE_ENV" value="n"/>
  </node>
  <group ns="$(arg robot)" clear_params="true">
    <remap from="chatter" to="local_chatter"/>
    <param name="~group_private" value="gp"/>
    <param name="rel" value="r"/>
    <node pkg="demo_pkg" type="listener" name="listener" required="true" clear_params="true"/>
    <group ns="inner" if="$(arg use_sim)">
      <node pkg="demo_pkg" type="listener" name="l2" ns="deeper" cwd="ros_home"/>
    </group>
    <group unless="$(eval use_sim)">
      <node pkg="demo_pkg" type="never" name="never"/>
    </group>
    <include file="$(find demo_pkg)/launch/sub.launch" ns="sub" clear_params="true">
      <arg name="who" value="$(arg robot)_sub"/>
      <env name="INC_ENV" value="i"/>
    </include>
  </group>
  <include file="$(dirname)/sub.launch" pass_all_args="true">
    <arg name="who" value="all"/>
  </include>
  <node pkg="demo_pkg" type="talker.py" name="talker2" if="true" output="log"/>
  <node pkg="demo_pkg" type="talker.py" name="talker3" unless="1"/>
  <test test-name="t1" pkg="demo_pkg" type="test_x"><param name="tp" value="1"/></test>
  <master auto="start"/>
</launch>
"""

SUB = """
<launch>
  <arg name="who"/>
  <arg name="robot" default="fallback"/>
  <arg name="level" default="$(eval 2 * 3)"/>
  <param name="who" value="$(arg who)"/>
  <param name="level" value="$(arg level)"/>
  <param name="robot_seen" value="$(arg robot)"/>
  <param name="~sub_private" value="sp"/>
  <node pkg="demo_pkg" type="talker.py" name="$(arg who)_node">
    <remap from="x" to="y"/>
  </node>
  <include file="$(dirname)/leaf.launch"><arg name="depth" value="2"/></include>
</launch>
"""

LEAF = """
<launch>
  <arg name="depth"/>
  <param name="depth" value="$(arg depth)"/>
  <node pkg="demo_pkg" type="leaf" name="leaf_$(arg depth)" args="$(arg depth)"/>
</launch>
"""

PARAMS_YAML = """
gains: {kp: 1.5, ki: 0, kd: 0.01}
topic_name: /scan
queue_size: 10
flags: [true, false]
empty: {}
nested:
  deep:
    value: "quoted"
angle: deg(45)
"""

ANON = """
<launch>
  <arg name="id" value="$(anon shared)"/>
  <node pkg="demo_pkg" type="t" name="$(anon worker)" args="$(anon worker) $(arg id)"/>
  <group ns="g">
    <node pkg="demo_pkg" type="t" name="$(anon worker)"/>
    <node pkg="demo_pkg" type="t" name="$(anon other)"/>
  </group>
  <node pkg="demo_pkg" type="t" name="$(anon other)" args="$(anon shared)"/>
  <include file="$(dirname)/anon_inc.launch"/>
  <param name="evald" value="$(eval anon('worker') + '|' + anon('fresh'))"/>
</launch>
"""

ANON_INC = """
<launch>
  <node pkg="demo_pkg" type="t" name="$(anon worker)"/>
</launch>
"""

LEAK = """
<launch>
  <param name="~first" value="1"/>
  <include file="$(dirname)/leak_inc.launch"/>
  <node pkg="demo_pkg" type="t" name="after"/>
  <group>
    <param name="~in_group" value="2"/>
    <node pkg="demo_pkg" type="t" name="in_group_node"/>
  </group>
  <node pkg="demo_pkg" type="t" name="after_group"/>
</launch>
"""

LEAK_INC = """
<launch>
  <node pkg="demo_pkg" type="t" name="inside"/>
  <param name="~leaked" value="3"/>
</launch>
"""

NS_ROOT = """
<launch>
  <arg name="__ns" default="unused"/>
  <param name="p" value="1"/>
  <node pkg="demo_pkg" type="t" name="n"/>
  <group ns="/absolute"><node pkg="demo_pkg" type="t" name="m"/></group>
</launch>
"""


def build(ws: Workspace) -> None:
    """Write demo_pkg: launch files, YAML, text and binary files."""
    pkg = ws.package("demo_pkg")
    for name, text in (("main", MAIN), ("sub", SUB), ("leaf", LEAF), ("anon", ANON),
                       ("anon_inc", ANON_INC), ("leak", LEAK), ("leak_inc", LEAK_INC),
                       ("ns_root", NS_ROOT)):
        ws.write(f"src/demo_pkg/launch/{name}.launch", text)
    ws.write("src/demo_pkg/config/params.yaml", PARAMS_YAML)
    ws.write("src/demo_pkg/config/text.txt", "line1\nline2\n")
    ws.write("src/demo_pkg/config/number.txt", "  12\n")
    ws.write("src/demo_pkg/config/blob.bin", b"\x00\x01binary\xff")
    assert pkg.is_dir()


#: (launch file under demo_pkg/launch, command-line args) loaded by both ddes and roslaunch.
CASES: list[tuple[str, dict[str, str]]] = [
    ("main.launch", {}),
    ("main.launch", {"robot": "r9", "rate": "5.5", "use_sim": "false"}),
    ("main.launch", {"use_sim": "0"}),
    ("anon.launch", {}),
    ("leak.launch", {}),
    ("ns_root.launch", {"__ns": "robot_ns"}),
    ("sub.launch", {"who": "direct", "robot": "rx"}),
]
