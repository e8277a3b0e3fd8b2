"""Feedback a student can act on: the output cap named with its size, a package-name mismatch
named as such, no negative durations, evidence never cut mid-word, no grading-machine paths or
ddes API names in what a launch error says."""

from __future__ import annotations

import shutil
import textwrap
from pathlib import Path
from typing import Any

from ddes.grading import REGISTRY, Criterion, Exercise, grade
from ddes.grading.course import _student_text, package_hint
from ddes.grading.exercises.common import relative
from ddes.grading.grader import _cut
from ddes.grading.sandbox import Limits

REPO = Path(__file__).resolve().parents[2]


def _nothing(_facts: Any) -> tuple[float, list[str]]:
    return 1.0, []


def test_output_past_the_cap_is_named_with_its_size(tmp_path: Path) -> None:
    (tmp_path / "loud.py").write_text(textwrap.dedent("""\
        import rospy
        rospy.init_node("loud")
        while True:
            print("x" * 1000)
    """))
    ex = Exercise(id="loud", title="Loud", duration=1.0, scripts=(("loud.py", ()),),
                  criteria=(Criterion("1", "runs", 1, _nothing),))
    report = grade(ex, tmp_path, limits=Limits(file_bytes=1 << 20))
    # Python ignores SIGXFSZ: the write past the limit fails with EFBIG and the node dies of it
    assert len(report.problems) == 1
    assert report.problems[0].startswith("public: your node /loud died at t=0.000 s: OSError: "
                                         "[Errno 27] File too large (at loud.py:4 in <module>)")
    assert report.problems[0].endswith(" — your output (or a file) passed the 1 MiB a grade "
                                       "allows: print and log less"), report.problems


def test_a_package_name_mismatch_is_named_as_such(tmp_path: Path) -> None:
    sub = tmp_path / "sub"
    shutil.copytree(REPO / "solutions" / "ex4b_actions" / "smb_follow_path",
                    sub / "smb_follow_path")
    xml = sub / "smb_follow_path" / "package.xml"
    xml.write_text(xml.read_text().replace("<name>smb_follow_path</name>",
                                           "<name>smb_followpath</name>"))
    assert package_hint(sub, "smb_follow_path") == (
        "the folder smb_follow_path/ declares package 'smb_followpath' in its package.xml, not "
        "'smb_follow_path': ROS finds a package by the <name> of its package.xml, so make the "
        "two the same")
    report = grade(REGISTRY.get("ex4b_actions"), sub, public=True)
    shown = report.to_text()
    assert "declares package 'smb_followpath'" in shown
    for internal in ("RosPack(", "World(package_path", "DDES_PACKAGE_PATH", "/ddes/packages"):
        assert internal not in shown, internal


def test_a_missing_package_lists_what_the_submission_has(tmp_path: Path) -> None:
    (tmp_path / "mine").mkdir()
    (tmp_path / "mine" / "package.xml").write_text("<package><name>mine</name></package>")
    text = _student_text("x.launch:3: <include>: $(find theirs): package 'theirs' not found; "
                         "searched: /grader/path. Pass its parent folder on the package path "
                         "(RosPack(paths))", tmp_path)
    assert text == ("x.launch:3: <include>: $(find theirs): your submission's packages are "
                    "'mine' (mine/); none is named 'theirs'")


def test_durations_are_never_negative() -> None:
    assert relative(1_500_000_000, "the cancel") == "1.50 s after the cancel"
    assert relative(-1_500_000_000, "the cancel") == "1.50 s before the cancel"
    assert relative(1_000_000, "the cancel") == "at the cancel"


def test_evidence_is_cut_at_a_word() -> None:
    text = "word " * 200
    cut = _cut(text, 500)
    assert len(cut) <= 500 and cut.endswith("word…")
    assert _cut("short", 500) == "short"


def test_the_graders_own_log_lines_are_not_printed(tmp_path: Path, capfd: Any) -> None:
    """Exercise 4b's schedule drives the robot into the grader's pillar: the simulator's
    "collision with grader_pillar" is the grader's doing, never printed as the student's."""
    from ddes.grading.exercise import Scenario
    from ddes.grading.grader import run_scenario

    ex = Exercise(id="quiet", title="Quiet", duration=0.5, build=_warns, scripts=(),
                  criteria=(Criterion("1", "runs", 1, _nothing),))
    world, _facts = run_scenario(ex, Scenario("public", 0), tmp_path, None)
    out, err = capfd.readouterr()
    assert "collision" not in out + err
    assert any("collision with grader_pillar" in str(ev.details.get("msg", ""))
               for ev in world.trace.select(kind="log"))


def _warns(world: Any, _scenario: Any) -> None:
    node = world.create_node("/ddes_sim")
    world.call_at(100_000_000, lambda: node.logwarn("collision with grader_pillar"))
