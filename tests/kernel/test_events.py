"""kernel/events.py: the one module on SimPy's internals behaves exactly like SimPy."""

from __future__ import annotations

from collections.abc import Generator
from typing import Any

import pytest
import simpy
from hypothesis import given
from hypothesis import strategies as st

from ddes.kernel.events import NsEnvironment, Posted, is_pending, post, queued_events


def _scenario(env: simpy.Environment, delays: list[int], log: list[tuple[int, str]]) -> None:
    """Processes, timeouts, a failure caught by a process, and plain callbacks."""
    def proc(k: int, d: int) -> Generator[Any, Any, None]:
        yield env.timeout(d)
        log.append((int(env.now), f"p{k}"))
        ev = env.event()
        ev.fail(ValueError(k))
        try:
            yield ev
        except ValueError:
            log.append((int(env.now), f"caught{k}"))
    for k, d in enumerate(delays):
        env.process(proc(k, d))
        env.timeout(d).callbacks.append(lambda _e, k=k: log.append((int(env.now), f"t{k}")))


@given(st.lists(st.integers(min_value=0, max_value=50), max_size=12),
       st.integers(min_value=0, max_value=60))
def test_step_is_simpy_s_step(delays: list[int], until: int) -> None:
    ours: list[tuple[int, str]] = []
    theirs: list[tuple[int, str]] = []
    a, b = NsEnvironment(), simpy.Environment()
    _scenario(a, delays, ours)
    _scenario(b, delays, theirs)
    a.run(until=until or None)
    b.run(until=until or None)
    assert ours == theirs
    assert a.now == a.now_ns == b.now


def test_an_undefused_failure_crashes_the_run_as_in_simpy() -> None:
    env = NsEnvironment()
    ev = env.event()
    ev.fail(KeyError("boom"))
    with pytest.raises(KeyError, match="boom"):
        env.run()


def test_run_until_an_event_stops_there_and_can_go_on() -> None:
    env = NsEnvironment()
    seen: list[int] = []
    stop = env.timeout(5)
    for t in (3, 5, 7):
        env.timeout(t).callbacks.append(lambda _e, t=t: seen.append(t))
    env.run(until=stop)
    assert env.now_ns == 5 and seen == [3]
    env.run()
    assert seen == [3, 5, 7] and env.now_ns == 7


def test_posted_events_carry_their_payload_and_time() -> None:
    env = NsEnvironment()
    got: list[tuple[Any, int, int]] = []
    ev = post(env, 9, "x", lambda e: got.append((e.payload, e.at_ns, env.now_ns)))
    assert isinstance(ev, Posted) and ev.value == "x" and not is_pending(ev)
    assert queued_events(env) == 1
    env.run()
    assert got == [("x", 9, 9)] and queued_events(env) == 0
