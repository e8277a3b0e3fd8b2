"""Shared fixtures: strict worlds, and a runner for real ROS 1 (system Python).

``world`` (a fresh ``ddes.World`` on ``--ddes-seed``, 0 by default) and ``ddes_seed`` come from
ddes's own pytest plugin (ddes/testing/pytest_plugin.py), which pytest loads wherever ddes is
installed; the console tests' ``console`` (tests/console/conftest.py) builds on ``ddes_seed``.

Tests marked ``ros`` compare ddes with real ROS 1 Noetic (Debian packages,
which run under Debian's system Python, not the virtual environment).  The
``ros_python`` fixture runs a script there and returns its stdout; it skips
the test cleanly when ROS is not installed.
"""

from __future__ import annotations

import functools
import json
import os
import shutil
import subprocess
from collections.abc import Callable
from typing import Any

import pytest
from hypothesis import HealthCheck, settings

# Simulated time makes every test deterministic, but the 2-core CI machine's
# wall-clock speed is not: no per-example deadlines, no "too slow" checks.
settings.register_profile(
    "ddes", deadline=None, suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large]
)
settings.load_profile("ddes")


@pytest.fixture(autouse=True, scope="session")
def _strict_worlds() -> Any:
    """The suite's worlds are strict: an assertion failing inside a callback fails its test.

    Tests of rospy's default rule (log and go on) say ``World(strict=False)``.
    """
    from ddes.graph.failures import strict_worlds

    with strict_worlds():
        yield


def _system_python() -> str | None:
    rosbag = shutil.which("rosbag")
    if rosbag:
        with open(rosbag, encoding="utf-8", errors="replace") as f:
            first = f.readline().strip()
        if first.startswith("#!"):
            interp = first[2:].split()[0]
            if os.path.exists(interp):
                return interp
    return "/usr/bin/python3" if os.path.exists("/usr/bin/python3") else None


@functools.lru_cache(maxsize=1)
def ros_interpreter() -> str | None:
    """Debian's python with rospy/genpy importable, or None."""
    interp = _system_python()
    if interp is None:
        return None
    probe = subprocess.run(
        [interp, "-c", "import genpy, genmsg, rospy, rosbag, actionlib"],
        capture_output=True,
        timeout=60,
    )
    return interp if probe.returncode == 0 else None


@pytest.fixture
def ros_python() -> Callable[..., Any]:
    """Run a Python script under real ROS 1; returns stdout (or JSON with as_json=True)."""
    interp = ros_interpreter()
    if interp is None:
        pytest.skip("real ROS 1 Noetic is not installed (bash .ci/install-ros installs it)")

    def run(script: str, *, as_json: bool = False, stdin: str | None = None,
            timeout: float = 120) -> Any:
        env = {k: v for k, v in os.environ.items() if not k.startswith("PYTHON")}
        proc = subprocess.run(
            [interp, "-c", script], capture_output=True, text=True, input=stdin,
            timeout=timeout, env=env,
        )
        if proc.returncode != 0:
            raise AssertionError(f"ROS reference script failed:\n{proc.stderr}")
        return json.loads(proc.stdout) if as_json else proc.stdout

    return run

