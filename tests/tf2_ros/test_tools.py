"""The TF programs in the console: static_transform_publisher (tf2_ros's and tf1's forms),
tf_echo's texts, view_frames.py's frames.gv, and the matplotlib drawing of the tree."""

from __future__ import annotations

import re
from pathlib import Path
from typing import Any

import ddes
from ddes.console.shell import Console
from ddes.display.figure import DisplayFigure
from ddes.msg import get_message_class
from ddes.tf2_ros import Buffer, TransformListener, plot_frames
from ddes.tf2_ros.tools import atof, generate_dot
from ddes.time.rostime import Time


def test_static_transform_publisher_latches_both_forms() -> None:
    console = Console(seed=0)
    out = console.run("rosrun tf2_ros static_transform_publisher 0.2 0 0.1 0 0 0 1 base laser &")
    assert out.splitlines()[-1] == (
        "[ INFO] [0.000000000]: Spinning until killed publishing base to laser")
    console.run("rosrun tf2_ros static_transform_publisher 0 0 0 1.5707963267948966 0 0 base cam &")
    console.run("sleep 1")
    info = console.run("rostopic info /tf_static")
    assert info.startswith("Type: tf2_msgs/TFMessage\n")
    assert " * /static_transform_publisher_1 (" in info and " * /static_transform_publisher_2 (" in info
    # a late listener gets both latched transforms, each its publisher's authority
    echo = console.run("rostopic echo -n 2 /tf_static")
    assert 'child_frame_id: "laser"' in echo and 'child_frame_id: "cam"' in echo
    console.run("rosrun tf tf_echo base cam &")
    assert console.run("sleep 0.5").splitlines() == [
        "At time 0.000",
        "- Translation: [0.000, 0.000, 0.000]",
        "- Rotation: in Quaternion [0.000, 0.000, 0.707, 0.707]",
        "            in RPY (radian) [0.000, -0.000, 1.571]",
        "            in RPY (degree) [0.000, -0.000, 90.000]",
    ]


def test_static_transform_publisher_usage_and_errors() -> None:
    console = Console(seed=0)
    bad = console.execute("rosrun tf2_ros static_transform_publisher 1 2 3 0 0 0 a a")
    assert bad.code == 1
    assert "target_frame and source frame are the same (a, a) this cannot work" in bad.out + bad.err
    usage = console.execute("rosrun tf2_ros static_transform_publisher 1 2")
    assert usage.code == 255
    assert "Usage: static_transform_publisher /param_name " in usage.out
    console.run("rosparam set /laser_tf \"{header: {frame_id: base}, child_frame_id: laser, "
                "transform: {translation: {x: 1, y: 0, z: 0}, rotation: {x: 0, y: 0, z: 0, "
                "w: 1}}}\"")
    out = console.run("rosrun tf2_ros static_transform_publisher /laser_tf &")
    assert "Looking for TF in parameter: /laser_tf" in out
    assert "Spinning until killed publishing base to laser" in out
    missing = console.execute("rosrun tf2_ros static_transform_publisher /nope")
    assert missing.code == 255 and "Could not read TF from parameter server: /nope" in (
        missing.out + missing.err)


def test_tf1_static_transform_publisher_future_dates_on_tf() -> None:
    console = Console(seed=0)
    console.run("rosrun tf static_transform_publisher 1 0 0 0 0 0 odom base 100 &")
    echo = console.run("rostopic echo -n 3 /tf")
    # sent at 0.1, 0.2, 0.3 (the connection takes 1 ms) and stamped a period later
    assert re.findall(r"nsecs: +(\d+)", echo) == ["200000000", "300000000", "400000000"]
    assert "time: " not in echo and 'child_frame_id: "base"' in echo
    assert "static_transform_publisher_1" in console.run("rosnode list")
    usage = console.execute("rosrun tf static_transform_publisher 1 2 3")
    assert usage.code == 255 and "period(milliseconds)" in usage.out


def test_tf_echo_failure_block_and_rate() -> None:
    console = Console(seed=0)
    console.run("rosrun tf2_ros static_transform_publisher 1 2 3 0 0 0 base laser &")
    console.run("rosrun tf tf_echo base nope &")
    assert console.run("sleep 1.5").splitlines() == [
        "Failure at 1.000000000",
        'Exception thrown:"nope" passed to lookupTransform argument source_frame does not '
        "exist. ",
        "The current list of frames is:",
        "Frame laser exists with parent base.",
        "",
    ] * 2  # the wait's second ends, then roscpp's Rate does not sleep the missed cycle
    console.run("kill %2")
    console.run("rosrun tf tf_echo base laser 4 &")
    assert console.run("sleep 1").count("At time 0.000") == 5  # 4 Hz, both ends included
    bad = console.execute("rosrun tf tf_echo base")
    assert bad.code == 255 and bad.out.startswith("Usage: tf_echo source_frame target_frame")


def test_view_frames_writes_frames_gv(tmp_path: Path) -> None:
    console = Console(seed=0)
    console.run(f"cd {tmp_path}")
    console.run("rosrun tf2_ros static_transform_publisher 1 2 3 0 0 0 base laser &")
    out = console.run("rosrun tf2_tools view_frames.py")
    assert out.splitlines() == ["[INFO] [0.000000]: Listening to tf data during 5 seconds...",
                                "[INFO] [5.000010]: Generating graph in frames.pdf file..."]
    assert (tmp_path / "frames.gv").read_text() == (
        'digraph G {\n"base" -> "laser"[label=" Broadcaster: /static_transform_publisher_1\\n'
        'Average rate: 10000.0\\nBuffer length: 0.0\\nMost recent transform: 0.0\\n'
        'Oldest transform: 0.0\\n"];\nedge [style=invis];\n subgraph cluster_legend { '
        'style=bold; color=black; label ="view_frames Result";\n"Recorded at time: 5.00001"'
        '[ shape=plaintext ] ;\n}->"base";\n}')
    assert (tmp_path / "frames.pdf").read_bytes().startswith(b"%PDF")
    assert generate_dot({}, 0.0) == 'digraph G { "No tf data received" }'


def test_plot_frames_draws_the_tree() -> None:
    world = ddes.World()
    robot = world.create_node("robot")
    buf = Buffer()
    TransformListener(world.create_node("viewer"), buf)
    from ddes.tf2_ros import StaticTransformBroadcaster, TransformBroadcaster

    ts_class = get_message_class("geometry_msgs/TransformStamped")

    def t(parent: str, child: str, stamp: Any) -> Any:
        ts = ts_class()
        ts.header.frame_id, ts.child_frame_id, ts.header.stamp = parent, child, stamp
        ts.transform.rotation.w = 1.0
        return ts

    StaticTransformBroadcaster(robot).sendTransform([t("base_link", "laser", Time()),
                                                     t("base_link", "camera", Time())])
    br = TransformBroadcaster(robot)

    def drive() -> Any:
        for _ in range(20):
            br.sendTransform(t("odom", "base_link", robot.get_rostime()))
            yield robot.sleep(0.1)

    robot.process(drive())
    world.run(until=2.0)
    fig = plot_frames(buf)
    assert isinstance(fig, DisplayFigure)
    texts = [x.get_text() for x in fig.axes[0].texts]
    for frame in ("odom", "base_link", "laser", "camera"):
        assert frame in texts
    assert "/robot\nstatic" in texts
    assert any(x.startswith("/robot\n1") and x.endswith(" Hz") for x in texts)
    assert fig._repr_png_() is not None
    empty = plot_frames(Buffer())
    assert [x.get_text() for x in empty.axes[0].texts] == ["No tf data received"]


def test_atof_reads_as_c_does() -> None:
    assert [atof(x) for x in ("1.5", "-2e3", "3m", "abc", ".5", " 7")] == [
        1.5, -2000.0, 3.0, 0.0, 0.5, 7.0]


def test_the_programs_start_from_a_launch_file(tmp_path: Path) -> None:
    launch = tmp_path / "tf.launch"
    launch.write_text(
        '<launch>\n'
        '  <node pkg="tf2_ros" type="static_transform_publisher" name="laser_tf"\n'
        '        args="0.2 0 0.1 0 0 0 base_link laser"/>\n'
        '  <node pkg="tf" type="tf_echo" name="echo" args="base_link laser" output="screen"/>\n'
        '</launch>\n')
    out = Console(seed=0).run(f"roslaunch --duration 1.5 {launch}")
    assert out.count("- Translation: [0.200, 0.000, 0.100]") == 2
    assert "process[laser_tf-1]: started with pid" in out
