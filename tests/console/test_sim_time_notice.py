"""Simulated time that stands still says so (issue 42, item 3.2).

Under ``/use_sim_time`` with nothing publishing ``/clock``, every node on simulated time waits for
ever, and real ROS prints nothing at all.  ddes prints one line (a documented deviation,
docs/console.md) on standard error, once per command that lets the world run.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from ddes.console.shell import Console
from ddes.console.tooling import sim_time_notice

NOTICE = ("[ddes] /use_sim_time is true and nothing publishes /clock: simulated time stands "
          "still at 0 (start rosbag play --clock, or a node publishing /clock)")


def test_the_lecture_4_student_is_told_why_nothing_happens(console: Console) -> None:
    console.run("rosparam set use_sim_time true")
    console.run("rosrun --quiet rospy_tutorials talker &")
    for line in ("sleep 1", "rosservice call /rosout/get_loggers",
                 "rostopic echo -n 1 --duration 2 /chatter"):
        result = console.execute(line)
        assert result.err.splitlines().count(NOTICE) == 1, line  # once per waiting command
        assert result.err.startswith(NOTICE + "\n"), line  # before what the command prints
    result = console.execute("rosrun roscpp_tutorials listener &")  # nothing waits: no notice
    assert result.err == ""
    assert console.execute("rosparam get /use_sim_time").err == ""


def test_no_notice_on_kernel_time_or_while_a_clock_runs(console: Console) -> None:
    assert console.execute("sleep 1").err == ""  # /use_sim_time unset
    console.run("rosparam set use_sim_time false")
    assert console.execute("sleep 1").err == ""
    console.run("rosparam set use_sim_time true")
    console.run('rostopic pub -r 10 /clock rosgraph_msgs/Clock "clock: {secs: 5}" &')
    console.run("rosrun --quiet rospy_tutorials talker &")  # on simulated time
    assert console.execute("sleep 1").err == ""  # something publishes /clock
    console.run("kill %1")  # the clock stops; the talker's time stays at its last /clock
    assert console.execute("sleep 1").err == (
        "[ddes] /use_sim_time is true and nothing publishes /clock: simulated time stands still "
        "at 5.000000000, the last /clock (start rosbag play --clock, or a node publishing "
        "/clock)\n")


def test_rosbag_play_without_clock_is_named(console: Console, tmp_path: Path,
                                            monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(tmp_path)
    console.run("rosrun --quiet rospy_tutorials talker &")
    console.run("rosbag record -O talk --duration 1 /chatter")
    console.run("kill %1")
    console.run("rosparam set use_sim_time true")
    played = console.execute("rosbag play -q talk.bag")  # play.cpp advertises /clock anyway
    assert played.code == 0
    assert ("[ddes] /use_sim_time is true and nothing publishes /clock: simulated time stands "
            "still at 0 (rosbag play publishes it only with --clock)\n") in played.err
    assert "[ddes]" not in console.execute("rosbag play -q --clock talk.bag").err


def test_the_notice_is_a_function_of_the_world(console: Console) -> None:
    assert sim_time_notice(console.world) is None
    console.world.master.params.set_param("/use_sim_time", True)
    assert sim_time_notice(console.world) == NOTICE
