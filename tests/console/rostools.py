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

__all__ = ["ROSBASH", "real_tool", "ros_env", "run_real"]

#: rosbash's shell functions (roscd, rosed, ...), as Debian installs them.
ROSBASH = "/usr/share/bash-completion/completions/rosbash"


def real_tool(name: str) -> str:
    """The path of the real ROS tool ``name``; skips the test when it is not installed."""
    exe = shutil.which(name)
    if exe is None:
        pytest.skip(f"the real {name} is not installed (bash .ci/install-ros installs it)")
    return exe


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
