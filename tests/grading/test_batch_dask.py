"""``ddes grade batch --workers N``: the same bytes for any number of workers (Dask distributed),
the same report as ``grade()``, and a clear message without the ``batch`` extra."""

from __future__ import annotations

import builtins
import dataclasses
from pathlib import Path
from typing import Any

import pytest

from ddes.cli.main import main
from ddes.grading.batch import MISSING, assemble, run_tasks, task_key, tasks_of
from ddes.grading.exercise import REGISTRY
from ddes.grading.grader import grade

HERE = Path(__file__).resolve().parent
EXERCISES = str(HERE / "fixtures" / "ex0_talker.py")
REFERENCE = (HERE / "fixtures" / "solutions" / "ex0_talker" / "talker.py").read_text()


def submissions(root: Path) -> Path:
    """The reference, the five_hz mutant (loses the rate's 4 points) and a missing file."""
    subs = root / "subs"
    for name, text in (("reference", REFERENCE),
                       ("five_hz", REFERENCE.replace("rospy.Rate(10)", "rospy.Rate(5)"))):
        (subs / name).mkdir(parents=True)
        (subs / name / "talker.py").write_text(text)
    (subs / "empty").mkdir()
    return subs


def files(out: Path) -> dict[str, bytes]:
    return {str(p.relative_to(out)): p.read_bytes() for p in sorted(out.rglob("*")) if p.is_file()}


def test_workers_0_and_2_write_the_same_bytes(tmp_path: Path,
                                              capsys: pytest.CaptureFixture[str]) -> None:
    subs = submissions(tmp_path)
    outs = {}
    for workers in (0, 2):
        outs[workers] = tmp_path / f"out{workers}"
        assert main(["grade", "--exercises", EXERCISES, "batch", "ex0_talker", str(subs),
                     "--out", str(outs[workers]), "--workers", str(workers)]) == 0
    printed = capsys.readouterr().out
    assert "Dask dashboard: http://" in printed
    serial, dask = files(outs[0]), files(outs[2])
    assert serial == dask
    summary = serial["summary.csv"].decode().splitlines()
    assert summary[0] == "submission,score,max_score,percent,0.1,0.2,0.3,problems"
    assert [r.split(",")[:5] for r in summary[1:]] == [
        ["empty", "0", "10", "0.0", "0"], ["five_hz", "6", "10", "60.0", "2"],
        ["reference", "10", "10", "100.0", "2"]]
    assert sorted(serial) == sorted(f"{n}/{f}" for n in ("empty", "five_hz", "reference")
                                    for f in ("junit.xml", "report.txt", "results.json")
                                    ) + ["summary.csv"]


def test_the_tasks_assemble_to_what_grade_gives(tmp_path: Path) -> None:
    REGISTRY.load_file(EXERCISES)
    exercise = REGISTRY.get("ex0_talker")
    sub = submissions(tmp_path) / "five_hz"
    scenarios, tasks = tasks_of(exercise, sub, seed=3, public=False, limits=None, key=None)
    keys = [task_key(t, "five_hz", s.name) for t, s in zip(tasks, scenarios, strict=True)]
    assert len(set(keys)) == len(keys) and keys[0].startswith("ddes-ex0_talker-five_hz-")
    outcomes = run_tasks(tasks, keys)
    assert not any(isinstance(o, str) for o in outcomes)
    batch = assemble(exercise, str(sub), scenarios, outcomes,  # type: ignore[arg-type]
                     seed=3, public=False, key=None)
    alone = grade(exercise, sub, seed=3)
    assert dataclasses.replace(alone, execution_time=0.0) == batch
    assert batch.score == 6


def test_without_distributed_workers_is_a_usage_error(tmp_path: Path, monkeypatch: Any,
                                                      capsys: pytest.CaptureFixture[str]) -> None:
    real = builtins.__import__

    def no_dask(name: str, *args: Any, **kwargs: Any) -> Any:
        if name == "distributed" or name.startswith("distributed."):
            raise ImportError(f"No module named {name!r}")
        return real(name, *args, **kwargs)

    monkeypatch.setattr(builtins, "__import__", no_dask)
    subs = submissions(tmp_path)
    assert main(["grade", "--exercises", EXERCISES, "batch", "ex0_talker", str(subs),
                 "--out", str(tmp_path / "o"), "--workers", "2"]) == 2
    err = capsys.readouterr().err
    assert 'pip install "ddes[batch]"' in err and MISSING in err
    assert not (tmp_path / "o").exists()  # nothing graded, nothing written
    assert main(["grade", "--exercises", EXERCISES, "batch", "ex0_talker", str(subs),
                 "--out", str(tmp_path / "o"), "--workers", "-1"]) == 2
    assert "--workers -1" in capsys.readouterr().err
