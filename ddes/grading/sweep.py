"""``ddes grade sweep``: one submission graded over many seeds, and the score's distribution.

On the reference solution the bar is **zero false failures** (every seed at full marks): a seed
where the reference loses points is a flaw of the grader or of the solution, never a student's.
On a student's submission the distribution shows whether a controller is robust or lucky.
:func:`sweep` grades each seed on the engine of ``ddes grade batch``
(:func:`~ddes.grading.batch.grade_all`: one task per (seed, scenario), serially or on Dask; the
same scenarios, digests and scores as a plain grade of that seed, ``execution_time`` the wall
seconds of its tasks; a seed whose task failed is listed as a grader infrastructure error); :class:`SweepResult` prints min/median/max, a text
histogram and every seed below full marks with its replay command, draws the histogram as a
:class:`~ddes.display.figure.DisplayFigure`, and writes it all to a folder
(:meth:`SweepResult.write`, ``ddes grade sweep --out DIR``).
"""

from __future__ import annotations

import csv
import io
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, TextIO

from ddes.grading.batch import Job, grade_all
from ddes.grading.exercise import Exercise
from ddes.grading.report import GradeReport
from ddes.grading.sandbox import Limits
from ddes.grading.scenarios import HiddenKey

__all__ = ["SweepResult", "histogram", "sweep"]

#: Bins of the histogram, in percent: [0, 10), [10, 20), ..., [90, 100), and 100 on its own.
BINS = 10


def _median(values: Sequence[float]) -> float:
    s = sorted(values)
    n = len(s)
    return s[n // 2] if n % 2 else (s[n // 2 - 1] + s[n // 2]) / 2


def _bin(percent: float) -> int:
    """The bin of a percentage: ``BINS`` for full marks, else ``floor(percent / 10)``."""
    if percent >= 100.0:
        return BINS
    return max(0, min(BINS - 1, int(percent // (100 / BINS))))


def _label(i: int) -> str:
    width = 100 // BINS
    return "100 %" if i == BINS else f"{i * width:>2}-{(i + 1) * width:<3}%"


def histogram(percents: Sequence[float], width: int = 40) -> list[str]:
    """A text histogram of percentages: one line per bin, ``#`` bars scaled to ``width``."""
    counts = [0] * (BINS + 1)
    for p in percents:
        counts[_bin(p)] += 1
    top = max(counts) or 1
    return [f"{_label(i):>7} | {'#' * (-(-c * width // top)) if c else '':<{width}} {c}"
            for i, c in enumerate(counts)]


@dataclass
class SweepResult:
    """The grades of one submission over seeds."""

    exercise: str
    submission: str
    max_score: float
    #: ``(seed, report)``, in seed order.
    grades: list[tuple[int, GradeReport]] = field(default_factory=list)
    #: ``(seed, text)`` of the seeds whose grade failed (grader infrastructure errors).
    errors: list[tuple[int, str]] = field(default_factory=list)
    #: The exercise's criterion ids, in order (the columns of ``summary.csv``).
    criteria: list[str] = field(default_factory=list)

    @property
    def scores(self) -> list[float]:
        return [r.score for _, r in self.grades]

    @property
    def percents(self) -> list[float]:
        return [r.percent for _, r in self.grades]

    def failures(self) -> list[tuple[int, GradeReport]]:
        """The seeds below full marks (on a reference solution: false failures)."""
        return [(s, r) for s, r in self.grades if r.score < r.max_score]

    def below(self, percent: float) -> list[tuple[int, GradeReport]]:
        return [(s, r) for s, r in self.grades if r.percent < percent]

    def to_text(self, fail_under: float | None = None) -> str:
        seeds = [s for s, _ in self.grades]
        scores = self.scores
        out = [f"{self.exercise} — {self.submission}: {len(seeds)} seed(s)"
               + (f", {seeds[0]}..{seeds[-1]}" if seeds else "")]
        if scores:
            out.append(f"score min {min(scores):g}  median {_median(scores):g}  "
                       f"max {max(scores):g}  (of {self.max_score:g})")
        out += histogram(self.percents)
        failed = self.failures()
        out.append(f"below full marks: {len(failed)} of {len(seeds)} seed(s)")
        for seed, r in failed:
            out.append(f"  seed {seed}: {r.score:g}/{r.max_score:g}")
            for c in r.criteria:
                if not c.passed:
                    out.append(f"    {c.id} {c.points:g}/{c.max_points:g}  replay: {c.replay}")
            out += [f"    problem: {p}" for p in r.problems]
        for seed, text in self.errors:
            out.append(f"  seed {seed}: grader infrastructure error: {text}")
        if fail_under is not None:
            out.append(f"below --fail-under {fail_under:g} %: {len(self.below(fail_under))} "
                       "seed(s)")
        return "\n".join(out) + "\n"

    def figure(self) -> Any:
        """The score histogram as a :class:`~ddes.display.figure.DisplayFigure`."""
        from ddes.display.figure import new_figure

        fig = new_figure(figsize=(6.0, 3.2))
        ax = fig.add_subplot(1, 1, 1)
        counts = [0] * (BINS + 1)
        for p in self.percents:
            counts[_bin(p)] += 1
        ax.bar(range(BINS + 1), counts, color=["tab:orange"] * BINS + ["tab:green"],
               edgecolor="black", gid="scores")
        ax.set_xticks(range(BINS + 1), [_label(i).replace(" ", "") for i in range(BINS + 1)],
                      rotation=45, fontsize=8)
        ax.set_xlabel("score [% of the maximum]")
        ax.set_ylabel("number of seeds")
        ax.set_title(f"{self.exercise}: {len(self.grades)} seeds, "
                     f"{len(self.failures())} below full marks")
        fig.tight_layout()
        return fig


    def summary_csv(self) -> str:
        """One row per seed, in seed order: ``seed, score, max_score, percent, <criterion
        ids…>, problems`` (a seed not graded: empty scores and the error), no wall time."""
        from ddes.grading.report import utf8_safe

        buf = io.StringIO()
        writer = csv.writer(buf, lineterminator="\n")
        writer.writerow(["seed", "score", "max_score", "percent", *self.criteria, "problems"])
        rows: list[tuple[int, list[str]]] = []
        for seed, r in self.grades:
            by_id = {c.id: c.points for c in r.criteria}
            rows.append((seed, [str(seed), f"{r.score:g}", f"{r.max_score:g}", f"{r.percent:.1f}",
                                *[f"{by_id[c]:g}" if c in by_id else "" for c in self.criteria],
                                utf8_safe("; ".join(r.problems)[:500])]))
        for seed, text in self.errors:
            rows.append((seed, [str(seed), "", f"{self.max_score:g}", "",
                                *[""] * len(self.criteria),
                                utf8_safe(f"grader infrastructure error: {text}")]))
        writer.writerows(row for _, row in sorted(rows, key=lambda sr: sr[0]))
        return buf.getvalue()

    def write(self, out: str | Path, fail_under: float | None = None) -> list[Path]:
        """Write the sweep to the folder ``out`` (made if need be); returns the files written:
        ``sweep.txt`` (what :meth:`to_text` prints), ``summary.csv`` (:meth:`summary_csv`),
        ``histogram.png`` (:meth:`figure`) and, for each graded seed, ``seed_N/`` with its
        ``results.json`` (its wall time as ``execution_time``), ``junit.xml`` and
        ``report.txt``, as ``ddes grade --out`` writes them."""
        from ddes.grading.report import write_atomic

        folder = Path(out)
        folder.mkdir(parents=True, exist_ok=True)
        written = []
        for seed, r in self.grades:
            sub = folder / f"seed_{seed}"
            r.write_results(sub / "results.json")
            r.write_junit(sub / "junit.xml")
            write_atomic(sub / "report.txt", r.to_text())
            written += [sub / "results.json", sub / "junit.xml", sub / "report.txt"]
        write_atomic(folder / "summary.csv", self.summary_csv())
        write_atomic(folder / "sweep.txt", self.to_text(fail_under=fail_under))
        self.figure().savefig(str(folder / "histogram.png"), dpi=100)
        return [*written, folder / "summary.csv", folder / "sweep.txt",
                folder / "histogram.png"]


def sweep(exercise: Exercise, submission: str | Path, seeds: Sequence[int] | range, *,
          public: bool = False, limits: Limits | None = None, key: HiddenKey | None = None,
          progress: Callable[[str], None] | None = None, workers: int = 0,
          scheduler: str | None = None, retries: int | None = None,
          bar: TextIO | None = None) -> SweepResult:
    """Grade ``submission`` once per seed in ``seeds`` (``workers``, ``scheduler``,
    ``retries``: see :func:`~ddes.grading.batch.run_tasks`; ``progress`` gets a line per seed
    as it finishes, ``bar`` draws the progress bar)."""
    seeds = list(seeds)
    result = SweepResult(exercise=exercise.id, submission=str(submission),
                         max_score=exercise.max_points, criteria=[c.id for c in exercise.criteria])
    name = Path(submission).name or "submission"
    jobs = [Job(name, Path(submission), seed=seed, public=public, key=key) for seed in seeds]

    def said(j: int, got: GradeReport | str) -> None:
        if progress is not None:
            progress(f"seed {seeds[j]}: " + (f"grader infrastructure error: {got}"
                                             if isinstance(got, str)
                                             else f"{got.score:g}/{got.max_score:g}"))

    reports = grade_all(exercise, jobs, limits=limits, workers=workers, scheduler=scheduler,
                        retries=retries, on_report=said, progress=bar)
    for seed, got in zip(seeds, reports, strict=True):
        if isinstance(got, str):
            result.errors.append((seed, got))
        else:
            result.grades.append((seed, got))
    return result
