"""Entry point of the ``ddes`` command."""

from __future__ import annotations

import argparse
import importlib
import os
import sys
from collections.abc import Sequence

import ddes
from ddes.errors import DdesError

__all__ = ["COMMAND_MODULES", "EXIT_BROKEN_PIPE", "build_parser", "main"]

#: Exit code when standard output is a pipe whose reader has gone (``| head``): 128 + SIGPIPE,
#: what a shell shows for a command ended by SIGPIPE; no traceback is printed.
EXIT_BROKEN_PIPE = 141

#: Modules adding a ROS tool subcommand.  Each provides ``register(subparsers)``,
#: which adds its parser and sets ``func`` (args -> exit code) with
#: ``set_defaults``; a new tool is one more line here.
COMMAND_MODULES: tuple[str, ...] = (
    "ddes.console.rosmsg",
    "ddes.console.rosbag",
    "ddes.cli.console",
    "ddes.cli.run",
    "ddes.cli.rostest",
    "ddes.cli.catkin",
    "ddes.cli.grade",
    "ddes.cli.course",
    "ddes.console.viz",
)


def build_parser() -> argparse.ArgumentParser:
    """The argument parser; ROS tool subcommands register here as they land."""
    return _build()[0]


def _build() -> tuple[argparse.ArgumentParser, list[str]]:
    """The parser and its command names, in the order ``ddes -h`` lists them."""
    parser = argparse.ArgumentParser(
        prog="ddes",
        description="Deterministic discrete-event ROS 1 testbed on simulated time.",
    )
    parser.add_argument("--version", action="version", version=f"ddes {ddes.__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    demo = sub.add_parser("demo", help="run the guided demo and print its trace digest")
    demo.add_argument("--seed", type=int, default=0, help="world seed (default 0)")
    demo.add_argument("--until", type=float, default=2.0,
                      help="simulated seconds of the first part (default 2)")
    demo.add_argument("--pictures", metavar="DIR", default=None,
                      help="folder for the robot's top view (default: a new temporary folder)")
    for name in COMMAND_MODULES:
        importlib.import_module(name).register(sub)
    return parser, list(sub.choices)


def main(argv: Sequence[str] | None = None) -> int:
    """Run the ``ddes`` command; returns the exit code (141 when standard output is a closed
    pipe: ``ddes rosbag info x.bag | head -1`` ends quietly)."""
    parser, commands = _build()
    args = parser.parse_args(argv)
    try:
        if args.command == "demo":
            from ddes.cli.demo import run_tour

            run_tour(seed=args.seed, until=args.until, pictures=args.pictures)
            return 0
        if getattr(args, "func", None) is not None:
            return int(args.func(args))
    except BrokenPipeError:  # `ddes ... | head`: the reader left; end quietly, as a shell shows
        _silence_stdout()
        return EXIT_BROKEN_PIPE
    except DdesError as exc:
        print(f"ERROR: {exc}", file=sys.stderr)
        return 1
    # No command: the usage and an error on stderr, exit 2, as argparse does for any missing
    # argument (``ddes -h`` prints the help and exits 0).
    parser.error(f"a command is required: {', '.join(commands)} ('ddes -h' says more)")


def _silence_stdout() -> None:
    """Point standard output at /dev/null so the interpreter's last flush cannot fail."""
    try:
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        os.close(devnull)
    except (OSError, ValueError):
        pass


if __name__ == "__main__":
    sys.exit(main())
