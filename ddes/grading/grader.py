"""Grade one submission: prepare it, run each scenario in lockstep, score the criteria.

A criterion's points are the mean over scenarios of what its check earned in each (partial
credit across scenarios).  A check that raises earns 0 for that scenario and says so (fail
closed); points are clamped to ``[0, max]`` and anything not a finite number earns 0.  A
problem with the submission (it cannot be read, a required file is missing) is reported with
what it costs; the criteria are still computed on whatever ran.
"""

from __future__ import annotations

import os
import re
import shlex
import shutil
import tempfile
import time
from collections.abc import Callable
from pathlib import Path

import ddes
from ddes._floats import left_sum
from ddes.errors import SubmissionError
from ddes.grading.bridge import Lockstep
from ddes.grading.exercise import Exercise, Facts, Scenario
from ddes.grading.report import CriterionReport, GradeReport, finite_points
from ddes.grading.sandbox import Limits, RunBudget, Sandbox, SandboxOutcome
from ddes.grading.scenarios import HiddenKey, select_scenarios
from ddes.grading.submission import prepare
from ddes.graph.world import World
from ddes.time import Time
from ddes.time.units import to_ns

__all__ = ["grade", "replay_command", "run_scenario", "score_scenario"]


def replay_command(exercise: Exercise, submission: str, scenario: Scenario, seed: int,
                   key: HiddenKey | None = None) -> str:
    """``ddes grade replay EX SUBMISSION --scenario NAME --seed N`` (with ``--student`` and
    ``--attempt`` for a hidden scenario of a keyed grade, whose secret the replay reads from
    ``--secret-file`` or ``$DDES_GRADE_SECRET``; with ``--exercises FILE`` for an exercise
    loaded from a file)."""
    words = ["ddes", "grade", "replay", exercise.id, submission, "--scenario", scenario.name,
             "--seed", str(seed)]
    if scenario.hidden and key is not None:
        words += ["--student", key.student, "--attempt", str(key.attempt)]
    if exercise.origin:
        words += ["--exercises", exercise.origin]
    return shlex.join(words)


def grade(exercise: Exercise, submission: str | Path, *, seed: int = 0, public: bool = False,
          limits: Limits | None = None, key: HiddenKey | None = None) -> GradeReport:
    """Grade ``submission`` (a folder, .zip or .ipynb) for ``exercise``; never raises for a bad
    submission or a misbehaving student process.  ``key`` derives the hidden scenarios from the
    course secret (ddes.grading.scenarios)."""
    start = time.perf_counter()  # wall time, reported only (Gradescope's execution_time)
    shown = str(submission)
    report = GradeReport(exercise=exercise.id, title=exercise.title, submission=shown, seed=seed,
                         public=public, ddes_version=ddes.__version__)
    scores: dict[str, list[float]] = {c.id: [] for c in exercise.criteria}
    evidence: dict[str, list[str]] = {c.id: [] for c in exercise.criteria}
    tmp = Path(tempfile.mkdtemp(prefix="ddes-submission-"))
    try:
        prepared: Path | None = tmp / "submission"
        assert prepared is not None
        try:
            report.submission_sha256 = prepare(submission, prepared)
        except SubmissionError as exc:
            report.problems.append(f"{exc} — costs every criterion")
            prepared = None
        missing = [] if prepared is None else [
            f for f in exercise.required() if not (prepared / f).is_file()]
        if missing:
            report.problems.append(f"missing file(s): {', '.join(missing)} — costs the criteria "
                                   "that need them")
        first_failure: dict[str, Scenario] = {}
        # the whole grade's wall budget (every scenario and child): a budget, never a score
        deadline = time.monotonic() + (limits or Limits()).grade_wall_s
        for scenario in select_scenarios(exercise, seed, public, key):
            world, facts = run_scenario(exercise, scenario, prepared, limits, deadline)
            _note_problems(report, facts, limits or Limits())
            report.digests[scenario.name] = _digest(world)
            for cid, earned, lines in score_scenario(exercise, facts):
                scores[cid].append(earned)
                if lines:
                    evidence[cid] += lines
                    first_failure.setdefault(cid, scenario)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    for c in exercise.criteria:
        got = scores[c.id]
        points = left_sum(got) / len(got) if got else 0.0
        failed = first_failure.get(c.id)
        report.criteria.append(CriterionReport(
            id=c.id, name=c.name, points=float(round(points, 4)), max_points=float(c.max_points),
            visibility=c.visibility, evidence=evidence[c.id],
            replay="" if failed is None else replay_command(exercise, shown, failed, seed, key)))
    report.execution_time = time.perf_counter() - start
    return report


def _digest(world: World) -> str:
    try:
        return world.digest()
    except Exception:  # noqa: BLE001 - an exercise that filters its trace has no digest
        return ""


def submission_paths(prepared: Path) -> dict[str, str]:
    """The prepared submission's temporary folder (as given and resolved) shown as
    ``/submission`` in what nodes log (World.display_paths), in the grader's world and the
    child's: a grade's digest does not depend on where the submission was unpacked."""
    return {str(prepared): SHOWN_ROOT, os.path.realpath(prepared): SHOWN_ROOT}


#: The name a submission's folder has in logs and traces of a grade.
SHOWN_ROOT = "/submission"


#: The most student nodes (children) one run starts; a launch file's others are refused.
MAX_CHILDREN = 16
#: The seed of every child's world, whatever the scenario: what the student's nodes draw from it
#: (``random``, their named streams) is the same in every scenario, so it tells nothing of which
#: scenario runs, public or hidden.
CHILD_SEED = 0


def run_scenario(exercise: Exercise, scenario: Scenario, prepared: Path | None,
                 limits: Limits | None, deadline: float | None = None) -> tuple[World, Facts]:
    """Build the trusted world of ``scenario``, run the prepared submission (None: it could not
    be read) in lockstep with it, and return the world and the facts of the run.  ``deadline``
    (``time.monotonic()``) ends the children still running then (the grade's wall budget)."""
    world = World(scenario.seed, wall_budget=None)
    # the trusted world prints nothing where the grade runs: its nodes' lines (the simulator's
    # "collision with grader_pillar", which the grader's own schedule causes) are not the
    # student's; they stay in the trace
    world.log_output = False
    if prepared is not None:  # logs name the submission's files as /submission/...
        world.display_paths = submission_paths(prepared)
    exercise.build(world, scenario)
    until = to_ns(exercise.duration, "duration")
    scripts = [] if prepared is None else exercise.student_scripts(world, scenario, prepared)
    if scripts:
        assert prepared is not None
        # /use_sim_time crosses into the child, so its nodes follow the /clock the grader forwards
        params = {"/use_sim_time": True} if world.use_sim_time else {}
        # a child per student node, as ROS runs each node in a process of its own: each has its
        # own budgets, and one that hangs or dies leaves the others running
        budget = RunBudget()  # shared by the children of this run
        extra = scripts[MAX_CHILDREN:]
        scripts = scripts[:MAX_CHILDREN]
        sandboxes = [Sandbox(prepared, [script], seed=CHILD_SEED, limits=limits, params=params,
                             grade_deadline=deadline, run_budget=budget)
                     for script in scripts]
        lock = Lockstep(world, sandboxes)
        finished = exercise.finished
        outcome = lock.run(until, done=None if finished is None else lambda: finished(world))
        refused = list(lock.problems)
        if extra:
            refused.append((0, f"{len(extra)} more student node(s) than the {MAX_CHILDREN} a "
                               f"grade runs were not started ({extra[0][0]}, …)"))
        nodes = list(lock.proxies)
        deaths, failures, reads = lock.deaths, lock.callback_failures, lock.param_reads
        outcomes = [(path, o) for (path, _args), o in zip(scripts, lock.outcomes)]
    else:  # no student node to run: no child, no lockstep (nothing of the submission executes)
        _run_alone(world, until, exercise.finished if prepared is not None else None)
        outcome = SandboxOutcome(state="not started", reason=(
            "the submission could not be read" if prepared is None else
            "no student node to run: the student's process was not started"))
        refused, nodes = [], []
        deaths, failures, reads = [], [], []
        outcomes = []
    facts = Facts(exercise=exercise, scenario=scenario, world=world, outcome=outcome,
                  refused=refused, submission=prepared if prepared is not None else Path("/nonexistent"),
                  student_nodes=nodes, deaths=deaths, callback_failures=failures,
                  param_reads=reads, outcomes=outcomes)
    return world, facts


def _run_alone(world: World, until_ns: int, finished: Callable[[World], bool] | None) -> None:
    """Run ``world`` as :meth:`Lockstep.run` would with a child that has no node: the same
    instants (the first at 0), ``finished(world)`` checked after each, the same end."""
    if finished is None:
        world.run(until=Time._from_ns(until_ns))
        return
    t = 0
    while t < until_ns:
        world.run_through(t)
        if finished(world):
            return
        t = int(min(world.env.peek(), until_ns))
    if world.now < until_ns:
        world.run(until=Time._from_ns(until_ns))


def _note_problems(report: GradeReport, facts: Facts, limits: Limits) -> None:
    outcome, refused, name = facts.outcome, facts.refused, facts.scenario.name
    if outcome.enforced:
        report.enforced = list(outcome.enforced)
    each = [(f"{path}: ", o) for path, o in facts.outcomes] if len(facts.outcomes) > 1 else \
        [("", outcome)]
    for who, o in each:  # a child per node: each one that ended early, with its own output
        if o.state in ("killed", "exited"):
            failed = o.returncode != 0  # an error's traceback ends a failing run's output
            report.problems.append(f"{name}: {who}{o.reason}"
                                   + (_last_words(o.output_tail) if failed else ""))
        if o.leftovers:
            shown = "; ".join(_cut(x, 80) for x in o.leftovers[:3])
            report.problems.append(
                f"{name}: {who}{len(o.leftovers)} process(es) your node started were still "
                f"running after it ended, and the grader killed them ({shown}): a node must "
                "not start processes")
    for t, who, text in facts.deaths:
        cap = ""
        if "[Errno 27] File too large" in text:
            from ddes.grading.sandbox import _size

            cap = (f" — your output (or a file) passed the {_size(limits.file_bytes)} a grade "
                   "allows: print and log less")
        report.problems.append(f"{name}: your node {who} died at t={t / 1e9:.3f} s: "
                               f"{death_summary(text)}{cap}")
    for t, who, text in facts.callback_failures:
        callback = text.partition(":")[0].removeprefix("in the callback ")
        report.problems.append(f"{name}: your node {who} raised in its callback {callback} at "
                               f"t={t / 1e9:.3f} s (the node goes on, as in ROS): "
                               f"{death_summary(text)}")
    if refused:
        report.problems.append(f"{name}: the grader refused {len(refused)} item(s) from "
                               f"the student's process, first at t={refused[0][0] / 1e9:.3f} s: "
                               f"{refused[0][1]}")


def _last_words(tail: str) -> str:
    """The end of the student's own output (a traceback's file, line and error), quoted and
    labelled as theirs: shown to the student, never used for a score."""
    lines = [line.strip() for line in tail.splitlines()
             if line.strip() and not line.startswith("[ddes grading sandbox]")]
    if not lines:
        return ""
    where = next((line for line in reversed(lines[:-1]) if line.startswith("File ")), None)
    if where is not None:  # the path inside the submission, not the sandbox's copy of it
        where = re.sub(r'^File "[^"]*?/ddes-grade-[^/"]*/work/', 'File "', where)
    said = " / ".join(x for x in (where, lines[-1]) if x)
    return f"; its output ends with: {said[:300]!r}"


def _cut(text: str, limit: int) -> str:
    """``text`` of at most ``limit`` characters, cut at a word's end with "…" (never mid-word)."""
    if len(text) <= limit:
        return text
    head = text[:limit - 1]
    space = head.rfind(" ")
    return (head[:space] if space > limit // 2 else head).rstrip() + "…"


def death_summary(text: str) -> str:
    """One line of a dead node's traceback: the exception, then the student's frames from the
    innermost out (``file:line in function``, base names as the child sent them)."""
    lines = [line for line in text.splitlines() if line.strip()]
    if not lines:
        return "(no traceback)"
    error = lines[-1].strip()
    frames = []
    for line in lines:
        m = re.match(r'\s*File "([^"]*)", line (\d+), in (.+)$', line)
        if m:
            frames.append(f"{m.group(1)}:{m.group(2)} in {m.group(3)}")
    where = f" (at {' <- '.join(reversed(frames[-4:]))})" if frames else ""
    return (error + where)[:400]


def _death_note(facts: Facts) -> str:
    """What a criterion that lost points in a scenario where a student node died says of it."""
    if facts.deaths:
        t, who, text = facts.deaths[0]
        more = f" (and {len(facts.deaths) - 1} more)" if len(facts.deaths) > 1 else ""
        return (f"your node {who} died at t={t / 1e9:.3f} s{more} "
                f"({death_summary(text)[:160]}); what it would have done after that is missing")
    if facts.callback_failures:
        t, who, text = facts.callback_failures[0]
        return (f"a callback of your node {who} raised at t={t / 1e9:.3f} s "
                f"({death_summary(text)[:160]}); see the problem lines")
    return ""


def score_scenario(exercise: Exercise, facts: Facts) -> list[tuple[str, float, list[str]]]:
    """``(criterion id, points, evidence lines)`` of every criterion on one scenario's facts;
    the evidence is empty when the criterion earned its maximum."""
    scenario = facts.scenario
    out = []
    for c in exercise.criteria:
        try:
            points, lines = c.check(facts)
            got = finite_points(points, c.max_points)
            root = str(facts.submission)  # paths shown inside the submission, not its copy
            lines = [_cut(str(x).replace(root + "/", "").replace(root, "."), 500)
                     for x in list(lines)[:20]]
        except Exception as exc:  # noqa: BLE001 - a check that fails earns nothing and says why
            got, lines = 0.0, [f"the check could not be computed: {type(exc).__name__}: {exc}"]
        shown: list[str] = []
        if got < c.max_points:
            tag = f"{scenario.name} (seed {scenario.seed})" if not scenario.hidden else scenario.name
            shown = [f"{tag}: {line}" for line in lines] or [f"{tag}: failed"]
            died = _death_note(facts)
            if died:
                shown.append(f"{tag}: {died}")
        out.append((c.id, got, shown))
    return out
