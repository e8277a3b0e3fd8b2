"""The course exercises' grader sensitivity and seed sweeps (issue 19, items 5 and 6).

* ``ddes grade sensitivity EX`` over each course exercise exits 0: the reference loses nothing,
  every bug mutant of ``solutions/<ex>/mutants/`` loses (only) the criteria it lists, every
  equivalent mutant loses nothing; its kill matrix is the transcript in docs/grading.md
  ("Mutants of the course exercises").
* The reference has zero false failures over 20 seeds per exercise (each seed a plain grade:
  the public scenario and two hidden ones drawn from the seed).  Every test run grades seeds 0
  and 1; CI grades seeds 2-4 as well (marked ``slow`` and ``ci``); the other 15 are marked
  ``slow`` (deselected by default: run them with ``pytest -m slow``), which keeps CI under its
  time limit.

A sensitivity grades the reference and every mutant (12 to 22 gradings, one to four minutes on
two cores each), so these eight are marked ``slow`` and ``ci``: they stay out of a student's
``pytest`` (tests/grading/test_mutants.py checks the sensitivity of the demo exercise there) and
CI runs them (``.ci/run``: ``pytest -m "slow and ci"``).
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from ddes.cli.main import main
from ddes.grading import REGISTRY
from ddes.grading.sweep import sweep

REPO = Path(__file__).resolve().parents[2]
SOLUTIONS = REPO / "solutions"
DOCS = REPO / "docs" / "grading.md"
EXERCISES = ["ex1_console", "ex2_package", "ex3_pillar", "ex4a_services", "ex4b_actions",
             "ex4c_time", "ex4d_bags", "ex5_safety"]
SEEDS = range(20)
#: The seeds every test run sweeps, then the ones CI sweeps as well (``-m "slow and ci"``); the
#: rest of SEEDS run with ``pytest -m slow``.
SAMPLE = range(2)
CI_SAMPLE = range(2, 5)


def transcript(exercise: str) -> str:
    """The kill matrix docs/grading.md shows for ``exercise``: the text block that starts with
    ``$ ddes grade sensitivity <exercise>``, without that line."""
    text = DOCS.read_text(encoding="utf-8")
    m = re.search(rf"```text\n\$ ddes grade sensitivity {exercise}\n(.*?)```", text, re.S)
    assert m is not None, f"docs/grading.md shows no kill matrix of {exercise}"
    return m.group(1)


@pytest.mark.slow
@pytest.mark.ci
@pytest.mark.parametrize("exercise", EXERCISES)
def test_sensitivity_of_the_course_exercise(exercise: str,
                                            capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["grade", "sensitivity", exercise, "--solutions", str(SOLUTIONS)]) == 0
    out = capsys.readouterr().out
    assert out == transcript(exercise), out
    assert "all gates hold" in out


def check_sweep(exercise: str, seeds: range) -> None:
    swept = sweep(REGISTRY.get(exercise), SOLUTIONS / exercise, seeds)
    assert [s for s, _ in swept.grades] == list(seeds)
    assert not swept.failures(), swept.to_text()
    # the hidden scenarios really differ from seed to seed (the sweep is not copies of one)
    assert len({r.digests["hidden-1"] for _, r in swept.grades}) == len(seeds)


@pytest.mark.parametrize("exercise", EXERCISES)
def test_the_reference_has_no_false_failure_over_a_sample_of_seeds(exercise: str) -> None:
    check_sweep(exercise, SAMPLE)


@pytest.mark.slow
@pytest.mark.ci
@pytest.mark.parametrize("exercise", EXERCISES)
def test_the_reference_has_no_false_failure_over_the_ci_sample_of_seeds(exercise: str) -> None:
    check_sweep(exercise, CI_SAMPLE)


@pytest.mark.slow
@pytest.mark.parametrize("exercise", EXERCISES)
def test_the_reference_has_no_false_failure_over_the_other_seeds(exercise: str) -> None:
    check_sweep(exercise, range(CI_SAMPLE.stop, SEEDS.stop))
