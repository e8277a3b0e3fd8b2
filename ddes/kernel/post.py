"""A fast path for the kernel's hottest operation: schedule a value with one callback.

``post(env, delay, value, callback)`` is exactly
``env.timeout(delay, value).callbacks.append(callback)`` — the same event
type, the same ``(time, NORMAL, sequence)`` heap key, so the same-time order
— without two Python calls per message.  It relies on SimPy 4's
``Environment._queue``/``_eid`` and ``Timeout``'s slots; ``tests/kernel``
checks that it orders events exactly like ``env.timeout``.
"""

from __future__ import annotations

from collections.abc import Callable
from heapq import heappush
from typing import Any

from simpy.events import NORMAL, Timeout

__all__ = ["post"]


def post(env: Any, delay: int, value: Any, callback: Callable[[Any], Any]) -> Timeout:
    """Schedule ``callback(event)`` after ``delay`` ns (>= 0) with ``event.value == value``."""
    ev = Timeout.__new__(Timeout)
    ev.env = env
    ev.callbacks = [callback]
    ev._value = value
    ev._delay = delay
    ev._ok = True
    heappush(env._queue, (env._now + delay, NORMAL, next(env._eid), ev))
    return ev
