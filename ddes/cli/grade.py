"""``ddes grade``: the autograder's command line (docs/grading.md).

* ``ddes grade list``: the exercises and their criteria;
* ``ddes grade EXERCISE SUBMISSION [--results FILE] [--junit FILE] [--out DIR] [--seed N]
  [--public] [--fail-under PCT]``: grade one folder, ``.zip`` or notebook; prints the report;
* ``ddes grade batch EXERCISE DIR --out OUT [--workers N | --scheduler ADDRESS]``: grade every
  submission in ``DIR``, one task per (submission, scenario), serially or on Dask distributed
  (``OUT/<submission>/results.json`` and ``OUT/summary.csv``, the same bytes for any N);
* ``replay``, ``sweep``, ``sensitivity`` and the hidden-scenario key (``--secret-file``,
  ``--student``, ``--attempt``): ddes/cli/grade_tools.py.

``--exercises FILE`` (repeatable) loads an instructor's exercise file first.  Exit status: 0
when grading completed, whatever the score; 1 under ``--fail-under`` when the score is below it;
2 for a usage error (an unknown exercise, a bad option).
"""

from __future__ import annotations

import argparse
import csv
import io
import re
import sys
from pathlib import Path
from typing import Any

from ddes.cli.grade_tools import TOOLS, add_arguments, hidden_key
from ddes.errors import GradingError

__all__ = ["register", "run_grade"]

_USAGE = ("ddes grade list | ddes grade EXERCISE SUBMISSION [options] | "
          "ddes grade batch EXERCISE DIR --out OUT [--workers N | --scheduler ADDRESS] | "
          "ddes grade replay EXERCISE SUBMISSION --scenario NAME | "
          "ddes grade sweep EXERCISE SUBMISSION --seeds A:B | ddes grade sensitivity EXERCISE")


def register(sub: argparse._SubParsersAction[argparse.ArgumentParser]) -> None:
    p = sub.add_parser("grade", help="grade a submission in a sandbox (docs/grading.md)",
                       usage=_USAGE, description=__doc__,
                       formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("words", nargs="+", metavar="ARG",
                   help="list | EXERCISE SUBMISSION | batch EXERCISE DIR | replay EXERCISE "
                        "SUBMISSION | sweep EXERCISE SUBMISSION | sensitivity EXERCISE")
    p.add_argument("--results", metavar="FILE", help="write Gradescope's results.json here")
    p.add_argument("--junit", metavar="FILE", help="write JUnit XML here")
    p.add_argument("--out", metavar="DIR",
                   help="write results.json, junit.xml and report.txt here (batch: one folder "
                        "per submission and summary.csv)")
    p.add_argument("--seed", type=int, default=0, help="scenario seed (default 0)")
    p.add_argument("--public", action="store_true", help="public scenarios only")
    p.add_argument("--fail-under", type=float, metavar="PCT",
                   help="exit 1 when the score is below PCT percent (for CI)")
    p.add_argument("--exercises", action="append", default=[], metavar="FILE",
                   help="load exercises from an instructor's Python file (EXERCISES = [...])")
    p.add_argument("--timeout", type=float, default=None, metavar="S",
                   help="wall budget of one step of the student's process (default 5 s)")
    p.add_argument("--mem", default=None, metavar="SIZE",
                   help="address-space limit of the student's process (e.g. 512M; default 768M)")
    p.add_argument("--workers", type=int, default=0, metavar="N",
                   help="batch: grade on a Dask LocalCluster of N processes (default 0: "
                        "serially in this process; needs pip install \"ddes[batch]\")")
    p.add_argument("--scheduler", default=None, metavar="ADDRESS",
                   help="batch: grade on the existing Dask cluster of this scheduler")
    add_arguments(p)
    p.set_defaults(func=run_grade)


def _size(text: str) -> int:
    m = re.fullmatch(r"(\d+)([KMG]?)", text.strip().upper())
    if m is None:
        raise GradingError(f"--mem {text!r}: give a size such as 512M or 1G")
    return int(m.group(1)) * {"": 1, "K": 1 << 10, "M": 1 << 20, "G": 1 << 30}[m.group(2)]


def run_grade(args: argparse.Namespace) -> int:
    try:
        return _run(args)
    except GradingError as exc:
        print(f"ddes grade: error: {exc}", file=sys.stderr)
        return 2


def _run(args: argparse.Namespace) -> int:
    from ddes.grading.exercise import REGISTRY
    from ddes.grading.sandbox import Limits, check_limits

    for path in args.exercises:
        REGISTRY.load_file(path)
    words = list(args.words)
    limits = Limits()
    changes: dict[str, object] = {}
    if args.timeout is not None:
        if not args.timeout > 0:
            raise GradingError(f"--timeout {args.timeout}: give seconds > 0")
        changes["step_wall_s"] = float(args.timeout)
    if args.mem is not None:
        changes["memory_bytes"] = _size(args.mem)
    if changes:
        limits = Limits(**{**limits.__dict__, **changes})  # type: ignore[arg-type]
        check_limits(limits)
    if words == ["list"]:
        return _list()
    if words[0] in TOOLS:
        return TOOLS[words[0]](REGISTRY, words[1:], args, limits)
    if words[0] == "batch":
        if len(words) != 3 or not args.out:
            raise GradingError(f"usage: ddes grade batch EXERCISE DIR --out OUT (got {words[1:]})")
        if args.student is not None:
            raise GradingError("batch: the student of each submission is its name; leave out "
                               "--student")
        return _batch(REGISTRY.get(words[1]), Path(words[2]), Path(args.out), args, limits)
    if len(words) != 2:
        raise GradingError(f"usage: {_USAGE}")
    from ddes.grading.grader import grade

    report = grade(REGISTRY.get(words[0]), words[1], seed=args.seed, public=args.public,
                   limits=limits, key=hidden_key(args, words[1]))
    sys.stdout.write(report.to_text())
    if args.results:
        report.write_results(args.results)
    if args.junit:
        report.write_junit(args.junit)
    if args.out:
        _write_all(report, Path(args.out))
    if args.fail_under is not None and report.percent < args.fail_under:
        print(f"score {report.percent:.1f} % is below --fail-under {args.fail_under:g} %",
              file=sys.stderr)
        return 1
    return 0


def _write_all(report: object, out: Path) -> None:
    from ddes.grading.report import GradeReport, write_atomic

    assert isinstance(report, GradeReport)
    out.mkdir(parents=True, exist_ok=True)
    report.write_results(out / "results.json")
    report.write_junit(out / "junit.xml")
    write_atomic(out / "report.txt", report.to_text())


def _list() -> int:
    from ddes.grading.exercise import REGISTRY

    found = REGISTRY.exercises()
    if not found:
        print("no exercises registered (load an instructor's file with --exercises FILE)")
    for ex in found:
        print(f"{ex.id}  {ex.title}  ({ex.max_points:g} points, {ex.duration:g} s simulated)")
        for c in ex.criteria:
            print(f"  {c.id:6} {c.max_points:>5g}  {c.name}  [{c.visibility}]")
    return 0


def _safe_name(name: str) -> str:
    return re.sub(r"[^A-Za-z0-9._-]", "_", name)[:100] or "_"


def _batch(exercise: object, folder: Path, out: Path, args: argparse.Namespace,
           limits: object) -> int:
    from ddes.grading.batch import assemble, run_tasks, task_key, tasks_of
    from ddes.grading.exercise import Exercise
    from ddes.grading.report import write_atomic
    from ddes.grading.sandbox import Limits

    assert isinstance(exercise, Exercise) and isinstance(limits, Limits)
    if not folder.is_dir():
        raise GradingError(f"batch: {folder} is not a folder of submissions")
    if args.workers and args.scheduler:
        raise GradingError("batch: give --workers N or --scheduler ADDRESS, not both")
    entries = sorted(p for p in folder.iterdir()
                     if p.is_dir() or p.suffix in (".zip", ".ipynb"))
    ids = [c.id for c in exercise.criteria]
    used: set[str] = set()
    # (entry, folder name, key, scenarios, its first task, its number of tasks or what failed)
    plan: list[tuple[Path, str, Any, list[Any], int, int | str]] = []
    tasks: list[Any] = []
    keys: list[str] = []
    for entry in entries:
        name = _safe_name(entry.name)
        while name in used or name == "summary.csv":
            name += "_"
        used.add(name)
        try:
            key = hidden_key(args, entry)
            scenarios, mine = tasks_of(exercise, entry, seed=args.seed, public=args.public,
                                       limits=limits, key=key)
        except Exception as exc:  # noqa: BLE001 - one broken grade never ends the batch
            plan.append((entry, name, None, [], -1, f"{type(exc).__name__}: {exc}"))
            continue
        plan.append((entry, name, key, scenarios, len(tasks), len(mine)))
        keys += [task_key(t, name, scenarios[t.index].name if t.index is not None else "")
                 for t in mine]
        tasks += mine
    results = run_tasks(tasks, keys, workers=args.workers, scheduler=args.scheduler)
    rows: list[list[str]] = []
    for entry, name, key, scenarios, first, count in plan:
        got = [count] if isinstance(count, str) else results[first:first + count]
        broken = [r for r in got if isinstance(r, str)]
        if broken:
            rows.append([entry.name, "", f"{exercise.max_points:g}", "",
                         *[""] * len(ids), f"grader infrastructure error: {broken[0]}"])
            print(f"{entry.name}: grader infrastructure error: {broken[0]}", file=sys.stderr)
            continue
        report = assemble(exercise, str(entry), scenarios,
                          [r for r in got if not isinstance(r, str)],
                          seed=args.seed, public=args.public, key=key)
        _write_all(report, out / name)
        by_id = {c.id: c.points for c in report.criteria}
        rows.append([entry.name, f"{report.score:g}", f"{report.max_score:g}",
                     f"{report.percent:.1f}", *[f"{by_id[i]:g}" for i in ids],
                     "; ".join(report.problems)[:500]])
        print(f"{entry.name}: {report.score:g}/{report.max_score:g}")
    buf = io.StringIO()
    writer = csv.writer(buf, lineterminator="\n")
    writer.writerow(["submission", "score", "max_score", "percent", *ids, "problems"])
    writer.writerows(rows)
    write_atomic(out / "summary.csv", buf.getvalue())
    return 0
