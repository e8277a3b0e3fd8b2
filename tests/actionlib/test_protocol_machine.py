"""The protocol machine (ddes.testing.actions): no violation on the reference servers, and it
finds (and shrinks) the bugs planted in broken ones."""

from __future__ import annotations

from typing import Any

import pytest
from hypothesis import strategies as st

from ddes.testing.actions import ActionProtocolMachine, ProtocolViolation, run_protocol_machine

from .servers import (
    make_leaky_fibonacci,
    make_sampling,
    make_sampling_forgetful,
    make_tester,
    make_timed,
)


def _tenths(n: int) -> dict[str, int]:
    return {"secs": n // 10, "nsecs": (n % 10) * 100_000_000}


#: Goals for simple_tester_server: every ending but LOSE (which breaks the protocol on purpose).
tester_goals = st.fixed_dictionaries({
    "terminate_status": st.sampled_from([0, 1, 2, 4, 5]),
    "ignore_cancel": st.booleans(),
    "the_result": st.integers(-3, 3),
    "delay_terminate": st.integers(0, 30).map(_tenths),
})
small_goals = st.integers(0, 20).map(lambda g: {"goal": g})

TestTesterServerProtocol = ActionProtocolMachine.for_server(
    make_tester, goals=tester_goals, max_examples=100, derandomize=True)
TestTimedActionServerProtocol = ActionProtocolMachine.for_server(
    make_timed, goals=small_goals, max_examples=100, derandomize=True)
TestSamplingServerProtocol = ActionProtocolMachine.for_server(
    make_sampling, goals=small_goals, max_examples=100, derandomize=True)


@pytest.mark.slow
def test_reference_servers_survive_many_more_schedules() -> None:
    for make, goals in ((make_tester, tester_goals), (make_timed, small_goals),
                        (make_sampling, small_goals)):
        run_protocol_machine(make, goals=goals, max_examples=200, stateful_step_count=40)


def violation_of(make: Any, goals: Any) -> str:
    with pytest.raises(ProtocolViolation) as info:
        run_protocol_machine(make, goals=goals, settle=5.0, max_examples=200,
                             stateful_step_count=10, derandomize=True, database=None)
    return str(info.value)


def test_finds_the_missing_return_after_set_preempted() -> None:
    text = violation_of(make_leaky_fibonacci,
                        st.integers(2, 6).map(lambda n: {"order": n}))
    assert "illegal goal-handle call: set_succeeded" in text
    assert "in state PREEMPTED" in text
    assert "replay: world seed" in text
    # shrunk to a short schedule: the goal, something that preempts it, time passing
    schedule = text.split("schedule (simulated time, step):")[1].split("last messages")[0]
    steps = [line for line in schedule.splitlines() if line.strip()]
    assert len(steps) <= 6, text


def test_finds_a_preempted_goal_that_never_ends() -> None:
    text = violation_of(make_sampling_forgetful, small_goals)
    assert "never got a result" in text or "not DONE on the client" in text
    assert "replay: world seed" in text


def test_machine_needs_a_server() -> None:
    from ddes.errors import DdesTypeError, DdesValueError

    with pytest.raises(DdesTypeError):
        ActionProtocolMachine.machine_for("not callable")  # type: ignore[arg-type]
    with pytest.raises(DdesValueError, match="pass action= and ns="):
        ActionProtocolMachine.machine_for(lambda world, node: object())


def test_machine_reads_type_and_namespace_from_the_server() -> None:
    machine = ActionProtocolMachine.machine_for(make_timed)
    assert machine.ns == "/timed"
    assert machine.action._type == "actionlib/TestAction"
