"""Mutants: the strict unified-diff applier, mutants.yaml, and ``ddes grade sensitivity`` on the
demo exercise (every bug mutant killed where expected, equivalents and reference lose nothing)
and on broken sets (exit 1, the failing gate named)."""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest

from ddes.cli.main import main
from ddes.errors import GradingError
from ddes.grading.mutants import apply_diff, load_mutants

from .conftest import EXERCISE_FILE, FIXTURES

SOLUTIONS = FIXTURES / "solutions"


def _tree(tmp_path: Path) -> Path:
    root = tmp_path / "sol"
    (root / "pkg").mkdir(parents=True)
    (root / "pkg" / "a.py").write_text("one\ntwo\n\nthree\nfour\n")
    (root / "gone.txt").write_text("bye\n")
    return root


DIFF = """\
diff --git a/pkg/a.py b/pkg/a.py
--- a/pkg/a.py
+++ b/pkg/a.py
@@ -1,4 +1,4 @@
 one
-two
+TWO
\x20
 three
@@ -5 +5,2 @@
 four
+five
\\ No newline at end of file
--- /dev/null
+++ b/pkg/new.py
@@ -0,0 +1 @@
+print('new')
--- a/gone.txt
+++ /dev/null
@@ -1 +0,0 @@
-bye
"""


def test_apply_diff_changes_creates_and_deletes(tmp_path: Path) -> None:
    root = _tree(tmp_path)
    assert apply_diff(root, DIFF, "m") == ["pkg/a.py", "pkg/new.py", "gone.txt"]
    assert (root / "pkg" / "a.py").read_text() == "one\nTWO\n\nthree\nfour\nfive"
    assert (root / "pkg" / "new.py").read_text() == "print('new')\n"
    assert not (root / "gone.txt").exists()


@pytest.mark.parametrize("diff, text", [
    (DIFF.replace("-two", "-deux"), "mutant m: pkg/a.py: line 2 does not match the diff (diff "
     "line 6): the solution has 'two\\n', the diff expects 'deux\\n'"),
    (DIFF.replace("@@ -5 +5,2 @@", "@@ -9 +9,2 @@"), "starts at line 9, past the end (5 lines)"),
    (DIFF.replace("@@ -5 +5,2 @@", "@@ -2 +2,2 @@"), "overlaps the one before"),
    (DIFF.replace("@@ -1,4 +1,4 @@", "@@ -1,5 +1,4 @@"), "'@@ -5 +5,2 @@' is not a hunk line"),
    (DIFF.replace("a/pkg/a.py\n+++ b/pkg/a.py", "a/../a.py\n+++ b/../a.py"), "not a path inside"),
    (DIFF.replace("a/gone.txt", "a/absent.txt"), "patches absent.txt, which the solution does "
     "not have"),
    ("just text\n", "the diff changes no file"),
    (DIFF.replace("@@ -1,4 +1,4 @@", "@@ one @@"), "bad hunk header"),
])
def test_a_diff_that_does_not_apply_names_the_mutant(tmp_path: Path, diff: str,
                                                     text: str) -> None:
    with pytest.raises(GradingError, match="mutant m: ") as info:
        apply_diff(_tree(tmp_path), diff, "m")
    assert text in str(info.value)


def test_the_demo_mutants_apply_to_the_demo_solution(ex0, tmp_path: Path) -> None:  # type: ignore[no-untyped-def]
    mutants = load_mutants(SOLUTIONS / "ex0_talker", ex0)
    assert [(m.name, m.kind, m.loses) for m in mutants] == [
        ("bigger_queue", "equivalent", ()), ("five_hz", "bug", ("0.2",)),
        ("no_count", "bug", ("0.3",)), ("typed_message", "equivalent", ()),
        ("wrong_topic", "bug", ("0.1", "0.2", "0.3"))]
    for m in mutants:
        dest = tmp_path / m.name
        shutil.copytree(SOLUTIONS / "ex0_talker", dest, ignore=shutil.ignore_patterns("mutants"))
        assert apply_diff(dest, m.diff.read_text(), m.name) == ["talker.py"]
        assert (dest / "talker.py").read_text() != (SOLUTIONS / "ex0_talker" / "talker.py").read_text()


def test_sensitivity_of_the_demo_exercise(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["grade", "--exercises", str(EXERCISE_FILE), "sensitivity", "ex0_talker",
                 "--solutions", str(SOLUTIONS)]) == 0
    assert capsys.readouterr().out == """\
ex0_talker: kill matrix (points lost; * = expected to lose; seed 0)
mutant         kind        0.1  0.2  0.3  verdict
(reference)    reference    .    .    .   ok
bigger_queue   equivalent   .    .    .   ok
five_hz        bug          .    4*   .   killed
no_count       bug          .    .    4*  killed
typed_message  equivalent   .    .    .   ok
wrong_topic    bug          2*   4*   4*  killed
bug mutants killed: 3 of 3; all gates hold
"""


def _solutions_with(tmp_path: Path, yaml_text: str, diffs: list[str]) -> Path:
    root = tmp_path / "solutions"
    shutil.copytree(SOLUTIONS / "ex0_talker", root / "ex0_talker",
                    ignore=shutil.ignore_patterns("*.diff", "*.yaml"))
    for name in diffs:
        shutil.copy(SOLUTIONS / "ex0_talker" / "mutants" / f"{name}.diff",
                    root / "ex0_talker" / "mutants" / f"{name}.diff")
    (root / "ex0_talker" / "mutants" / "mutants.yaml").write_text(yaml_text)
    return root


def test_a_failing_gate_exits_1_and_names_it(tmp_path: Path,
                                             capsys: pytest.CaptureFixture[str]) -> None:
    root = _solutions_with(tmp_path, """\
five_hz: {kind: bug, loses: ["0.3"]}
no_count: {kind: equivalent, loses: []}
""", ["five_hz", "no_count"])
    assert main(["grade", "--exercises", str(EXERCISE_FILE), "sensitivity", "ex0_talker",
                 "--solutions", str(root)]) == 1
    out = capsys.readouterr().out
    assert "five_hz      bug          .    4    .*  SURVIVES in 0.3; also loses 0.2" in out
    assert "no_count     equivalent   .    .    4   LOSES POINTS in 0.3" in out
    assert "bug mutants killed: 0 of 1; GATES FAIL: five_hz, no_count" in out


@pytest.mark.parametrize("yaml_text, diffs, text", [
    ("five_hz: {kind: bug, loses: []}\n", ["five_hz"], "a bug mutant must name the criteria"),
    ("five_hz: {kind: typo, loses: []}\n", ["five_hz"], "give kind: bug or kind: equivalent"),
    ("five_hz: {kind: bug, loses: ['9.9']}\n", ["five_hz"], "unknown criterion id(s) ['9.9']"),
    ("five_hz: {kind: equivalent, loses: ['0.2']}\n", ["five_hz"], "loses nothing (loses: [])"),
    ("{}\n", ["five_hz"], "mutant(s) five_hz have a diff but no entry"),
    ("ghost: {kind: bug, loses: ['0.1']}\n", [], "no ghost.diff in"),
    ("[1, 2]\n", [], "must map each mutant's name"),
])
def test_bad_mutant_metadata_exits_2(tmp_path: Path, yaml_text: str, diffs: list[str], text: str,
                                     capsys: pytest.CaptureFixture[str]) -> None:
    root = _solutions_with(tmp_path, yaml_text, diffs)
    assert main(["grade", "--exercises", str(EXERCISE_FILE), "sensitivity", "ex0_talker",
                 "--solutions", str(root)]) == 2
    assert text in capsys.readouterr().err


def test_a_broken_diff_and_a_missing_solution_exit_2(tmp_path: Path,
                                                     capsys: pytest.CaptureFixture[str]) -> None:
    root = _solutions_with(tmp_path, "five_hz: {kind: bug, loses: ['0.2']}\n", ["five_hz"])
    talker = root / "ex0_talker" / "talker.py"
    talker.write_text(talker.read_text().replace("rospy.Rate(10)", "rospy.Rate(10.0)"))
    assert main(["grade", "--exercises", str(EXERCISE_FILE), "sensitivity", "ex0_talker",
                 "--solutions", str(root)]) == 2
    err = capsys.readouterr().err
    assert "mutant five_hz: talker.py: line 10 does not match the diff" in err
    assert main(["grade", "--exercises", str(EXERCISE_FILE), "sensitivity", "ex0_talker",
                 "--solutions", str(tmp_path / "nope")]) == 2
    assert "no solution of ex0_talker in" in capsys.readouterr().err
