"""Clocks: where a node's ROS time comes from.

* :class:`KernelClock` reads the world's kernel time.  It is every node's
  clock unless the node uses simulated time, and it is always the clock of
  the Wall* variants (``WallTime``, ``WallDuration``, ``WallRate``).
* :class:`SimClock` is the ``use_sim_time`` clock: its time is the latest
  value received on ``/clock`` and **zero until the first one**, as in ROS.
  It does not advance between updates, and it may jump backwards (for
  example ``rosbag play --loop --clock``); sleepers see that jump as ROS
  defines it.

Both hand out events to ``yield``: :meth:`wait_until` fires once the clock
has reached an instant.
"""

from __future__ import annotations

import heapq
from collections.abc import Callable
from typing import TYPE_CHECKING, Protocol

from ddes.errors import ROSTimeMovedBackwardsException
from ddes.time.rostime import Time, WallTime

if TYPE_CHECKING:
    import simpy
    from simpy.events import ProcessGenerator

    from ddes.time.units import HasNsec

__all__ = ["Clock", "ClockMessage", "ClockOwner", "KernelClock", "NsEnv", "SimClock"]


class NsEnv(Protocol):
    """The SimPy environment of a world as the clocks use it: ``now`` is integer
    nanoseconds (the kernel's ``NsEnvironment``)."""

    #: The kernel's time as a plain attribute, and its events at that time after the first.
    now_ns: int
    _same_instant: int
    #: Blocking calls since the kernel's last step (:func:`ddes.time.sleep.must_yield`).
    unyielded: list[int]

    @property
    def now(self) -> int: ...

    def timeout(self, delay: int = 0, value: object = None) -> simpy.Timeout: ...

    def event(self) -> simpy.Event: ...

    def process(self, generator: ProcessGenerator) -> simpy.Process: ...


class ClockMessage(Protocol):
    """A ``rosgraph_msgs/Clock`` message: its ``clock`` field is the time."""

    @property
    def clock(self) -> HasNsec: ...


class Clock:
    """Interface shared by the clocks (see module docstring)."""

    is_sim: bool = False

    def __init__(self, env: NsEnv) -> None:
        #: The SimPy environment whose ``now`` is integer nanoseconds.
        self.env = env

    def now_ns(self) -> int:
        """Current time of this clock, integer nanoseconds."""
        raise NotImplementedError

    def get_rostime(self) -> Time:
        """Current time as :class:`Time`."""
        return Time._from_ns(self.now_ns())

    def get_time(self) -> float:
        """Current time as float seconds (rospy.get_time)."""
        return self.now_ns() / 1e9

    def is_valid(self) -> bool:
        """False while a simulated clock has not received its first /clock."""
        return True

    def wait_valid(self) -> simpy.Event:
        """Event that fires once :meth:`is_valid` is true."""
        raise NotImplementedError

    def wait_until(self, target_ns: int, start_ns: int | None = None) -> simpy.Event:
        """Event that fires once the clock reads at least ``target_ns``.

        If ``start_ns`` is given and the clock jumps back below it, the event
        fails with :class:`ROSTimeMovedBackwardsException` (rospy.sleep).
        """
        raise NotImplementedError

    def add_jump_listener(self, fn: Callable[[int, int], None]) -> None:
        """Call ``fn(old_ns, new_ns)`` whenever the clock jumps backwards."""

    def remove_jump_listener(self, fn: Callable[[int, int], None]) -> None:
        """Undo :meth:`add_jump_listener`."""


class KernelClock(Clock):
    """The world's kernel time (never jumps backwards)."""

    is_sim = False

    def now_ns(self) -> int:
        return self.env.now

    def get_walltime(self) -> WallTime:
        """Kernel time as a WallTime."""
        return WallTime._from_ns(self.env.now)

    def wait_valid(self) -> simpy.Event:
        return self.env.timeout(0)

    def wait_until(self, target_ns: int, start_ns: int | None = None) -> simpy.Event:
        delay = target_ns - self.env.now
        return self.env.timeout(delay if delay > 0 else 0)


class SimClock(Clock):
    """ROS time driven by ``/clock`` (use_sim_time); zero until the first update."""

    is_sim = True

    def __init__(self, env: NsEnv) -> None:
        super().__init__(env)
        self._now = 0
        self._seq = 0
        # (target_ns, seq, start_ns or -1, event)
        self._waiters: list[tuple[int, int, int, simpy.Event]] = []
        self._valid_waiters: list[simpy.Event] = []
        self._jump_listeners: list[Callable[[int, int], None]] = []
        #: Number of /clock updates received.
        self.updates = 0

    def now_ns(self) -> int:
        return self._now

    def is_valid(self) -> bool:
        return self._now != 0

    def update(self, t: int | HasNsec | ClockMessage) -> None:
        """Set the time from a ``/clock`` message, a Time or integer ns."""
        if isinstance(t, int):
            new = t
        else:
            clock_field = getattr(t, "clock", None)  # rosgraph_msgs/Clock
            # Without a clock field, t is a Time (HasNsec).
            new = (clock_field if clock_field is not None else t).to_nsec()  # type: ignore[union-attr]
        old = self._now
        self._now = new
        self.updates += 1
        if new < old:
            keep = []
            for item in self._waiters:
                target, _seq, start, ev = item
                if start >= 0 and new < start:
                    if not ev.triggered:
                        ev.fail(ROSTimeMovedBackwardsException((start - new) / 1e9))
                else:
                    keep.append(item)
            heapq.heapify(keep)
            self._waiters = keep
            for fn in list(self._jump_listeners):
                fn(old, new)
        if old == 0 and new != 0 and self._valid_waiters:
            waiters, self._valid_waiters = self._valid_waiters, []
            for ev in waiters:
                if not ev.triggered:
                    ev.succeed()
        while self._waiters and self._waiters[0][0] <= new:
            ev = heapq.heappop(self._waiters)[3]
            if not ev.triggered:
                ev.succeed()

    def wait_valid(self) -> simpy.Event:
        ev = self.env.event()
        if self._now != 0:
            ev.succeed()
        else:
            self._valid_waiters.append(ev)
        return ev

    def wait_until(self, target_ns: int, start_ns: int | None = None) -> simpy.Event:
        ev = self.env.event()
        if self._now >= target_ns:
            ev.succeed()
        else:
            self._seq += 1
            heapq.heappush(
                self._waiters, (target_ns, self._seq, -1 if start_ns is None else start_ns, ev)
            )
        return ev

    def add_jump_listener(self, fn: Callable[[int, int], None]) -> None:
        self._jump_listeners.append(fn)

    def remove_jump_listener(self, fn: Callable[[int, int], None]) -> None:
        if fn in self._jump_listeners:
            self._jump_listeners.remove(fn)


class ClockOwner(Protocol):
    """A node as :func:`~ddes.time.sleep.sleep` and the rates see it: it has a :attr:`clock`."""

    @property
    def clock(self) -> Clock: ...
