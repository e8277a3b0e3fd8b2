"""Fixtures of the grader's tests: the demo exercise and its submissions."""

from __future__ import annotations

from pathlib import Path

import pytest

from ddes.grading import ExerciseRegistry

HERE = Path(__file__).resolve().parent
FIXTURES = HERE / "fixtures"
ATTACKS = HERE / "attacks"
SOLUTION = FIXTURES / "ex0_solution"
EXERCISE_FILE = FIXTURES / "ex0_talker.py"


@pytest.fixture(scope="session")
def ex0():  # type: ignore[no-untyped-def]
    """The demo exercise ex0_talker, loaded as ``ddes grade --exercises`` loads it."""
    registry = ExerciseRegistry()
    (exercise,) = registry.load_file(EXERCISE_FILE)
    return exercise
