"""``ddes course build [--check]``: regenerate ``exercises/`` from ``solutions/``.

Solution blocks (``### BEGIN SOLUTION`` … ``### END SOLUTION``) become stubs
(:mod:`ddes.grading.starter`).  With ``--check`` nothing is written and the exit status is 1
when a file of ``exercises/`` is out of date (each is named), 0 when all are current.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

__all__ = ["register", "run_course"]


def register(sub: argparse._SubParsersAction[argparse.ArgumentParser]) -> None:
    p = sub.add_parser("course", help="course tools: build exercises/ from solutions/",
                       description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("action", choices=["build"], help="build: regenerate the starter code")
    p.add_argument("exercise", nargs="*", help="only these exercises (default: all)")
    p.add_argument("--check", action="store_true",
                   help="write nothing; exit 1 naming every out-of-date file")
    p.add_argument("--root", default=".", help="the repository root (default: .)")
    p.set_defaults(func=run_course)


def run_course(args: argparse.Namespace) -> int:
    from ddes.errors import GradingError
    from ddes.grading.starter import build

    root = Path(args.root)
    try:
        changed = build(root / "solutions", root / "exercises", check=args.check,
                        only=list(args.exercise) or None)
    except GradingError as exc:
        print(f"ddes course: {exc}", file=sys.stderr)
        return 2
    if args.check:
        for rel in changed:
            print(f"out of date: exercises/{rel}")
        if changed:
            print("run 'ddes course build' to regenerate exercises/ from solutions/",
                  file=sys.stderr)
            return 1
        print("exercises/ is up to date")
        return 0
    for rel in changed:
        print(f"wrote exercises/{rel}")
    print(f"{len(changed)} file(s) changed")
    return 0
