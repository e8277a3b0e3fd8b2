"""``ddes course build [--check]``: regenerate ``exercises/`` from ``solutions/``;
``ddes course make-bag [PATH] [--seed N]``: write the localisation exercise's kit bag.

Solution blocks (``### BEGIN SOLUTION`` … ``### END SOLUTION``) become stubs
(:mod:`ddes.grading.starter`).  With ``--check`` nothing is written and the exit status is 1
when a file of ``exercises/`` is out of date (each is named), 0 when all are current.

``make-bag`` drives the simulator (seed 2021 unless ``--seed``) and records
``smb_navigation.bag`` (default: ``./smb_navigation.bag``), the same bytes on every run
(:mod:`ddes.grading.kitbag`); ``--plot PNG`` also draws robot_localization's EKF on it against
the simulator's ground truth (docs/localization.md).
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

__all__ = ["register", "run_course"]


def register(sub: argparse._SubParsersAction[argparse.ArgumentParser]) -> None:
    p = sub.add_parser("course", help="course tools: build exercises/ from solutions/",
                       description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("action", choices=["build", "make-bag"],
                   help="build: regenerate the starter code; make-bag: write the kit bag")
    p.add_argument("exercise", nargs="*",
                   help="only these exercises (default: all); make-bag: the bag's path")
    p.add_argument("--seed", type=int, default=None,
                   help="make-bag: the drive's seed (default: 2021, the kit's)")
    p.add_argument("--plot", metavar="PNG", default=None,
                   help="make-bag: also plot the EKF's x/y on the bag against the simulator's "
                        "ground truth")
    p.add_argument("--check", action="store_true",
                   help="write nothing; exit 1 naming every out-of-date file")
    p.add_argument("--root", default=".", help="the repository root (default: .)")
    p.set_defaults(func=run_course)


def run_course(args: argparse.Namespace) -> int:
    from ddes.errors import GradingError

    if args.action == "make-bag":
        return _make_bag(args)
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


def _make_bag(args: argparse.Namespace) -> int:
    from ddes.errors import DdesError
    from ddes.grading.kitbag import KIT_SEED, make_bag, plot_localization

    if len(args.exercise) > 1:
        print("ddes course make-bag: give one path, got " + " ".join(args.exercise),
              file=sys.stderr)
        return 2
    path = args.exercise[0] if args.exercise else "smb_navigation.bag"
    seed = KIT_SEED if args.seed is None else args.seed
    try:
        kit = make_bag(path, seed)
    except (DdesError, OSError) as exc:
        print(f"ddes course make-bag: {exc}", file=sys.stderr)
        return 2
    counts = ", ".join(f"{topic} {n}" for topic, n in kit.counts.items())
    print(f"wrote {path} (seed {seed}): {counts}")
    if args.plot:
        e = plot_localization(kit, args.plot)
        print(f"wrote {args.plot}: EKF position error vs ground truth final {e.ekf_final:.3f} m, "
              f"max {e.ekf_max:.3f} m; wheel odometry final {e.odom_final:.3f} m, "
              f"max {e.odom_max:.3f} m")
    return 0
