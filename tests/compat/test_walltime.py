"""Wall time in rospy scripts: ``time`` and ``rospy.rostime`` on the kernel clock, which plays the
wall clock, while a sim-time node's ROS time follows ``/clock`` (lecture 4, ROS time)."""

from __future__ import annotations

import textwrap
from pathlib import Path

import pytest

import ddes
from ddes.compat.scripts import run_script
from ddes.msg import get_message_class

Clock = get_message_class("rosgraph_msgs/Clock")


def _run(tmp_path: Path, body: str, *, sim: bool, clock_from: float = 0.0,
         until: float = 3.5) -> list[str]:
    path = tmp_path / "node.py"
    path.write_text(textwrap.dedent(body))
    lines: list[str] = []
    world = ddes.World(seed=3)
    world.log_output = lambda line, _level: lines.append(line)
    world.use_sim_time = sim
    if sim:  # /clock at half the kernel's speed from clock_from (kernel) s on
        node = world.create_node("/clock_source", use_sim_time=False)
        pub = node.advertise("/clock", Clock, queue_size=1)

        def tick(_event: object) -> None:
            if world.now >= clock_from * 1e9:
                pub.publish(Clock(clock=ddes.Time._from_ns(world.now // 2)))

        ddes.Timer(node, 0.01, tick)
    run_script(world, path)
    world.run(until=until)
    return lines


def test_time_time_and_sleep_read_the_kernel_clock_and_ros_time_follows_the_clock(
        tmp_path: Path) -> None:
    lines = _run(tmp_path, """
        import threading
        import time

        import rospy

        def status():
            while not rospy.is_shutdown():
                rospy.loginfo("wall=%.1f ros=%.1f", time.time(), rospy.get_time())
                time.sleep(1.0)

        rospy.init_node("watch")
        threading.Thread(target=status).start()
        rospy.spin()
    """, sim=True)
    texts = [line.split(": ", 1)[1] for line in lines]
    assert texts == ["wall=0.0 ros=0.0", "wall=1.0 ros=0.5", "wall=2.0 ros=1.0",
                     "wall=3.0 ros=1.5"]


def test_wall_sleep_goes_on_while_the_clock_stands_still(tmp_path: Path) -> None:
    lines = _run(tmp_path, """
        import time
        import rospy
        from rospy.rostime import wallsleep

        rospy.init_node("watch")
        rospy.loginfo("wallclock %s", rospy.rostime.is_wallclock())
        wallsleep(0.5)
        rospy.rostime.wallsleep(0.25)
        rospy.loginfo("%d ns %.3f", time.time_ns(), rospy.get_time())
        rospy.sleep(0.5)  # waits for the first /clock (at 2 s), then 0.5 s of ROS time
        rospy.loginfo("%.3f %.3f", time.monotonic(), rospy.get_time())
        try:
            time.sleep(-1)
        except ValueError as exc:
            rospy.loginfo(str(exc))
    """, sim=True, clock_from=2.0)
    texts = [line.split(": ", 1)[1] for line in lines]
    assert texts == ["wallclock False", "750000000 ns 0.000", "3.000 1.500",
                     "sleep length must be non-negative"]


def test_without_sim_time_ros_time_is_the_wall_clock(tmp_path: Path) -> None:
    lines = _run(tmp_path, """
        import time
        import rospy
        rospy.init_node("watch")
        time.sleep(1.25)
        rospy.loginfo("%s %.2f %.2f", rospy.rostime.is_wallclock(), time.perf_counter(),
                      rospy.get_time())
    """, sim=False)
    assert [line.split(": ", 1)[1] for line in lines] == ["True 1.25 1.25"]


@pytest.mark.parametrize("bad", ["'1'", "float('nan')", "float('inf')"])
def test_time_sleep_refuses_what_python_refuses(tmp_path: Path, bad: str) -> None:
    lines = _run(tmp_path, f"""
        import time
        import rospy
        rospy.init_node("watch")
        try:
            time.sleep({bad})
        except (TypeError, ValueError, OverflowError) as exc:
            rospy.loginfo(type(exc).__name__)
    """, sim=False)
    assert len(lines) == 1 and lines[0].split(": ", 1)[1] in ("TypeError", "ValueError",
                                                                "OverflowError")
