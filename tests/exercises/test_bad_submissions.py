"""Bad submissions get a report that names the problem and the criterion it costs, in the
submission's own paths, never a traceback (issue 19, "Bad input"): a syntax error, a package
whose package.xml names another package, a launch file that does not parse, a missing folder."""

from __future__ import annotations

import shutil
from pathlib import Path

from ddes.grading import REGISTRY, grade

REPO = Path(__file__).resolve().parents[2]
SOLUTION = REPO / "solutions" / "ex3_pillar"
PKG = "smb_highlevel_controller"
NODE = f"{PKG}/scripts/smb_highlevel_controller_node.py"
LAUNCH = f"{PKG}/launch/smb_highlevel_controller.launch"


def copy(tmp_path: Path) -> Path:
    dst = tmp_path / "submission"
    shutil.copytree(SOLUTION, dst, ignore=shutil.ignore_patterns("mutants"))
    return dst


def report_text(submission: Path) -> tuple[str, dict[str, float]]:
    report = grade(REGISTRY.get("ex3_pillar"), submission, public=True)
    text = report.to_text()
    assert "Traceback" not in text
    # paths inside the submission, not the grader's copy of it
    assert "ddes-grade-" not in text and "ddes-submission-" not in text
    return text, {c.id: c.points for c in report.criteria}


def test_a_syntax_error_is_named_with_its_file_and_line(tmp_path: Path) -> None:
    sub = copy(tmp_path)
    with open(sub / NODE, "a", encoding="utf-8") as f:
        f.write("def broken(:\n")
    text, points = report_text(sub)
    assert f'File "{NODE}", line' in text and "SyntaxError" in text
    assert points["3.2"] == 0 and points["3.4"] == 0


def test_a_package_named_otherwise_in_package_xml_is_not_found(tmp_path: Path) -> None:
    sub = copy(tmp_path)
    manifest = sub / PKG / "package.xml"
    manifest.write_text(manifest.read_text().replace(f"<name>{PKG}<", "<name>my_controller<"))
    text, points = report_text(sub)
    # rospack goes by package.xml's <name>: the report names the mismatch
    assert (f"the folder {PKG}/ declares package 'my_controller' in its package.xml, not "
            f"'{PKG}'") in text
    assert sum(points.values()) <= 20


def test_a_launch_file_that_does_not_parse_is_named(tmp_path: Path) -> None:
    sub = copy(tmp_path)
    (sub / LAUNCH).write_text("<launch><node")
    text, points = report_text(sub)
    assert f"{LAUNCH} does not load: {LAUNCH}:1: Invalid roslaunch XML syntax" in text
    assert points["3.1"] == points["3.2"] == points["3.4"] == 0


def test_a_missing_submission_costs_every_criterion(tmp_path: Path) -> None:
    text, points = report_text(tmp_path / "nowhere")
    assert "does not exist — costs every criterion" in text
    assert sum(points.values()) == 0
