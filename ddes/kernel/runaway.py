"""Budgets against runaway user code: a wall-clock watchdog and livelock reports.

Simulated time costs nothing, so two kinds of student code can hang a run
forever: a callback that never returns (``while True:`` without ``yield``),
and a zero-time livelock (events forever at one instant, such as a loop of
``yield env.timeout(0)``).  The kernel stops both and says where:

* :class:`Watchdog` — while :meth:`ddes.kernel.Kernel.run` runs, a
  ``SIGALRM`` interval timer checks that the kernel keeps taking steps; when
  one step has taken longer than the wall budget it raises
  :class:`WallBudgetExceeded` (a ``BaseException``, so a student's
  ``except Exception`` cannot swallow it) inside the running code.  This is
  ddes's one use of the wall clock: it never decides anything in the trace,
  it only stops code that would never stop.  Off outside the main thread and
  on systems without ``SIGALRM``.
* The instant budget is counted by :meth:`ddes.kernel.events.NsEnvironment.step`.

Both end in :class:`~ddes.errors.RunawayError` with the node, the callback
(the innermost frame of user code) and the simulated time.
"""

from __future__ import annotations

import os
import signal
import threading
import time
from types import FrameType, TracebackType

import simpy

from ddes.kernel.events import ZeroTimeLivelock

__all__ = [
    "DEFAULT_WALL_BUDGET",
    "WallBudgetExceeded",
    "Watchdog",
    "describe_livelock",
    "describe_runaway",
]

#: Default wall-clock seconds one kernel step (one callback) may take.
DEFAULT_WALL_BUDGET = 10.0

#: The machine's monotonic clock, taken when ddes is imported: the grading child answers
#: ``time.monotonic()`` from the simulated clock for the student's code
#: (:mod:`ddes.grading.determinism`), and a budget must keep measuring wall time.
_monotonic = time.monotonic

#: Where ddes's code (less its bundled packages' node code) and SimPy's are installed: the
#: frames that are not the user's (found from the modules, not from folder names, which a clone
#: of the repository may share).
_DDES_DIR = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
_PACKAGES_DIR = os.path.join(_DDES_DIR, "packages")
_SIMPY_DIR = os.path.dirname(os.path.abspath(simpy.__file__))


def _library_path(path: str) -> bool:
    path = os.path.abspath(path)
    if path.startswith(_SIMPY_DIR + os.sep):
        return True
    return path.startswith(_DDES_DIR + os.sep) and not path.startswith(_PACKAGES_DIR + os.sep)


class WallBudgetExceeded(BaseException):  # noqa: N818 - an internal signal, not an error type
    """Raised inside user code by the watchdog; :meth:`Kernel.run` turns it into RunawayError."""


class Watchdog:
    """Context manager: a ``SIGALRM`` interval timer watching ``env.progress()`` move."""

    def __init__(self, env: object, budget: float | None) -> None:
        self.env = env
        self.budget = budget
        self.active = False
        self._old_handler: object = None
        self._old_timer: tuple[float, float] = (0.0, 0.0)
        self._last_mark: object = None
        self._last_change = 0.0

    def __enter__(self) -> Watchdog:
        if (self.budget is None or not hasattr(signal, "setitimer")
                or threading.current_thread() is not threading.main_thread()):
            return self
        old = signal.getsignal(signal.SIGALRM)
        if isinstance(old, _Handler):  # a nested run(): the outer watchdog already watches
            return self
        self._old_handler = old
        self._last_mark = self.env.progress()  # type: ignore[attr-defined]
        # The wall clock, on purpose: it only stops code that would never stop and
        # decides nothing in the trace (see the module docstring).
        self._last_change = _monotonic()
        signal.signal(signal.SIGALRM, _Handler(self))
        interval = min(max(self.budget / 4, 0.05), 1.0)
        self._old_timer = signal.setitimer(signal.ITIMER_REAL, interval, interval)
        self.active = True
        return self

    def check(self) -> None:
        """The alarm: raise if the kernel took no step for longer than the budget."""
        mark = self.env.progress()  # type: ignore[attr-defined]
        now = _monotonic()
        if mark != self._last_mark:
            self._last_mark, self._last_change = mark, now
            return
        assert self.budget is not None
        if now - self._last_change >= self.budget:
            stuck, self._last_change = now - self._last_change, now  # one raise per stuck step
            raise WallBudgetExceeded(stuck)

    def __exit__(self, *exc: object) -> None:
        if not self.active:
            return
        signal.setitimer(signal.ITIMER_REAL, 0, 0)
        signal.signal(signal.SIGALRM, self._old_handler)  # type: ignore[arg-type]
        delay, interval = self._old_timer
        if delay or interval:  # give a timer that was running before back its time
            signal.setitimer(signal.ITIMER_REAL, delay, interval)
        self.active = False


class _Handler:
    """The SIGALRM handler of one watchdog (a class, so nested runs recognise it)."""

    def __init__(self, dog: Watchdog) -> None:
        self.dog = dog

    def __call__(self, signum: int, frame: FrameType | None) -> None:
        self.dog.check()


def _frames(tb: TracebackType | None) -> list[FrameType]:
    out = []
    while tb is not None:
        out.append(tb.tb_frame)
        tb = tb.tb_next
    return out


def _where(frames: list[FrameType]) -> tuple[str, str]:
    """(node, callback) from a stack, innermost last: the user's frame and its node."""
    callback = "unknown code"
    for frame in reversed(frames):
        path = frame.f_code.co_filename
        if not _library_path(path):
            name = getattr(frame.f_code, "co_qualname", frame.f_code.co_name)
            callback = f"{name} ({path.rsplit('/', 1)[-1]}:{frame.f_lineno})"
            break
    node = "no node"
    for frame in reversed(frames):
        owner = frame.f_locals.get("self")
        found = getattr(getattr(owner, "node", None), "name", None)
        if isinstance(found, str):
            node = found
            break
    return node, callback


def describe_runaway(stop: WallBudgetExceeded, t_ns: int, budget: float | None) -> str:
    """The message of a RunawayError for a step that outran the wall budget."""
    exc: BaseException | None = stop
    frames: list[FrameType] = []
    while exc is not None:  # a generator callback's failure carries the original as __cause__
        frames = _frames(exc.__traceback__) or frames
        exc = exc.__cause__
    node, callback = _where(frames)
    return (f"node {node}: callback {callback} ran for more than {budget:g} s of wall-clock time "
            f"at simulated t={t_ns / 1e9:.9f} s without returning or yielding (a loop without "
            "'yield'?); simulated time cannot pass inside a callback: yield an event "
            "(yield rate.sleep()) or return, or raise the budget with World(wall_budget=...)")


def describe_livelock(live: ZeroTimeLivelock, budget: int | None) -> str:
    """The message of a RunawayError for a zero-time livelock."""
    callbacks = live.event.callbacks or []
    names = []
    node = "no node"
    for cb in callbacks:
        owner = getattr(cb, "__self__", None)
        names.append(getattr(cb, "__qualname__", type(cb).__name__))
        found = getattr(getattr(owner, "node", None), "name", None)
        if isinstance(found, str):
            node = found
    process = getattr(callbacks[0], "__self__", None) if callbacks else None
    if isinstance(process, simpy.Process):
        names.append(f"the process {process.name}")
    what = ", ".join(names) or type(live.event).__name__
    return (f"node {node}: zero-time livelock at simulated t={live.t_ns / 1e9:.9f} s: "
            f"{live.count} events at one instant (budget {budget}) without time passing; the last "
            f"one ran {what}. A loop that yields only zero delays never lets time pass: give it "
            "a positive delay, or raise the budget with World(instant_budget=...)")
