"""The autograder: student code in a sandboxed process, the score computed outside it.

See docs/grading.md.  ``grade(exercise, submission)`` returns a :class:`GradeReport`;
``ddes grade`` is the command line (ddes/cli/grade.py).
"""

from __future__ import annotations

from ddes.grading.bridge import Lockstep
from ddes.grading.exercise import REGISTRY, Criterion, Exercise, ExerciseRegistry, Facts, Scenario
from ddes.grading.grader import grade
from ddes.grading.report import CriterionReport, GradeReport
from ddes.grading.sandbox import Limits, Sandbox, SandboxOutcome
from ddes.grading.submission import prepare

__all__ = [
    "REGISTRY",
    "Criterion",
    "CriterionReport",
    "Exercise",
    "ExerciseRegistry",
    "Facts",
    "GradeReport",
    "Limits",
    "Lockstep",
    "Sandbox",
    "SandboxOutcome",
    "Scenario",
    "grade",
    "prepare",
]
