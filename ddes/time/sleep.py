"""``sleep(d)`` as an event to yield, with rospy's semantics.

* On the kernel clock a negative duration returns at once (a zero-delay
  event, so the sleeper resumes in the same instant).
* On a simulated clock it first waits for the first ``/clock`` while time
  reads zero, then waits until ``start + d``; if time jumps back below the
  start it fails with :class:`ROSTimeMovedBackwardsException`.
* roscpp's ``Duration::sleep()`` is :func:`duration_sleep`: the event's
  value is False if time jumped backwards during the sleep.
"""

from __future__ import annotations

from collections.abc import Generator
from typing import Any

import simpy

from ddes.errors import DdesTypeError, ForgottenYieldError, ROSTimeMovedBackwardsException
from ddes.time.clock import Clock, ClockOwner
from ddes.time.rospy_calls import REQUIRED, arg_text, missing_node
from ddes.time.units import DurationLike, duration_to_ns

__all__ = ["MUST_YIELD", "duration_sleep", "must_yield", "sleep", "sleep_ns"]

#: The attribute naming a blocking call on the event it returned; the kernel warns
#: (``NeverYieldedWarning``) when such an event fires with nobody waiting on it.
MUST_YIELD = "ddes_must_yield"


#: Blocking calls in a row, with the kernel taking no step between them, after which the loop
#: making them is stopped as one whose ``yield`` is missing (a loop that yields runs the kernel
#: between its calls; one that does not spins at one instant forever).
FORGOTTEN_YIELD_CALLS = 100_000


def must_yield(event: simpy.Event, label: str) -> simpy.Event:
    """Mark ``event`` as the result of the blocking call ``label`` (``"rate.sleep()"``).

    :data:`FORGOTTEN_YIELD_CALLS` of them in a row with no kernel step between raise
    :class:`~ddes.errors.ForgottenYieldError` naming the missing ``yield``."""
    setattr(event, MUST_YIELD, label)
    env: Any = event.env
    box = getattr(env, "unyielded", None)
    if box is not None:
        now, same = env.now_ns, env._same_instant
        if box[0] == now and box[1] == same:
            n = box[2] = box[2] + 1
            if n >= FORGOTTEN_YIELD_CALLS:
                forgotten_yield(label, now)
        else:
            box[0], box[1], box[2] = now, same, 1
    return event


def forgotten_yield(label: str, now_ns: int) -> None:
    """Raise the error of a loop that calls ``label`` without yielding it."""
    raise ForgottenYieldError(
        f"{label} was called {FORGOTTEN_YIELD_CALLS} times in a row at simulated "
        f"t={now_ns / 1e9:.9f} s without the kernel running in between: a blocking call returns "
        f"an event that waits only when it is yielded. Write `yield {label}` in a generator "
        f"(def main(): ... yield {label}) and start it with node.process(main())")


def _sim_sleep(clock: Clock, d_ns: int) -> Generator[simpy.Event, object, bool]:
    start = clock.now_ns()
    if start == 0:
        yield clock.wait_valid()
        start = clock.now_ns()
    target = start + d_ns
    if clock.now_ns() >= target:
        return False
    yield clock.wait_until(target, start)
    return True


def sleep_ns(clock: Clock, d_ns: int) -> simpy.Event:
    """Sleep ``d_ns`` nanoseconds of ``clock`` time (see module docstring)."""
    if not clock.is_sim:
        return clock.env.timeout(d_ns if d_ns > 0 else 0)
    return clock.env.process(_sim_sleep(clock, d_ns))


def _clock_for(fn: str, method: str, clock: object, duration: object) -> Clock:
    """The clock of ``clock`` (a node or a clock); a rospy-shaped ``fn(0.5)`` is explained."""
    if duration is REQUIRED:
        if getattr(clock, "clock", clock) is clock and not isinstance(clock, Clock):
            d = arg_text(clock)
            raise missing_node(f"ddes.{fn}({d})",
                               f"yield node.{method}({d})    # or: yield ddes.{fn}(node, {d})",
                               "(in the node's process, node.process(main()), or in a "
                               "generator callback)")
        raise DdesTypeError(f"ddes.{fn} needs a duration: yield node.{method}(0.5)")
    clk = getattr(clock, "clock", clock)  # a node's clock, or the clock
    if not isinstance(clk, Clock):
        raise DdesTypeError(f"ddes.{fn}(node, duration) needs a node or a clock first, got "
                            f"{clock!r}: yield node.{method}({arg_text(duration)})")
    return clk


def sleep(clock: Clock | ClockOwner, duration: DurationLike = REQUIRED) -> simpy.Event:
    """rospy.sleep: ``yield sleep(node, 0.5)`` or ``yield node.sleep(0.5)``."""
    clk = _clock_for("sleep", "sleep", clock, duration)
    return must_yield(sleep_ns(clk, duration_to_ns(duration)), "sleep(...)")


def _cpp_sim_sleep(clock: Clock, d_ns: int) -> Generator[simpy.Event, object, bool]:
    try:
        slept = yield from _sim_sleep(clock, d_ns)
    except ROSTimeMovedBackwardsException:
        return False
    return bool(slept)


def duration_sleep(clock: Clock | ClockOwner, duration: DurationLike = REQUIRED) -> simpy.Event:
    """roscpp ``Duration::sleep()``: the event's value is True if it slept.

    Under simulated time it is False when time jumped backwards or no sleep
    was needed at all, as roscpp reports.
    """
    clk = _clock_for("duration_sleep", "duration_sleep", clock, duration)
    d_ns = duration_to_ns(duration)
    if not clk.is_sim:
        return clk.env.timeout(d_ns if d_ns > 0 else 0, True)
    return clk.env.process(_cpp_sim_sleep(clk, d_ns))
