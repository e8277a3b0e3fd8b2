"""``ddes grade batch --workers N``: the same bytes for any number of workers (Dask distributed)
over references, starters and mutants, the same report as ``grade()``, a worker killed mid-batch
(retried; past the retry limit one infrastructure error, every other result intact), an
interrupted batch resumed without regrading, sweep and sensitivity on the same engine, the
progress bar, and a clear message without the ``batch`` extra."""

from __future__ import annotations

import builtins
import dataclasses
import io
import json
import shutil
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest

import ddes.grading.batch as batch
from ddes.cli.main import main
from ddes.grading.batch import (
    MISSING,
    Progress,
    assemble,
    run_tasks,
    task_key,
    tasks_of,
    without_wall_time,
)
from ddes.grading.exercise import REGISTRY
from ddes.grading.grader import grade
from ddes.grading.mutants import load_mutants, sensitivity, write_subjects
from ddes.grading.sweep import sweep

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent.parent
EXERCISES = str(HERE / "fixtures" / "ex0_talker.py")
KILLER = str(HERE / "fixtures" / "ex0_killer.py")
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
    """A batch's output files, with the one thing that differs between runs, each grade's wall
    time (``execution_time`` of results.json, ``time`` of junit.xml), set to 0."""
    return {name: without_wall_time(name, p.read_bytes()) for p in sorted(out.rglob("*"))
            if p.is_file() and (name := str(p.relative_to(out)))}


def wall_times(out: Path) -> dict[str, float]:
    """Each graded submission's ``execution_time`` in its results.json."""
    return {p.parent.name: json.loads(p.read_text())["execution_time"]
            for p in sorted(out.glob("*/results.json"))}


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
    assert dataclasses.replace(alone, execution_time=0.0) == dataclasses.replace(
        batch, execution_time=0.0)
    assert batch.score == 6
    # the batch's execution_time is the grade's wall time: its tasks' (here, one scenario's)
    assert batch.execution_time == sum(o.seconds for o in outcomes)  # type: ignore[union-attr]
    assert 0.05 < batch.execution_time < 10 * alone.execution_time + 1


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


def course_submissions(solutions: Path, exercise: str, dest: Path,
                       starter: Path | None = None) -> Path:
    """The reference, every mutant and the starter of an exercise, as a folder of submissions
    (``reference``, ``mutant_<name>``, ``starter``)."""
    solution = solutions / exercise
    subjects = write_subjects(solution, load_mutants(solution, REGISTRY.get(exercise)),
                              dest / "subjects")
    subs = dest / "subs"
    subs.mkdir()
    for name, kind, _, folder in subjects:
        folder.rename(subs / (name if kind == "reference" else f"mutant_{name}"))
    if starter is not None:
        shutil.copytree(starter, subs / "starter", ignore=shutil.ignore_patterns("__pycache__"))
    return subs


def same_bytes_for_0_2_4_workers(subs: Path, exercise: str, out: Path,
                                 extra: list[str]) -> dict[str, bytes]:
    outs = {}
    for workers in (0, 2, 4):
        assert main(["grade", *extra, "batch", exercise, str(subs), "--out",
                     str(out / str(workers)), "--workers", str(workers)]) == 0
        outs[workers] = files(out / str(workers))
        # results.json carries each grade's real wall time, as Gradescope shows it ...
        times = wall_times(out / str(workers))
        assert times and all(t > 0 for t in times.values()), times
        raw = (out / str(workers) / "summary.csv").read_bytes()
        assert outs[workers]["summary.csv"] == raw  # ... the summary none
    assert outs[0] == outs[2] == outs[4]  # the same bytes, the wall times set aside
    return outs[0]


def test_reference_mutants_and_starter_give_the_same_bytes_on_0_2_and_4_workers(
        tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """The demo exercise's reference, its five mutants, a starter (whose stub raises
    NotImplementedError: a crash is a result) and an empty submission; four workers on two
    cores: the bytes cannot depend on how many processes share them."""
    REGISTRY.load_file(EXERCISES)
    starter = tmp_path / "starter"
    starter.mkdir()
    (starter / "talker.py").write_text(REFERENCE.replace(
        '    rospy.init_node("talker")', '    raise NotImplementedError("your code here")'))
    subs = course_submissions(HERE / "fixtures" / "solutions", "ex0_talker", tmp_path, starter)
    (subs / "empty").mkdir()
    got = same_bytes_for_0_2_4_workers(subs, "ex0_talker", tmp_path / "out",
                                       ["--exercises", EXERCISES])
    assert capsys.readouterr().out.count("Dask dashboard: http://") == 2
    summary = got["summary.csv"].decode().splitlines()
    assert summary[0] == "submission,score,max_score,percent,0.1,0.2,0.3,problems"
    assert [r.split(",")[:7] for r in summary[1:]] == [
        ["empty", "0", "10", "0.0", "0", "0", "0"],
        ["mutant_bigger_queue", "10", "10", "100.0", "2", "4", "4"],
        ["mutant_five_hz", "6", "10", "60.0", "2", "0", "4"],
        ["mutant_no_count", "6", "10", "60.0", "2", "4", "0"],
        ["mutant_typed_message", "10", "10", "100.0", "2", "4", "4"],
        ["mutant_wrong_topic", "0", "10", "0.0", "0", "0", "0"],
        ["reference", "10", "10", "100.0", "2", "4", "4"],
        ["starter", "0", "10", "0.0", "0", "0", "0"]]
    assert sorted(got) == sorted(f"{n}/{f}" for n in [r.split(",")[0] for r in summary[1:]]
                                 for f in ("batch.json", "junit.xml", "report.txt",
                                           "results.json")) + ["summary.csv"]


@pytest.mark.slow
@pytest.mark.parametrize("exercise", ["ex1_console"])
def test_a_course_exercise_gives_the_same_bytes_on_0_2_and_4_workers(
        exercise: str, tmp_path: Path) -> None:
    """A course exercise's reference, starter (exercises/<id>/) and mutants: about a minute of
    CPU.  All six course exercises (86 submissions, 0, 1, 2 and 4 workers) are checked by
    ``python benchmarks/run.py batch``, too long for every CI run."""
    subs = course_submissions(ROOT / "solutions", exercise, tmp_path,
                              ROOT / "exercises" / exercise)
    got = same_bytes_for_0_2_4_workers(subs, exercise, tmp_path / "out", [])
    summary = got["summary.csv"].decode().splitlines()
    assert f"reference,{REGISTRY.get(exercise).max_points:g}," in "\n".join(summary)
    assert not any("grader infrastructure error" in row for row in summary)


def talkers(root: Path, texts: dict[str, str]) -> Path:
    """One submission per name, a talker publishing its text on /chatter."""
    for name, text in texts.items():
        (root / name).mkdir(parents=True)
        (root / name / "talker.py").write_text(
            REFERENCE.replace('f"hello world {n}"', repr(text)))
    return root


def test_a_killed_worker_is_retried_and_past_the_limit_costs_only_its_task(
        tmp_path: Path, monkeypatch: Any, capsys: pytest.CaptureFixture[str]) -> None:
    """b_once's grader kills its worker once (retried, graded); c_always's every time: after
    --retries 1 (two dead workers) it is a grader infrastructure error; a and d are intact."""
    marks = tmp_path / "marks"
    marks.mkdir()
    monkeypatch.setenv("DDES_TEST_KILL_DIR", str(marks))
    subs = talkers(tmp_path / "subs", {"a_fine": "hello", "b_once": "kill the worker once",
                                       "c_always": "kill the worker always", "d_fine": "hi"})
    out = tmp_path / "out"
    assert main(["grade", "--exercises", KILLER, "batch", "ex0_killer", str(subs),
                 "--out", str(out), "--workers", "2", "--retries", "1"]) == 0
    assert (marks / "killed-once-public").is_file()  # b_once's first worker did die
    summary = (out / "summary.csv").read_text().splitlines()
    assert summary[1:3] == ["a_fine,2,2,100.0,2,", "b_once,2,2,100.0,2,"]
    assert summary[4] == "d_fine,2,2,100.0,2,"
    assert summary[3] == (
        'c_always,,2,,,"grader infrastructure error: KilledWorker: every worker that ran this '
        'task died, past the retry limit (distributed.scheduler.allowed-failures = 1)"')
    assert not (out / "c_always").exists()
    assert "c_always: grader infrastructure error: KilledWorker" in capsys.readouterr().err
    # the others are what a serial batch of them gives, byte for byte
    shutil.rmtree(subs / "c_always")
    assert main(["grade", "--exercises", KILLER, "batch", "ex0_killer", str(subs),
                 "--out", str(tmp_path / "serial")]) == 0
    serial = files(tmp_path / "serial")
    assert {k: v for k, v in files(out).items() if k != "summary.csv"} == {
        k: v for k, v in serial.items() if k != "summary.csv"}


class Counted:
    """The tasks run in this process (serial batches), by submission folder name; with
    ``stop_at`` set, the instructor's ^C (KeyboardInterrupt) before that many tasks ran."""

    def __init__(self) -> None:
        self.ran: list[str] = []
        self.stop_at: int | None = None
        self.real = batch.grade_scenario

    def __call__(self, task: batch.Task, exercise: Any = None) -> batch.ScenarioOutcome:
        if self.stop_at is not None and len(self.ran) == self.stop_at:
            raise KeyboardInterrupt
        self.ran.append(Path(task.submission).name)
        return self.real(task, exercise)


def test_an_interrupted_batch_resumes_without_regrading_finished_submissions(
        tmp_path: Path, monkeypatch: Any, capsys: pytest.CaptureFixture[str]) -> None:
    counted = Counted()
    monkeypatch.setattr(batch, "grade_scenario", counted)
    subs = submissions(tmp_path)
    args = ["grade", "--exercises", EXERCISES, "batch", "ex0_talker", str(subs)]
    assert main([*args, "--out", str(tmp_path / "fresh")]) == 0
    fresh = files(tmp_path / "fresh")
    counted.ran, counted.stop_at = [], 2  # ^C on the third task (reference)
    out = tmp_path / "out"
    with pytest.raises(KeyboardInterrupt):
        main([*args, "--out", str(out)])
    assert counted.ran == ["empty", "five_hz"]
    assert (out / "five_hz" / "batch.json").is_file() and not (out / "summary.csv").exists()
    assert not (out / "reference").exists()
    counted.ran, counted.stop_at = [], None
    capsys.readouterr()
    assert main([*args, "--out", str(out), "--resume"]) == 0
    assert counted.ran == ["reference"]  # empty and five_hz kept
    assert "resuming: 2 finished submission(s) kept, 1 to grade" in capsys.readouterr().out
    assert files(out) == fresh
    # a changed submission is graded again; so is everything without --resume
    (subs / "five_hz" / "talker.py").write_text(REFERENCE)
    counted.ran = []
    assert main([*args, "--out", str(out), "--resume"]) == 0
    assert counted.ran == ["five_hz"]
    assert "five_hz,10,10,100.0" in (out / "summary.csv").read_text()
    counted.ran = []
    assert main([*args, "--out", str(out)]) == 0
    assert counted.ran == ["empty", "five_hz", "reference"]


def test_the_progress_bar_counts_tasks_without_wall_time() -> None:
    stream = io.StringIO()
    bar = Progress(4, stream)
    for _ in range(4):
        bar.step()
    bar.close()
    frames = stream.getvalue().split("\r")[1:]
    assert frames[0] == "grading [..............................] 0/4 tasks"
    assert frames[2] == "grading [###############...............] 2/4 tasks"
    assert frames[-1] == "grading [##############################] 4/4 tasks\n"
    silent = io.StringIO()
    Progress(0, silent).close()  # nothing to grade: no bar
    assert silent.getvalue() == ""


@pytest.fixture(scope="module")
def scheduler() -> Iterator[str]:
    """A LocalCluster of two one-thread workers, joined with --scheduler."""
    from distributed import LocalCluster

    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                      dashboard_address=":0") as cluster:
        yield cluster.scheduler_address


def test_sweep_and_sensitivity_run_on_the_same_engine(
        ex0: Any, scheduler: str, capsys: pytest.CaptureFixture[str]) -> None:
    from .conftest import FIXTURES, SOLUTION

    serial = sweep(ex0, SOLUTION, range(0, 2))
    dask = sweep(ex0, SOLUTION, range(0, 2), scheduler=scheduler)
    untimed = [(seed, dataclasses.replace(r, execution_time=0.0)) for seed, r in serial.grades]
    assert [(seed, dataclasses.replace(r, execution_time=0.0)) for seed, r in dask.grades] \
        == untimed and dask.errors == []
    assert all(r.execution_time > 0 for _, r in dask.grades)
    assert dask.to_text() == serial.to_text()
    alone = grade(ex0, SOLUTION, seed=1)
    assert dataclasses.replace(alone, execution_time=0.0) == untimed[1][1]
    solutions = FIXTURES / "solutions"
    matrix = sensitivity(ex0, solutions).to_text()
    assert main(["grade", "--exercises", EXERCISES, "sensitivity", "ex0_talker",
                 "--solutions", str(solutions), "--scheduler", scheduler]) == 0
    captured = capsys.readouterr()
    assert captured.out.startswith("Dask dashboard: http://")
    assert captured.out.endswith(matrix) and "bug mutants killed: 3 of 3; all gates" in matrix
    assert main(["grade", "--exercises", EXERCISES, "sweep", "ex0_talker", str(SOLUTION),
                 "--seeds", "0:2", "--scheduler", scheduler, "--workers", "2"]) == 2
    assert "not both" in capsys.readouterr().err
    assert main(["grade", "--exercises", EXERCISES, "sweep", "ex0_talker", str(SOLUTION),
                 "--seeds", "0:2", "--scheduler", scheduler, "--retries", "1"]) == 2
    assert "--retries sets the retry limit" in capsys.readouterr().err


def test_an_exercise_defined_in_code_grades_serially_but_not_on_dask(tmp_path: Path) -> None:
    from ddes.errors import GradingError
    from ddes.grading.batch import Job, grade_all

    REGISTRY.load_file(EXERCISES)
    in_code = dataclasses.replace(REGISTRY.get("ex0_talker"), origin="")  # in no registry
    sub = submissions(tmp_path) / "reference"
    (report,) = grade_all(in_code, [Job("reference", sub)])
    assert not isinstance(report, str) and report.score == 10
    with pytest.raises(GradingError, match="neither built in nor loaded from a file"):
        grade_all(in_code, [Job("reference", sub)], workers=2)
