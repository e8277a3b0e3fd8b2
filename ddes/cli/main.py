"""Entry point of the ``ddes`` command."""

from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence

import ddes
from ddes.errors import DdesError

__all__ = ["build_parser", "main"]


def build_parser() -> argparse.ArgumentParser:
    """The argument parser; ROS tool subcommands register here as they land."""
    parser = argparse.ArgumentParser(
        prog="ddes",
        description="Deterministic discrete-event ROS 1 testbed on simulated time.",
    )
    parser.add_argument("--version", action="version", version=f"ddes {ddes.__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    demo = sub.add_parser("demo", help="run the guided demo and print its trace digest")
    demo.add_argument("--seed", type=int, default=0, help="world seed (default 0)")
    demo.add_argument("--until", type=float, default=2.0, help="simulated seconds (default 2)")
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Run the ``ddes`` command; returns the exit code."""
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        if args.command == "demo":
            from ddes.cli.demo import run_demo

            run_demo(seed=args.seed, until=args.until)
            return 0
        parser.print_help()
        return 0
    except DdesError as exc:
        print(f"ERROR: {exc}", file=sys.stderr)
        return 1


if __name__ == "__main__":
    sys.exit(main())
