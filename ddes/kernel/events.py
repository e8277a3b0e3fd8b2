"""SimPy on integer nanoseconds: the one module that touches SimPy's internals.

Everything else in ddes uses SimPy's public API (``env.now``, ``env.event()``,
``env.timeout()``, ``env.process()``, ``event.callbacks``, ``event.value``)
or the functions here.  SimPy is pinned to ``>=4.1,<5``; ``tests/kernel``
checks the assumptions below against the installed version.

Same-time order.  SimPy keeps one heap keyed ``(time, priority, sequence)``:
events due at the same instant fire urgent-first (process starts and
interrupts), then in the order they were *scheduled* (FIFO by a global
sequence number).  ddes schedules everything through this one heap, so the
order of same-time events is a pure function of the program and the seed.

:func:`post` is the kernel's hottest operation — schedule a value with one
callback.  It is exactly ``env.timeout(delay, value).callbacks.append(cb)``:
the same event type, the same ``(time, NORMAL, sequence)`` heap key, so the
same same-time order, without two Python calls per message.
"""

from __future__ import annotations

from collections.abc import Callable
from heapq import heappush
from typing import Any

import simpy
from simpy.events import NORMAL, PENDING, Event, Timeout

__all__ = ["NsEnvironment", "is_pending", "post", "queued_events"]


class NsEnvironment(simpy.Environment):
    """A SimPy environment whose clock holds integer nanoseconds."""

    @property
    def now(self) -> int:
        """Current kernel time, integer nanoseconds."""
        return self._now  # type: ignore[return-value]


def post(env: simpy.Environment, delay: int, value: Any,
         callback: Callable[[Timeout], object]) -> Timeout:
    """Schedule ``callback(event)`` after ``delay`` ns (>= 0); ``event.value == value``."""
    ev = Timeout.__new__(Timeout)
    ev.env = env
    ev.callbacks = [callback]
    ev._value = value
    ev._delay = delay
    ev._ok = True
    heappush(env._queue, (env._now + delay, NORMAL, next(env._eid), ev))  # type: ignore[attr-defined]
    return ev


def is_pending(event: Event) -> bool:
    """True while ``event`` has neither succeeded nor failed (no value yet)."""
    return event._value is PENDING


def queued_events(env: simpy.Environment) -> int:
    """How many events wait in the kernel's queue (for diagnostics and budgets)."""
    return len(env._queue)  # type: ignore[attr-defined]
