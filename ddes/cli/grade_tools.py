"""The instructor's and student's tools of ``ddes grade`` (docs/grading.md):

* ``ddes grade replay EXERCISE SUBMISSION --scenario NAME [--seed N] [--trace FILE]
  [--bag FILE] [--picture FILE]``: one scenario again, exactly (same digest as in the grade);
* ``ddes grade sweep EXERCISE SUBMISSION --seeds A:B [--out DIR] [--figure FILE]
  [--fail-under PCT]``: the score over seeds (``--out``: every seed's grade files, summary.csv,
  the text and the histogram in DIR);
* ``ddes grade sensitivity EXERCISE [--solutions DIR] [--seed N]``: the mutants' kill matrix;
* ``ddes grade operators EXERCISE [--solutions DIR] [--sample N] [--seed S] [--jobs J]
  [--min-rate PCT]``: the operator sweep's kill rate (ddes/grading/operators.py);

both on the engine of ``ddes grade batch`` (``--workers N``, ``--scheduler ADDRESS``,
``--retries R``: one task per (seed or mutant, scenario));

and the hidden-scenario key of every grade: ``--secret-file FILE`` (or ``$DDES_GRADE_SECRET``),
``--student ID`` (default: the submission's name), ``--attempt K`` (default 0).
"""

from __future__ import annotations

import argparse
import re
import sys
from collections.abc import Callable
from pathlib import Path
from typing import Any

from ddes.errors import GradingError

__all__ = ["TOOLS", "add_arguments", "hidden_key", "progress_stream"]


def add_arguments(p: argparse.ArgumentParser) -> None:
    """The options of replay, sweep, sensitivity and the hidden-scenario key."""
    p.add_argument("--scenario", metavar="NAME", help="replay: the scenario to run again")
    p.add_argument("--trace", metavar="FILE", help="replay: write the trace (JSON lines)")
    p.add_argument("--bag", metavar="FILE", help="replay: write a bag (.bag or .mcap)")
    p.add_argument("--picture", metavar="FILE",
                   help="replay: write a picture of what the criteria judged (PNG): the "
                        "top view, the exercise's time panels, the topic rates")
    p.add_argument("--seeds", metavar="A:B", help="sweep: the seeds A, A+1, ..., B-1")
    p.add_argument("--figure", metavar="FILE", help="sweep: write a histogram of the scores (PNG)")
    p.add_argument("--solutions", metavar="DIR", default="solutions",
                   help="sensitivity: where <exercise>/ and <exercise>/mutants/ are "
                        "(default solutions)")
    p.add_argument("--sample", type=int, default=None, metavar="N",
                   help="operators: grade an evenly spaced sample of N mutants (drawn with "
                        "--seed)")
    p.add_argument("--jobs", type=int, default=0, metavar="J",
                   help="operators: grade on J worker processes (--workers J)")
    p.add_argument("--min-rate", type=float, default=95.0, metavar="PCT",
                   help="operators: exit 1 when the kill rate is below PCT percent "
                        "(default 95)")
    p.add_argument("--secret-file", metavar="FILE",
                   help="the course secret hidden scenarios derive from (else "
                        "$DDES_GRADE_SECRET; without either, the open default scenarios)")
    p.add_argument("--student", metavar="ID",
                   help="the student hidden scenarios derive from (default: the submission's "
                        "name)")
    p.add_argument("--attempt", type=int, default=0, metavar="K",
                   help="the attempt hidden scenarios derive from (default 0)")


def progress_stream() -> Any:
    """Where batch, sweep and sensitivity draw their progress bar: standard error when it is a
    terminal (else nowhere)."""
    return sys.stderr if sys.stderr.isatty() else None


def _engine(args: argparse.Namespace) -> dict[str, Any]:
    """The grading engine's options (ddes.grading.batch.grade_all): serial or on Dask."""
    if args.workers and args.scheduler:
        raise GradingError("give --workers N or --scheduler ADDRESS, not both")
    return {"workers": args.workers, "scheduler": args.scheduler, "retries": args.retries,
            "bar": progress_stream()}


def hidden_key(args: argparse.Namespace, submission: str | Path) -> Any:
    """The :class:`HiddenKey` of a grade, or None when no secret is given."""
    from ddes.grading.scenarios import HiddenKey, read_secret

    secret = read_secret(args.secret_file)
    if secret is None:
        if args.student is not None or args.attempt:
            raise GradingError("--student/--attempt choose hidden scenarios from the course "
                               "secret: give --secret-file FILE or set $DDES_GRADE_SECRET")
        return None
    if args.attempt < 0:
        raise GradingError(f"--attempt {args.attempt}: give an integer >= 0")
    student = args.student if args.student is not None else _name_of(submission)
    if not student or "/" in student:
        raise GradingError(f"--student {student!r}: give an id without '/'")
    return HiddenKey(secret=secret, student=student, attempt=args.attempt)


def _name_of(submission: str | Path) -> str:
    path = Path(submission)
    name = path.resolve().name if path.name in ("", ".", "..") else path.name
    return re.sub(r"\.(zip|ipynb)$", "", name)


def _replay(registry: Any, words: list[str], args: argparse.Namespace, limits: Any) -> int:
    from ddes.grading.replay import replay

    if len(words) != 2 or not args.scenario:
        raise GradingError("usage: ddes grade replay EXERCISE SUBMISSION --scenario NAME "
                           "[--seed N] [--trace FILE] [--bag FILE] [--picture FILE]")
    exercise = registry.get(words[0])
    result = replay(exercise, words[1], args.scenario, seed=args.seed,
                    key=hidden_key(args, words[1]), limits=limits, trace=args.trace,
                    bag=args.bag, picture=args.picture)
    sys.stdout.write(result.to_text())
    return 0


def _seeds(text: str | None) -> range:
    m = re.fullmatch(r"(\d+):(\d+)", (text or "").strip())
    if m is None or int(m.group(2)) <= int(m.group(1)):
        raise GradingError(f"--seeds {text!r}: give A:B with 0 <= A < B (the seeds A..B-1)")
    return range(int(m.group(1)), int(m.group(2)))


def _sweep(registry: Any, words: list[str], args: argparse.Namespace, limits: Any) -> int:
    from ddes.grading.sweep import sweep

    if len(words) != 2 or not args.seeds:
        raise GradingError("usage: ddes grade sweep EXERCISE SUBMISSION --seeds A:B "
                           "[--out DIR] [--figure FILE] [--fail-under PCT]")
    exercise = registry.get(words[0])
    result = sweep(exercise, words[1], _seeds(args.seeds), public=args.public, limits=limits,
                   key=hidden_key(args, words[1]),
                   progress=lambda line: print(line, file=sys.stderr), **_engine(args))
    sys.stdout.write(result.to_text(fail_under=args.fail_under))
    if args.figure:
        result.figure().savefig(args.figure, dpi=100)
        print(f"wrote histogram: {args.figure}")
    if args.out:
        written = result.write(args.out, fail_under=args.fail_under)
        print(f"wrote {len(written)} files to {args.out}: summary.csv, sweep.txt, "
              f"histogram.png and seed_N/ (results.json, junit.xml, report.txt) per seed")
    if result.errors:
        print(f"{len(result.errors)} seed(s) not graded: grader infrastructure error",
              file=sys.stderr)
        return 1
    if args.fail_under is not None and result.below(args.fail_under):
        print(f"{len(result.below(args.fail_under))} seed(s) below --fail-under "
              f"{args.fail_under:g} %", file=sys.stderr)
        return 1
    return 0


def _sensitivity(registry: Any, words: list[str], args: argparse.Namespace, limits: Any) -> int:
    from ddes.grading.mutants import sensitivity

    if len(words) != 1:
        raise GradingError("usage: ddes grade sensitivity EXERCISE [--solutions DIR] [--seed N]")
    exercise = registry.get(words[0])
    result = sensitivity(exercise, Path(args.solutions), seed=args.seed, limits=limits,
                         progress=lambda line: print(line, file=sys.stderr), **_engine(args))
    sys.stdout.write(result.to_text())
    return 0 if result.ok else 1


def _operators(registry: Any, words: list[str], args: argparse.Namespace, limits: Any) -> int:
    from ddes.grading.operators import sweep

    if len(words) != 1:
        raise GradingError("usage: ddes grade operators EXERCISE [--solutions DIR] [--sample N] "
                           "[--seed S] [--jobs J] [--min-rate PCT]")
    if args.sample is not None and args.sample < 1:
        raise GradingError(f"--sample {args.sample}: give N >= 1")
    if args.jobs < 0:
        raise GradingError(f"--jobs {args.jobs}: give J >= 0")
    if args.jobs and args.workers and args.jobs != args.workers:
        raise GradingError("give --jobs J or --workers N, not both")
    engine = _engine(args)
    engine["workers"] = args.jobs or args.workers
    if engine["workers"] and args.scheduler:
        raise GradingError("give --jobs J or --scheduler ADDRESS, not both")
    exercise = registry.get(words[0])
    result = sweep(exercise, Path(args.solutions), n=args.sample, sample_seed=args.seed,
                   seed=args.seed, limits=limits, min_rate=args.min_rate,
                   progress=lambda line: print(line, file=sys.stderr), **engine)
    sys.stdout.write(result.to_text())
    for name in result.wrong_equivalents:
        print(f"{name} is listed as equivalent in operators.yaml but was killed",
              file=sys.stderr)
    if not result.reference_ok:
        print("the reference does not get full points: fix the solution or the grader first",
              file=sys.stderr)
    if result.rate < result.min_rate:
        print(f"kill rate {result.rate:.1f} % is below --min-rate {result.min_rate:g} %",
              file=sys.stderr)
    return 0 if result.ok else 1


def _no_out(tool: Callable[[Any, list[str], argparse.Namespace, Any], int], name: str,
            instead: str) -> Callable[[Any, list[str], argparse.Namespace, Any], int]:
    """``tool``, refusing ``--out`` (which it would otherwise ignore without a word)."""
    def run(registry: Any, words: list[str], args: argparse.Namespace, limits: Any) -> int:
        if getattr(args, "out", None):
            raise GradingError(f"{name} writes no folder: leave out --out ({instead})")
        return tool(registry, words, args, limits)
    return run


#: ``ddes grade WORD ...`` -> its function ``(registry, words after WORD, args, limits)``.
TOOLS: dict[str, Callable[[Any, list[str], argparse.Namespace, Any], int]] = {
    "replay": _no_out(_replay, "replay", "it writes --trace FILE, --bag FILE, --picture FILE"),
    "sweep": _sweep,
    "sensitivity": _no_out(_sensitivity, "sensitivity", "it prints the kill matrix"),
    "operators": _no_out(_operators, "operators", "it prints the kill rate")}
