"""Run the real ROS 1 command-line tools (rospack, rosmsg, roscore, rosbash's roscd).

For the interop tests of the console's own tools: each test that uses these
asks for the ``ros_python`` fixture first, which skips it cleanly where ROS
is not installed; :func:`real_tool` skips it where a single tool is missing.
"""

from __future__ import annotations

import os
import shutil
import subprocess
from pathlib import Path

import pytest

from ddes.rospack import BUNDLED_PATH

__all__ = ["ONE_COPY_OF_EACH_PACKAGE", "ROSBASH", "real_python_tool", "real_tool", "ros_env",
           "run_real"]

#: rosbash's shell functions (roscd, rosed, ...), as Debian installs them.
ROSBASH = "/usr/share/bash-completion/completions/rosbash"

#: Python that a real ROS tool runs first, so that it sees one copy of each package: the one on
#: ``ROS_PACKAGE_PATH``.  rosmsg reads a package's ``msg/`` folder where rospack finds the
#: package *and* in the first catkin workspace holding ``share/PKG``.  Upstream catkin's
#: workspaces are the ``CMAKE_PREFIX_PATH`` entries with a ``.catkin`` marker (a
#: :func:`ros_env` has none), but Debian's catkin always adds ``/usr``: there, with
#: ``ros-std-msgs`` or ``ros-geometry-msgs`` installed, ``/usr/share/std_msgs/msg`` is a second
#: copy of a package ddes bundles, and ``rosmsg show String`` or ``rosmsg md5 Twist`` print
#: their type twice.  On a ROS install the two lookups find one tree, and ddes, which reads
#: only the package path, prints each type once, as rosmsg does there.  With no such Debian
#: package installed this changes nothing.
ONE_COPY_OF_EACH_PACKAGE = r"""
import os as _os
import catkin.find_in_workspaces as _fiw
from catkin.workspace import CATKIN_MARKER_FILE as _MARKER

def _upstream_workspaces():
    paths = _os.environ.get("CMAKE_PREFIX_PATH", "").split(_os.pathsep)
    return [p for p in paths if p and _os.path.isfile(_os.path.join(p, _MARKER))]

_fiw.get_workspaces = _upstream_workspaces
"""

_RUN_TOOL = ONE_COPY_OF_EACH_PACKAGE + r"""
import runpy, sys
sys.argv = sys.argv[1:]
runpy.run_path(sys.argv[0], run_name="__main__")
"""


def real_tool(name: str) -> str:
    """The path of the real ROS tool ``name``; skips the test when it is not installed."""
    exe = shutil.which(name)
    if exe is None:
        pytest.skip(f"the real {name} is not installed (bash .ci/install-ros installs it)")
    return exe


def real_python_tool(name: str) -> list[str]:
    """The command line (before the tool's arguments) that runs the real Python tool ``name``
    (rosmsg, rossrv) under its own interpreter, seeing one copy of each package (see
    :data:`ONE_COPY_OF_EACH_PACKAGE`); skips the test when the tool is not installed."""
    exe = real_tool(name)
    with open(exe, encoding="utf-8", errors="replace") as f:
        first = f.readline()
    interp = first[2:].split()[0] if first.startswith("#!") and first[2:].split() else None
    if interp is None or not os.path.exists(interp):
        pytest.skip(f"the real {name} is not a Python script with an interpreter here")
    return [interp, "-c", _RUN_TOOL, exe]


def ros_env(home: Path, package_path: list[Path] | None = None, **extra: str) -> dict[str, str]:
    """The environment of a real tool: its own ROS_HOME, ddes's packages first on the path."""
    env = {k: v for k, v in os.environ.items()
           if not k.startswith(("PYTHON", "ROS_", "CMAKE_PREFIX_PATH"))}
    paths = [*(package_path or []), BUNDLED_PATH]
    env.update(ROS_HOME=str(home), ROS_PACKAGE_PATH=os.pathsep.join(str(p) for p in paths),
               **extra)
    return env


def run_real(argv: list[str], env: dict[str, str], cwd: Path | None = None,
             stdin: str = "") -> tuple[int, str, str]:
    """Run a real tool: ``(exit code, stdout, stderr)``."""
    proc = subprocess.run(argv, capture_output=True, text=True, env=env, cwd=cwd, input=stdin,
                          timeout=120)
    return proc.returncode, proc.stdout, proc.stderr
