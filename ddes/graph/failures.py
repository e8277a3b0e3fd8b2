"""What happens when user code raises: rospy's rule by default, strict on request.

Default (rospy's rule).  An exception in a subscriber, timer, service or
action callback is logged as rospy logs it — ``bad callback: <callback>`` and
the user's traceback, at ERROR on the node's log (``/rosout``, the printed
log) and on stderr — recorded as ``callback.exception`` in the trace and in
``world.callback_errors``, and the world keeps running.  An exception in a
node's main process (``node.process(...)``) shuts that node down with a
logged error (``node.exit`` with ``code=1``); the other nodes keep running.

Strict (``World(strict=True)``, or :func:`strict_worlds` around code that
makes worlds).  ``world.run()`` raises the first such exception itself, with
the user's frames at the top of its traceback, not SimPy's.  Tests and
graders use it so that a failing assertion inside a callback fails the test.

Tracebacks in the log and the trace show file *base names* and only the
user's frames, so a failing run has the same digest on every machine.
"""

from __future__ import annotations

import os
import sys
import traceback
from collections.abc import Iterator
from contextlib import contextmanager
from contextvars import ContextVar
from pathlib import PurePath
from types import TracebackType

import simpy

__all__ = [
    "NODE_OF_PROCESS",
    "STRICT_DEFAULT",
    "is_library_file",
    "print_to_stderr",
    "strict_worlds",
    "user_frames",
    "user_traceback",
]

#: The attribute a node's process carries, naming its node (set by ``Node.process``).
NODE_OF_PROCESS = "ddes_node"

#: The strictness a new World takes when none is given (see :func:`strict_worlds`).
STRICT_DEFAULT: ContextVar[bool] = ContextVar("ddes_strict_default", default=False)

#: Where ddes's own code and SimPy's are on this machine (found from the modules, not from
#: folder names: a clone of the repository may itself be called ``ddes``).
_DDES_DIR = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
_PACKAGES_DIR = os.path.join(_DDES_DIR, "packages")
_SIMPY_DIR = os.path.dirname(os.path.abspath(simpy.__file__))


@contextmanager
def strict_worlds(strict: bool = True) -> Iterator[None]:
    """Worlds created inside this block default to ``strict`` (``World(strict=...)`` wins).

    A context variable, not a global: it is undone when the block ends and
    does not leak into other threads or tasks.
    """
    token = STRICT_DEFAULT.set(strict)
    try:
        yield
    finally:
        STRICT_DEFAULT.reset(token)


def is_library_file(filename: str) -> bool:
    """True for a file of ddes (its code, not its bundled packages' node code) or SimPy, by
    where those are installed: a user's file in a folder that happens to be called ``ddes``
    keeps its frames."""
    path = os.path.abspath(filename)
    if _inside(path, _SIMPY_DIR):
        return True
    return _inside(path, _DDES_DIR) and not _inside(path, _PACKAGES_DIR)


def _inside(path: str, folder: str) -> bool:
    return path.startswith(folder + os.sep)


def user_frames(tb: TracebackType | None) -> TracebackType | None:
    """``tb`` without its leading library frames (the user's code comes first)."""
    while tb is not None and is_library_file(tb.tb_frame.f_code.co_filename):
        tb = tb.tb_next
    return tb


def user_traceback(exc: BaseException) -> str:
    """The traceback of ``exc`` as rospy prints it, with only the user's frames, by base name."""
    frames = [f for f in traceback.extract_tb(exc.__traceback__)
              if not is_library_file(f.filename)]
    lines = ["Traceback (most recent call last):"]
    for f in frames:
        lines.append(f'  File "{PurePath(f.filename).name}", line {f.lineno}, in {f.name}')
        if f.line:
            lines.append(f"    {f.line}")
    lines.extend(traceback.format_exception_only(type(exc), exc)[-1:])
    return "\n".join(line.rstrip("\n") for line in lines)


def print_to_stderr(text: str) -> None:
    """Write an error the way an uncaught exception in a rospy thread reaches stderr."""
    sys.stderr.write(text + "\n")
