"""``ddes grade batch`` over hostile submissions (issue 38): one bad zip or notebook among good
submissions — a file where a folder must be, a corrupt stream, a zip bomb, JSON nested 200,000
deep, a name that is not UTF-8 — gets its own report (0 points and the reason), every other
submission is graded as usual, and every file the batch writes or prints is UTF-8."""

from __future__ import annotations

import csv
import io
import json
import os
import shutil
import sys
import zipfile
from pathlib import Path

import pytest

from ddes.cli.main import main

HERE = Path(__file__).resolve().parent
EXERCISES = str(HERE / "fixtures" / "ex0_talker.py")
SOLUTION = HERE / "fixtures" / "ex0_solution"
DEEP = 200_000

#: submission -> what its problem line says
BAD = {
    "file_dir.zip": "file_dir.zip: 'x' is both a file (entry 'x') and a folder (entry 'x/y' is "
                    "inside it): a path cannot be both; rename one of them — costs every criterion",
    "corrupt.zip": "corrupt.zip: entry talker.py cannot be read (",
    "bomb.zip": "bomb.zip: entry a.txt inflates more than 200× (a zip bomb) — costs every "
                "criterion",
    "garbage.zip": "garbage.zip: not a readable zip (File is not a zip file) — costs every "
                   "criterion",
    "long.zip": "is 303 bytes long, past the 255 bytes a file or folder name may have: shorten it",
    "deep.ipynb": "deep.ipynb: not a notebook (its JSON nests deeper than Python's recursion "
                  "limit; a notebook nests a few levels): save it again with Jupyter",
    "cells.ipynb": "cells.ipynb: cell 0's source is a list holding the number 3 at item 1",
    "s\ufffd.zip": "s\ufffd.zip: 'x' is both a file",
}


def hostile(root: Path) -> Path:
    subs = root / "subs"
    subs.mkdir()
    shutil.copytree(SOLUTION, subs / "good")
    with zipfile.ZipFile(subs / "good.zip", "w") as zf:
        zf.write(SOLUTION / "talker.py", "talker.py")
    for name, entries in (("file_dir.zip", [("x", b"1"), ("x/y", b"2")]),
                          ("corrupt.zip", [("talker.py", b"print(1)\n" * 1000)]),
                          ("bomb.zip", [("a.txt", b"\0" * (4 << 20))]),
                          ("long.zip", [("a" * 300 + ".py", b"1")])):
        with zipfile.ZipFile(subs / name, "w", zipfile.ZIP_DEFLATED) as zf:
            for entry, data in entries:
                zf.writestr(entry, data)
    raw = bytearray((subs / "corrupt.zip").read_bytes())
    raw[40:60] = b"\xff" * 20
    (subs / "corrupt.zip").write_bytes(bytes(raw))
    (subs / "garbage.zip").write_bytes(b"PK\x03\x04 not really")
    (subs / "deep.ipynb").write_bytes(b"[" * DEEP + b"]" * DEEP)
    (subs / "cells.ipynb").write_text(json.dumps({"cells": [{
        "cell_type": "code", "metadata": {"tags": ["export"]},
        "source": ["# file: talker.py\n", 3]}]}))
    shutil.copy(subs / "file_dir.zip", os.path.join(os.fsencode(subs), b"s\xff.zip"))
    return subs


def test_one_bad_submission_never_ends_the_batch(tmp_path: Path,
                                                 monkeypatch: pytest.MonkeyPatch) -> None:
    subs = hostile(tmp_path)
    out = tmp_path / "out"
    # standard output as a UTF-8 terminal has it: a lone surrogate would raise
    stdout = io.TextIOWrapper(io.BytesIO(), encoding="utf-8", errors="strict")
    monkeypatch.setattr(sys, "stdout", stdout)
    words = ["grade", "--exercises", EXERCISES, "--timeout", "2", "batch", "ex0_talker",
             str(subs), "--out", str(out)]
    assert main(words) == 0
    summary = (out / "summary.csv").read_bytes().decode("utf-8")  # strict UTF-8
    rows = {r["submission"]: r for r in csv.DictReader(io.StringIO(summary))}
    assert set(rows) == {"good", "good.zip", *BAD}
    for name in ("good", "good.zip"):
        assert rows[name]["score"] == "10" and rows[name]["problems"] == "", rows[name]
    for name, said in BAD.items():
        row = rows[name]
        assert row["score"] == "0" and said in row["problems"], (name, row)
        assert "grader infrastructure error" not in row["problems"]
    folders = {p.name for p in out.iterdir() if p.is_dir()}
    assert "s_.zip" in folders and len(folders) == len(rows)
    for folder in folders:
        results = json.loads((out / folder / "results.json").read_bytes().decode("utf-8"))
        assert isinstance(results["score"], (int, float))
        (out / folder / "report.txt").read_bytes().decode("utf-8")
        (out / folder / "junit.xml").read_bytes().decode("utf-8")
    results = json.loads((out / "s_.zip" / "results.json").read_bytes().decode("utf-8"))
    assert results["score"] == 0 and "Problem: s\ufffd.zip: 'x' is both a file" in results["output"]
    stdout.flush()
    printed = stdout.buffer.getvalue().decode("utf-8")  # type: ignore[attr-defined]
    assert "good: 10/10" in printed and "s\ufffd.zip: 0/10" in printed and "bomb.zip: 0/10" in printed
    # --resume keeps the finished grades and grades the unreadable ones again, without a crash
    assert main([*words, "--resume"]) == 0
    again = {r["submission"]: r for r in csv.DictReader(io.StringIO(
        (out / "summary.csv").read_text(encoding="utf-8")))}
    assert again == rows
    stdout.flush()
    printed = stdout.buffer.getvalue().decode("utf-8")  # type: ignore[attr-defined]
    assert f"resuming: 2 finished submission(s) kept, {len(BAD)} to grade" in printed


def test_a_bad_submission_alone_is_a_report_with_the_reason(tmp_path: Path,
                                                            monkeypatch: pytest.MonkeyPatch) -> None:
    subs = hostile(tmp_path)
    stdout = io.TextIOWrapper(io.BytesIO(), encoding="utf-8", errors="strict")
    monkeypatch.setattr(sys, "stdout", stdout)
    bad = os.fsdecode(os.path.join(os.fsencode(subs), b"s\xff.zip"))
    out = tmp_path / "one"
    assert main(["grade", "--exercises", EXERCISES, "ex0_talker", bad, "--out", str(out)]) == 0
    stdout.flush()
    text = stdout.buffer.getvalue().decode("utf-8")  # type: ignore[attr-defined]
    assert "problem: s\ufffd.zip: 'x' is both a file" in text and "total: 0/10" in text
    results = json.loads((out / "results.json").read_bytes().decode("utf-8"))
    assert results["score"] == 0
