"""``ddes console`` in a real pseudo-terminal: readline, prompts, completion, the lecture-1 tour."""

from __future__ import annotations

import fcntl
import os
import re
import select
import subprocess
import sys
import termios
from pathlib import Path

import pytest

pty = pytest.importorskip("pty")  # POSIX only; CI runs on Linux

PROMPT = re.compile(rb"ddes \[(\d+\.\d{3})\] \$ ")


def _controlling_terminal() -> None:
    """In the child: a new session whose controlling terminal is the pty (so Ctrl+C is SIGINT)."""
    os.setsid()
    fcntl.ioctl(0, termios.TIOCSCTTY, 0)


class Terminal:
    """``ddes console`` on a pseudo-terminal, driven line by line."""

    def __init__(self, home: Path, *options: str) -> None:
        master, slave = pty.openpty()
        env = {k: v for k, v in os.environ.items() if not k.startswith("PYTHON")}
        env.update({"HOME": str(home), "TERM": "dumb", "DDES_HISTORY": str(home / "hist"),
                    "INPUTRC": "/dev/null", "COLUMNS": "200"})
        self.proc = subprocess.Popen([sys.executable, "-m", "ddes.cli.main", "console",
                                      *(options or ("--rtf", "inf"))],
                                     stdin=slave, stdout=slave, stderr=slave, env=env,
                                     close_fds=True, preexec_fn=_controlling_terminal)
        os.close(slave)
        self.fd = master
        self.buffer = b""

    def read_until_prompt(self) -> tuple[str, str]:
        """Everything printed up to the next prompt, and the time the prompt shows."""
        while True:
            m = PROMPT.search(self.buffer)
            if m:
                text, self.buffer = self.buffer[:m.start()], self.buffer[m.end():]
                return text.decode().replace("\r\n", "\n"), m.group(1).decode()
            ready, _, _ = select.select([self.fd], [], [], 60)  # a safety net, not a timing check
            if not ready:
                raise AssertionError(f"no prompt; output so far: {self.buffer!r}")
            try:
                chunk = os.read(self.fd, 4096)
            except OSError:
                chunk = b""
            if not chunk:
                raise AssertionError(f"console ended; output: {self.buffer!r}")
            self.buffer += chunk

    def command(self, line: str) -> tuple[str, str]:
        """Type ``line`` and Enter; returns (what it printed, the next prompt's time)."""
        os.write(self.fd, line.encode() + b"\n")
        text, t = self.read_until_prompt()
        echo = line + "\n"
        assert text.startswith(echo), (text, line)  # the terminal echoes what was typed
        return text[len(echo):], t

    def close(self) -> int:
        os.write(self.fd, b"\x04")  # Ctrl+D
        code = self.proc.wait(timeout=60)
        os.close(self.fd)
        return code


@pytest.fixture
def term(tmp_path: Path):  # type: ignore[no-untyped-def]
    t = Terminal(tmp_path)
    yield t
    if t.proc.poll() is None:
        t.proc.kill()
        t.proc.wait()


def test_lecture_one_in_a_terminal(term: Terminal, tmp_path: Path) -> None:
    intro, t = term.read_until_prompt()
    assert "ddes console" in intro and t == "0.000"

    out, t = term.command("rosrun --quiet rospy_tutorials talker &")
    assert (out, t) == ("[1] rosrun --quiet rospy_tutorials talker\n", "0.000")
    out, _ = term.command("rosrun rospy_tutorials listener &")
    assert out == "[2] rosrun rospy_tutorials listener\n"
    out, _ = term.command("rosnode list")
    assert out == "/listener_2\n/rosout\n/talker_1\n"
    out, _ = term.command("rostopic list")
    assert out == "/chatter\n/rosout\n/rosout_agg\n"
    out, _ = term.command("rostopic info /chatter")
    assert out.startswith("Type: std_msgs/String\n\nPublishers: \n * /talker_1 (http://")
    out, t = term.command("rostopic echo -n 3 /chatter")
    assert out.count('data: "hello world 0.') == 3 and out.count("---\n") == 3
    assert "/listener_2I heard hello world 0.1" in out  # the listener logs as time passes
    assert t == "0.300"
    out, t = term.command("rostopic hz --duration 2 /chatter")
    assert out.count("average rate: 10.000") == 2
    assert "\tmin: 0.100s max: 0.100s std dev: 0.00000s window: " in out
    assert t == "2.300"
    out, _ = term.command("roslaunch --duration 1 rospy_tutorials param_talker.launch")
    assert "/foo/utterance is Hello World" in out and "gains are 1.0, 2.0, 3.0" in out
    assert "[ INFO] [3.300000000]: I heard: [Hello World]" in out
    assert out.endswith("done\n")
    os.write(term.fd, b'rostopic pub -1 /q std_msgs/Header "seq: 7\n')
    os.write(term.fd, b'frame_id: map"\n')
    out, _ = term.read_until_prompt()
    assert "> frame_id: map" in out and "publishing and latching message for 3.0 seconds" in out
    out, _ = term.command("rostopic nope")
    assert out == ("ERROR: unknown command 'rostopic nope'; rostopic commands: bw, delay, echo, "
                   "find, hz, info, list, pub, type\n")
    out, t = term.command("time")
    assert out == "simulated time: 6.300000000 s\n" and t == "6.300"
    assert term.close() == 0
    assert "rostopic hz --duration 2 /chatter" in (tmp_path / "hist").read_text()


def test_tab_completes_a_topic_name(term: Terminal) -> None:
    term.read_until_prompt()
    term.command("rosrun --quiet rospy_tutorials talker &")
    os.write(term.fd, b"rostopic echo -n 1 /cha\t")
    os.write(term.fd, b"\n")
    text, _ = term.read_until_prompt()
    assert "rostopic echo -n 1 /chatter" in text
    assert 'data: "hello world 0.1"\n---\n' in text
    os.write(term.fd, b"rosn\t")
    os.write(term.fd, b"list\n")
    text, _ = term.read_until_prompt()
    assert "rosnode list" in text and "/talker_1\n" in text
    assert term.close() == 0


def _read_until(term: Terminal, marker: bytes) -> None:
    """Read the terminal's output until ``marker`` has appeared (kept in the buffer)."""
    while marker not in term.buffer:
        ready, _, _ = select.select([term.fd], [], [], 60)  # a safety net, not a timing check
        if not ready:
            raise AssertionError(f"{marker!r} never printed; output so far: {term.buffer!r}")
        term.buffer += os.read(term.fd, 4096)


def test_foreground_commands_run_paced_until_ctrl_c(tmp_path: Path) -> None:
    """What ROS runs until Ctrl+C runs until Ctrl+C, paced; the prompt then shows the time."""
    term = Terminal(tmp_path, "--rtf", "20")  # 20x real time: a simulated second in 50 ms
    try:
        term.read_until_prompt()
        os.write(term.fd, b"rosrun rospy_tutorials talker\n")
        _read_until(term, b"hello world 0.5")  # the talker logs as simulated time passes
        os.write(term.fd, b"\x03")  # Ctrl+C: the foreground node shuts down, as in ROS
        out, t = term.read_until_prompt()
        assert "[INFO] [0.100000]: hello world 0.1\n" in out
        assert float(t) >= 0.5
        out, t2 = term.command("rosnode list")
        assert out == "/rosout\n" and t2 == t  # the talker is gone; time stood still again
        os.write(term.fd, b"rostopic echo /nobody\n")
        _read_until(term, b"WARNING: topic [/nobody] does not appear to be published yet")
        os.write(term.fd, b"\x03")  # an echo that never got a message still ends on Ctrl+C
        out, t3 = term.read_until_prompt()
        assert "Traceback" not in out and float(t3) >= float(t)
        out, _ = term.command("rtf")
        assert out == ("real-time factor: 20 (foreground commands run paced until they end or "
                       "Ctrl+C)\n")
        assert term.close() == 0
    finally:
        if term.proc.poll() is None:
            term.proc.kill()
            term.proc.wait()


def _visible(line: str) -> str:
    """A line as the terminal shows it: a carriage return starts it over (what follows overwrites
    what came before; here what follows is always the longer text)."""
    return line.rsplit("\r", 1)[-1]


def test_ctrl_c_says_what_it_stopped_on_a_line_of_its_own(tmp_path: Path) -> None:
    """Ctrl+C prints the console's message (docs/console.md, "Interactive Ctrl+C") over the ``^C``
    the terminal echoed, and the prompt starts on a new line."""
    term = Terminal(tmp_path, "--rtf", "20")
    try:
        term.read_until_prompt()
        os.write(term.fd, b"rostopic echo /nobody\n")
        _read_until(term, b"does not appear to be published yet")
        os.write(term.fd, b"\x03")
        out, _ = term.read_until_prompt()
        message = ("^C: stopped the foreground command 'rostopic echo /nobody' (its nodes were "
                   "shut down; background jobs keep running: 'jobs' lists them)")
        assert out.endswith("\n")  # the prompt comes on a line of its own
        last = out.rstrip("\n").split("\n")[-1]
        assert last == "^C\r" + message  # the terminal's echo, then the message written over it
        assert _visible(last) == message
        out, _ = term.command("rosnode list")
        assert out == "/rosout\n"  # the echo's node was shut down
        assert term.close() == 0
    finally:
        if term.proc.poll() is None:
            term.proc.kill()
            term.proc.wait()


def test_clear_erases_the_screen_as_a_shell_does(term: Terminal) -> None:
    term.read_until_prompt()
    out, _ = term.command("clear")
    assert out == "\x1b[H\x1b[2J\x1b[3J"  # clear's ANSI on an xterm; the prompt follows at once
    out, _ = term.command("clear -x")
    assert out == "\x1b[H\x1b[2J"  # -x keeps the scrollback
    assert term.close() == 0
