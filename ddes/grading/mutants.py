"""Grader sensitivity: mutants of a reference solution and their kill matrix.

A solution folder ``<solutions>/<exercise id>/`` holds ``mutants/``: one unified diff per mutant
(``<name>.diff``, against the solution folder, paths ``a/…``/``b/…`` or plain) and
``mutants.yaml``::

    five_hz:
      kind: bug              # a typical student bug ...
      loses: ["0.2"]         # ... that must cost these criteria (each loses > 0 points)
      description: rospy.Rate(5) instead of 10
    typed_message:
      kind: equivalent       # a different but correct program: must lose nothing
      loses: []

:func:`apply_diff` applies a diff strictly (every hunk at its stated line, context and removed
lines exactly as written, no fuzz, no offset; new and deleted files through ``/dev/null``); a
diff that does not apply is a :class:`~ddes.errors.GradingError` naming the mutant, the file and
the line.  :func:`sensitivity` grades the reference and every mutant (each applied to a temporary
copy of the solution, ``mutants/`` left out) and builds the kill matrix: rows mutants, columns
criteria, cells points lost; they are graded on the engine of ``ddes grade batch``
(:func:`~ddes.grading.batch.grade_all`: one task per (mutant, scenario), serially or on Dask).
It fails when the reference loses points, a bug mutant survives (a
criterion of its ``loses`` keeps all its points), a bug mutant loses points outside its
``loses`` (the grader is not specific), an equivalent mutant loses anything, or a row could not
be graded (a grader infrastructure error).
"""

from __future__ import annotations

import re
import shutil
import tempfile
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path, PurePosixPath
from typing import TextIO

from ddes.errors import GradingError
from ddes.grading.batch import Job, grade_all
from ddes.grading.exercise import Exercise
from ddes.grading.report import GradeReport
from ddes.grading.sandbox import Limits

__all__ = ["Mutant", "SensitivityResult", "apply_diff", "load_mutants", "sensitivity",
           "solution_dir", "write_subjects"]

KINDS = ("bug", "equivalent")
_HUNK = re.compile(r"@@ -(\d+)(?:,(\d+))? \+(\d+)(?:,(\d+))? @@")


@dataclass(frozen=True)
class Mutant:
    """One mutant: its name, kind, the criteria it must lose, its diff file."""

    name: str
    kind: str
    loses: tuple[str, ...]
    diff: Path
    description: str = ""


def _diff_path(raw: str, mutant: str) -> str | None:
    """The file a ``---``/``+++`` line names (None for /dev/null), checked to stay inside."""
    text = raw.split("\t", 1)[0].strip()
    if text == "/dev/null":
        return None
    if text.startswith(("a/", "b/")):
        text = text[2:]
    path = PurePosixPath(text)
    if not text or path.is_absolute() or ".." in path.parts or "\\" in text:
        raise GradingError(f"mutant {mutant}: the diff names {raw.strip()!r}, not a path inside "
                           "the solution")
    return str(path)


def _split_lines(text: str) -> list[str]:
    """Lines with their endings (the last one may have none)."""
    return text.splitlines(keepends=True)


def apply_diff(root: Path, diff_text: str, mutant: str) -> list[str]:
    """Apply the unified diff ``diff_text`` to the files under ``root``; returns the files
    changed.  Strict (see the module text); raises :class:`GradingError` naming ``mutant``."""
    lines = diff_text.splitlines(keepends=True)
    i, changed = 0, []
    while i < len(lines):
        if not lines[i].startswith("--- "):
            i += 1  # "diff --git", "index", text before the first file
            continue
        if i + 1 >= len(lines) or not lines[i + 1].startswith("+++ "):
            raise GradingError(f"mutant {mutant}: diff line {i + 1}: '---' is not followed by "
                               "'+++'")
        old = _diff_path(lines[i][4:], mutant)
        new = _diff_path(lines[i + 1][4:], mutant)
        i += 2
        target = new if new is not None else old
        if target is None:
            raise GradingError(f"mutant {mutant}: diff line {i - 1}: both sides are /dev/null")
        if old is None:
            if (root / target).exists():
                raise GradingError(f"mutant {mutant}: creates {target}, which already exists")
            source: list[str] = []
        else:
            path = root / old
            if not path.is_file():
                raise GradingError(f"mutant {mutant}: patches {old}, which the solution does "
                                   "not have")
            source = _split_lines(path.read_text(encoding="utf-8"))
        result: list[str] = []
        pos = 0  # next line of source (0-based) not yet copied
        hunks = 0
        while i < len(lines) and lines[i].startswith("@@"):
            m = _HUNK.match(lines[i])
            if m is None:
                raise GradingError(f"mutant {mutant}: diff line {i + 1}: bad hunk header "
                                   f"{lines[i].rstrip()!r}")
            start = int(m.group(1))
            old_len = 1 if m.group(2) is None else int(m.group(2))
            new_len = 1 if m.group(4) is None else int(m.group(4))
            first = start - 1 if old_len else start  # a pure insertion names the line before
            if first < pos:
                raise GradingError(f"mutant {mutant}: {target}: hunk at diff line {i + 1} "
                                   "overlaps the one before")
            if first > len(source):
                raise GradingError(f"mutant {mutant}: {target}: hunk at diff line {i + 1} starts "
                                   f"at line {start}, past the end ({len(source)} lines)")
            result += source[pos:first]
            pos = first
            i += 1
            seen_old = seen_new = 0
            while seen_old < old_len or seen_new < new_len:
                if i >= len(lines):
                    raise GradingError(f"mutant {mutant}: {target}: the diff ends inside a hunk")
                raw = lines[i]
                tag, body = raw[:1], raw[1:]
                if i + 1 < len(lines) and lines[i + 1].startswith("\\"):
                    body = body.rstrip("\n")  # "\ No newline at end of file"
                if tag in (" ", "-"):
                    have = source[pos] if pos < len(source) else None
                    if have != body:
                        raise GradingError(
                            f"mutant {mutant}: {target}: line {pos + 1} does not match the diff "
                            f"(diff line {i + 1}): the solution has {have!r}, the diff expects "
                            f"{body!r}; regenerate the diff against the solution")
                    pos += 1
                    seen_old += 1
                    if tag == " ":
                        result.append(body)
                        seen_new += 1
                elif tag == "+":
                    result.append(body)
                    seen_new += 1
                elif raw == "\n":  # an empty context line whose space was stripped
                    have = source[pos] if pos < len(source) else None
                    if have != "\n":
                        raise GradingError(f"mutant {mutant}: {target}: line {pos + 1} does not "
                                           f"match the diff (diff line {i + 1})")
                    result.append(have)
                    pos += 1
                    seen_old += 1
                    seen_new += 1
                else:
                    raise GradingError(f"mutant {mutant}: diff line {i + 1}: {raw.rstrip()!r} "
                                       "is not a hunk line")
                i += 1
                if i < len(lines) and lines[i].startswith("\\"):
                    i += 1
            if seen_old != old_len or seen_new != new_len:
                raise GradingError(f"mutant {mutant}: {target}: a hunk's line counts do not "
                                   "match its header")
            hunks += 1
        if hunks == 0:
            raise GradingError(f"mutant {mutant}: {target}: no hunk")
        result += source[pos:]
        dest = root / target
        if new is None:
            if result:
                raise GradingError(f"mutant {mutant}: deletes {old} but leaves lines in it")
            dest.unlink()
        else:
            dest.parent.mkdir(parents=True, exist_ok=True)
            dest.write_text("".join(result), encoding="utf-8")
        changed.append(target)
    if not changed:
        raise GradingError(f"mutant {mutant}: the diff changes no file (no '---'/'+++' lines)")
    return changed


def solution_dir(solutions: Path, exercise: Exercise) -> Path:
    path = solutions / exercise.id
    if not path.is_dir():
        raise GradingError(f"no solution of {exercise.id} in {solutions} (expected the folder "
                           f"{path}; give --solutions DIR)")
    return path


def load_mutants(solution: Path, exercise: Exercise) -> list[Mutant]:
    """The mutants of ``solution/mutants/``, checked against ``mutants.yaml`` and the
    exercise's criteria, in name order."""
    import yaml

    folder = solution / "mutants"
    meta_path = folder / "mutants.yaml"
    if not meta_path.is_file():
        raise GradingError(f"{meta_path} does not exist: list each mutant there "
                           "(name: {kind: bug|equivalent, loses: [criterion ids]})")
    try:
        meta = yaml.safe_load(meta_path.read_text(encoding="utf-8"))
    except yaml.YAMLError as exc:
        raise GradingError(f"{meta_path} is not YAML: {exc}") from None
    if not isinstance(meta, dict):
        raise GradingError(f"{meta_path} must map each mutant's name to its kind and losses")
    diffs = {p.stem: p for p in folder.glob("*.diff")}
    unlisted = sorted(set(diffs) - set(meta))
    if unlisted:
        raise GradingError(f"{meta_path}: mutant(s) {', '.join(unlisted)} have a diff but no "
                           "entry")
    ids = [c.id for c in exercise.criteria]
    out = []
    for name in sorted(meta, key=str):
        entry = meta[name]
        where = f"{meta_path}: mutant {name}"
        if str(name) not in diffs:
            raise GradingError(f"{where}: no {name}.diff in {folder}")
        if not isinstance(entry, dict) or entry.get("kind") not in KINDS:
            raise GradingError(f"{where}: give kind: bug or kind: equivalent")
        loses = entry.get("loses", [])
        if not isinstance(loses, list):
            raise GradingError(f"{where}: loses must be a list of criterion ids")
        loses = [str(x) for x in loses]
        unknown = [x for x in loses if x not in ids]
        if unknown:
            raise GradingError(f"{where}: unknown criterion id(s) {unknown} (the exercise's: "
                               f"{ids})")
        if entry["kind"] == "bug" and not loses:
            raise GradingError(f"{where}: a bug mutant must name the criteria it loses")
        if entry["kind"] == "equivalent" and loses:
            raise GradingError(f"{where}: an equivalent mutant loses nothing (loses: [])")
        out.append(Mutant(name=str(name), kind=entry["kind"], loses=tuple(loses),
                          diff=diffs[str(name)], description=str(entry.get("description", ""))))
    return out


def _copy_solution(solution: Path, dest: Path) -> None:
    shutil.copytree(solution, dest, ignore=shutil.ignore_patterns("mutants", "__pycache__"))


def write_subjects(solution: Path, mutants: list[Mutant],
                   dest: Path) -> list[tuple[str, str, tuple[str, ...], Path]]:
    """Write the reference (``dest/reference``) and each mutant (``dest/mutants/<name>``) as
    submissions; ``(name, kind, loses, folder)`` of each, the reference first."""
    _copy_solution(solution, dest / "reference")
    out: list[tuple[str, str, tuple[str, ...], Path]] = [
        ("reference", "reference", (), dest / "reference")]
    for m in mutants:
        folder = dest / "mutants" / m.name
        _copy_solution(solution, folder)
        apply_diff(folder, m.diff.read_text(encoding="utf-8"), m.name)
        out.append((m.name, m.kind, m.loses, folder))
    return out


@dataclass
class Row:
    """One row of the kill matrix: a mutant (or the reference) and the points it lost."""

    name: str
    kind: str
    lost: dict[str, float]
    expected: tuple[str, ...] = ()
    verdict: str = "ok"
    ok: bool = True
    report: GradeReport | None = field(default=None, repr=False)


@dataclass
class SensitivityResult:
    """The kill matrix of one exercise and whether the gates hold."""

    exercise: str
    criteria: list[str]
    seed: int
    rows: list[Row] = field(default_factory=list)

    @property
    def ok(self) -> bool:
        return all(r.ok for r in self.rows)

    def to_text(self) -> str:
        name_w = max([len(r.name) for r in self.rows] + [10])
        table = [[(f"{r.lost.get(c, 0.0):.4g}" if r.lost.get(c, 0.0) else ".")
                  + ("*" if c in r.expected else " ") for c in self.criteria] for r in self.rows]
        col_w = max([len(c) for c in self.criteria] + [len(x) for row in table for x in row]
                    + [4])  # wide enough for a partial loss such as "6.667*"
        head = f"{'mutant':<{name_w}}  {'kind':<10} " + " ".join(
            f"{c:>{col_w}}" for c in self.criteria) + "  verdict"
        out = [f"{self.exercise}: kill matrix (points lost; * = expected to lose; seed "
               f"{self.seed})", head]
        for r, cells in zip(self.rows, table):
            out.append(f"{r.name:<{name_w}}  {r.kind:<10} "
                       + " ".join(f"{x:>{col_w}}" for x in cells) + f"  {r.verdict}")
        bugs = [r for r in self.rows if r.kind == "bug"]
        killed = sum(1 for r in bugs if r.ok)
        out.append(f"bug mutants killed: {killed} of {len(bugs)}; "
                   + ("all gates hold" if self.ok else "GATES FAIL: "
                      + ", ".join(r.name for r in self.rows if not r.ok)))
        return "\n".join(out) + "\n"


def _judge(row: Row, criteria: list[str]) -> None:
    lost = {c for c in criteria if row.lost.get(c, 0.0) > 0}
    if row.kind in ("reference", "equivalent"):
        if lost:
            row.ok = False
            row.verdict = f"LOSES POINTS in {', '.join(sorted(lost))}"
        return
    survived = [c for c in row.expected if c not in lost]
    extra = sorted(lost - set(row.expected))
    problems = []
    if survived:
        problems.append(f"SURVIVES in {', '.join(survived)}")
    if extra:
        problems.append(f"also loses {', '.join(extra)}")
    row.ok = not problems
    row.verdict = "; ".join(problems) if problems else "killed"


def sensitivity(exercise: Exercise, solutions: Path, *, seed: int = 0,
                limits: Limits | None = None,
                progress: Callable[[str], None] | None = None, workers: int = 0,
                scheduler: str | None = None, retries: int | None = None,
                bar: TextIO | None = None) -> SensitivityResult:
    """Grade the reference and every mutant of ``solutions/<exercise id>/`` (see the module
    text); the mutants' diffs are all applied before any grading, so a broken diff fails fast.
    ``workers``, ``scheduler``, ``retries``: see :func:`~ddes.grading.batch.run_tasks`."""
    solution = solution_dir(solutions, exercise)
    mutants = load_mutants(solution, exercise)
    criteria = [c.id for c in exercise.criteria]
    result = SensitivityResult(exercise=exercise.id, criteria=criteria, seed=seed)
    tmp = Path(tempfile.mkdtemp(prefix="ddes-mutants-"))
    try:
        subjects = write_subjects(solution, mutants, tmp)
        rows: list[Row | None] = [None] * len(subjects)

        def judged(j: int, report: GradeReport | str) -> None:
            name, kind, loses, _ = subjects[j]
            row = Row(name=f"({name})" if kind == "reference" else name, kind=kind, lost={},
                      expected=tuple(loses))
            if isinstance(report, str):
                row.ok, row.verdict = False, f"grader infrastructure error: {report}"
            else:
                row.report = report
                row.lost = {c.id: float(round(c.max_points - c.points, 4))
                            for c in report.criteria}
                _judge(row, criteria)
            rows[j] = row
            if progress is not None:
                score = ("" if isinstance(report, str)
                         else f"{report.score:g}/{report.max_score:g} ")
                progress(f"{row.name}: {score}{row.verdict}")

        jobs = [Job(name, folder, seed=seed) for name, _, _, folder in subjects]
        grade_all(exercise, jobs, limits=limits, workers=workers, scheduler=scheduler,
                  retries=retries, on_report=judged, progress=bar)
        result.rows = [r for r in rows if r is not None]
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    return result
