"""The actionlib state tables: properties, and comparison with real actionlib."""

from __future__ import annotations

import itertools
import json
from pathlib import Path

import pytest
from hypothesis import HealthCheck, Phase, given, settings
from hypothesis import strategies as st

from ddes.actionlib import (
    COMM_TRANSITIONS,
    INVALID_TRANSITION,
    NO_TRANSITION,
    SERVER_STATES,
    SERVER_TRANSITIONS,
    TERMINAL_STATUSES,
    CommState,
    GoalStatus,
    ServerEvent,
    SimpleCallback,
    SimpleGoalState,
    apply_comm_cancel,
    apply_comm_result,
    apply_comm_status,
    comm_target,
    render_tables,
    rospy_status_name,
    server_transition,
    simple_get_state,
    simple_transition,
)
from ddes.errors import DdesTypeError, DdesValueError

from ..docsnippets import run_snippet
from .ros_harness import (
    COMM_SCRIPT,
    COMM_TABLE_SCRIPT,
    GOAL_HANDLE_SCRIPT,
    SIMPLE_SCRIPT,
    replay_comm,
    replay_goal_handle,
)

# the ros_python fixture is stateless, and one example is a batch of many runs
INTEROP_CHECKS = [HealthCheck.function_scoped_fixture, HealthCheck.data_too_large,
                  HealthCheck.too_slow]
DOC = Path(__file__).resolve().parents[2] / "docs" / "actionlib.md"

events = st.sampled_from(list(ServerEvent))
server_states = st.sampled_from(SERVER_STATES)
comm_states = st.sampled_from(list(CommState))
wire_statuses = st.integers(min_value=0, max_value=255)


# --- enums ----------------------------------------------------------------------------------------


def test_enum_values_are_ros_values() -> None:
    assert [(s.name, s.value) for s in GoalStatus] == [
        ("PENDING", 0), ("ACTIVE", 1), ("PREEMPTED", 2), ("SUCCEEDED", 3), ("ABORTED", 4),
        ("REJECTED", 5), ("PREEMPTING", 6), ("RECALLING", 7), ("RECALLED", 8), ("LOST", 9),
    ]
    assert [c.name for c in CommState] == [
        "WAITING_FOR_GOAL_ACK", "PENDING", "ACTIVE", "WAITING_FOR_RESULT",
        "WAITING_FOR_CANCEL_ACK", "RECALLING", "PREEMPTING", "DONE", "LOST",
    ]
    assert [c.value for c in CommState] == list(range(9))
    assert [(s.name, s.value) for s in SimpleGoalState] == [("PENDING", 0), ("ACTIVE", 1), ("DONE", 2)]
    assert {s.name for s in TERMINAL_STATUSES} == {
        "PREEMPTED", "SUCCEEDED", "ABORTED", "REJECTED", "RECALLED"
    }


# --- the server goal table --------------------------------------------------------------------------


def test_server_table_is_complete_over_wire_states() -> None:
    assert set(SERVER_TRANSITIONS) == set(SERVER_STATES)
    assert GoalStatus.LOST not in SERVER_TRANSITIONS
    for row in SERVER_TRANSITIONS.values():
        assert set(row) == set(ServerEvent)


@given(server_states.filter(lambda s: s in TERMINAL_STATUSES), events)
def test_terminal_states_are_absorbing(state: GoalStatus, event: ServerEvent) -> None:
    tr = server_transition(state, event)
    assert not tr.legal
    assert tr.after is state


@given(st.lists(events, max_size=12))
def test_every_path_from_pending_stays_in_legal_states(path: list[ServerEvent]) -> None:
    reachable = {
        GoalStatus.PENDING, GoalStatus.ACTIVE, GoalStatus.RECALLING, GoalStatus.PREEMPTING,
    } | TERMINAL_STATUSES
    state = GoalStatus.PENDING
    terminal_reached = False
    for event in path:
        tr = server_transition(state, event)
        assert tr.before is state
        assert tr.after in reachable
        if tr.legal:
            assert tr.after is SERVER_TRANSITIONS[state][event]
            assert tr.error is None
            assert tr.terminal == (tr.after in TERMINAL_STATUSES)
        else:
            assert tr.after is state
            assert (tr.error is None) == (event is ServerEvent.CANCEL_REQUEST)
        # once terminal, always that terminal state
        if terminal_reached:
            assert tr.after is state and not tr.legal
        terminal_reached = tr.after in TERMINAL_STATUSES
        state = tr.after


@given(server_states, events)
def test_cancel_request_only_from_pending_or_active(state: GoalStatus, event: ServerEvent) -> None:
    tr = server_transition(state, ServerEvent.CANCEL_REQUEST)
    assert tr.legal == (state in (GoalStatus.PENDING, GoalStatus.ACTIVE))
    # a legal transition never leads back to PENDING or ACTIVE from a cancel state
    t2 = server_transition(state, event)
    if state in (GoalStatus.RECALLING, GoalStatus.PREEMPTING) and t2.legal:
        assert t2.after not in (GoalStatus.PENDING, GoalStatus.ACTIVE)


def test_illegal_transition_texts_are_rospys() -> None:
    assert server_transition(3, "accept").error == (
        "To transition to an active state, the goal must be in a pending or recalling state, "
        "it is currently in state: 3"
    )
    assert server_transition(GoalStatus.ACTIVE, ServerEvent.REJECT).error == (
        "To transition to a rejected state, the goal must be in a pending or recalling state, "
        "it is currently in state: 1"
    )
    assert server_transition(GoalStatus.PENDING, "succeed").error == (
        "To transition to a succeeded state, the goal must be in a preempting or active state, "
        "it is currently in state: 0"
    )
    assert server_transition(GoalStatus.RECALLING, "abort").error == (
        "To transition to an aborted state, the goal must be in a preempting or active state, "
        "it is currently in state: 7"
    )
    assert server_transition(GoalStatus.RECALLED, "cancel").error == (
        "To transition to a cancelled state, the goal must be in a pending, recalling, active, "
        "or preempting state, it is currently in state: 8"
    )
    refused = server_transition(GoalStatus.PREEMPTING, "cancel_request")
    assert not refused.legal and refused.error is None


def test_server_transition_rejects_bad_input() -> None:
    with pytest.raises(DdesValueError, match="'finish'"):
        server_transition(GoalStatus.PENDING, "finish")
    with pytest.raises(DdesValueError, match="42 is not a GoalStatus"):
        server_transition(42, "accept")
    with pytest.raises(DdesTypeError, match="GoalStatus"):
        server_transition("PENDING", "accept")  # type: ignore[arg-type]
    with pytest.raises(DdesTypeError):
        server_transition(GoalStatus.PENDING, 3)  # type: ignore[arg-type]


def test_ros_method_names() -> None:
    assert [e.ros_method for e in ServerEvent] == [
        "set_accepted", "set_rejected", "set_canceled", "set_cancel_requested",
        "set_succeeded", "set_aborted",
    ]


# --- the client comm table -------------------------------------------------------------------------


def test_comm_table_shape() -> None:
    assert set(COMM_TRANSITIONS) == set(CommState) - {CommState.LOST}
    for row in COMM_TRANSITIONS.values():
        assert set(row) == set(GoalStatus) - {GoalStatus.LOST}
    assert comm_target(CommState.WAITING_FOR_GOAL_ACK, GoalStatus.SUCCEEDED) == (
        CommState.ACTIVE, CommState.WAITING_FOR_RESULT,
    )
    assert comm_target(CommState.PENDING, GoalStatus.RECALLED) == (
        CommState.RECALLING, CommState.WAITING_FOR_RESULT,
    )
    assert comm_target(CommState.WAITING_FOR_CANCEL_ACK, GoalStatus.SUCCEEDED) == (
        CommState.PREEMPTING, CommState.WAITING_FOR_RESULT,
    )
    with pytest.raises(DdesValueError, match="LOST"):
        comm_target(CommState.LOST, GoalStatus.PENDING)
    with pytest.raises(DdesValueError, match="LOST"):
        comm_target(CommState.ACTIVE, GoalStatus.LOST)


@given(comm_states.filter(lambda c: c is not CommState.LOST), st.sampled_from(list(GoalStatus)[:9]))
def test_comm_status_then_same_status_again_changes_nothing(c: CommState, s: GoalStatus) -> None:
    # the server re-publishes the same status at 5 Hz: repeating it must be harmless
    first = apply_comm_status(c, s)
    again = apply_comm_status(first.after, s)
    assert again.passed == ()
    assert again.after is first.after


@given(comm_states, st.one_of(st.none(), wire_statuses))
def test_comm_status_update_is_consistent(c: CommState, s: int | None) -> None:
    u = apply_comm_status(c, s)
    assert u.before is c
    assert u.after is (u.passed[-1] if u.passed else c)
    if c is CommState.DONE:
        assert u == apply_comm_status(c, None) and u.passed == () and not u.errors
    if u.lost:
        assert s is None and u.after is CommState.DONE and u.latest_status == GoalStatus.LOST
    if s is None:
        assert u.lost == (c not in (CommState.WAITING_FOR_GOAL_ACK,
                                    CommState.WAITING_FOR_RESULT, CommState.DONE))
    elif c is not CommState.DONE:
        assert u.latest_status == s
    # DONE is never entered from a status array, only by LOST or a result
    assert CommState.DONE not in u.passed or u.lost


@given(comm_states, st.integers(min_value=0, max_value=9))
def test_comm_result_reaches_done_exactly_once(c: CommState, s: int) -> None:
    u = apply_comm_result(c, s)
    assert u.latest_status == s
    if c is CommState.DONE:
        assert u.passed == () and u.errors == ("Got a result when we were already in the DONE state",)
    elif c is CommState.LOST:
        assert u.passed == () and u.errors == ("In a funny state: 8",)
    else:
        assert u.passed[-1] is CommState.DONE and u.passed.count(CommState.DONE) == 1
        fed = apply_comm_status(c, s)
        assert u.passed[:-1] == fed.passed and u.errors == fed.errors


def test_comm_error_texts() -> None:
    assert apply_comm_status(CommState.ACTIVE, GoalStatus.REJECTED).errors == (
        "Invalid goal status transition from ACTIVE to REJECTED",
    )
    # rospy prints status 0 as "_has_header" (GoalStatus.to_string's dict scan)
    assert apply_comm_status(CommState.ACTIVE, GoalStatus.PENDING).errors == (
        "Invalid goal status transition from ACTIVE to _has_header",
    )
    assert apply_comm_status(CommState.ACTIVE, 9).errors == (
        "Got an unknown status from the ActionServer: 9",
    )
    assert apply_comm_status(CommState.LOST, 1).errors == (
        "CommStateMachine is in a funny state: 8",
    )
    assert rospy_status_name(10) == "NO_SUCH_STATE_10"
    with pytest.raises(DdesValueError, match="uint8"):
        apply_comm_status(CommState.ACTIVE, 256)
    with pytest.raises(DdesValueError, match="CommState"):
        apply_comm_status(9, 1)


def test_terminal_statuses_only_wait_for_the_result() -> None:
    for c in (CommState.WAITING_FOR_RESULT, CommState.DONE):
        for s in TERMINAL_STATUSES:
            assert COMM_TRANSITIONS[c][s] is NO_TRANSITION
    for s in (GoalStatus.PENDING, GoalStatus.REJECTED, GoalStatus.RECALLING, GoalStatus.RECALLED):
        assert COMM_TRANSITIONS[CommState.ACTIVE][s] is INVALID_TRANSITION


@given(comm_states)
def test_client_cancel_moves_to_waiting_for_cancel_ack_from_anywhere(c: CommState) -> None:
    u = apply_comm_cancel(c)
    assert u.passed == (CommState.WAITING_FOR_CANCEL_ACK,) and u.after is u.passed[0]


# --- SimpleActionClient -------------------------------------------------------------------------------


@given(st.sampled_from(list(SimpleGoalState)), comm_states)
def test_simple_state_never_leaves_done(s: SimpleGoalState, c: CommState) -> None:
    u = simple_transition(s, c, "/fib")
    if s is SimpleGoalState.DONE:
        assert u.after is SimpleGoalState.DONE and u.callback is None
    if u.callback is SimpleCallback.DONE:
        assert u.after is SimpleGoalState.DONE and c is CommState.DONE
    if u.callback is SimpleCallback.ACTIVE:
        assert s is SimpleGoalState.PENDING and u.after is SimpleGoalState.ACTIVE


def test_simple_error_texts_and_get_state() -> None:
    assert simple_transition(SimpleGoalState.DONE, CommState.ACTIVE, "/fib").error == (
        "Received comm state ACTIVE when in simple state DONE with SimpleActionClient in NS /fib"
    )
    assert simple_transition(2, 7).error == "SimpleActionClient received DONE twice"
    assert simple_get_state(None) == GoalStatus.LOST
    assert simple_get_state(GoalStatus.RECALLING) == GoalStatus.PENDING
    assert simple_get_state(GoalStatus.PREEMPTING) == GoalStatus.ACTIVE
    assert simple_get_state(GoalStatus.SUCCEEDED) == GoalStatus.SUCCEEDED


# --- the doc ---------------------------------------------------------------------------------------------


def test_doc_contains_current_tables() -> None:
    text = DOC.read_text(encoding="utf-8")
    assert render_tables() in text, "docs/actionlib.md is stale: paste render_tables() output"


# --- against real actionlib -------------------------------------------------------------------------------


@pytest.mark.ros
def test_comm_table_equals_actionlib_transitions(ros_python) -> None:
    ros = ros_python(COMM_TABLE_SCRIPT, as_json=True)
    assert (ros["no"], ros["invalid"]) == (NO_TRANSITION.value, INVALID_TRANSITION.value)
    mine = {}
    for c, row in COMM_TRANSITIONS.items():
        cells: dict[str, object] = {}
        for s, target in row.items():
            if target is NO_TRANSITION:
                cells[str(int(s))] = "NO_TRANSITION"
            elif target is INVALID_TRANSITION:
                cells[str(int(s))] = "INVALID_TRANSITION"
            else:
                assert isinstance(target, tuple)
                cells[str(int(s))] = [int(x) for x in target]
        mine[str(int(c))] = cells
    assert mine == ros["table"]


def _all_sequences(alphabet: list[str], max_len: int) -> list[list[str]]:
    return [list(p) for n in range(1, max_len + 1) for p in itertools.product(alphabet, repeat=n)]


@pytest.mark.ros
def test_server_goal_handle_matches_actionlib_on_every_sequence(ros_python) -> None:
    # every event sequence up to length 5 (9330 of them): the table has paths of length <= 3
    seqs = _all_sequences([e.value for e in ServerEvent], 5)
    ros = ros_python(GOAL_HANDLE_SCRIPT, as_json=True, stdin=json.dumps(seqs))
    mine = replay_goal_handle(seqs)
    for seq, r, m in zip(seqs, ros, mine):
        assert m == r, seq


def _comm_ops() -> list[list[object]]:
    ops: list[list[object]] = [["status", None], ["status", 200], ["cancel"]]
    ops += [["status", s] for s in range(10)] + [["result", s] for s in range(10)]
    return ops


@pytest.mark.ros
def test_comm_state_machine_matches_actionlib_exhaustively(ros_python) -> None:
    # from every CommState, every op sequence of length <= 2 (and the real start, length 3)
    ops = _comm_ops()
    cases = [{"start": c, "ops": [a, b]} for c in range(9) for a in ops for b in ops]
    cases += [{"start": c, "ops": [a]} for c in range(9) for a in ops]
    cases += [{"start": 0, "ops": [a, b, c]} for a in ops for b in ops for c in ops]
    ros = ros_python(COMM_SCRIPT, as_json=True, stdin=json.dumps(cases))
    mine = replay_comm(cases)
    for case, r, m in zip(cases, ros, mine):
        assert m == r, case


@pytest.mark.ros
@settings(max_examples=3, deadline=None, derandomize=True, suppress_health_check=INTEROP_CHECKS,
          phases=[Phase.explicit, Phase.reuse, Phase.generate])  # a batch: no slow shrinking
@given(st.lists(st.lists(st.sampled_from(_comm_ops()), min_size=5, max_size=25),
                min_size=50, max_size=50))
def test_comm_state_machine_matches_actionlib_on_long_runs(ros_python, runs) -> None:
    cases = [{"start": 0, "ops": ops} for ops in runs]
    ros = ros_python(COMM_SCRIPT, as_json=True, stdin=json.dumps(cases))
    assert replay_comm(cases) == ros


@pytest.mark.ros
def test_simple_action_client_matches_actionlib(ros_python) -> None:
    ros = ros_python(SIMPLE_SCRIPT, as_json=True)
    for r in ros["transitions"]:
        u = simple_transition(r["simple"], r["comm"], "/fib")
        calls: list[object] = []
        if u.callback is SimpleCallback.ACTIVE:
            calls = ["active_cb"]
        elif u.callback is SimpleCallback.DONE:
            calls = [["done_cb", int(u.before)]]  # done_cb runs before the state is DONE
        assert (int(u.after), calls, [] if u.error is None else [u.error]) == (
            r["after"], r["calls"], r["errors"]), r
    for status, state in ros["get_state"]:
        assert simple_get_state(status) == state


def test_doc_race_snippets_run() -> None:
    text = DOC.read_text(encoding="utf-8")
    section = text.split("## Known ROS races, made replayable", 1)[1].split("\n## ", 1)[0]
    blocks = [b.split("```", 1)[0] for b in section.split("```python\n")[1:]]
    assert len(blocks) >= 5
    for i, block in enumerate(blocks):
        run_snippet(block, DOC, f"'Known ROS races' block {i}")
