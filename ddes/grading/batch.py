"""Batches of grades: one task per (submission, scenario), serially or on Dask distributed.

:func:`grade_scenario` is one task: it prepares the submission in a folder of its own, runs one
scenario in lockstep (:func:`~ddes.grading.grader.run_scenario`) and scores it
(:func:`~ddes.grading.grader.score_scenario`), returning a small picklable
:class:`ScenarioOutcome`.  :func:`assemble` folds a submission's outcomes, in scenario order,
into the :class:`~ddes.grading.report.GradeReport` that :func:`~ddes.grading.grader.grade`
gives (tests/grading/test_batch_dask.py checks they agree), with ``execution_time`` 0: a batch's
files carry no wall time, so they are byte-identical for any number of workers.

:func:`run_tasks` runs the tasks in-process (``workers=0``) or on a Dask cluster: a
``LocalCluster`` of ``workers`` processes of one thread each, or the scheduler at ``scheduler``.
Each task has an explicit key (:func:`task_key`), so submitting it again is idempotent, and the
results are taken future by future in input order.  A task that raises — or whose worker died
past Dask's retry limit (``KilledWorker``) — is that one task's failure, reported by its text;
the others are kept.  ``distributed`` is imported here only, and only when a cluster is asked
for (the ``batch`` extra: ``pip install "ddes[batch]"``).
"""

from __future__ import annotations

import hashlib
import json
import shutil
import tempfile
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path

import ddes
from ddes.errors import GradingError, SubmissionError
from ddes.grading.exercise import REGISTRY, Exercise, Scenario
from ddes.grading.grader import (
    _digest,
    _note_problems,
    replay_command,
    run_scenario,
    score_scenario,
)
from ddes.grading.report import CriterionReport, GradeReport
from ddes.grading.sandbox import Limits
from ddes.grading.scenarios import HiddenKey, select_scenarios
from ddes.grading.submission import prepare

__all__ = ["ScenarioOutcome", "Task", "assemble", "grade_scenario", "run_tasks", "task_key"]

#: What ``--workers N`` without the extra says.
MISSING = ('--workers/--scheduler grade on Dask distributed, which is not installed: '
           'pip install "ddes[batch]" (or grade serially with --workers 0)')


@dataclass(frozen=True)
class Task:
    """One (submission, scenario) of a batch; ``index`` None only prepares (no scenario)."""

    exercise: str
    origin: str  # the instructor's exercise file a worker loads ("" for a built-in exercise)
    submission: str  # an absolute path the workers can read
    index: int | None
    seed: int
    public: bool
    limits: Limits | None
    key: HiddenKey | None


@dataclass
class ScenarioOutcome:
    """What one task found: the submission's digest and set-up problems, the scenario's
    problems, enforcement, trace digest and ``(criterion, points, evidence)`` scores."""

    scenario: str
    sha256: str = ""
    setup_problems: list[str] = field(default_factory=list)
    problems: list[str] = field(default_factory=list)
    enforced: list[str] = field(default_factory=list)
    digest: str = ""
    scores: list[tuple[str, float, list[str]]] = field(default_factory=list)


def _exercise(task: Task) -> Exercise:
    try:
        return REGISTRY.get(task.exercise)
    except GradingError:
        if not task.origin:
            raise
    REGISTRY.load_file(task.origin)  # a fresh worker process: load the instructor's file
    return REGISTRY.get(task.exercise)


def grade_scenario(task: Task) -> ScenarioOutcome:
    """Run and score one scenario of one submission (the unit of work of a batch)."""
    exercise = _exercise(task)
    scenario = (None if task.index is None
                else select_scenarios(exercise, task.seed, task.public, task.key)[task.index])
    out = ScenarioOutcome(scenario="" if scenario is None else scenario.name)
    tmp = Path(tempfile.mkdtemp(prefix="ddes-submission-"))
    try:
        prepared: Path | None = tmp / "submission"
        assert prepared is not None
        try:
            out.sha256 = prepare(task.submission, prepared)
        except SubmissionError as exc:
            out.setup_problems.append(f"{exc} — costs every criterion")
            prepared = None
        missing = [] if prepared is None else [
            f for f in exercise.required() if not (prepared / f).is_file()]
        if missing:
            out.setup_problems.append(f"missing file(s): {', '.join(missing)} — costs the "
                                      "criteria that need them")
        if scenario is not None:
            world, facts = run_scenario(exercise, scenario, prepared, task.limits)
            notes = GradeReport(exercise="", title="", submission="", seed=0, public=False)
            _note_problems(notes, facts)
            out.problems, out.enforced = notes.problems, notes.enforced
            out.digest = _digest(world)
            out.scores = score_scenario(exercise, facts)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    return out


def tasks_of(exercise: Exercise, submission: Path, *, seed: int, public: bool,
             limits: Limits | None, key: HiddenKey | None) -> tuple[list[Scenario], list[Task]]:
    """The scenarios of one submission's grade and its tasks (one per scenario, or one that
    only prepares when the exercise has none)."""
    scenarios = select_scenarios(exercise, seed, public, key)
    origin = str(Path(exercise.origin).resolve()) if exercise.origin else ""
    path = str(Path(submission).resolve())
    indexes: list[int | None] = list(range(len(scenarios))) or [None]
    return scenarios, [Task(exercise.id, origin, path, i, seed, public, limits, key)
                       for i in indexes]


def task_key(task: Task, name: str, scenario: str) -> str:
    """``ddes-<exercise>-<submission>-<scenario>-<seed>-<hash>``: the hash covers the path,
    ``public``, the limits and the student/attempt (never the secret), so one key is one
    piece of work and resubmitting it is idempotent."""
    what = json.dumps([task.submission, task.public, repr(task.limits),
                       None if task.key is None else [task.key.student, task.key.attempt]])
    tag = hashlib.sha256(what.encode()).hexdigest()[:12]
    return f"ddes-{task.exercise}-{name}-{scenario or 'prepare'}-{task.seed}-{tag}"


def assemble(exercise: Exercise, shown: str, scenarios: Sequence[Scenario],
             outcomes: Sequence[ScenarioOutcome], *, seed: int, public: bool,
             key: HiddenKey | None) -> GradeReport:
    """The report :func:`~ddes.grading.grader.grade` gives, from the outcomes of one
    submission's tasks in scenario order (``execution_time`` 0)."""
    report = GradeReport(exercise=exercise.id, title=exercise.title, submission=shown, seed=seed,
                         public=public, ddes_version=ddes.__version__)
    scores: dict[str, list[float]] = {c.id: [] for c in exercise.criteria}
    evidence: dict[str, list[str]] = {c.id: [] for c in exercise.criteria}
    first_failure: dict[str, Scenario] = {}
    if outcomes:
        report.submission_sha256 = outcomes[0].sha256
        report.problems += outcomes[0].setup_problems
    for scenario, got in zip(scenarios, outcomes, strict=False):
        if got.enforced:
            report.enforced = list(got.enforced)
        report.problems += got.problems
        report.digests[scenario.name] = got.digest
        for cid, earned, lines in got.scores:
            scores[cid].append(earned)
            if lines:
                evidence[cid] += lines
                first_failure.setdefault(cid, scenario)
    for c in exercise.criteria:
        points = sum(scores[c.id]) / len(scores[c.id]) if scores[c.id] else 0.0
        failed = first_failure.get(c.id)
        report.criteria.append(CriterionReport(
            id=c.id, name=c.name, points=float(round(points, 4)), max_points=float(c.max_points),
            visibility=c.visibility, evidence=evidence[c.id],
            replay="" if failed is None else replay_command(exercise, shown, failed, seed, key)))
    return report


def run_tasks(tasks: Sequence[Task], keys: Sequence[str], *, workers: int = 0,
              scheduler: str | None = None,
              say: Callable[[str], None] = print) -> list[ScenarioOutcome | str]:
    """Each task's outcome, in input order, or the text of its failure (an exception in the
    task, or ``KilledWorker`` past Dask's retries).  ``workers=0`` and no ``scheduler``: in this
    process, one after the other."""
    if workers < 0:
        raise GradingError(f"--workers {workers}: give 0 (serial) or a number of processes")
    if not workers and not scheduler:
        results: list[ScenarioOutcome | str] = []
        for task in tasks:
            try:
                results.append(grade_scenario(task))
            except Exception as exc:  # noqa: BLE001 - one broken task never ends the batch
                results.append(f"{type(exc).__name__}: {exc}")
        return results
    try:
        from distributed import Client, LocalCluster
    except ImportError:
        raise GradingError(MISSING) from None
    cluster = None
    if scheduler:
        client = Client(scheduler)
    else:
        cluster = LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                               dashboard_address=":0")
        client = Client(cluster)
    try:
        if client.dashboard_link:
            say(f"Dask dashboard: {client.dashboard_link}")
        futures = [client.submit(grade_scenario, task, key=k, pure=False)
                   for task, k in zip(tasks, keys, strict=True)]
        results = []
        for future in futures:
            try:
                results.append(future.result())
            except Exception as exc:  # noqa: BLE001 - a task's failure, a dead worker's too
                results.append(f"{type(exc).__name__}: {exc}")
        return results
    finally:
        client.close()
        if cluster is not None:
            cluster.close()
