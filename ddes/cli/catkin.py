"""``ddes catkin_make ...`` and ``ddes catkin build ...``: build a catkin workspace's C++ nodes
against ddes's roscpp (:mod:`ddes.roscpp.catkin`; docs/roscpp.md, "Building with catkin").

Every argument after the command is catkin_make's (or catkin's), as ROS's command takes them;
the workspace is the current folder (``$PWD`` when it names it, as catkin_make reads it).
"""

from __future__ import annotations

import argparse
import os
import sys

__all__ = ["register"]


def _cwd() -> str:
    pwd = os.environ.get("PWD")
    try:
        if pwd and os.path.samefile(pwd, os.curdir):
            return pwd
    except OSError:
        pass
    return os.getcwd()


def _out(line: str) -> None:
    sys.stdout.write(line + "\n")
    sys.stdout.flush()


def _err(line: str) -> None:
    sys.stdout.flush()
    sys.stderr.write(line + "\n")
    sys.stderr.flush()


def _catkin_make(args: argparse.Namespace) -> int:
    from ddes.roscpp.catkin import catkin_make

    return catkin_make(args.argv, cwd=_cwd(), out=_out, err=_err)


def _catkin(args: argparse.Namespace) -> int:
    from ddes.roscpp.catkin import catkin_tool

    return catkin_tool(args.argv, cwd=_cwd(), out=_out, err=_err)


def register(sub: argparse._SubParsersAction[argparse.ArgumentParser]) -> None:
    """Add ``ddes catkin_make`` and ``ddes catkin`` to the ``ddes`` command."""
    p = sub.add_parser(
        "catkin_make", add_help=False, prefix_chars="+",
        help="build a catkin workspace's C++ nodes against ddes's roscpp (catkin_make)",
        description="catkin_make [-C DIR] [-j N] [--pkg PKG ...] [-DVAR=VALUE ...] "
                    "[--force-cmake] [--timeout SECONDS] [--make-args ...] [targets]")
    p.add_argument("argv", nargs=argparse.REMAINDER)
    p.set_defaults(func=_catkin_make)
    c = sub.add_parser(
        "catkin", add_help=False, prefix_chars="+",
        help="catkin_tools' catkin build / clean / init, on ddes's catkin",
        description="catkin build [PKG ...] [-j N] [--no-deps] [--force-cmake] | catkin clean "
                    "| catkin init")
    c.add_argument("argv", nargs=argparse.REMAINDER)
    c.set_defaults(func=_catkin)
