"""``ddes console``: the entry point of the console (the engine is :mod:`ddes.console`)."""

from __future__ import annotations

import argparse
import os
import sys
from pathlib import Path

from ddes.console.shell import interact, run_script
from ddes.errors import ROSConsoleError

__all__ = ["main", "register"]


def _history_file() -> str | None:
    path = os.environ.get("DDES_HISTORY")
    if path is not None:
        return path or None
    home = os.path.expanduser("~")
    return os.path.join(home, ".ddes_history") if os.path.isdir(home) else None


def main(args: argparse.Namespace) -> int:
    """``ddes console [--script FILE] [--keep-going] [--seed N] [--no-core]``."""
    from ddes.rospack import env_package_path
    from ddes.world import Console, World

    # The one place the environment is read: when the command starts.
    world = World(seed=args.seed, package_path=env_package_path(os.environ))
    console = Console(world, core=not args.no_core)

    def write(text: str) -> None:
        sys.stdout.write(text + "\n")
        sys.stdout.flush()

    if args.script is not None:
        path = Path(args.script)
        try:
            text = path.read_text(encoding="utf-8")
        except OSError as exc:
            raise ROSConsoleError(f"cannot read script {args.script}: {exc.strerror}") from None
        return run_script(console, text.splitlines(), write, keep_going=args.keep_going)
    if not sys.stdin.isatty():
        return run_script(console, sys.stdin, write, keep_going=args.keep_going)
    return interact(console, _history_file())


def register(sub: argparse._SubParsersAction[argparse.ArgumentParser]) -> None:
    """Add ``ddes console`` to the ``ddes`` command."""
    p = sub.add_parser("console", help="interactive ROS console on a simulated roscore",
                       description="A roscore on simulated time with rosrun, roslaunch, "
                                   "rostopic, rosnode, rosparam ... in one shell.")
    p.add_argument("--script", metavar="FILE", default=None,
                   help="run the commands of FILE and print a transcript")
    p.add_argument("--keep-going", "-k", action="store_true",
                   help="in a script, go on after a failing command (exit 1 at the end)")
    p.add_argument("--seed", type=int, default=0, help="world seed (default 0)")
    p.add_argument("--no-core", action="store_true",
                   help="start without the /rosout node and roscore's parameters")
    p.set_defaults(func=main)
