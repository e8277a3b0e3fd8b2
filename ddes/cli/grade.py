"""``ddes grade``: the autograder's command line (docs/grading.md).

* ``ddes grade list``: the exercises and their criteria;
* ``ddes grade EXERCISE SUBMISSION [--results FILE] [--junit FILE] [--out DIR] [--seed N]
  [--public] [--fail-under PCT]``: grade one folder, ``.zip`` or notebook; prints the report;
* ``ddes grade batch EXERCISE DIR --out OUT [--workers N [--retries R] | --scheduler ADDRESS]
  [--resume]``: grade every submission in ``DIR``, one task per (submission, scenario), serially
  or on Dask distributed (``OUT/<submission>/results.json`` and ``OUT/summary.csv``, the same
  bytes for any N); each submission's files are written as soon as it is graded, and
  ``--resume`` keeps those of an interrupted batch (``OUT/<submission>/batch.json``);
* ``replay``, ``sweep``, ``sensitivity``, ``operators`` and the hidden-scenario key
  (``--secret-file``, ``--student``, ``--attempt``): ddes/cli/grade_tools.py.

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

from ddes.cli.grade_tools import TOOLS, add_arguments, hidden_key, progress_stream
from ddes.errors import GradingError

__all__ = ["register", "run_grade"]

_USAGE = ("ddes grade list | ddes grade EXERCISE SUBMISSION [options] | "
          "ddes grade batch EXERCISE DIR --out OUT [--workers N | --scheduler ADDRESS] "
          "[--resume] | "
          "ddes grade replay EXERCISE SUBMISSION --scenario NAME | "
          "ddes grade sweep EXERCISE SUBMISSION --seeds A:B | ddes grade sensitivity EXERCISE | "
          "ddes grade operators EXERCISE [--sample N]")


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
                        "per submission and summary.csv; sweep: one folder per seed, "
                        "summary.csv, sweep.txt and histogram.png)")
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
                   help="batch, sweep, sensitivity: grade on a Dask LocalCluster of N processes "
                        "(default 0: serially in this process; needs pip install "
                        "\"ddes[batch]\")")
    p.add_argument("--scheduler", default=None, metavar="ADDRESS",
                   help="batch, sweep, sensitivity: grade on the existing Dask cluster of this "
                        "scheduler")
    p.add_argument("--retries", type=int, default=None, metavar="R",
                   help="with --workers N: run a task whose worker died up to R more times "
                        "(default 3), then report a grader infrastructure error")
    p.add_argument("--resume", action="store_true",
                   help="batch: keep the submissions OUT already holds finished grades of "
                        "(same submission, exercise and options); grade the rest")
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
    import json

    from ddes.grading.batch import Job, fingerprint, grade_all
    from ddes.grading.exercise import Exercise
    from ddes.grading.report import GradeReport, utf8_safe, write_atomic
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
    rows: list[list[str] | None] = [None] * len(entries)
    names: list[str] = []
    errors: dict[int, str] = {}
    jobs: list[Job] = []
    where: list[tuple[int, str | None]] = []  # (entry, fingerprint) of each job
    kept = 0
    for i, entry in enumerate(entries):
        name = _safe_name(entry.name)
        while name in used or name == "summary.csv":
            name += "_"
        used.add(name)
        names.append(name)
        try:
            key = hidden_key(args, entry)
        except Exception as exc:  # noqa: BLE001 - one broken grade never ends the batch
            errors[i] = f"{type(exc).__name__}: {exc}"
            continue
        job = Job(name, entry, seed=args.seed, public=args.public, key=key)
        mark = fingerprint(exercise, job, limits)
        marker = out / name / "batch.json"
        if args.resume and mark is not None and marker.is_file():
            try:
                done = json.loads(marker.read_text(encoding="utf-8"))
            except (OSError, ValueError):
                done = None
            if isinstance(done, dict) and done.get("fingerprint") == mark:
                rows[i] = [str(x) for x in done["summary"]]
                kept += 1
                continue
        if marker.is_file():
            marker.unlink()  # graded again: this folder is not finished until it is rewritten
        jobs.append(job)
        where.append((i, mark))
    if args.resume:
        print(f"resuming: {kept} finished submission(s) kept, {len(jobs)} to grade")

    def finished(j: int, got: GradeReport | str) -> None:
        i, mark = where[j]
        if isinstance(got, str):
            errors[i] = got
            return
        _write_all(got, out / names[i])
        by_id = {c.id: c.points for c in got.criteria}
        # a name that is not UTF-8 (read with surrogateescape) is shown with U+FFFD
        row = [utf8_safe(entries[i].name), f"{got.score:g}", f"{got.max_score:g}",
               f"{got.percent:.1f}", *[f"{by_id[c]:g}" for c in ids],
               utf8_safe("; ".join(got.problems)[:500])]
        rows[i] = row
        if mark is not None:  # last: its presence says the folder is finished
            write_atomic(out / names[i] / "batch.json",
                         json.dumps({"fingerprint": mark, "summary": row}, indent=1) + "\n")

    grade_all(exercise, jobs, limits=limits, workers=args.workers, scheduler=args.scheduler,
              retries=args.retries, on_report=finished, progress=progress_stream())
    for i, entry in enumerate(entries):
        shown = utf8_safe(entry.name)
        if i in errors:
            rows[i] = [shown, "", f"{exercise.max_points:g}", "", *[""] * len(ids),
                       utf8_safe(f"grader infrastructure error: {errors[i]}")]
            print(utf8_safe(f"{shown}: grader infrastructure error: {errors[i]}"),
                  file=sys.stderr)
        else:
            row = rows[i]
            assert row is not None
            print(f"{shown}: {row[1]}/{row[2]}")
    buf = io.StringIO()
    writer = csv.writer(buf, lineterminator="\n")
    writer.writerow(["submission", "score", "max_score", "percent", *ids, "problems"])
    writer.writerows(r for r in rows if r is not None)
    write_atomic(out / "summary.csv", buf.getvalue())
    return 0
