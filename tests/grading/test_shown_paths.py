"""A grade's digest does not depend on where the submission was unpacked: logs name the
submission's temporary folder ``/submission`` (World.display_paths), in the grader's world and in
the student's child process, and the SimpleActionServer's traceback names files by base name."""

from __future__ import annotations

import shutil
from pathlib import Path

from ddes.grading import grade
from ddes.graph.world import World

SOLUTION = Path(__file__).resolve().parent / "fixtures" / "ex0_solution"


def test_a_node_logs_a_display_path_under_its_shown_name() -> None:
    world = World(0, wall_budget=None)
    world.display_paths = {"/tmp/ddes-submission-abc/submission": "/submission",
                           "/tmp/ddes-submission-abc": "/elsewhere"}
    node = world.create_node("/player")
    got: list[str] = []
    log = world.messages.get_message_class("rosgraph_msgs/Log")
    world.create_node("/watch").subscribe("/rosout", log, lambda m: got.append(m.msg))
    world.run(until=0.1)
    node.loginfo("Opening %s", "/tmp/ddes-submission-abc/submission/pkg/bag/x.bag")
    node.loginfo("next to it: /tmp/ddes-submission-abc/other")
    world.run(until=0.2)
    assert got == ["Opening /submission/pkg/bag/x.bag", "next to it: /elsewhere/other"]
    assert [e.details["msg"] for e in world.trace.select(kind="log", source="/player")] == got


def test_two_grades_in_different_folders_have_the_same_digests(ex0, tmp_path: Path) -> None:  # type: ignore[no-untyped-def]
    # a talker that logs where it runs from: its folder differs between the two grades
    text = (SOLUTION / "talker.py").read_text(encoding="utf-8").replace(
        '    rospy.init_node("talker")\n',
        '    rospy.init_node("talker")\n'
        '    import os\n'
        '    rospy.loginfo("running in %s from %s", os.getcwd(), __file__)\n')
    assert "os.getcwd()" in text
    first, second = tmp_path / "a" / "deep" / "folder", tmp_path / "b"
    for where in (first, second):
        shutil.copytree(SOLUTION, where)
        (where / "talker.py").write_text(text, encoding="utf-8")
    one, two = grade(ex0, first), grade(ex0, second)
    assert one.digests and one.digests == two.digests
    assert one.score == two.score == grade(ex0, SOLUTION).score
