"""/use_sim_time across the sandbox boundary: the grader's setting reaches the child before the
student's node starts, the node follows the /clock the grader publishes (zero until the first),
while its wall time (``time.time()``) is the kernel clock; the proxies keep no clock."""

from __future__ import annotations

import textwrap
from pathlib import Path

import ddes
from ddes.grading import Lockstep, Sandbox
from ddes.graph.world import World
from ddes.msg import get_message_class

NODE = textwrap.dedent("""\
    import time
    import rospy
    from std_msgs.msg import Header
    rospy.init_node("timed")
    pub = rospy.Publisher("/beat", Header, queue_size=10)
    rate = rospy.Rate(2, reset=True)
    while not rospy.is_shutdown():
        rate.sleep()
        h = Header()
        h.stamp = rospy.Time.now()
        h.frame_id = "wall=%.2f wallclock=%s" % (time.time(), rospy.rostime.is_wallclock())
        pub.publish(h)
""")


def _run(tmp_path: Path, sim: bool) -> tuple[World, list[tuple[int, int, str]]]:
    (tmp_path / "node.py").write_text(NODE)
    world = World(0, wall_budget=None)
    world.use_sim_time = sim
    clock = get_message_class("rosgraph_msgs/Clock")
    src = world.create_node("/clock_source", use_sim_time=False)
    pub = src.advertise("/clock", clock, queue_size=1)

    def tick(_event: object) -> None:  # /clock from 1 s on, at half the kernel's speed
        if world.now >= 1_000_000_000:
            pub.publish(clock(clock=ddes.Time._from_ns(world.now // 2)))

    ddes.Timer(src, 0.01, tick)
    params = {"/use_sim_time": True} if world.use_sim_time else {}
    lock = Lockstep(world, Sandbox(tmp_path, [("node.py", [])], params=params))
    assert lock.run(4_000_000_000).state == "finished"
    assert not lock.proxies["/timed"].use_sim_time
    header = get_message_class("std_msgs/Header")
    beats = [(ev.t, header().deserialize(ev.details["data"]))
             for ev in world.trace.select(kind="topic.publish", topic="/beat")]
    return world, [(t, h.stamp.to_nsec(), h.frame_id) for t, h in beats]


def test_the_graders_use_sim_time_reaches_the_student_node(tmp_path: Path) -> None:
    _world, beats = _run(tmp_path, sim=True)
    # nothing before the first /clock (1 s, ROS 0.5 s); rospy's first sleep ends 0.5 s of ROS
    # time after it (ROS 1.0 s), one period behind the Rate's start at ROS 0, so the next
    # sleep returns at once (rospy catches up); then every 0.5 s of ROS time = 1 s of wall time
    assert [(t // 10**7, s // 10**7, f) for t, s, f in beats] == [
        (200, 100, "wall=2.00 wallclock=False"), (200, 100, "wall=2.00 wallclock=False"),
        (300, 150, "wall=3.00 wallclock=False")]


def test_without_it_the_node_runs_on_the_kernel_clock(tmp_path: Path) -> None:
    _world, beats = _run(tmp_path, sim=False)
    assert [(t, s) for t, s, _ in beats] == [(k * 500_000_000,) * 2 for k in range(1, 8)]
    assert beats[0][2] == "wall=0.50 wallclock=True"
