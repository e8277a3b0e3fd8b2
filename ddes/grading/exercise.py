"""Exercises, criteria and the facts criteria are computed from.

An :class:`Exercise` names the student's scripts (run in the sandbox), how to build the trusted
world around them (``build(world, scenario)``: simulator, drivers, recorders), how long to run,
its scenarios, and its :class:`Criterion` list.  A criterion's ``check(facts)`` returns the
points earned out of its ``max_points`` with evidence lines; it reads only :class:`Facts` — the
trusted world after the run, its trace, the messages recorded there, how the student's process
ended, and artefacts read as text from the submission (never imported).

Exercises live in an :class:`ExerciseRegistry`; :data:`REGISTRY` is the one ``ddes grade`` uses
(course exercises register there from :data:`BUILTIN_MODULES`; an instructor's own file is
loaded with :meth:`ExerciseRegistry.load_file` or ``ddes grade --exercises FILE``).
"""

from __future__ import annotations

import dataclasses
import importlib
import importlib.util
import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

from ddes.errors import GradingError

if TYPE_CHECKING:
    from ddes.grading.sandbox import SandboxOutcome
    from ddes.graph.world import World

__all__ = [
    "BUILTIN_MODULES",
    "REGISTRY",
    "VISIBILITIES",
    "Check",
    "Criterion",
    "Exercise",
    "ExerciseRegistry",
    "Facts",
    "Scenario",
]

#: Gradescope's visibility values.
VISIBILITIES = ("visible", "hidden", "after_due_date", "after_published")
#: Modules that register the course's exercises when the registry is first read.
BUILTIN_MODULES: tuple[str, ...] = ("ddes.grading.exercises",)


@dataclass(frozen=True)
class Scenario:
    """One run of an exercise: a name, a seed, whether it is hidden, and its parameters."""

    name: str
    seed: int
    hidden: bool = False
    params: dict[str, Any] = field(default_factory=dict)


@dataclass
class Facts:
    """What a criterion may look at, all from the trusted side."""

    exercise: Exercise
    scenario: Scenario
    world: World
    #: How the student's process ended (state, reason, output tail, what was enforced).
    outcome: SandboxOutcome
    #: What the grader refused from the child: ``(t_ns, text)``.
    refused: list[tuple[int, str]]
    #: The prepared submission (a read-only copy: read artefacts as text, never import them).
    submission: Path
    #: Names of the student's nodes (their proxies in the grader's world).
    student_nodes: list[str]
    #: Student nodes whose main raised: ``(t_ns, node or script, traceback)`` (the child's
    #: word, for feedback: never a reason to give points).
    deaths: list[tuple[int, str, str]] = field(default_factory=list)
    #: The first failure of each student callback (the node went on, as rospy's does):
    #: ``(t_ns, node, "in the callback NAME:" + traceback)``.
    callback_failures: list[tuple[int, str, str]] = field(default_factory=list)
    #: How each student node's child ended: ``(its script, relative to the submission, the
    #: outcome)``, in the order the exercise gave the scripts (``outcome`` combines them).
    outcomes: list[tuple[str, SandboxOutcome]] = field(default_factory=list)
    #: Parameters the student's nodes read: ``(t_ns, node, resolved key, found)``, once each.
    param_reads: list[tuple[int, str, str, bool]] = field(default_factory=list)

    def messages(self, topic: str, publisher: str | None = None) -> list[tuple[int, str, Any]]:
        """``(t_ns, publisher, message)`` of every message published on ``topic`` in the
        grader's world (decoded with the grader's own class), oldest first."""
        entry = self.world.master.topics.get(topic)
        if entry is None or entry.type == "*":
            return []
        cls = self.world.messages.get_message_class(entry.type)
        out = []
        for ev in self.world.trace.select(kind="topic.publish", topic=topic):
            if publisher is not None and ev.source != publisher:
                continue
            out.append((ev.t, ev.source, cls.__new__(cls)._deserialize_from(ev.details["data"])))
        return out

    def read_text(self, relpath: str, limit: int = 1 << 20) -> str | None:
        """A submission file as text (at most ``limit`` bytes), or None if absent or unsafe."""
        root = self.submission.resolve()
        path = (root / relpath).resolve()
        if root not in path.parents or not path.is_file() or path.is_symlink():
            return None
        with open(path, "rb") as f:
            return f.read(limit).decode("utf-8", "replace")


#: A check: facts -> (points, evidence lines).
Check = Callable[[Facts], tuple[float, Sequence[str]]]


@dataclass(frozen=True)
class Criterion:
    """One graded item: ``check(facts)`` earns up to ``max_points`` per scenario."""

    id: str
    name: str
    max_points: float
    check: Check
    visibility: str = "visible"
    #: Where the text comes from ("after ETH Zurich, Programming for Robotics, exercise 3").
    credit: str = ""

    def __post_init__(self) -> None:
        if self.visibility not in VISIBILITIES:
            raise GradingError(f"criterion {self.id}: visibility {self.visibility!r} is not one "
                               f"of {', '.join(VISIBILITIES)}")
        if not (isinstance(self.max_points, (int, float)) and math.isfinite(self.max_points)
                and self.max_points >= 0):
            raise GradingError(f"criterion {self.id}: max_points {self.max_points!r} must be a "
                               "finite number >= 0")


def _no_build(_world: World, _scenario: Scenario) -> None:
    return None


def _one_public(seed: int, public: bool) -> list[Scenario]:
    return [Scenario("public", seed)]


@dataclass(frozen=True)
class Exercise:
    """An exercise: the student's scripts, the trusted world around them, the criteria."""

    id: str
    title: str
    criteria: tuple[Criterion, ...]
    #: The student's scripts: ``(path in the submission, arguments)``; run in the sandbox.
    scripts: tuple[tuple[str, tuple[str, ...]], ...]
    #: Simulated seconds per scenario.
    duration: float = 10.0
    #: Builds the trusted world of a scenario (simulator, drivers, recorders).
    build: Callable[[World, Scenario], None] = _no_build
    #: ``scenarios(seed, public)``: the runs; hidden ones only when ``public`` is False.
    scenarios: Callable[[int, bool], list[Scenario]] = _one_public
    #: Files the submission must hold (the scripts are added).
    required_files: tuple[str, ...] = ()
    #: ``finished(world)``: True once the scenario's schedule is over; the run then ends before
    #: ``duration`` (which stays the cap).  Checked at each lockstep instant; None: never.
    finished: Callable[[World], bool] | None = None
    #: The instructor's file it was loaded from (``load_file``), so replay commands name it.
    origin: str = field(default="", compare=False)

    def __post_init__(self) -> None:
        ids = [c.id for c in self.criteria]
        if len(set(ids)) != len(ids):
            raise GradingError(f"exercise {self.id}: criterion ids repeat: {ids}")

    @property
    def max_points(self) -> float:
        return float(sum(c.max_points for c in self.criteria))

    def required(self) -> list[str]:
        return list(dict.fromkeys([*self.required_files, *(p for p, _ in self.scripts)]))

    def student_scripts(self, world: World, scenario: Scenario,
                        submission: Path) -> list[tuple[str, list[str]]]:
        """The scripts the child runs in ``scenario`` (after :attr:`build`): :attr:`scripts`
        that the submission holds.  Exercises driven by the student's launch file override it
        (:class:`ddes.grading.course.CourseExercise`)."""
        return [(p, list(a)) for p, a in self.scripts if (submission / p).is_file()]


class ExerciseRegistry:
    """Exercises by id."""

    def __init__(self, modules: Sequence[str] = ()) -> None:
        self._exercises: dict[str, Exercise] = {}
        self._modules = list(modules)
        self._loaded = False

    def register(self, exercise: Exercise) -> Exercise:
        """Add an exercise (the same id twice replaces it: a reloaded instructor file)."""
        self._exercises[exercise.id] = exercise
        return exercise

    def _load(self) -> None:
        if not self._loaded:
            self._loaded = True
            for name in self._modules:
                importlib.import_module(name)

    def get(self, exercise_id: str) -> Exercise:
        self._load()
        try:
            return self._exercises[exercise_id]
        except KeyError:
            known = ", ".join(self._exercises) or "none registered"
            raise GradingError(f"unknown exercise {exercise_id!r} (known: {known}); "
                               "'ddes grade list' lists them") from None

    def exercises(self) -> list[Exercise]:
        self._load()
        return list(self._exercises.values())

    def load_file(self, path: str | Path) -> list[Exercise]:
        """Run an instructor's exercise file (trusted code) and register its ``EXERCISES``."""
        path = Path(path)
        if not path.is_file():
            raise GradingError(f"exercise file {path} does not exist")
        spec = importlib.util.spec_from_file_location(f"ddes_grading_user_{path.stem}", path)
        if spec is None or spec.loader is None:
            raise GradingError(f"cannot load exercise file {path}")
        module = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(module)
        found = getattr(module, "EXERCISES", None)
        if not isinstance(found, (list, tuple)) or not all(isinstance(e, Exercise) for e in found):
            raise GradingError(f"{path} must define EXERCISES = [Exercise(...), ...]")
        loaded = [dataclasses.replace(ex, origin=str(path)) for ex in found]
        for ex in loaded:
            self.register(ex)
        return loaded


#: The registry ``ddes grade`` reads.
REGISTRY = ExerciseRegistry(BUILTIN_MODULES)
