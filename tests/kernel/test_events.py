"""kernel/events.py: the one module on SimPy's internals behaves exactly like SimPy."""

from __future__ import annotations

from collections.abc import Generator
from typing import Any

import pytest
import simpy
from hypothesis import given
from hypothesis import strategies as st

from ddes.kernel.events import (
    NsEnvironment,
    Posted,
    is_pending,
    post,
    queued_events,
    repost,
    succeed,
)


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


def test_repost_schedules_a_processed_event_again_where_post_would() -> None:
    env = NsEnvironment()
    seen: list[tuple[int, object, int]] = []

    def again(e: Posted[str]) -> None:
        seen.append((env.now_ns, e.payload, id(e)))
        if sum(1 for _, q, _ in seen if q == "p") < 3:
            assert repost(env, e, 4, again) is e

    first = post(env, 2, "p", again)
    # due at 6 like the first repost, scheduled earlier: it goes first, as with post()
    env.timeout(6).callbacks.append(lambda _e: seen.append((env.now_ns, "t", 0)))
    env.run()
    assert [(t, p) for t, p, _ in seen] == [(2, "p"), (6, "t"), (6, "p"), (10, "p")]
    assert {i for _, p, i in seen if p == "p"} == {id(first)}
    assert first.at_ns == 10 and first.value == "p" and queued_events(env) == 0


def test_a_periodic_timer_rearms_the_event_that_woke_it() -> None:
    import ddes

    world = ddes.World()
    fired: list[int] = []
    timer = world.create_node("n").create_timer(0.001, lambda ev: fired.append(ev.current_real.to_nsec()))
    world.run(until=0.0035)
    armed = timer._armed
    world.run(until=0.0065)
    assert fired == [1_000_000 * k for k in range(1, 7)]
    assert timer._armed is armed and armed is not None and armed.at_ns == 7_000_000


def test_timeouts_are_of_the_posted_class_and_print_as_simpy_timeouts() -> None:
    env = NsEnvironment()
    t = env.timeout(5, value="v")
    p = post(env, 3, None, lambda _e: None)
    # one class for the kernel's two common events (CPython specializes attribute access to it)
    assert type(t) is type(p) is Posted and isinstance(t, simpy.Timeout)
    assert repr(t).startswith("<Timeout(5, value=v) object at 0x")
    assert repr(p).startswith("<Timeout(3) object at 0x")
    assert repr(env.timeout(1.5)).startswith("<Timeout(1.5) object at 0x")  # SimPy's own
    env.run()
    assert t.value == "v" and env.now_ns == 5


@given(st.lists(st.tuples(st.integers(min_value=0, max_value=5), st.booleans()), max_size=12))
def test_succeed_and_event_order_as_simpy_s(steps: list[tuple[int, bool]]) -> None:
    """Events made by env.event() and triggered by succeed() fire where SimPy's would."""
    def scenario(env: simpy.Environment, trigger: Any) -> list[tuple[int, int, object]]:
        log: list[tuple[int, int, object]] = []
        for k, (delay, ours) in enumerate(steps):
            ev = env.event()
            assert is_pending(ev) and ev.callbacks == [] and not ev.triggered
            ev.callbacks.append(lambda e, k=k: log.append((int(env.now), k, e.value)))

            def fire(_e: Any, ev: Any = ev, k: int = k, ours: bool = ours) -> None:
                log.append((int(env.now), -1 - k, None))
                (trigger if ours else simpy.Event.succeed)(ev, k)
            env.timeout(delay).callbacks.append(fire)
        env.run()
        return log

    assert scenario(NsEnvironment(), succeed) == scenario(simpy.Environment(), simpy.Event.succeed)


def test_succeed_refuses_an_event_triggered_already() -> None:
    env = NsEnvironment()
    ev = env.event()
    succeed(ev, 1)
    assert ev.triggered and ev.ok and ev.value == 1
    with pytest.raises(RuntimeError, match="has already been triggered"):
        succeed(ev, 2)
    with pytest.raises(RuntimeError, match="has already been triggered"):
        ev.succeed(2)


def test_env_event_holds_what_simpy_s_event_holds() -> None:
    env = NsEnvironment()
    ours, theirs = env.event(), simpy.Event(env)
    assert type(ours) is simpy.Event
    assert list(vars(ours)) == list(vars(theirs))  # the same attributes, in the same order
    assert is_pending(ours) and ours.callbacks == []


@given(st.lists(st.integers(min_value=0, max_value=3), min_size=1, max_size=20))
def test_progress_grows_with_every_step_and_now_follows_the_events(delays: list[int]) -> None:
    """env.progress() (what the wall-clock watchdog watches) is larger after every step, and
    now_ns (stored only when the time moves) is every event's time, as SimPy's now is."""
    env, ref = NsEnvironment(), simpy.Environment()
    for e in (env, ref):
        for d in delays:
            e.timeout(d).callbacks.append(lambda ev: ev.env.timeout(0))  # one more at that time
    marks, times = [env.progress()], []
    while env.peek() != float("inf"):
        env.step()
        ref.step()
        marks.append(env.progress())
        times.append((env.now_ns, env.now, int(ref.now)))
    assert all(a < b for a, b in zip(marks, marks[1:])), marks
    assert all(a == b == c for a, b, c in times), times
    assert len(marks) == 2 * len(delays) + 1
