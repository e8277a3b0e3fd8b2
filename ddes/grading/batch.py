"""Batches of grades: one task per (submission, scenario), serially or on Dask distributed.

:func:`grade_scenario` is one task: it prepares the submission in a folder of its own, runs one
scenario in lockstep (:func:`~ddes.grading.grader.run_scenario`) and scores it
(:func:`~ddes.grading.grader.score_scenario`), returning a small picklable
:class:`ScenarioOutcome`.  :func:`assemble` folds a submission's outcomes, in scenario order,
into the :class:`~ddes.grading.report.GradeReport` that :func:`~ddes.grading.grader.grade`
gives (tests/grading/test_batch_dask.py checks they agree).  Its ``execution_time`` is the wall
time of the grade as Gradescope shows it: the sum of its tasks' wall seconds (each measured
where it ran, preparing, running and scoring its scenario), what the grade took whether its
scenarios ran one after the other or on several workers.  That time is the one thing of a
batch's files that differs from run to run: ``summary.csv``, ``report.txt`` and ``batch.json``
carry none and are byte-identical for any number of workers, and so are ``results.json`` and
``junit.xml`` once :func:`without_wall_time` has set their time to 0.

:func:`run_tasks` runs the tasks in-process (``workers=0``) or on a Dask cluster: a
``LocalCluster`` of ``workers`` processes of one thread each (one task per worker at a time,
``worker-saturation`` 1.0), or the scheduler at ``scheduler``.  Each task has an explicit key
(:func:`task_key`), so submitting it again is idempotent; results are taken as they complete
(``on_result``) and returned in input order.  A task that raises — or whose worker died past
Dask's retry limit (``KilledWorker`` after ``allowed-failures`` = ``retries`` deaths) — is that
one task's failure, reported by its text; the others are kept.  :func:`grade_all` is the engine
of ``ddes grade batch``, ``sweep`` and ``sensitivity``: it turns :class:`Job` s (one submission,
seed and key each) into tasks and folds each job's outcomes into its report as soon as they are
all in (``on_report``), which is what lets an interrupted batch keep its finished submissions.
:func:`fingerprint` names what a finished grade depends on, so ``--resume`` can keep it.
``distributed`` is imported here only, and only when a cluster is asked for (the ``batch``
extra: ``pip install "ddes[batch]"``).
"""

from __future__ import annotations

import hashlib
import json
import math
import re
import shutil
import tempfile
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import TextIO

import ddes
from ddes._floats import left_sum
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

__all__ = ["Job", "Progress", "ScenarioOutcome", "Task", "assemble", "fingerprint", "grade_all",
           "grade_scenario", "run_tasks", "task_key", "without_wall_time"]

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
    problems, enforcement, trace digest and ``(criterion, points, evidence)`` scores, and the
    task's wall time (seconds; reported only, as ``execution_time``)."""

    scenario: str
    sha256: str = ""
    setup_problems: list[str] = field(default_factory=list)
    problems: list[str] = field(default_factory=list)
    enforced: list[str] = field(default_factory=list)
    digest: str = ""
    scores: list[tuple[str, float, list[str]]] = field(default_factory=list)
    seconds: float = 0.0


def _exercise(task: Task) -> Exercise:
    try:
        return REGISTRY.get(task.exercise)
    except GradingError:
        if not task.origin:
            raise
    REGISTRY.load_file(task.origin)  # a fresh worker process: load the instructor's file
    return REGISTRY.get(task.exercise)


def grade_scenario(task: Task, exercise: Exercise | None = None) -> ScenarioOutcome:
    """Run and score one scenario of one submission (the unit of work of a batch); a Dask
    worker finds the exercise by its id (built in, or loaded from ``task.origin``), a serial
    batch may hand it over (an exercise defined in the caller's code)."""
    start = time.perf_counter()  # wall time, reported only (Gradescope's execution_time)
    if exercise is None:
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
            _note_problems(notes, facts, task.limits or Limits())
            out.problems, out.enforced = notes.problems, notes.enforced
            out.digest = _digest(world)
            out.scores = score_scenario(exercise, facts)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    out.seconds = time.perf_counter() - start
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
    submission's tasks in scenario order; its ``execution_time`` is the sum of their wall
    times."""
    report = GradeReport(exercise=exercise.id, title=exercise.title, submission=shown, seed=seed,
                         public=public, ddes_version=ddes.__version__)
    scores: dict[str, list[float]] = {c.id: [] for c in exercise.criteria}
    evidence: dict[str, list[str]] = {c.id: [] for c in exercise.criteria}
    first_failure: dict[str, Scenario] = {}
    report.execution_time = math.fsum(o.seconds for o in outcomes)
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
        points = left_sum(scores[c.id]) / len(scores[c.id]) if scores[c.id] else 0.0
        failed = first_failure.get(c.id)
        report.criteria.append(CriterionReport(
            id=c.id, name=c.name, points=float(round(points, 4)), max_points=float(c.max_points),
            visibility=c.visibility, evidence=evidence[c.id],
            replay="" if failed is None else replay_command(exercise, shown, failed, seed, key)))
    return report


class Progress:
    """A text progress bar of a batch's tasks on ``stream`` (none when ``stream`` is None): the
    count of finished tasks only, no wall time, redrawn in place with a carriage return."""

    WIDTH = 30

    def __init__(self, total: int, stream: TextIO | None, what: str = "tasks") -> None:
        self.total, self.done, self.what = total, 0, what
        self.stream = stream if total else None
        self._draw()

    def _draw(self) -> None:
        if self.stream is None:
            return
        full = self.WIDTH * self.done // self.total
        self.stream.write(f"\rgrading [{'#' * full}{'.' * (self.WIDTH - full)}] "
                          f"{self.done}/{self.total} {self.what}")
        self.stream.flush()

    def step(self) -> None:
        self.done += 1
        self._draw()

    def close(self) -> None:
        if self.stream is not None:
            self.stream.write("\n")
            self.stream.flush()
            self.stream = None


def _failure(exc: BaseException, retries: int | None) -> str:
    """The text of one task's failure; a ``KilledWorker`` without the worker's address, so the
    text is the same on every run."""
    if type(exc).__name__ == "KilledWorker":
        limit = ("the cluster's distributed.scheduler.allowed-failures" if retries is None
                 else f"distributed.scheduler.allowed-failures = {retries}")
        return (f"KilledWorker: every worker that ran this task died, past the retry limit "
                f"({limit})")
    return f"{type(exc).__name__}: {exc}"


def run_tasks(tasks: Sequence[Task], keys: Sequence[str], *, workers: int = 0,
              scheduler: str | None = None, retries: int | None = None,
              on_result: Callable[[int, ScenarioOutcome | str], None] | None = None,
              progress: TextIO | None = None, exercise: Exercise | None = None,
              say: Callable[[str], None] = print) -> list[ScenarioOutcome | str]:
    """Each task's outcome, in input order, or the text of its failure (an exception in the
    task, or ``KilledWorker`` past the retries).  ``workers=0`` and no ``scheduler``: in this
    process, one after the other.  ``retries``: how many times a task whose worker died is run
    again (Dask's ``allowed-failures``; default 3) on the ``LocalCluster`` this starts.
    ``on_result(index, outcome)`` is called as each task finishes, in the order they finish;
    ``exercise``: the tasks' exercise, used as is by a serial batch."""
    if workers < 0:
        raise GradingError(f"--workers {workers}: give 0 (serial) or a number of processes")
    if retries is not None and retries < 0:
        raise GradingError(f"--retries {retries}: give a number of retries >= 0")
    if len(set(keys)) != len(keys):
        raise GradingError("two tasks of the batch have the same key: give each submission "
                           "its own name")
    results: list[ScenarioOutcome | str | None] = [None] * len(tasks)
    bar = Progress(len(tasks), progress)

    def record(i: int, outcome: ScenarioOutcome | str) -> None:
        results[i] = outcome
        bar.step()
        if on_result is not None:
            on_result(i, outcome)

    if not workers and not scheduler:
        try:
            for i, task in enumerate(tasks):
                try:
                    outcome: ScenarioOutcome | str = grade_scenario(task, exercise)
                except Exception as exc:  # noqa: BLE001 - one broken task never ends the batch
                    outcome = _failure(exc, retries)
                record(i, outcome)
        finally:
            bar.close()
        return [r for r in results if r is not None]
    try:
        import dask
        from distributed import Client, LocalCluster, as_completed
    except ImportError:
        bar.close()
        raise GradingError(MISSING) from None
    if scheduler and retries is not None:
        bar.close()
        raise GradingError("--retries sets the retry limit of the LocalCluster that --workers N "
                           "starts; a cluster joined with --scheduler keeps its scheduler's "
                           "distributed.scheduler.allowed-failures")
    cluster = None
    try:
        if scheduler:
            client = Client(scheduler)
        else:
            config: dict[str, object] = {"distributed.scheduler.worker-saturation": 1.0}
            if retries is not None:
                config["distributed.scheduler.allowed-failures"] = retries
            with dask.config.set(config):
                cluster = LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                                       dashboard_address=":0")
            client = Client(cluster)
        try:
            if client.dashboard_link:
                say(f"Dask dashboard: {client.dashboard_link}")
            futures = [client.submit(grade_scenario, task, key=k, pure=False)
                       for task, k in zip(tasks, keys, strict=True)]
            index = {k: i for i, k in enumerate(keys)}
            for future in as_completed(futures):
                try:
                    outcome = future.result()
                except Exception as exc:  # noqa: BLE001 - a task's failure, a dead worker's too
                    outcome = _failure(exc, retries)
                record(index[future.key], outcome)
                future.release()
        finally:
            client.close()
    finally:
        bar.close()
        if cluster is not None:
            cluster.close()
    return [r for r in results if r is not None]


@dataclass(frozen=True)
class Job:
    """One submission's grade: ``name`` (unique in the batch: it names the tasks' keys), the
    path, the seed, ``public`` and the hidden-scenario key."""

    name: str
    submission: Path
    seed: int = 0
    public: bool = False
    key: HiddenKey | None = None


def grade_all(exercise: Exercise, jobs: Sequence[Job], *, limits: Limits | None = None,
              workers: int = 0, scheduler: str | None = None, retries: int | None = None,
              on_report: Callable[[int, GradeReport | str], None] | None = None,
              progress: TextIO | None = None,
              say: Callable[[str], None] = print) -> list[GradeReport | str]:
    """Grade every job, one task per (submission, scenario) through :func:`run_tasks`; returns
    each job's report (``execution_time``: its tasks' wall seconds) or the text of its grader
    infrastructure error, in
    job order.  ``on_report(index, report or error)`` is called as soon as a job's tasks are all
    done, in the order jobs finish."""
    tasks: list[Task] = []
    keys: list[str] = []
    owner: list[int] = []
    plans: list[tuple[list[Scenario], int, int] | str] = []
    for j, job in enumerate(jobs):
        try:
            scenarios, mine = tasks_of(exercise, job.submission, seed=job.seed,
                                       public=job.public, limits=limits, key=job.key)
        except Exception as exc:  # noqa: BLE001 - one broken grade never ends the batch
            plans.append(f"{type(exc).__name__}: {exc}")
            continue
        plans.append((scenarios, len(tasks), len(mine)))
        keys += [task_key(t, job.name, scenarios[t.index].name if t.index is not None else "")
                 for t in mine]
        tasks += mine
        owner += [j] * len(mine)
    outcomes: list[ScenarioOutcome | str | None] = [None] * len(tasks)
    left = [0 if isinstance(p, str) else p[2] for p in plans]
    done: list[GradeReport | str | None] = [None] * len(jobs)

    def finish(j: int) -> None:
        plan, job = plans[j], jobs[j]
        got: GradeReport | str
        if isinstance(plan, str):
            got = plan
        else:
            scenarios, first, count = plan
            mine = outcomes[first:first + count]
            broken = [o for o in mine if isinstance(o, str)]
            got = broken[0] if broken else assemble(
                exercise, str(job.submission), scenarios,
                [o for o in mine if isinstance(o, ScenarioOutcome)],
                seed=job.seed, public=job.public, key=job.key)
        done[j] = got
        if on_report is not None:
            on_report(j, got)

    def on_result(i: int, outcome: ScenarioOutcome | str) -> None:
        outcomes[i] = outcome
        left[owner[i]] -= 1
        if not left[owner[i]]:
            finish(owner[i])

    for j, plan in enumerate(plans):
        if isinstance(plan, str):
            finish(j)
    if (workers or scheduler) and not exercise.origin:
        try:
            known = REGISTRY.get(exercise.id) is exercise
        except GradingError:
            known = False
        if not known:
            raise GradingError(f"exercise {exercise.id} is neither built in nor loaded from a "
                               "file (--exercises FILE), so Dask workers cannot load it: grade "
                               "it with workers=0")
    run_tasks(tasks, keys, workers=workers, scheduler=scheduler, retries=retries,
              on_result=on_result, progress=progress, exercise=exercise, say=say)
    return [d for d in done if d is not None]


def fingerprint(exercise: Exercise, job: Job, limits: Limits | None) -> str | None:
    """What a finished grade of ``job`` depends on, hashed: the exercise (and its instructor's
    file), the ddes version, the submission's content, seed, ``public``, the limits and the
    hidden key (the secret by its hash).  None when the submission cannot be read (it is then
    always graded again)."""
    tmp = Path(tempfile.mkdtemp(prefix="ddes-fingerprint-"))
    try:
        content = prepare(job.submission, tmp / "submission")
    except Exception:  # noqa: BLE001 - unreadable (its grade says why), or the machine failed
        return None
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    origin = (hashlib.sha256(Path(exercise.origin).read_bytes()).hexdigest()
              if exercise.origin else "")
    key = None if job.key is None else [hashlib.sha256(job.key.secret).hexdigest(),
                                        job.key.student, job.key.attempt]
    what = json.dumps([exercise.id, ddes.__version__, origin, content, job.seed, job.public,
                       repr(limits), key])
    return hashlib.sha256(what.encode()).hexdigest()


_RESULTS_TIME = re.compile(rb'("execution_time": )[-+0-9.eE]+')
_JUNIT_TIME = re.compile(rb'(<testsuite [^>]*?\btime=")[0-9.]+(")')


def without_wall_time(name: str, data: bytes) -> bytes:
    """A batch's file with its wall time set to 0 (``execution_time`` of a ``results.json``,
    the testsuite's ``time`` of a ``junit.xml``; any other file as it is): what is the same for
    any number of workers, and on every run."""
    if name.endswith("results.json"):
        return _RESULTS_TIME.sub(rb"\g<1>0", data, count=1)
    if name.endswith("junit.xml"):
        return _JUNIT_TIME.sub(rb"\g<1>0.000\g<2>", data, count=1)
    return data
