"""A student node that dies is named: the exception, the student's own frames, the simulated
time; a criterion that lost points in that scenario says so.  A callback that raises is named
too (the node goes on, as rospy's).  The parameters a node read cross as facts."""

from __future__ import annotations

import textwrap
from pathlib import Path
from typing import Any

from ddes.grading import Criterion, Exercise, grade
from ddes.grading.exercise import Facts

TALKS = "says something on /chatter"


def _said(facts: Facts) -> tuple[float, list[str]]:
    texts = [m.data for _t, who, m in facts.messages("/chatter") if who in facts.student_nodes]
    return (5.0, []) if len(texts) >= 5 else (0.0, [f"{len(texts)} message(s)"])


def _build(world: Any, _scenario: Any) -> None:
    listener = world.create_node("/grader_listener")
    listener.subscribe("/chatter", world.messages.get_message_class("std_msgs/String"),
                       lambda m: None)


SEEN: list[Facts] = []


def _keep(facts: Facts) -> tuple[float, list[str]]:
    SEEN.append(facts)
    return 1.0, []


EXERCISE = Exercise(id="talks", title="Talk", duration=1.0, build=_build,
                    scripts=(("talker.py", ()),),
                    criteria=(Criterion("1", TALKS, 5, _said), Criterion("2", "kept", 1, _keep)))


def _submit(tmp_path: Path, source: str) -> Path:
    sub = tmp_path / "sub"
    sub.mkdir()
    (sub / "talker.py").write_text(textwrap.dedent(source))
    return sub


def test_a_node_that_dies_is_named_with_its_frames_and_time(tmp_path: Path) -> None:
    sub = _submit(tmp_path, """\
        import rospy
        from std_msgs.msg import String

        def ratio(x):
            return 1 / x

        rospy.init_node("talker")
        pub = rospy.Publisher("chatter", String, queue_size=10)
        rospy.sleep(0.25)
        pub.publish("one")
        ratio(0)
    """)
    report = grade(EXERCISE, sub)
    assert report.problems == [
        "public: your node /talker died at t=0.250 s: ZeroDivisionError: division by zero "
        "(at talker.py:5 in ratio <- talker.py:11 in <module>)"]
    evidence = report.criteria[0].evidence
    assert evidence[0] == "public (seed 0): 1 message(s)"
    assert evidence[1].startswith("public (seed 0): your node /talker died at t=0.250 s (")
    assert evidence[1].endswith("what it would have done after that is missing")
    assert "ddes" not in " ".join(report.problems)  # no frame of ddes's own, no internal path


def test_a_script_that_dies_before_init_node_is_named_by_its_file(tmp_path: Path) -> None:
    sub = _submit(tmp_path, """\
        import rospy
        settings = {}
        rate = settings["rate"]
        rospy.init_node("talker")
    """)
    report = grade(EXERCISE, sub)
    assert report.problems == ["public: your node talker.py died at t=0.000 s: KeyError: "
                               "'rate' (at talker.py:3 in <module>)"]


def test_a_raising_callback_is_named_once_and_the_node_goes_on(tmp_path: Path) -> None:
    sub = _submit(tmp_path, """\
        import rospy
        from std_msgs.msg import String

        def tick(event):
            n[0] += 1
            if n[0] % 2:
                raise ValueError("odd tick %d" % n[0])
            pub.publish("tick")

        n = [0]
        rospy.init_node("talker")
        pub = rospy.Publisher("chatter", String, queue_size=10)
        rospy.Timer(rospy.Duration(0.1), tick)
        rospy.spin()
    """)
    report = grade(EXERCISE, sub)
    assert report.problems == [
        "public: your node /talker raised in its callback tick at t=0.100 s (the node goes on, "
        "as in ROS): ValueError: odd tick 1 (at talker.py:7 in tick)"]
    assert report.criteria[0].points == 0  # 4 messages in 1 s: one in two ticks failed
    assert "a callback of your node /talker raised at t=0.100 s" in report.criteria[0].evidence[1]


def test_a_healthy_node_has_no_problem_line_and_its_parameter_reads_cross(tmp_path: Path) -> None:
    sub = _submit(tmp_path, """\
        import rospy
        from std_msgs.msg import String

        rospy.init_node("talker")
        rate = rospy.get_param(rospy.get_name() + "/rate", 10)
        for name in ("greeting",):
            rospy.get_param("~" + name, "hello")
        rospy.has_param("/global_flag")
        pub = rospy.Publisher("chatter", String, queue_size=10)
        r = rospy.Rate(rate)
        while not rospy.is_shutdown():
            pub.publish("hi")
            r.sleep()
    """)
    SEEN.clear()
    report = grade(EXERCISE, sub)
    assert report.problems == []
    assert report.score == report.max_score
    reads = [(node, key, found) for _t, node, key, found in SEEN[-1].param_reads]
    assert reads == [("/talker", "/talker/rate", False), ("/talker", "/talker/greeting", False),
                     ("/talker", "/global_flag", False)]
    assert SEEN[-1].deaths == [] and SEEN[-1].callback_failures == []
