"""Exercise 2: the reference earns 100 %, the starter at most 20 %, typical bugs lose their
criteria; the starter generator and ``ddes course build --check``."""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest

from ddes.cli.main import main
from ddes.errors import GradingError
from ddes.grading import REGISTRY, grade
from ddes.grading.starter import starter_text

REPO = Path(__file__).resolve().parents[2]
SOLUTION = REPO / "solutions" / "ex2_package"
STARTER = REPO / "exercises" / "ex2_package"
NODE = "smb_highlevel_controller/scripts/smb_highlevel_controller_node.py"


def points(report):
    return {c.id: c.points for c in report.criteria}


def variant(tmp_path: Path, old: str, new: str, rel: str = NODE) -> Path:
    dst = tmp_path / "submission"
    shutil.copytree(SOLUTION, dst)
    text = (dst / rel).read_text()
    assert old in text
    (dst / rel).write_text(text.replace(old, new))
    return dst


def test_course_build_check_is_clean(capsys):
    assert main(["course", "build", "--check", "--root", str(REPO)]) == 0
    assert "up to date" in capsys.readouterr().out


def test_course_build_check_names_a_stale_file(tmp_path, capsys):
    shutil.copytree(REPO / "solutions" / "ex2_package", tmp_path / "solutions" / "ex2_package")
    assert main(["course", "build", "--root", str(tmp_path)]) == 0
    (tmp_path / "exercises" / "ex2_package" / "README.md").write_text("edited\n")
    (tmp_path / "exercises" / "ex2_package" / "extra.txt").write_text("extra\n")
    capsys.readouterr()
    assert main(["course", "build", "--check", "--root", str(tmp_path)]) == 1
    out = capsys.readouterr().out
    assert "out of date: exercises/ex2_package/README.md" in out
    assert "out of date: exercises/ex2_package/extra.txt" in out


def test_starter_text_stubs():
    py = "def f():\n    ### BEGIN SOLUTION\n    return 1\n    ### END SOLUTION\n"
    assert starter_text(py, "a.py") == 'def f():\n    raise NotImplementedError("your code here")\n'
    custom = "    ### BEGIN SOLUTION stub: pass  # your code here\n    x = 1\n    ### END SOLUTION\n"
    assert starter_text(custom, "a.py") == "    pass  # your code here\n"
    xml = "<a>\n  <!-- ### BEGIN SOLUTION -->\n  <b/>\n  <!-- ### END SOLUTION -->\n</a>\n"
    assert starter_text(xml, "x.launch") == "<a>\n  <!-- your code here -->\n</a>\n"
    assert starter_text("### BEGIN SOLUTION\nk: 1\n### END SOLUTION\n", "c.yaml") == \
        "# your code here\n"
    with pytest.raises(GradingError, match="a.py:1: BEGIN SOLUTION is never closed"):
        starter_text("### BEGIN SOLUTION\nx\n", "a.py")
    with pytest.raises(GradingError, match="END SOLUTION without"):
        starter_text("### END SOLUTION\n", "a.py")


def test_reference_scores_full_marks():
    report = grade(REGISTRY.get("ex2_package"), SOLUTION)
    assert points(report) == {"2.1": 40, "2.2": 30, "2.3": 15, "2.4": 15}, report.to_text()
    # one grading's wall time (3 scenarios of 8 simulated seconds, a sandboxed child each)
    print(f"ex2_package reference: {report.execution_time:.2f} s wall")
    assert report.execution_time < 60


def test_starter_scores_at_most_20_percent():
    report = grade(REGISTRY.get("ex2_package"), STARTER)
    assert report.score <= 0.2 * report.max_score
    assert points(report) == {"2.1": 0, "2.2": 6, "2.3": 0, "2.4": 0}, report.to_text()


def test_hard_coded_topic_and_queue_size_lose_2_3(tmp_path):
    sub = variant(tmp_path, 'self.scan_topic = rospy.get_param("~scan_topic")',
                  'self.scan_topic = "/scan"')
    got = points(grade(REGISTRY.get("ex2_package"), sub))
    # the public scenario uses the student's own file; the two hidden ones move the laser
    assert got["2.3"] == pytest.approx(5 + 10 / 3, abs=1e-3)
    assert got["2.1"] == pytest.approx(40 / 3, abs=1e-3)
    assert got["2.2"] == 30 and got["2.4"] == 15


def test_largest_range_and_wrong_frame_lose_2_1_and_2_4(tmp_path):
    sub = variant(tmp_path, "return min(valid) if valid else math.inf",
                  "return max(valid) if valid else math.inf",
                  rel="smb_highlevel_controller/src/smb_highlevel_controller/algorithm.py")
    rviz = sub / "smb_highlevel_controller/rviz/smb_highlevel_controller.rviz"
    rviz.write_text(rviz.read_text().replace("Fixed Frame: odom", "Fixed Frame: map"))
    got = points(grade(REGISTRY.get("ex2_package"), sub, public=True))
    assert got == {"2.1": 0, "2.2": 30, "2.3": 15, "2.4": 10}
