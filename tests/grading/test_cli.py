"""``ddes grade``: list, one submission (folder, zip, notebook), results files, exit codes."""

from __future__ import annotations

import json
import xml.etree.ElementTree as ET
import zipfile
from pathlib import Path

import pytest

from ddes.cli.main import main

HERE = Path(__file__).resolve().parent
EXERCISES = str(HERE / "fixtures" / "ex0_talker.py")
SOLUTION = HERE / "fixtures" / "ex0_solution"


def grade(*words: str) -> int:
    return main(["grade", "--exercises", EXERCISES, *words])


def test_list(capsys: pytest.CaptureFixture[str]) -> None:
    assert grade("list") == 0
    out = capsys.readouterr().out
    assert "ex0_talker  Demo: a rospy talker  (10 points, 2 s simulated)" in out
    assert "0.3" in out and "[after_published]" in out


def test_a_folder_grades_with_results_and_junit(tmp_path: Path,
                                                capsys: pytest.CaptureFixture[str]) -> None:
    results, junit = tmp_path / "r" / "results.json", tmp_path / "j.xml"
    assert grade("ex0_talker", str(SOLUTION), "--results", str(results), "--junit", str(junit),
                 "--out", str(tmp_path / "o"), "--fail-under", "100") == 0
    assert "total: 10/10 (100.0 %, all scenarios)" in capsys.readouterr().out
    data = json.loads(results.read_text())
    assert data["score"] == 10 and [t["number"] for t in data["tests"]] == ["0.1", "0.2", "0.3"]
    assert ET.parse(junit).getroot().find("testsuite").get("failures") == "0"  # type: ignore[union-attr]
    assert sorted(p.name for p in (tmp_path / "o").iterdir()) == [
        "junit.xml", "report.txt", "results.json"]


def test_zip_and_notebook_submissions(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    source = (SOLUTION / "talker.py").read_text()
    z = tmp_path / "s.zip"
    with zipfile.ZipFile(z, "w") as zf:
        zf.writestr("talker.py", source)
    assert grade("ex0_talker", str(z)) == 0
    assert "total: 10/10" in capsys.readouterr().out
    nb = tmp_path / "s.ipynb"
    nb.write_text(json.dumps({"cells": [{"cell_type": "code", "metadata": {"tags": ["export"]},
                                         "source": "# file: talker.py\n" + source,
                                         "outputs": []}]}))
    assert grade("ex0_talker", str(nb)) == 0
    assert "total: 10/10" in capsys.readouterr().out


def test_a_bad_submission_is_a_report_not_a_traceback(tmp_path: Path,
                                                      capsys: pytest.CaptureFixture[str]) -> None:
    z = tmp_path / "evil.zip"
    with zipfile.ZipFile(z, "w") as zf:
        zf.writestr("../talker.py", "x")
    assert grade("ex0_talker", str(z)) == 0
    out = capsys.readouterr().out
    assert "problem: evil.zip: entry '../talker.py' climbs out of the submission ('..') — costs " \
           "every criterion" in out
    assert "total: 0/10" in out
    empty = tmp_path / "empty"
    empty.mkdir()
    assert grade("ex0_talker", str(empty), "--fail-under", "50") == 1
    captured = capsys.readouterr()
    assert "problem: missing file(s): talker.py" in captured.out
    assert "below --fail-under 50 %" in captured.err


def test_a_crashing_submission_costs_only_its_criteria(tmp_path: Path,
                                                       capsys: pytest.CaptureFixture[str]) -> None:
    (tmp_path / "talker.py").write_text((SOLUTION / "talker.py").read_text().replace(
        "n += 1", "n += 1\n        if n == 12:\n            raise SystemExit(1)").replace(
        'f"hello world {n}"', '"hello"'))
    assert grade("ex0_talker", str(tmp_path)) == 0
    out = capsys.readouterr().out
    assert "0.1 publishes on /chatter ......" in out and " 2/2" in out
    assert "10 Hz within 5 % ....................................... 4/4" in out
    assert "'hello' is not 'hello world N'" in out
    assert "replay: ddes grade replay ex0_talker" in out


@pytest.mark.parametrize("words, text", [
    (["nope", "x"], "unknown exercise 'nope'"),
    (["ex0_talker"], "usage:"),
    (["batch", "ex0_talker", "d"], "usage: ddes grade batch"),
    (["ex0_talker", "x", "--mem", "lots"], "--mem 'lots'"),
    (["ex0_talker", "x", "--mem", "1M"], "below 128 MiB"),
])
def test_usage_errors_exit_2(words: list[str], text: str,
                             capsys: pytest.CaptureFixture[str]) -> None:
    assert grade(*words) == 2
    assert text in capsys.readouterr().err
