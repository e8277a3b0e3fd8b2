"""``ddes grade sweep``: the demo reference has zero false failures over its seeds; the text
shows the distribution, the figure its histogram, ``--out DIR`` writes them and every seed's
grade files there."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from matplotlib.patches import Rectangle

from ddes.cli.main import main
from ddes.display.figure import DisplayFigure
from ddes.grading.sweep import histogram, sweep

from .conftest import EXERCISE_FILE, SOLUTION


def test_histogram_bins_and_bars() -> None:
    lines = histogram([100.0, 100.0, 60.0, 0.0, 99.9], width=4)
    assert len(lines) == 11
    assert lines[0] == " 0-10 % | ##   1"
    assert lines[1] == "10-20 % |      0"
    assert lines[6] == "60-70 % | ##   1"
    assert lines[9] == "90-100% | ##   1"
    assert lines[10] == "  100 % | #### 2"


def test_the_reference_has_no_false_failure_over_its_seeds(
        ex0, tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:  # type: ignore[no-untyped-def]
    result = sweep(ex0, SOLUTION, range(0, 4))
    assert result.failures() == [] and result.scores == [10.0] * 4
    assert [s for s, _ in result.grades] == [0, 1, 2, 3]
    fig = result.figure()
    assert isinstance(fig, DisplayFigure)
    bars = [p for p in fig.axes[0].patches if isinstance(p, Rectangle)]
    assert [b.get_height() for b in bars] == [0] * 10 + [4]
    figure = tmp_path / "h.png"
    assert main(["grade", "--exercises", str(EXERCISE_FILE), "sweep", "ex0_talker",
                 str(SOLUTION), "--seeds", "0:3", "--figure", str(figure),
                 "--fail-under", "100"]) == 0
    out = capsys.readouterr().out
    assert f"ex0_talker — {SOLUTION}: 3 seed(s), 0..2" in out
    assert "score min 10  median 10  max 10  (of 10)" in out
    assert "  100 % | ######################################## 3" in out
    assert "below full marks: 0 of 3 seed(s)" in out
    assert figure.read_bytes()[:4] == b"\x89PNG"


def test_a_failing_submission_lists_its_seeds_with_replay_lines(
        tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    sub = tmp_path / "five_hz"
    sub.mkdir()
    (sub / "talker.py").write_text((SOLUTION / "talker.py").read_text().replace(
        "rospy.Rate(10)", "rospy.Rate(5)"))
    out = tmp_path / "swept"
    assert main(["grade", "--exercises", str(EXERCISE_FILE), "sweep", "ex0_talker",
                 str(sub), "--seeds", "5:7", "--fail-under", "80", "--out", str(out)]) == 1
    captured = capsys.readouterr()
    # --out DIR: the text, the summary, the histogram and each seed's grade files
    assert sorted(str(p.relative_to(out)) for p in out.rglob("*") if p.is_file()) == [
        "histogram.png", "seed_5/junit.xml", "seed_5/report.txt", "seed_5/results.json",
        "seed_6/junit.xml", "seed_6/report.txt", "seed_6/results.json", "summary.csv",
        "sweep.txt"]
    assert f"wrote 9 files to {out}" in captured.out
    text = (out / "sweep.txt").read_text()
    assert captured.out.startswith(text) and "below --fail-under 80 %: 2 seed(s)" in text
    assert (out / "summary.csv").read_text().splitlines() == [
        "seed,score,max_score,percent,0.1,0.2,0.3,problems", "5,6,10,60.0,2,0,4,",
        "6,6,10,60.0,2,0,4,"]
    results = json.loads((out / "seed_6" / "results.json").read_text())
    assert results["score"] == 6 and results["extra_data"]["seed"] == 6
    assert results["execution_time"] > 0  # the seed's grade's wall seconds
    assert (out / "histogram.png").read_bytes()[:4] == b"\x89PNG"
    assert "score min 6  median 6  max 6  (of 10)" in captured.out
    assert "60-70 % | ######################################## 2" in captured.out
    assert "  seed 6: 6/10" in captured.out
    assert (f"    0.2 0/4  replay: ddes grade replay ex0_talker {sub} --scenario public "
            f"--seed 6 --exercises {EXERCISE_FILE}") in captured.out
    assert "below --fail-under 80 %: 2 seed(s)" in captured.out
    assert "2 seed(s) below --fail-under 80 %" in captured.err


@pytest.mark.parametrize("seeds", ["", "3", "4:2", "a:b"])
def test_bad_seed_ranges_exit_2(seeds: str, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["grade", "--exercises", str(EXERCISE_FILE), "sweep", "ex0_talker",
                 str(SOLUTION), "--seeds", seeds]) == 2
    assert "--seeds" in capsys.readouterr().err


@pytest.mark.parametrize("words", [
    ["replay", "ex0_talker", str(SOLUTION), "--scenario", "public"],
    ["sensitivity", "ex0_talker"]])
def test_tools_that_write_no_folder_refuse_out(words: list[str], tmp_path: Path,
                                               capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["grade", "--exercises", str(EXERCISE_FILE), *words,
                 "--out", str(tmp_path / "o")]) == 2
    assert "writes no folder: leave out --out" in capsys.readouterr().err
    assert not (tmp_path / "o").exists()
