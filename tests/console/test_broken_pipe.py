"""``ddes console ... | head`` ends quietly (issue 14, item 5).

A reader that goes away (``head -2``, or a pipe closed before anything is written) makes the
next write fail with EPIPE.  ``ddes console`` then ends as a shell shows a command killed by
SIGPIPE: exit 141, nothing on standard error, and the open recordings closed.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from ddes.rosbag import Bag

TIMEOUT = 120


def _env() -> dict[str, str]:
    env = {k: v for k, v in os.environ.items() if not k.startswith("DDES_")}
    env["DDES_HISTORY"] = ""
    return env


def _closed_early(args: list[str], cwd: Path, stdin: bytes = b"") -> tuple[int, bytes]:
    """Run ``ddes ARGS`` with standard output a pipe whose reader closed before it started."""
    read_end, write_end = os.pipe()
    os.close(read_end)
    try:
        proc = subprocess.run([sys.executable, "-m", "ddes.cli.main", *args], input=stdin,
                              stdout=write_end, stderr=subprocess.PIPE, cwd=cwd, env=_env(),
                              timeout=TIMEOUT)
    finally:
        os.close(write_end)
    return proc.returncode, proc.stderr


def test_a_script_into_a_closed_pipe(tmp_path: Path) -> None:
    (tmp_path / "s.txt").write_text("rostopic list\nrosnode list\n", encoding="utf-8")
    code, err = _closed_early(["console", "--script", "s.txt"], tmp_path)
    assert (code, err) == (141, b"")


def test_standard_input_into_a_closed_pipe(tmp_path: Path) -> None:
    code, err = _closed_early(["console"], tmp_path, stdin=b"rostopic list\n")
    assert (code, err) == (141, b"")


@pytest.mark.skipif(shutil.which("head") is None, reason="needs head(1) for the shell pipeline")
@pytest.mark.parametrize("how", ["--script s.txt", "< s.txt"])
def test_head_ends_it_quietly_and_the_recording_is_closed(tmp_path: Path, how: str) -> None:
    lines = ["rostopic pub -r 10 /chatter std_msgs/String 'data: hi' &",
             "rosbag record -O out /chatter &",
             "sleep 1"] + ["rossrv list"] * 600  # far more than a pipe holds
    (tmp_path / "s.txt").write_text("\n".join(lines) + "\n", encoding="utf-8")
    # head -5 leaves after the recording's own lines: it has started, whenever the pipe breaks
    pipeline = f"{sys.executable} -m ddes.cli.main console {how} | head -5"
    proc = subprocess.run(["bash", "-c", pipeline + '; echo "exit ${PIPESTATUS[0]}" >&2'],
                          capture_output=True, cwd=tmp_path, env=_env(), timeout=TIMEOUT)
    assert proc.stdout.decode().splitlines() == [
        "$ rostopic pub -r 10 /chatter std_msgs/String 'data: hi' &",
        "[1] rostopic pub -r 10 /chatter std_msgs/String 'data: hi'",
        "$ rosbag record -O out /chatter &",
        "[ INFO] [0.000000000]: Subscribing to /chatter",
        "[2] rosbag record -O out /chatter"]
    assert proc.stderr == b"exit 141\n"  # no traceback
    # closed on the way out: indexed and readable (how much it holds depends on when head left)
    assert Bag(str(tmp_path / "out.bag")).get_message_count("/chatter") <= 10
    assert not (tmp_path / "out.bag.active").exists()
