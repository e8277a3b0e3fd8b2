"""The attack families of grading.md §3, each a submission of tests/grading/attacks/: graded in one
batch with a clean submission, every attack earns 0, the clean one full marks, the grader lives."""

from __future__ import annotations

import csv
import json
import shutil
from pathlib import Path

import pytest

from ddes.cli.main import main

HERE = Path(__file__).resolve().parent
ATTACKS = sorted(p.name for p in (HERE / "attacks").iterdir() if p.is_dir())


def test_every_attack_earns_zero_while_a_clean_submission_earns_full_marks(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
        ) -> None:
    monkeypatch.setenv("DDES_TEST_SECRET", "s3cret")
    subs = tmp_path / "submissions"
    subs.mkdir()
    for name in ATTACKS:
        shutil.copytree(HERE / "attacks" / name, subs / name)
    shutil.copytree(HERE / "fixtures" / "ex0_solution", subs / "clean")
    out = tmp_path / "out"
    code = main(["grade", "--exercises", str(HERE / "fixtures" / "ex0_talker.py"), "--timeout",
                 "1", "batch", "ex0_talker", str(subs), "--out", str(out)])
    assert code == 0
    with open(out / "summary.csv", newline="") as f:
        rows = {r["submission"]: r for r in csv.DictReader(f)}
    assert set(rows) == {*ATTACKS, "clean"}
    assert rows["clean"]["score"] == "10", rows["clean"]
    for name in ATTACKS:
        assert rows[name]["score"] == "0", (name, rows[name])
        results = json.loads((out / name / "results.json").read_text())
        assert results["score"] == 0 and all(t["score"] == 0 for t in results["tests"]), name
        assert "PASSED" not in json.dumps(results)
    # forged results: nothing was written next to the submissions or the outputs
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out", "submissions"]
    assert not list(subs.rglob("results.json"))
    assert sorted(p.name for p in out.iterdir()) == sorted([*ATTACKS, "clean", "summary.csv"])
    assert ("infinite_loop: 0/10" in capsys.readouterr().out)


def test_attack_families_are_all_present() -> None:
    assert {"early_exit", "early_os_exit", "monkeypatch", "equality_spoof", "forged_results",
            "read_hidden", "stdout_spoof", "memory_bomb", "fork_bomb", "infinite_loop",
            "huge_file", "network"} <= set(ATTACKS)
