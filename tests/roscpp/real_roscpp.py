"""Real roscpp (Debian's Noetic) as the oracle: build a package with real catkin_make and run
its executables on a private roscore, for tests marked ``ros``.

Nothing here runs unless the test asks; :func:`available` says whether Debian's catkin,
roscpp's headers and roscore are installed.
"""

from __future__ import annotations

import os
import shutil
import signal
import socket
import subprocess
import time
from collections.abc import Sequence
from pathlib import Path

#: What real catkin_make and the real nodes run with: Debian's Python and tools first.
ENV_PATH = "/usr/bin:/bin"


def available() -> bool:
    return (Path("/usr/include/ros/ros.h").is_file() and shutil.which("catkin_make") is not None
            and shutil.which("roscore") is not None)


def build(src_packages: Sequence[Path], workspace: Path, targets: Sequence[str]) -> Path:
    """Copy the packages into ``workspace/src`` and build ``targets`` with real catkin_make;
    returns the devel space."""
    src = workspace / "src"
    src.mkdir(parents=True, exist_ok=True)
    for pkg in src_packages:
        dest = src / pkg.name
        if not dest.exists():
            shutil.copytree(pkg, dest)
    env = dict(os.environ, PATH=ENV_PATH, PWD=str(workspace.absolute()))
    for k in list(env):
        if k.startswith("PYTHON") or k in ("VIRTUAL_ENV", "ROS_PACKAGE_PATH", "CMAKE_PREFIX_PATH"):
            env.pop(k)
    proc = subprocess.run(["catkin_make", "-DPYTHON_EXECUTABLE=/usr/bin/python3", *targets],
                          cwd=workspace, env=env, capture_output=True, text=True, timeout=900)
    if proc.returncode != 0:
        raise AssertionError(f"real catkin_make failed:\n{proc.stdout[-4000:]}\n{proc.stderr[-4000:]}")
    return workspace / "devel"


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


def run(devel: Path, package: str, commands: Sequence[Sequence[str]], *, seconds: float,
        params: dict[str, str] | None = None) -> list[list[str]]:
    """Run each command (an executable of ``package`` and its arguments) on a private roscore,
    one after the other with a short pause, for ``seconds``; SIGINT, then each one's stdout
    lines (a command that ends by itself ends the wait early, when it is the last)."""
    port = _free_port()
    env = dict(os.environ, PATH=ENV_PATH, ROS_MASTER_URI=f"http://127.0.0.1:{port}",
               ROS_HOSTNAME="127.0.0.1", ROS_HOME=str(devel.parent / "ros_home"))
    for k in list(env):
        if k.startswith("PYTHON") or k == "VIRTUAL_ENV":
            env.pop(k)
    core = subprocess.Popen(["roscore", "-p", str(port)], env=env, stdout=subprocess.DEVNULL,
                            stderr=subprocess.DEVNULL, start_new_session=True)
    procs: list[subprocess.Popen[str]] = []
    try:
        deadline = time.monotonic() + 30
        while time.monotonic() < deadline:
            probe = subprocess.run(["rosparam", "list"], env=env, capture_output=True, timeout=30)
            if probe.returncode == 0:
                break
            time.sleep(0.2)
        for key, value in (params or {}).items():
            subprocess.run(["rosparam", "set", key, value], env=env, check=True, timeout=30)
        for cmd in commands:
            exe = devel / "lib" / package / cmd[0]
            procs.append(subprocess.Popen([str(exe), *cmd[1:]], env=env, stdout=subprocess.PIPE,
                                          stderr=subprocess.STDOUT, text=True,
                                          start_new_session=True))
            time.sleep(0.5)
        end = time.monotonic() + seconds
        while time.monotonic() < end:
            if procs[-1].poll() is not None:
                break
            time.sleep(0.1)
        out: list[list[str]] = []
        for p in procs:
            if p.poll() is None:
                p.send_signal(signal.SIGINT)
        for p in procs:
            try:
                text, _ = p.communicate(timeout=20)
            except subprocess.TimeoutExpired:
                p.kill()
                text, _ = p.communicate()
            out.append(text.splitlines())
        return out
    finally:
        for p in procs:
            if p.poll() is None:
                p.kill()
        os.killpg(core.pid, signal.SIGINT)
        try:
            core.wait(timeout=20)
        except subprocess.TimeoutExpired:
            os.killpg(core.pid, signal.SIGKILL)
            core.wait()
