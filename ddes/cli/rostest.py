"""``ddes rostest [--text] PKG FILE | PATH``: rostest on simulated time (docs/rostest.md).

The engine is :func:`ddes.console.rostest.run_rostest`; this is its shell command: the package
path is ``DDES_PACKAGE_PATH`` then ddes's bundled packages, each test's world is a
``ddes.World``, the results folder is ``--results-dir`` (default rostest's:
``ROS_TEST_RESULTS_DIR``, else ``ROS_HOME/test_results``, else ``~/.ros/test_results``), and
the exit code is rostest's (0 passed, 1 a test did not run or timed out, 2 tests failed).
"""

from __future__ import annotations

import argparse
import os
import sys

__all__ = ["register"]


def _main(args: argparse.Namespace) -> int:
    from ddes.console.rostest import run_rostest
    from ddes.rospack import RosPack, command_package_path
    from ddes.world import World

    rospack = RosPack(command_package_path(os.environ, os.getcwd()))
    def out(line: str) -> None:
        sys.stdout.write(line + "\n")

    def err(line: str) -> None:
        sys.stderr.write(line + "\n")

    report = run_rostest(args.argv, rospack=rospack, world_class=World, out=out, err=err,
                         environ=os.environ)
    return report.code


def register(sub: argparse._SubParsersAction[argparse.ArgumentParser]) -> None:
    """Add ``ddes rostest`` to the ``ddes`` command."""
    p = sub.add_parser(
        "rostest", add_help=False, prefix_chars="+",
        help="run a rostest file's <test>s on simulated time, a fresh world for each",
        description="rostest [--text] [--seed N] [--results-filename NAME] [--results-dir DIR] "
                    "PKG FILE | PATH [arg:=value ...]")
    p.add_argument("argv", nargs=argparse.REMAINDER)
    p.set_defaults(func=_main)
