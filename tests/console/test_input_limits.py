"""Hostile console input (issue 13, item 2): huge lines, bytes that are not UTF-8, a closed pipe."""

from __future__ import annotations

import io
import os
import subprocess
import sys
from pathlib import Path

import pytest

from ddes.console.shell import MAX_LINE, Console, interact

MEGA = "rostopic list " + "x" * (1 << 20)


def _ddes(*args: str, cwd: Path, stdin: bytes | None = None) -> subprocess.CompletedProcess[bytes]:
    env = dict(os.environ, DDES_HISTORY="")
    return subprocess.run([sys.executable, "-m", "ddes.cli.main", *args], input=stdin,
                          capture_output=True, cwd=cwd, env=env, timeout=120)


def test_a_megabyte_line_is_refused_and_the_console_goes_on() -> None:
    console = Console()
    result = console.execute(MEGA)
    assert result.code == 1
    assert f"over the console's limit of {MAX_LINE} (MAX_LINE, 64 KiB)" in result.err
    assert len(result.err) < 1000  # the line is not echoed back
    assert console.execute("time").code == 0


def test_script_mode_refuses_the_line_without_echoing_it() -> None:
    code, text = Console().transcript([MEGA, "time"], keep_going=True)
    assert code == 1
    assert "(1048590 characters)" in text and f"limit of {MAX_LINE}" in text
    assert text.rstrip().endswith("simulated time: 0.000000000 s")
    assert len(text) < 2000
    code, text = Console().transcript([MEGA, "time"])
    assert code == 1 and "simulated time" not in text  # a failing command stops a script


def test_an_open_quote_cannot_grow_past_the_limit() -> None:
    lines = ['rostopic pub /x std_msgs/String "data: '] + ["y" * 1000] * 100 + ["time"]
    code, text = Console().transcript(lines, keep_going=True)
    assert code == 1 and f"limit of {MAX_LINE}" in text


def test_interactive_mode_survives_a_megabyte_line(capsys: pytest.CaptureFixture[str]) -> None:
    stdin = io.StringIO(MEGA + "\ntime\n")
    assert interact(Console(), None, stdin=stdin) == 0
    out, err = capsys.readouterr()
    assert f"limit of {MAX_LINE}" in err
    assert "simulated time: 0.000000000 s" in out


def test_a_megabyte_line_on_stdin_of_the_command(tmp_path: Path) -> None:
    proc = _ddes("console", "--keep-going", cwd=tmp_path,
                 stdin=(MEGA + "\ntime\n").encode())
    assert proc.returncode == 1
    assert b"simulated time: 0.000000000 s" in proc.stdout
    assert b"Traceback" not in proc.stderr


def test_a_script_that_is_not_utf8(tmp_path: Path) -> None:
    (tmp_path / "bad.txt").write_bytes(b"time\n# caf\xe9\n")
    proc = _ddes("console", "--script", "bad.txt", cwd=tmp_path)
    assert proc.returncode == 1
    assert proc.stderr.decode() == (
        "ERROR: script bad.txt is not UTF-8 text: byte 0xe9 at byte offset 10 (line 2) cannot "
        "be decoded (invalid continuation byte); save the file as UTF-8\n")
    assert proc.stdout == b""  # refused before anything ran


def test_standard_input_that_is_not_utf8(tmp_path: Path) -> None:
    proc = _ddes("console", cwd=tmp_path, stdin=b"time\n\xff\n")
    assert proc.returncode == 1
    assert b"simulated time" in proc.stdout
    assert b"standard input is not UTF-8 text: byte 0xff at byte offset 5 (line 2)" in proc.stderr
    assert b"Traceback" not in proc.stderr


@pytest.mark.parametrize("args", [("console", "--script", "big.txt"), ("rosbag", "info", "x.bag"),
                                  ("console",)])
def test_a_closed_pipe_ends_quietly_with_141(tmp_path: Path, args: tuple[str, ...]) -> None:
    from ddes.rosbag import Bag

    script = "rossrv list\n" * 600  # well over a pipe's 64 KiB of output
    (tmp_path / "big.txt").write_text(script, encoding="utf-8")
    with Bag(str(tmp_path / "x.bag"), "w") as bag:
        from ddes import Time
        from ddes.msg import get_message_class

        String = get_message_class("std_msgs/String")
        for i in range(1500):  # many topics: a `rosbag info` longer than a pipe holds
            bag.write(f"/topic_{i}", String(data="x"), Time(1, i))
    env = dict(os.environ, DDES_HISTORY="")
    proc = subprocess.Popen([sys.executable, "-m", "ddes.cli.main", *args], cwd=tmp_path, env=env,
                            stdin=subprocess.PIPE, stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    assert proc.stdout is not None and proc.stderr is not None and proc.stdin is not None
    if args == ("console",):
        proc.stdin.write(script.encode())
    proc.stdin.close()
    assert proc.stdout.readline()  # `| head -1`
    proc.stdout.close()
    try:
        code = proc.wait(timeout=120)
    finally:
        proc.kill()
    err = proc.stderr.read()
    proc.stderr.close()
    assert code == 141, err
    assert err == b""


def test_yaml_arguments_of_rostopic_pub_are_bounded() -> None:
    """rostopic pub's YAML arguments go through the bounded loader (issue 38): nesting 5000
    deep was a RecursionError in PyYAML, an alias bomb a value of 387 million parts."""
    console = Console()
    result = console.execute("rostopic pub -1 /x std_msgs/String '" + "[" * 5000 + "]" * 5000 + "'")
    assert result.code == 1 and "YAML nested more than 64 deep" in result.err
    bomb = "[" + ",".join(["&a0 [x,x,x,x,x,x,x,x,x]"] + [
        f"&a{i} [" + ",".join([f"*a{i - 1}"] * 9) + "]" for i in range(1, 9)]) + "]"
    result = console.execute(f'rostopic pub -1 /x std_msgs/String "{bomb}"')
    assert result.code == 1 and "an alias bomb?" in result.err
    assert console.execute("rostopic pub -1 /x std_msgs/String hello").code == 0
