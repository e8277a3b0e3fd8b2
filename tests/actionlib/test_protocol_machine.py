"""The protocol machine (ddes.testing.actions): no violation on the reference servers, and it
finds (and shrinks) the bugs planted in broken ones; the replay call and the replay plot."""

from __future__ import annotations

import ast
import functools
import re
from collections.abc import Generator
from typing import Any

import matplotlib

matplotlib.use("Agg")

import pytest  # noqa: E402
from hypothesis import strategies as st  # noqa: E402

from ddes.actionlib import SimpleActionServer  # noqa: E402
from ddes.testing._replay import VIOLATION_GID  # noqa: E402
from ddes.testing.actions import (  # noqa: E402
    ActionProtocolMachine,
    ProtocolViolation,
    _same_problem,
    replay_action_schedule,
    run_protocol_machine,
)

from .servers import (  # noqa: E402
    FibFeedback,
    FibResult,
    RefFibonacciAction,
    make_leaky_fibonacci,
    make_sampling,
    make_sampling_forgetful,
    make_tester,
    make_timed,
)


def make_deaf_fibonacci(world: Any, node: Any) -> SimpleActionServer:
    """A planted bug: the execute callback never looks at is_preempt_requested(), so a cancelled
    goal runs on to the end (one number per second) and only then succeeds."""

    def execute(goal: Any) -> Generator[Any, Any, None]:
        seq = [0, 1]
        for i in range(1, goal.order):
            seq.append(seq[i] + seq[i - 1])
            server.publish_feedback(FibFeedback(sequence=seq))
            yield node.sleep(1.0)
        server.set_succeeded(FibResult(sequence=seq))

    server = SimpleActionServer(node, "fibonacci", RefFibonacciAction, execute, auto_start=False)
    server.start()
    return server


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

# The tester ignores cancels on purpose when a goal says so (ignore_cancel), and goals queued
# behind such a goal wait for it: no preemption deadline for it (preempt_timeout=None).
TestTesterServerProtocol = ActionProtocolMachine.for_server(
    make_tester, goals=tester_goals, preempt_timeout=None, max_examples=100, derandomize=True)
TestTimedActionServerProtocol = ActionProtocolMachine.for_server(
    make_timed, goals=small_goals, max_examples=100, derandomize=True)
TestSamplingServerProtocol = ActionProtocolMachine.for_server(
    make_sampling, goals=small_goals, max_examples=100, derandomize=True)


@pytest.mark.slow
def test_reference_servers_survive_many_more_schedules() -> None:
    for make, goals, preempt in ((make_tester, tester_goals, None), (make_timed, small_goals, 5.0),
                                 (make_sampling, small_goals, 5.0)):
        run_protocol_machine(make, goals=goals, preempt_timeout=preempt, max_examples=200,
                             stateful_step_count=40)


def violation_of(make: Any, goals: Any) -> ProtocolViolation:
    with pytest.raises(ProtocolViolation) as info:
        run_protocol_machine(make, goals=goals, settle=5.0, max_examples=200,
                             stateful_step_count=10, derandomize=True, database=None)
    return info.value


@functools.lru_cache(maxsize=1)
def leaky_violation() -> ProtocolViolation:
    """The machine on the leaky server (run once for the tests below)."""
    return violation_of(make_leaky_fibonacci, st.integers(2, 6).map(lambda n: {"order": n}))


def test_finds_the_missing_return_after_set_preempted() -> None:
    text = str(leaky_violation())
    assert "illegal goal-handle call: set_succeeded" in text
    assert "in state PREEMPTED" in text
    assert "replay: world seed" in text
    # shrunk to a short schedule: the goal, something that preempts it, time passing
    schedule = text.split("schedule (step, simulated time, what):")[1].split("last messages")[0]
    steps = [line for line in schedule.splitlines() if line.strip()]
    assert len(steps) <= 6, text
    # no step that changed nothing is left (the machine draws none)
    v = leaky_violation()
    assert v.noops == []
    assert replay_action_schedule(make_leaky_fibonacci, v.steps, seed=v.seed).noops == []


def test_finds_a_preempted_goal_that_never_ends() -> None:
    text = str(violation_of(make_sampling_forgetful, small_goals))
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


@functools.lru_cache(maxsize=1)
def deaf_violation() -> ProtocolViolation:
    """The machine on the deaf server (run once for the tests below)."""
    with pytest.raises(ProtocolViolation) as info:
        run_protocol_machine(make_deaf_fibonacci, goals=st.integers(0, 10).map(
            lambda n: {"order": n}), max_examples=30, stateful_step_count=8, derandomize=True,
            database=None)
    return info.value


def test_a_server_that_ignores_cancel_requests_fails_and_shrinks() -> None:
    v = deaf_violation()
    text = str(v)
    print(text)  # the shrunk schedule, as a user sees it
    assert "preemption ignored" in v.problem
    assert re.search(r"took a cancel request \((PREEMPTING|RECALLING)\)", v.problem)
    # shrunk: a goal long enough to outlast preempt_timeout (the final check cancels it), and
    # nothing the failure does not need: without any one step it no longer fails this way
    assert 1 <= len(v.steps) <= 3 and v.steps[0][0] == "send_goal", text
    assert v.step == len(v.steps)  # seen in the final check (cancel everything, settle)
    assert v.noops == []
    assert f"replay_action_schedule(make_deaf_fibonacci, {v.steps!r}, seed={v.seed}, " \
           "action='actionlib_tutorials/FibonacciAction', ns='/fibonacci')" in text
    for i in range(len(v.steps)):
        fewer = replay_action_schedule(make_deaf_fibonacci, v.steps[:i] + v.steps[i + 1:],
                                       seed=v.seed)
        assert fewer.violation is None or not _same_problem(fewer.violation.problem, v.problem)

    # the printed call replays it, and its plot marks the violating step
    call = ast.parse(v.replay, mode="eval").body
    assert isinstance(call, ast.Call)
    replay = eval(v.replay, {"replay_action_schedule": replay_action_schedule,  # noqa: S307
                             "make_deaf_fibonacci": make_deaf_fibonacci})
    assert replay.violation is not None and replay.violation.problem == v.problem
    assert replay.step == v.step and replay.world.now == v.t_ns
    fig = replay.plot()
    marks = [a for a in fig.axes[0].get_children() if a.get_gid() == VIOLATION_GID]
    lines = [a for a in marks if isinstance(a, matplotlib.lines.Line2D)]
    assert lines and lines[0].get_xdata()[0] == pytest.approx(v.t_ns / 1e9)
    assert any("final check" in getattr(a, "get_text", lambda: "")() for a in marks)


def test_replay_marks_the_step_that_broke_the_protocol() -> None:
    # the leaky server's set_succeeded after set_preempted happens during the third step
    steps = [("send_goal", {"order": 4}), ("cancel_all_goals",), ("advance", 1.0)]
    replay = replay_action_schedule(make_leaky_fibonacci, steps, seed=0)
    assert replay.violation is not None and replay.step == 2
    assert "illegal goal-handle call: set_" in replay.violation.problem
    start, end = replay.spans[2]
    assert end - start == 1_000_000_000 and replay.violation.t_ns == end
    fig = replay.plot()
    marks = [a for a in fig.axes[0].get_children() if a.get_gid() == VIOLATION_GID]
    texts = [a.get_text() for a in marks if hasattr(a, "get_text")]
    assert any(t.startswith("step 2: advance 1.0") for t in texts), texts
    band = [a for a in marks if isinstance(a, matplotlib.patches.Polygon
                                           | matplotlib.patches.Rectangle)]
    assert band, marks


def test_a_replay_marks_its_no_op_steps() -> None:
    # and a no-op is seen as one: a latency set to the value it has, advance 0.0 with nothing due
    replay = replay_action_schedule(make_timed, [("set_latency", "goal", 0.0), ("advance", 0.0),
                                                 ("advance", 0.5)], seed=0)
    assert replay.violation is None and replay.noops == [0, 1]


def test_a_replay_step_that_cannot_run_is_refused() -> None:
    from ddes.errors import DdesValueError

    with pytest.raises(DdesValueError, match="no goal to cancel"):
        replay_action_schedule(make_timed, [("cancel_all_goals",)])
    with pytest.raises(DdesValueError, match="unknown step"):
        replay_action_schedule(make_timed, [("jump",)])
