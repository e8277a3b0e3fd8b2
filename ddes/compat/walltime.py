"""``time`` as a rospy script sees it: the kernel clock plays the wall clock.

A rospy node takes wall time from Python's ``time`` module (rospy has no WallTime: a status line
prints ``time.time()``, a wall-paced loop calls ``time.sleep(1.0)``, and
``rospy.rostime.wallsleep`` is ``time.sleep``).  In ddes nothing reads the computer's clock: the
kernel's clock is the wall clock (docs/time.md), the clock that ``rosbag play -r 2`` and a
simulator's ``real_time_factor`` are measured against.  In a script, ``import time`` gives this
view (:mod:`ddes.compat.scripts`):

* ``time()``, ``monotonic()``, ``perf_counter()`` are the kernel time in float seconds (counted
  from the world's start, not from 1970), ``time_ns()``, ``monotonic_ns()``,
  ``perf_counter_ns()`` the same in integer ns;
* ``sleep(secs)`` blocks the calling node (greenlet) for ``secs`` of kernel time, whatever its
  ROS clock (a sim-time node's wall sleep goes on while ``/clock`` stands still); a negative
  value raises ``ValueError("sleep length must be non-negative")`` as Python's does;
* everything else is the real ``time`` module (``strftime``, ``struct_time`` ...).

Two runs of the same seed read the same times, so a script's log stays deterministic.
"""

from __future__ import annotations

import math
import time as _time
import types
from typing import TYPE_CHECKING, Any

from ddes.graph.blocking import wait_ns

if TYPE_CHECKING:
    from ddes.graph.world import World

__all__ = ["module"]


class _TimeView(types.ModuleType):
    def __getattr__(self, name: str) -> Any:
        return getattr(_time, name)


def module(world: World) -> types.ModuleType:
    """The ``time`` module of a script of ``world``: the kernel clock as the wall clock."""
    env = world.env
    mod = _TimeView("time")

    def now_ns() -> int:
        return int(env.now)

    def now() -> float:
        return int(env.now) / 1e9

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

    for name in ("time", "monotonic", "perf_counter"):
        setattr(mod, name, now)
    for name in ("time_ns", "monotonic_ns", "perf_counter_ns"):
        setattr(mod, name, now_ns)
    setattr(mod, "sleep", sleep)  # noqa: B010 - a module attribute
    return mod
