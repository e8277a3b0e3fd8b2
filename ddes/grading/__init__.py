"""The autograder: student code in a sandboxed process, the score computed outside it.

See docs/grading.md.  ``grade(exercise, submission)`` returns a :class:`GradeReport`;
``ddes grade`` is the command line (ddes/cli/grade.py).
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from ddes.grading.bridge import Lockstep
    from ddes.grading.exercise import (
        REGISTRY,
        Criterion,
        Exercise,
        ExerciseRegistry,
        Facts,
        Scenario,
    )
    from ddes.grading.grader import grade
    from ddes.grading.report import CriterionReport, GradeReport
    from ddes.grading.sandbox import Limits, Sandbox, SandboxOutcome
    from ddes.grading.submission import prepare

#: Where each public name lives.  The package imports them on first use (PEP 562), so that the
#: sandboxed child, which imports ``ddes.grading.child``, loads the protocol and nothing of the
#: grader: no exercise, scenario or scoring code is in its memory, and importing it there is
#: refused (ddes/grading/child.py).
_WHERE = {
    "Lockstep": "bridge", "REGISTRY": "exercise", "Criterion": "exercise",
    "Exercise": "exercise", "ExerciseRegistry": "exercise", "Facts": "exercise",
    "Scenario": "exercise", "grade": "grader", "CriterionReport": "report",
    "GradeReport": "report", "Limits": "sandbox", "Sandbox": "sandbox",
    "SandboxOutcome": "sandbox", "prepare": "submission",
}


def __getattr__(name: str) -> Any:
    where = _WHERE.get(name)
    if where is None:
        raise AttributeError(f"module 'ddes.grading' has no attribute {name!r}")
    import importlib

    return getattr(importlib.import_module(f"ddes.grading.{where}"), name)


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
