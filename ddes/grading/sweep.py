"""``ddes grade sweep``: one submission graded over many seeds, and the score's distribution.

On the reference solution the bar is **zero false failures** (every seed at full marks): a seed
where the reference loses points is a flaw of the grader or of the solution, never a student's.
On a student's submission the distribution shows whether a controller is robust or lucky.
:func:`sweep` grades each seed on the engine of ``ddes grade batch``
(:func:`~ddes.grading.batch.grade_all`: one task per (seed, scenario), serially or on Dask; the
same scenarios, digests and scores as a plain grade of that seed, ``execution_time`` 0; a seed
whose task failed is listed as a grader infrastructure error); :class:`SweepResult` prints min/median/max, a text
histogram and every seed below full marks with its replay command, and draws the histogram as a
:class:`~ddes.display.figure.DisplayFigure`.
"""

from __future__ import annotations

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
        ax.set_xlabel("score")
        ax.set_ylabel("seeds")
        ax.set_title(f"{self.exercise}: {len(self.grades)} seeds, "
                     f"{len(self.failures())} below full marks")
        fig.tight_layout()
        return fig


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
                         max_score=exercise.max_points)
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
