"""``ddes grade replay``: run one scenario of a grade again, exactly, and write what happened.

:func:`replay` prepares the submission as :func:`ddes.grading.grade` does, picks the scenario
by name among the grade's (``seed`` and, for a hidden scenario of a keyed grade, the
:class:`~ddes.grading.scenarios.HiddenKey`), runs it through the same
:func:`~ddes.grading.grader.run_scenario`, and scores it with the same checks.  Both kernels are
deterministic, so the trusted world's trace digest is the one the grade recorded
(``GradeReport.digests``).  It can write:

* the trace, as its canonical JSON lines (``Trace.dump``, docs/trace.md), one event a line;
* a bag (``.bag``, or ``.mcap`` by its name) of every message published in the trusted world —
  the grader's and the student's (through their proxies) — at its publish time, raw bytes with
  the grader's type and md5;
* a picture of what the exercise's criteria judged, as a PNG
  (:func:`ddes.grading.replay_picture.replay_picture`): the simulator's top view at the end of
  the run when there is one, the exercise's own time panels (an action exercise's goal
  timeline, the speed with the service calls, ...) and the rates of the topics its criteria
  count.
"""

from __future__ import annotations

import shutil
import tempfile
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from ddes.errors import GradingError, SubmissionError
from ddes.grading.exercise import Exercise, Scenario
from ddes.grading.grader import run_scenario, score_scenario
from ddes.grading.sandbox import Limits
from ddes.grading.scenarios import HiddenKey, select_scenarios
from ddes.grading.submission import prepare
from ddes.graph.world import World

__all__ = ["ReplayResult", "find_scenario", "replay", "write_bag"]


@dataclass
class ReplayResult:
    """One replayed scenario: its digest, each criterion's points there, what was written."""

    exercise: str
    scenario: Scenario
    digest: str
    #: ``(criterion id, name, points, max_points, evidence lines)``.
    criteria: list[tuple[str, str, float, float, list[str]]] = field(default_factory=list)
    problems: list[str] = field(default_factory=list)
    #: ``(what, path)`` of each file written.
    written: list[tuple[str, str]] = field(default_factory=list)
    #: The picture drawn (``picture=``): a DisplayFigure, or None.
    figure: Any = field(default=None, repr=False, compare=False)

    def to_text(self) -> str:
        s = self.scenario
        where = f"seed {s.seed}" if not s.hidden else "hidden"
        out = [f"{self.exercise} — scenario {s.name} ({where})"]
        out += [f"problem: {p}" for p in self.problems]
        for cid, name, got, top, lines in self.criteria:
            head = f"{cid} {name} "
            out.append(f"{head:.<60} {got:g}/{top:g}")
            out += [f"  {line}" for line in lines]
        out.append(f"digest: {self.digest or '(none: the trace is filtered)'}")
        out += [f"wrote {what}: {path}" for what, path in self.written]
        return "\n".join(out) + "\n"


def find_scenario(exercise: Exercise, name: str, seed: int,
                  key: HiddenKey | None = None) -> Scenario:
    """The scenario called ``name`` among the grade's (hidden ones included)."""
    scenarios = select_scenarios(exercise, seed, False, key)
    for s in scenarios:
        if s.name == name:
            return s
    known = ", ".join(s.name for s in scenarios)
    raise GradingError(f"exercise {exercise.id} has no scenario {name!r} for seed {seed} "
                       f"(its scenarios: {known})")


def replay(exercise: Exercise, submission: str | Path, scenario: str, *, seed: int = 0,
           key: HiddenKey | None = None, limits: Limits | None = None,
           trace: str | Path | None = None, bag: str | Path | None = None,
           picture: str | Path | None = None) -> ReplayResult:
    """Run ``scenario`` of the grade of ``submission`` again and write the files asked for."""
    chosen = find_scenario(exercise, scenario, seed, key)
    tmp = Path(tempfile.mkdtemp(prefix="ddes-replay-"))
    problems: list[str] = []
    try:
        prepared: Path | None = tmp / "submission"
        assert prepared is not None
        try:
            prepare(submission, prepared)
        except SubmissionError as exc:
            problems.append(f"{exc} — costs every criterion")
            prepared = None
        world, facts = run_scenario(exercise, chosen, prepared, limits)
        if facts.outcome.state in ("killed", "exited"):
            problems.append(f"{chosen.name}: {facts.outcome.reason}")
        if facts.refused:
            problems.append(f"{chosen.name}: the grader refused {len(facts.refused)} item(s) "
                            f"from the student's process, first at "
                            f"t={facts.refused[0][0] / 1e9:.3f} s: {facts.refused[0][1]}")
        scored = score_scenario(exercise, facts)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    try:
        digest = world.digest()
    except Exception:  # noqa: BLE001 - a filtered trace has no digest (as in the grade)
        digest = ""
    result = ReplayResult(exercise=exercise.id, scenario=chosen, digest=digest,
                          problems=problems)
    by_id = {c.id: c for c in exercise.criteria}
    for cid, got, lines in scored:
        c = by_id[cid]
        result.criteria.append((cid, c.name, got, float(c.max_points), lines))
    if trace is not None:
        Path(trace).parent.mkdir(parents=True, exist_ok=True)
        world.trace.dump(str(trace))
        result.written.append(("trace", str(trace)))
    if bag is not None:
        count = write_bag(world, bag)
        result.written.append((f"bag ({count} messages)", str(bag)))
    if picture is not None:
        from ddes.grading.replay_picture import replay_picture

        fig = replay_picture(exercise, chosen, world, facts)
        Path(picture).parent.mkdir(parents=True, exist_ok=True)
        fig.savefig(str(picture), dpi=100)
        result.figure = fig
        result.written.append(("picture", str(picture)))
    return result


def simulators(world: World) -> list[Any]:
    """The simulators of the trusted world, by node name."""
    from ddes.sim.simulator import Simulator

    return [e for n in sorted(world.nodes) for e in world.nodes[n].entities
            if isinstance(e, Simulator)]


def write_bag(world: World, path: str | Path) -> int:
    """Write every message published in ``world`` (from its trace) to a bag at ``path``; returns
    how many.  Each message keeps its publish time and its bytes; type and md5 are the grader's."""
    from ddes.rosbag.bag import Bag
    from ddes.time.rostime import Time

    Path(path).parent.mkdir(parents=True, exist_ok=True)
    classes: dict[str, Any] = {}
    count = 0
    with Bag(str(path), "w") as out:
        for ev in world.trace.select(kind="topic.publish"):
            topic = ev.details["topic"]
            if topic not in classes:
                entry = world.master.topics.get(topic)
                classes[topic] = (None if entry is None or entry.type == "*"
                                  else world.messages.get_message_class(entry.type))
            cls = classes[topic]
            if cls is None:
                continue
            out.write(topic, (cls._type, bytes(ev.details["data"]), cls._md5sum, cls),
                      t=Time.from_nsec(ev.t), raw=True)
            count += 1
    return count
