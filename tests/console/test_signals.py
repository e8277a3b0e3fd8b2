"""Recordings survive every way a console session ends (issue 13, item 3).

A ``ddes console`` reading commands from a pipe records ``/chatter`` at 100 Hz
for 2 simulated seconds (200 messages), prints a marker, then waits for the
next line; the test then ends the session: end of script, end of input
(Ctrl+D), SIGINT, SIGTERM, SIGKILL.  Every ending but SIGKILL leaves a
complete ``out.bag``; SIGKILL leaves ``out.bag.active`` whose chunks (the
console flushes after each command) ``rosbag reindex`` recovers.  Interactive
Ctrl+C stops only the foreground command and says so.
"""

from __future__ import annotations

import os
import queue
import signal
import subprocess
import sys
import threading
from pathlib import Path

import pytest

from ddes.console.shell import Console
from ddes.rosbag import Bag
from ddes.rosbag.recorder import open_recordings

SCRIPT = """rostopic pub -r 100 /chatter std_msgs/String "data: hello" &
rosbag record --chunksize 1 -O out /chatter &
sleep 2
time
"""
MARKER = "simulated time: 2.000000000 s"
EXPECTED = 200  # 100 Hz for 2 s, the first one at 0.01 s (the connection is up)
TIMEOUT = 60


def _env() -> dict[str, str]:
    env = dict(os.environ)
    env.pop("DDES_HISTORY", None)
    env["DDES_HISTORY"] = ""
    return env


def _start(cwd: Path, *args: str) -> subprocess.Popen[str]:
    return subprocess.Popen([sys.executable, "-m", "ddes.cli.main", "console", *args],
                            stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True, cwd=cwd, env=_env())


def _wait_for(proc: subprocess.Popen[str], marker: str) -> list[str]:
    """Lines of stdout up to the marker (a reader thread: never blocks past TIMEOUT)."""
    lines: queue.Queue[str | None] = queue.Queue()

    def reader() -> None:
        assert proc.stdout is not None
        for line in proc.stdout:
            lines.put(line.rstrip("\n"))
            if marker in line:
                return
        lines.put(None)

    threading.Thread(target=reader, daemon=True).start()
    seen: list[str] = []
    while True:
        try:
            line = lines.get(timeout=TIMEOUT)
        except queue.Empty:
            proc.kill()
            raise AssertionError(f"no {marker!r} within {TIMEOUT} s; got {seen}") from None
        if line is None:
            proc.kill()
            err = proc.stderr.read() if proc.stderr else ""
            raise AssertionError(f"the console ended before {marker!r}: {seen}\n{err}")
        seen.append(line)
        if marker in line:
            return seen


def _finish(proc: subprocess.Popen[str]) -> tuple[int, str]:
    """Wait for the exit (stdin stays as it is: closing it would be an end of input)."""
    try:
        proc.wait(timeout=TIMEOUT)
    except subprocess.TimeoutExpired:
        proc.kill()
        proc.wait()
        raise AssertionError("the console did not exit") from None
    err = proc.stderr.read() if proc.stderr is not None else ""
    for pipe in (proc.stdin, proc.stdout, proc.stderr):
        if pipe is not None:
            try:
                pipe.close()
            except BrokenPipeError:
                pass
    return proc.returncode, err


def _running(tmp_path: Path) -> subprocess.Popen[str]:
    proc = _start(tmp_path)
    assert proc.stdin is not None
    proc.stdin.write(SCRIPT)
    proc.stdin.flush()
    _wait_for(proc, MARKER)
    return proc


def _check_bag(path: Path) -> None:
    bag = Bag(str(path))
    msgs = list(bag.read_messages())
    assert len(msgs) == EXPECTED
    assert {m.message.data for m in msgs} == {"hello"}
    stamps = [m.timestamp.to_nsec() for m in msgs]
    assert stamps == [10_000_000 * (i + 1) for i in range(EXPECTED)]


def test_script_end_closes_the_recording(tmp_path: Path) -> None:
    (tmp_path / "s.txt").write_text(SCRIPT, encoding="utf-8")
    proc = _start(tmp_path, "--script", "s.txt")
    code, err = _finish(proc)
    assert code == 0, err
    assert not (tmp_path / "out.bag.active").exists()
    _check_bag(tmp_path / "out.bag")


def test_end_of_input_closes_the_recording(tmp_path: Path) -> None:
    proc = _running(tmp_path)
    assert proc.stdin is not None
    proc.stdin.close()  # Ctrl+D
    code, err = _finish(proc)
    assert code == 0, err
    assert not (tmp_path / "out.bag.active").exists()
    _check_bag(tmp_path / "out.bag")


@pytest.mark.parametrize(("sig", "code"), [(signal.SIGINT, 130), (signal.SIGTERM, 143)])
def test_signal_closes_the_recording(tmp_path: Path, sig: signal.Signals, code: int) -> None:
    proc = _running(tmp_path)
    proc.send_signal(sig)
    got, err = _finish(proc)
    assert got == code, err
    assert f"ddes console: {sig.name}: closing the open recordings" in err
    assert "Traceback" not in err
    assert not (tmp_path / "out.bag.active").exists()
    _check_bag(tmp_path / "out.bag")


def test_sigkill_leaves_an_active_file_reindex_recovers(tmp_path: Path) -> None:
    proc = _running(tmp_path)
    proc.kill()
    _finish(proc)
    active = tmp_path / "out.bag.active"
    assert not (tmp_path / "out.bag").exists()
    assert active.stat().st_size > 4096  # chunks, not only the placeholder header
    from ddes.cli.main import main

    assert main(["rosbag", "check", str(active)]) == 1  # unindexed
    assert main(["rosbag", "reindex", str(active)]) == 0
    assert (tmp_path / "out.bag.orig.active").exists()  # rosbag's backup name
    assert main(["rosbag", "check", str(active)]) == 0
    _check_bag(active)


def test_interactive_ctrl_c_stops_only_the_foreground_command(tmp_path: Path,
                                                              monkeypatch: pytest.MonkeyPatch,
                                                              ) -> None:
    monkeypatch.chdir(tmp_path)
    console = Console()
    console.run('rostopic pub -r 10 /chatter std_msgs/String "data: hi" &')
    console.run("rosbag record -O bg /chatter &")
    node = console.world.create_node("ctrl_c")

    def press(_ev: object) -> None:
        raise KeyboardInterrupt

    node.create_timer(1.0, press, oneshot=True)
    result = console.execute("rosbag record -O fg --duration 100 /chatter")
    assert result.code == 130
    assert "^C: stopped the foreground command 'rosbag record -O fg --duration 100 /chatter'" \
        in result.err
    assert Bag("fg.bag").get_message_count() > 0  # the foreground recording was written
    assert [r.path for r in open_recordings(console.world)] == ["bg.bag"]  # still recording
    console.run("sleep 1")
    assert console.close() == ["bg.bag"]
    assert Bag("bg.bag").get_message_count() > 0
