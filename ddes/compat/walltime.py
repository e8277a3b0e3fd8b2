"""``time`` as a rospy script sees it: the kernel clock plays the wall clock.

A rospy node takes wall time from Python's ``time`` module (rospy has no WallTime: a status line
prints ``time.time()``, a wall-paced loop calls ``time.sleep(1.0)``, and
``rospy.rostime.wallsleep`` is ``time.sleep``).  In ddes nothing reads the computer's clock: the
kernel's clock is the wall clock (docs/time.md), the clock that ``rosbag play -r 2`` and a
simulator's ``real_time_factor`` are measured against.  In a script, ``import time`` gives this
view (:mod:`ddes.compat.scripts`):

* ``time()``, ``monotonic()``, ``perf_counter()``, ``process_time()``, ``thread_time()`` and
  ``clock_gettime(clock)`` are the kernel time in float seconds (counted from the world's
  start, which a date reads as 1970-01-01 00:00 UTC), their ``_ns`` forms the same in integer
  ns;
* ``localtime()``, ``gmtime()``, ``ctime()``, ``asctime()`` and ``strftime(format)`` without a
  time read that clock too, and the view's local zone is UTC (``localtime`` is ``gmtime``,
  ``mktime`` its inverse, ``timezone`` 0), so no machine's zone reaches a log;
* ``sleep(secs)`` blocks the calling node (greenlet) for ``secs`` of kernel time, whatever its
  ROS clock (a sim-time node's wall sleep goes on while ``/clock`` stands still); a negative
  value raises ``ValueError("sleep length must be non-negative")`` as Python's does;
* everything else is the real ``time`` module (``struct_time``, ``get_clock_info`` ...).

Two runs of the same seed read the same times, so a script's log stays deterministic.
"""

from __future__ import annotations

import calendar
import math
import time as _time
import types
from collections.abc import Callable
from typing import TYPE_CHECKING, Any

from ddes.graph.blocking import wait_ns

if TYPE_CHECKING:
    from ddes.graph.world import World

__all__ = ["clock_functions", "module"]


class _TimeView(types.ModuleType):
    def __getattr__(self, name: str) -> Any:
        return getattr(_time, name)


#: The machine's conversions, taken at import: :func:`clock_functions` calls them, and the
#: grading child puts its own functions in their place in the real module.
_real_gmtime, _real_asctime, _real_strftime = _time.gmtime, _time.asctime, _time.strftime


def clock_functions(now_ns: Callable[[], int]) -> dict[str, Any]:
    """The clock functions of ``time`` answered from ``now_ns()`` (integer ns; see the module
    docstring), by name: what a script's view has, and what the grading child puts in the real
    module (:mod:`ddes.grading.determinism`)."""

    def now() -> float:
        return now_ns() / 1e9

    def clock_gettime(clk_id: int, /) -> float:
        clk_id.__index__()
        return now()

    def clock_gettime_ns(clk_id: int, /) -> int:
        clk_id.__index__()
        return now_ns()

    def gmtime(secs: float | None = None, /) -> _time.struct_time:
        return _real_gmtime(now() if secs is None else secs)

    def ctime(secs: float | None = None, /) -> str:
        return _real_asctime(gmtime(secs))

    def asctime(t: Any = None, /) -> str:
        return _real_asctime(gmtime() if t is None else t)

    def strftime(format: str, t: Any = None, /) -> str:  # noqa: A002 - time's own name
        return _real_strftime(format, gmtime() if t is None else t)

    def mktime(t: Any, /) -> float:
        return float(calendar.timegm(tuple(t)))

    out: dict[str, Any] = {}
    for name in ("time", "monotonic", "perf_counter", "process_time", "thread_time"):
        out[name] = now
        out[f"{name}_ns"] = now_ns
    out.update(clock_gettime=clock_gettime, clock_gettime_ns=clock_gettime_ns, gmtime=gmtime,
               localtime=gmtime, ctime=ctime, asctime=asctime, strftime=strftime, mktime=mktime)
    for name, fn in out.items():
        fn.__name__ = fn.__qualname__ = name
    return out


def module(world: World) -> types.ModuleType:
    """The ``time`` module of a script of ``world``: the kernel clock as the wall clock."""
    env = world.env
    mod = _TimeView("time")

    def now_ns() -> int:
        return int(env.now)

    def sleep(secs: float) -> None:
        """time.sleep on the kernel ("wall") clock: blocks only the calling node."""
        if isinstance(secs, bool) or not isinstance(secs, (int, float)):
            raise TypeError(f"'{type(secs).__name__}' object cannot be interpreted as an integer")
        if math.isnan(secs):
            raise ValueError("Invalid value NaN (not a number)")
        if secs < 0:
            raise ValueError("sleep length must be non-negative")
        if math.isinf(secs):
            raise OverflowError("sleep length is too large")
        wait_ns(env, round(secs * 1e9), "time.sleep()")

    for name, fn in clock_functions(now_ns).items():
        setattr(mod, name, fn)
    # the view's local zone is UTC
    mod.timezone = mod.altzone = mod.daylight = 0  # type: ignore[attr-defined]
    mod.tzname = ("UTC", "UTC")  # type: ignore[attr-defined]
    setattr(mod, "sleep", sleep)  # noqa: B010 - a module attribute
    return mod
