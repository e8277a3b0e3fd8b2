"""The named real-time mode: run a kernel with simulated time paced against the wall clock.

Everything else in ddes runs simulated time as fast as the CPU allows.  An
interactive console command that ROS runs until Ctrl+C (``rostopic echo``,
``rosrun talker``, ``roslaunch``) is paced instead: one simulated second
takes ``1 / rtf`` wall seconds, so messages scroll by as they would on a
robot, and the user stops it with Ctrl+C.

The wall clock only decides *when* the next instant is processed, never
*what* happens in it: the events, their order and the trace are the same
as in an unpaced run that stops at the same simulated instant.  The clock
and the sleep are parameters, so tests drive a pacer with a fake clock and
never sleep.

Ctrl+C: :func:`run_paced` takes a ``stopped()`` callable, checked between
instants and while waiting (in slices of at most :data:`POLL`), so an
interrupt never lands inside a callback; :class:`InterruptFlag` turns SIGINT
into such a flag for the duration of a run.
"""

from __future__ import annotations

import math
import signal
import threading
import time
from collections.abc import Callable
from types import FrameType, TracebackType
from typing import TYPE_CHECKING

from ddes.errors import DdesValueError

if TYPE_CHECKING:
    import simpy

    from ddes.kernel.kernel import Kernel

__all__ = ["POLL", "InterruptFlag", "PacedResult", "check_rtf", "run_paced"]

#: Longest wall-clock wait (seconds) between two checks of ``stopped()``.
POLL = 0.05


class PacedResult:
    """Why :func:`run_paced` returned: ``"done"`` or ``"stopped"``."""

    DONE = "done"
    STOPPED = "stopped"


def check_rtf(rtf: float) -> float:
    """``rtf`` as a positive real-time factor (``inf``: no pacing); a typed error otherwise."""
    try:
        value = float(rtf)
    except (TypeError, ValueError):
        raise DdesValueError(f"real-time factor {rtf!r} is not a number; give e.g. 1 (real "
                             "time), 0.5 (half speed) or 10 (ten times faster)") from None
    if not value > 0:
        raise DdesValueError(f"real-time factor {rtf!r} must be > 0 (1 is real time, 2 twice as "
                             "fast, inf as fast as possible)")
    return value


def run_paced(kernel: Kernel, until: simpy.Event, *, rtf: float = 1.0,
              stopped: Callable[[], bool] = lambda: False,
              clock: Callable[[], float] = time.monotonic,
              sleep: Callable[[float], None] = time.sleep) -> str:
    """Run ``kernel`` paced at ``rtf`` until the event ``until`` has been processed or
    ``stopped()``; returns :data:`PacedResult.DONE` or :data:`PacedResult.STOPPED`.

    Simulated time ``t`` is reached at wall time ``start + (t - t0) / rtf``;
    then the events due at ``t`` are processed one by one, exactly as
    ``kernel.run(until=until)`` would process them (the run stops right after
    ``until``), so a paced run and an unpaced one that end at the same event
    leave the same world and the same trace.  With nothing scheduled the run
    waits (the world is idle, as a ROS tool waiting for a message is) until
    ``stopped()``.
    """
    rtf = check_rtf(rtf)
    env = kernel.env
    t0 = env.now
    start = clock()
    while True:
        if until.processed:
            return PacedResult.DONE
        if stopped():
            return PacedResult.STOPPED
        t_next = env.peek()
        if t_next == math.inf:  # idle: only Ctrl+C ends it
            sleep(POLL)
            continue
        if rtf != math.inf:
            due = start + (int(t_next) - t0) / 1e9 / rtf
            while (wait := due - clock()) > 0:
                if stopped():
                    return PacedResult.STOPPED
                sleep(min(wait, POLL))
            if stopped():  # Ctrl+C during the last slice: the instant is not processed
                return PacedResult.STOPPED
        kernel.run_through(int(t_next), stop=until)


class InterruptFlag:
    """Context manager: SIGINT sets :attr:`raised` instead of raising KeyboardInterrupt.

    Used around a paced run, so Ctrl+C is seen between two instants.  Outside
    the main thread (where signals cannot be handled) it does nothing.
    """

    def __init__(self, *, second_raises: bool = False) -> None:
        self.raised = False
        #: A second Ctrl+C raises KeyboardInterrupt (a command that never looks at the flag
        #: can still be stopped).
        self.second_raises = second_raises
        self._old: object = None
        self._active = False

    def __call__(self) -> bool:
        return self.raised

    def _handle(self, signum: int, frame: FrameType | None) -> None:
        if self.raised and self.second_raises:
            raise KeyboardInterrupt
        self.raised = True

    def __enter__(self) -> InterruptFlag:
        if threading.current_thread() is threading.main_thread():
            self._old = signal.signal(signal.SIGINT, self._handle)
            self._active = True
        return self

    def __exit__(self, exc_type: type[BaseException] | None, exc: BaseException | None,
                 tb: TracebackType | None) -> None:
        if self._active:
            signal.signal(signal.SIGINT, self._old)  # type: ignore[arg-type]
            self._active = False
