"""GradeReport's formats, read back: Gradescope's results.json and JUnit XML."""

from __future__ import annotations

import json
import math
import xml.etree.ElementTree as ET
from pathlib import Path

from ddes.grading import CriterionReport, GradeReport
from ddes.grading.report import finite_points


def sample() -> GradeReport:
    r = GradeReport(exercise="ex0_talker", title="Demo", submission="sub", seed=3, public=True,
                    problems=["public: the student's process ended (exit code 1)"],
                    execution_time=1.23456, submission_sha256="ab" * 32, ddes_version="0.1.0")
    r.criteria = [
        CriterionReport("0.1", "publishes", 2, 2),
        CriterionReport("0.2", "rate", 1.5, 4, "after_published", ["public (seed 3): 9.1 Hz"],
                        "ddes grade ex0_talker sub --seed 3 --public"),
        CriterionReport("0.3", "text \x00<&>", 0, 4, evidence=["bad \x1b[31m text"]),
    ]
    return r


def test_results_json_follows_gradescope_and_reads_back(tmp_path: Path) -> None:
    path = tmp_path / "results.json"
    sample().write_results(path)
    data = json.loads(path.read_text())
    assert data["score"] == 3.5 and data["execution_time"] == 1.2346
    assert "Public scenarios only" in data["output"]
    assert data["extra_data"]["seed"] == 3
    tests = data["tests"]
    assert [t["name"] for t in tests] == ["0.1 publishes", "0.2 rate", "0.3 text \x00<&>"]
    assert [(t["score"], t["max_score"], t["status"]) for t in tests] == [
        (2, 2, "passed"), (1.5, 4, "failed"), (0, 4, "failed")]
    assert tests[1]["visibility"] == "after_published" and tests[0]["visibility"] == "visible"
    assert tests[1]["output"] == ("public (seed 3): 9.1 Hz\n"
                                  "replay: ddes grade ex0_talker sub --seed 3 --public")
    assert {"name", "score", "max_score", "output", "visibility"} <= set(tests[0])


def test_junit_xml_reads_back(tmp_path: Path) -> None:
    path = tmp_path / "junit.xml"
    sample().write_junit(path)
    root = ET.parse(path).getroot()
    suite = root.find("testsuite")
    assert suite is not None and suite.get("name") == "ddes.ex0_talker"
    assert (suite.get("tests"), suite.get("failures")) == ("3", "2")
    props = {p.get("name"): p.get("value") for p in suite.findall("properties/property")}
    assert props == {"score": "3.5", "max_score": "10", "seed": "3", "public": "true"}
    cases = suite.findall("testcase")
    assert [c.get("name") for c in cases] == ["0.1 publishes", "0.2 rate", "0.3 text \ufffd<&>"]
    assert cases[0].find("failure") is None
    fail = cases[1].find("failure")
    assert fail is not None and fail.get("message") == "1.5/4" and "replay:" in (fail.text or "")
    points = {p.get("name"): p.get("value") for p in cases[1].findall("properties/property")}
    assert points == {"points": "1.5", "max_points": "4"}
    assert "\ufffd[31m" in (cases[2].find("failure").text or "")  # type: ignore[union-attr]
    assert "exit code 1" in (suite.findtext("system-err") or "")


def test_text_report_names_points_evidence_and_replay() -> None:
    text = sample().to_text()
    assert "0.2 rate ....." in text and "1.5/4" in text
    assert "  replay: ddes grade ex0_talker sub --seed 3 --public" in text
    assert text.endswith("total: 3.5/10 (35.0 %, public scenarios only)\n")


def test_points_fail_closed() -> None:
    assert finite_points(math.nan, 4) == 0 and finite_points(math.inf, 4) == 0
    assert finite_points(True, 4) == 0 and finite_points("4", 4) == 0  # type: ignore[arg-type]
    assert finite_points(9, 4) == 4 and finite_points(-1, 4) == 0 and finite_points(2.5, 4) == 2.5
