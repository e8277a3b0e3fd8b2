"""``ddes console``: the entry point of the console (the engine is :mod:`ddes.console`).

Endings: when the script or the input ends (Ctrl+D), and on SIGINT and
SIGTERM, every open recording is closed (its index written, ``NAME.bag``
in place) before the command exits.  In a script (``--script FILE`` or
lines on standard input) SIGINT exits 130 and SIGTERM 143 (128 + the
signal, as a shell reports them); interactively Ctrl+C stops only the
foreground command (see :mod:`ddes.console.shell`) and SIGTERM exits 143.
A script that is not UTF-8 is refused naming the file and the byte offset
(exit 1); output into a closed pipe (``| head``) ends quietly with 141
(128 + SIGPIPE, what a shell shows for ``yes | head``).
"""

from __future__ import annotations

import argparse
import os
import signal
import sys
from collections.abc import Iterator
from pathlib import Path
from types import FrameType
from typing import IO

from ddes.console.shell import interact, run_script
from ddes.errors import ROSConsoleError

__all__ = ["EXIT_BROKEN_PIPE", "Signalled", "decode_lines", "main", "register",
           "silence_stdout"]

#: Exit code when standard output is a closed pipe (128 + SIGPIPE).
EXIT_BROKEN_PIPE = 141


class Signalled(BaseException):
    """SIGINT/SIGTERM in the console command: unwinds (stopping the foreground command) to
    :func:`main`, which closes the recordings and exits ``128 + signum``.  A BaseException so no
    ``except Exception`` of a node or tool swallows it."""

    def __init__(self, signum: int) -> None:
        super().__init__(signum)
        self.signum = signum


class _Handler:
    """Raises :class:`Signalled` until the recordings are being closed, then ignores signals."""

    def __init__(self) -> None:
        self.closing = False

    def __call__(self, signum: int, frame: FrameType | None) -> None:
        if not self.closing:
            raise Signalled(signum)


def silence_stdout() -> None:
    """Point standard output at /dev/null (after EPIPE), so nothing more fails or is printed."""
    try:
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        os.close(devnull)
    except (OSError, ValueError):
        pass


def decode_lines(stream: IO[bytes], name: str) -> Iterator[str]:
    """The lines of ``stream`` as UTF-8 text; invalid UTF-8 is a ROSConsoleError naming ``name``,
    the line and the byte offset."""
    offset = 0
    for number, raw in enumerate(iter(stream.readline, b""), 1):
        try:
            yield raw.decode("utf-8")
        except UnicodeDecodeError as exc:
            raise ROSConsoleError(_not_utf8(name, raw, exc, offset, number)) from None
        offset += len(raw)


def _not_utf8(name: str, data: bytes, exc: UnicodeDecodeError, base: int, line: int) -> str:
    return (f"{name} is not UTF-8 text: byte {data[exc.start]:#04x} at byte offset "
            f"{base + exc.start} (line {line}) cannot be decoded ({exc.reason}); save the file "
            "as UTF-8")


def _read_script(path: str) -> list[str]:
    try:
        data = Path(path).read_bytes()
    except OSError as exc:
        raise ROSConsoleError(f"cannot read script {path}: {exc.strerror}") from None
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError as exc:
        line = data.count(b"\n", 0, exc.start) + 1
        raise ROSConsoleError(_not_utf8(f"script {path}", data, exc, 0, line)) from None
    return text.splitlines()


def _history_file() -> str | None:
    path = os.environ.get("DDES_HISTORY")
    if path is not None:
        return path or None
    home = os.path.expanduser("~")
    return os.path.join(home, ".ddes_history") if os.path.isdir(home) else None


def main(args: argparse.Namespace) -> int:
    """``ddes console [--script FILE] [--keep-going] [--seed N] [--no-core] [--rtf R]
    [--until S]``."""
    from ddes.rospack import command_package_path
    from ddes.world import Console, World

    lines = _read_script(args.script) if args.script is not None else None
    interactive = lines is None and sys.stdin.isatty()
    # The one place the environment is read: when the command starts.
    world = World(seed=args.seed, package_path=command_package_path(os.environ, os.getcwd()))
    console = Console(world, core=not args.no_core,
                      rtf=args.rtf if interactive else None, until=args.until)

    def write(text: str) -> None:
        sys.stdout.write(text + "\n")
        sys.stdout.flush()

    handled = [signal.SIGTERM] if interactive else [signal.SIGINT, signal.SIGTERM]
    handler = _Handler()
    previous = {sig: signal.signal(sig, handler) for sig in handled}
    reason = "end of input"
    try:
        if lines is not None:
            code = run_script(console, lines, write, keep_going=args.keep_going)
        elif not interactive:
            binary = getattr(sys.stdin, "buffer", None)  # None: a text stream put in its place
            source = sys.stdin if binary is None else decode_lines(binary, "standard input")
            code = run_script(console, source, write, keep_going=args.keep_going)
        else:
            code = interact(console, _history_file())
    except Signalled as exc:
        name = signal.Signals(exc.signum).name
        reason = name
        code = 128 + exc.signum
        sys.stderr.write(f"ddes console: {name}: closing the open recordings and exiting\n")
    except BrokenPipeError:
        silence_stdout()
        reason = "broken pipe"
        code = EXIT_BROKEN_PIPE
    finally:
        handler.closing = True  # closing is not interrupted by a second signal
        try:
            try:
                console.close(reason)
            except BrokenPipeError:
                silence_stdout()
                console.close(reason)
        finally:
            for sig, old in previous.items():
                signal.signal(sig, old)
    return code


def _rtf(text: str) -> float:
    from ddes.errors import DdesError
    from ddes.kernel.realtime import check_rtf

    try:
        return check_rtf(float(text))
    except (ValueError, DdesError):
        raise argparse.ArgumentTypeError(f"invalid real-time factor {text!r}: give a number > 0 "
                                         "(1 = real time, 0.5 = half speed, inf = no pacing)") from None


def _until(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        value = -1.0
    if not value >= 0 or value == float("inf"):
        raise argparse.ArgumentTypeError(f"invalid time limit {text!r}: give simulated seconds "
                                         ">= 0, e.g. --until 30")
    return value


def register(sub: argparse._SubParsersAction[argparse.ArgumentParser]) -> None:
    """Add ``ddes console`` to the ``ddes`` command."""
    p = sub.add_parser("console", help="interactive ROS console on a simulated roscore",
                       description="A roscore on simulated time with rosrun, roslaunch, "
                                   "rostopic, rosnode, rosparam ... in one shell.")
    p.add_argument("--script", metavar="FILE", default=None,
                   help="run the commands of FILE and print a transcript")
    p.add_argument("--keep-going", "-k", action="store_true",
                   help="in a script, go on after a failing command (exit 1 at the end)")
    p.add_argument("--seed", type=int, default=0, help="world seed (default 0)")
    p.add_argument("--no-core", action="store_true",
                   help="start without the /rosout node and roscore's parameters")
    p.add_argument("--rtf", type=_rtf, default=1.0, metavar="FACTOR",
                   help="interactive: real-time factor of foreground commands that run until "
                        "Ctrl+C (default 1: one simulated second per second; inf: no pacing)")
    p.add_argument("--until", type=_until, default=None, metavar="SECONDS",
                   help="time limit (simulated seconds): foreground commands that run until "
                        "Ctrl+C in ROS stop there (a script needs it for them)")
    p.set_defaults(func=main)
