"""ActionServer/ActionClient on topics: ``test_ref_action_server.py`` scenarios, cancels, LOST,
illegal and invalid transitions, goal ids, wait_for_server, lifecycle."""

from __future__ import annotations

from collections.abc import Generator
from typing import Any

import pytest

import ddes
from ddes.actionlib import (
    ActionClient,
    ActionServer,
    ClientGoalHandle,
    CommState,
    GoalStatus,
    ServerGoalHandle,
)
from ddes.errors import ROSActionException
from ddes.msg import get_message_class

from .servers import RefAction, RefFeedback, RefGoal, RefResult, RefServer

GoalID = get_message_class("actionlib_msgs/GoalID")
GoalStatusMsg = get_message_class("actionlib_msgs/GoalStatus")
GoalStatusArray = get_message_class("actionlib_msgs/GoalStatusArray")
S = 1_000_000_000


def ref(world: ddes.World) -> tuple[RefServer, ActionClient]:
    server = RefServer(world.create_node("ref_server"))
    client = ActionClient(world.create_node("test_ref"), "reference_action", RefAction)
    ev = client.wait_for_server(ddes.Duration(2))
    world.run(until=ev)
    assert ev.value is True
    return server, client


def statuses(handles: list[ClientGoalHandle]) -> list[int]:
    return [h.get_goal_status() for h in handles]


def test_succeed_abort_reject(world: ddes.World) -> None:
    _, client = ref(world)
    handles = [client.send_goal(RefGoal(g)) for g in (1, 2, 3)]
    world.run(until=1.0)
    assert statuses(handles) == [GoalStatus.SUCCEEDED, GoalStatus.ABORTED, GoalStatus.REJECTED]
    assert [h.get_comm_state() for h in handles] == [CommState.DONE] * 3
    assert [h.get_terminal_state() for h in handles] == statuses(handles)
    assert [h.get_goal_status_text() for h in handles] == [
        "The ref server has succeeded", "The ref server has aborted", "The ref server has rejected"]


def test_abort_saved_goals(world: ddes.World) -> None:
    _, client = ref(world)
    work = [client.send_goal(RefGoal(4)) for _ in range(4)]
    world.run_for(0.5)
    assert statuses(work) == [GoalStatus.ACTIVE] * 4
    g5 = client.send_goal(RefGoal(6))
    world.run_for(0.5)
    assert g5.get_goal_status() == GoalStatus.SUCCEEDED
    assert statuses(work) == [GoalStatus.ABORTED] * 4


def test_feedback_to_saved_goals(world: ddes.World) -> None:
    _, client = ref(world)
    feedback: dict[int, Any] = {}
    work = [client.send_goal(RefGoal(4), feedback_cb=lambda g, f, i=i: feedback.__setitem__(i, f))
            for i in range(4)]
    world.run_for(0.5)
    g5 = client.send_goal(RefGoal(7))
    world.run_for(0.5)
    assert g5.get_goal_status() == GoalStatus.SUCCEEDED
    assert statuses(work) == [GoalStatus.ACTIVE] * 4
    assert [feedback[i].feedback for i in range(4)] == [4, 3, 2, 1]


def test_results_of_saved_goals(world: ddes.World) -> None:
    _, client = ref(world)
    work = [client.send_goal(RefGoal(4)) for _ in range(4)]
    world.run_for(0.5)
    client.send_goal(RefGoal(8))
    world.run_for(0.5)
    assert statuses(work) == [GoalStatus.SUCCEEDED, GoalStatus.ABORTED] * 2
    assert [h.get_result().result for h in work] == [4, 3, 2, 1]


def test_transition_callbacks_see_every_state_of_a_multi_step_transition(world: ddes.World) -> None:
    _, client = ref(world)
    world.set_link("/reference_action/status", latency=0.2)  # the result overtakes the status
    seen: list[str] = []
    client.send_goal(RefGoal(1), transition_cb=lambda gh: seen.append(gh.get_comm_state().name))
    world.run_for(1.0)
    assert seen == ["ACTIVE", "WAITING_FOR_RESULT", "DONE"]  # WAITING_FOR_GOAL_ACK + SUCCEEDED


def test_cancel_while_pending_recalls_and_while_active_preempts(world: ddes.World) -> None:
    node = world.create_node("server")

    def accept_later(gh: ServerGoalHandle) -> Generator[Any, Any, None]:
        yield node.sleep(0.5)
        if gh.status == GoalStatus.PENDING:
            gh.set_accepted()

    def cancel_cb(gh: ServerGoalHandle) -> None:
        gh.set_canceled(None, "canceled by request")

    server = ActionServer(node, "act", RefAction, lambda gh: node.process(accept_later(gh)),
                          cancel_cb)
    server.start()
    client = ActionClient(world.create_node("client"), "act", RefAction)
    world.run(until=0.1)
    early = client.send_goal(RefGoal(0))
    world.run(until=0.2)
    early.cancel()  # reaches the server while the goal is PENDING
    world.run(until=1.0)
    assert early.get_goal_status() == GoalStatus.RECALLED
    late = client.send_goal(RefGoal(0))
    world.run(until=1.4)
    assert late.get_goal_status() == GoalStatus.PENDING
    world.run(until=2.0)
    assert late.get_goal_status() == GoalStatus.ACTIVE
    late.cancel()
    world.run(until=2.5)
    assert late.get_goal_status() == GoalStatus.PREEMPTED
    assert late.get_goal_status_text() == "canceled by request"
    afters = [(e.details["id"] == late.get_goal_id(), e.details["after"])
              for e in world.trace.filter(kind="action.server.transition")]
    assert afters == [(False, "RECALLING"), (False, "RECALLED"), (True, "ACTIVE"),
                      (True, "PREEMPTING"), (True, "PREEMPTED")]
    assert server.illegal_transitions == 0


def test_a_slow_goal_callback_holds_the_spinner(world: ddes.World) -> None:
    """A generator goal callback takes simulated time; a cancel waits behind it (one spinner)."""
    node = world.create_node("server")

    def goal_cb(gh: ServerGoalHandle) -> Generator[Any, Any, None]:
        yield node.sleep(0.5)
        gh.set_accepted()

    server = ActionServer(node, "act", RefAction, goal_cb, lambda gh: gh.set_canceled())
    server.start()
    client = ActionClient(world.create_node("client"), "act", RefAction)
    world.run(until=0.1)
    gh = client.send_goal(RefGoal(0))
    world.run(until=0.2)
    gh.cancel()  # queued until the goal callback returns at 0.6
    world.run(until=1.0)
    assert gh.get_goal_status() == GoalStatus.PREEMPTED  # accepted first, then cancelled
    cancel = world.trace.filter(kind="action.server.cancel")[0]
    assert cancel.t == 600_000_000


def test_recalling_goal_accepted_becomes_preempting(world: ddes.World) -> None:
    node = world.create_node("server")
    handles: list[ServerGoalHandle] = []
    server = ActionServer(node, "act", RefAction, handles.append)
    server.start()
    client = ActionClient(world.create_node("client"), "act", RefAction)
    world.run(until=0.1)
    gh = client.send_goal(RefGoal(0))
    world.run(until=0.2)
    gh.cancel()
    world.run(until=0.3)
    assert handles[0].status == GoalStatus.RECALLING
    handles[0].set_accepted()
    assert handles[0].status == GoalStatus.PREEMPTING
    handles[0].set_succeeded(RefResult(5))
    world.run(until=0.4)
    assert gh.get_goal_status() == GoalStatus.SUCCEEDED
    assert gh.get_result().result == 5


@pytest.mark.parametrize("stamp", [ddes.Time(1, 500_000_000), 1.5], ids=["Time", "seconds"])
def test_cancel_by_stamp_and_cancel_all(world: ddes.World, stamp: ddes.Time | float) -> None:
    server, client = ref(world)
    world.run(until=1.0)
    a = client.send_goal(RefGoal(4))
    world.run(until=2.0)
    b = client.send_goal(RefGoal(4))
    world.run(until=2.5)
    client.cancel_goals_at_and_before_time(stamp)  # a Time, or seconds (the unit rule)
    world.run(until=3.0)
    # ref_server's cancel callback does nothing: a is PREEMPTING, b untouched
    assert statuses([a, b]) == [GoalStatus.PREEMPTING, GoalStatus.ACTIVE]
    assert server.server.last_cancel == ddes.Time(1, 500_000_000)  # rospy's attribute: a Time
    assert server.server.last_cancel_ns == 1_500_000_000
    client.cancel_all_goals()
    world.run(until=3.5)
    assert statuses([a, b]) == [GoalStatus.PREEMPTING, GoalStatus.PREEMPTING]
    late = client.send_goal(RefGoal(1))  # stamped after last_cancel: runs normally
    world.run(until=4.0)
    assert late.get_goal_status() == GoalStatus.SUCCEEDED


def test_goal_stamped_before_the_last_cancel_is_canceled_on_arrival(world: ddes.World) -> None:
    _, client = ref(world)
    world.run(until=1.0)
    world.set_link("/reference_action/goal", latency=1.0)
    old = client.send_goal(RefGoal(1))  # stamped 1.0, arrives 2.0
    world.run(until=1.5)
    client.cancel_goals_at_and_before_time(ddes.Time(1, 200_000_000))
    world.run(until=3.0)
    assert old.get_goal_status() == GoalStatus.RECALLED
    assert old.get_goal_status_text().startswith(
        "This goal handle was canceled by the action server because its timestamp is before")


def test_illegal_transition_is_recorded_counted_and_harmless(world: ddes.World) -> None:
    node = world.create_node("server")
    handles: list[ServerGoalHandle] = []
    server = ActionServer(node, "act", RefAction, handles.append)
    server.start()
    client = ActionClient(world.create_node("client"), "act", RefAction)
    world.run(until=0.1)
    gh = client.send_goal(RefGoal(0))
    world.run(until=0.2)
    handles[0].set_accepted()
    handles[0].set_succeeded()
    tr = handles[0].set_aborted()  # illegal: already SUCCEEDED
    assert tr is not None and not tr.legal
    handles[0].set_accepted()  # illegal too
    world.run(until=0.5)
    assert server.illegal_transitions == 2
    illegal = world.trace.filter(kind="action.server.illegal")
    assert [e.details["event"] for e in illegal] == ["set_aborted", "set_accepted"]
    assert illegal[0].details["error"] == (
        "To transition to an aborted state, the goal must be in a preempting or active state, "
        "it is currently in state: 3")
    assert world.trace.counts["action.server.illegal"] == 2
    assert gh.get_goal_status() == GoalStatus.SUCCEEDED  # nothing else was published
    assert len(world.trace.filter(kind="action.client.result")) == 1


def test_client_counts_invalid_transitions_from_a_bad_server(world: ddes.World) -> None:
    """A hand-written 'server' that reports ACTIVE then PENDING: INVALID in the comm table."""
    fake = world.create_node("fake_server")
    status_pub = fake.advertise("act/status", GoalStatusArray, queue_size=10, latch=True)
    ids: list[str] = []
    fake.subscribe("act/goal", get_message_class("actionlib/TestActionGoal"),
                   lambda g: ids.append(g.goal_id.id))
    for topic, cls in (("act/result", "actionlib/TestActionResult"),
                       ("act/feedback", "actionlib/TestActionFeedback")):
        fake.advertise(topic, get_message_class(cls), queue_size=10)
    fake.subscribe("act/cancel", GoalID)
    client = ActionClient(world.create_node("client"), "act", RefAction)
    world.run(until=0.1)
    gh = client.send_goal(RefGoal(0))
    world.run(until=0.2)

    def send(status: int) -> None:
        arr = GoalStatusArray(status_list=[GoalStatusMsg(goal_id=GoalID(id=ids[0]), status=status)])
        status_pub.publish(arr)

    send(GoalStatus.ACTIVE)
    world.run(until=0.3)
    send(GoalStatus.PENDING)
    world.run(until=0.4)
    assert gh.get_comm_state() == CommState.ACTIVE
    assert client.invalid_transitions == 1
    ev = world.trace.filter(kind="action.client.invalid")[0]
    assert ev.details["error"] == "Invalid goal status transition from ACTIVE to _has_header"
    status_pub.publish(GoalStatusArray())  # the goal vanished while ACTIVE: LOST
    world.run(until=0.5)
    assert gh.get_comm_state() == CommState.DONE
    assert gh.get_goal_status() == GoalStatus.LOST
    assert gh.get_terminal_state() == GoalStatus.LOST


def test_status_list_timeout_prunes_finished_goals(world: ddes.World) -> None:
    _, client = ref(world)
    gh = client.send_goal(RefGoal(1))
    arrays: list[tuple[int, list[str]]] = []
    client.node.subscribe("/reference_action/status", GoalStatusArray,
                          lambda m: arrays.append((world.now, [s.goal_id.id for s in m.status_list])))
    world.run(until=8.0)
    with_goal = [t for t, ids in arrays if gh.get_goal_id() in ids]
    without = [t for t, ids in arrays if gh.get_goal_id() not in ids]
    # finished at ~2 ms; kept while destruction + 5 s >= now: last seen at 5.0 s, gone at 5.2 s
    assert max(with_goal) == 5 * S
    assert min(t for t in without if t > 1 * S) == 5_200_000_000
    assert gh.get_comm_state() == CommState.DONE  # not LOST: it was DONE


def test_goal_ids_are_deterministic_and_per_node(world: ddes.World) -> None:
    RefServer(world.create_node("ref_server"))
    node = world.create_node("twins")
    a = ActionClient(node, "reference_action", RefAction)
    b = ActionClient(node, "reference_action", RefAction)
    world.run(until=0.5)
    ids = [a.send_goal(RefGoal(1)).get_goal_id(), b.send_goal(RefGoal(1)).get_goal_id()]
    assert ids == ["/twins-1-0.500", "/twins-2-0.500"]  # rospy: "%s-%i-%.3f", one counter


def test_server_generates_ids_for_goals_without_one(world: ddes.World) -> None:
    RefServer(world.create_node("ref_server"))
    raw = world.create_node("raw")
    ActionGoal = get_message_class("actionlib/TestActionGoal")
    pub = raw.advertise("/reference_action/goal", ActionGoal, queue_size=1)
    world.run(until=1.25)
    pub.publish(ActionGoal(goal=RefGoal(1)))
    world.run(until=1.5)
    goals = world.trace.filter(kind="action.server.goal")
    assert [(e.details["id"], e.details["stamp"]) for e in goals] == [
        ("/ref_server-1-1.250000000", 1_250_000_000)]


def test_wait_for_server_times_out_on_ros_time_then_succeeds(world: ddes.World) -> None:
    client = ActionClient(world.create_node("client"), "reference_action", RefAction)
    first = client.wait_for_server(ddes.Duration(1.5))
    world.run(until=first)
    assert first.value is False and world.now == 1_500_000_000
    forever = client.wait_for_server()
    world.run(until=3.0)
    assert not forever.triggered
    RefServer(world.create_node("ref_server"))
    world.run(until=forever)
    assert forever.value is True and world.now == 3_001_000_000


def test_not_started_server_ignores_goals_and_says_so(world: ddes.World) -> None:
    node = world.create_node("server")
    server = ActionServer(node, "act", RefAction, lambda gh: None)
    assert not server.started
    assert world.master.topics.get("/act/goal") is None  # topics appear on start()
    server.publish_status()
    texts = [e.details["text"] for e in world.trace.filter(kind="action.misuse")]
    assert texts == ["publish_status() on /act ignored: the action server is not started; "
                     "call start()"]


def test_auto_start_true_warns(world: ddes.World) -> None:
    node = world.create_node("server")
    server = ActionServer(node, "act", RefAction, lambda gh: None, auto_start=True)
    assert server.started
    assert [e.details["text"] for e in world.trace.filter(kind="action.misuse")] == [
        "You've passed in true for auto_start to the python action server, you should always "
        "pass in false to avoid race conditions."]


def test_stopped_server_ignores_nothing_silently(world: ddes.World) -> None:
    node = world.create_node("server")
    handles: list[ServerGoalHandle] = []
    server = ActionServer(node, "act", RefAction, handles.append)
    server.start()
    client = ActionClient(world.create_node("client"), "act", RefAction)
    world.run(until=0.1)
    client.send_goal(RefGoal(0))
    world.run(until=0.2)
    server.stop()
    assert world.master.topics["/act/status"].publishers == []
    with pytest.raises(ROSActionException, match="stopped"):
        handles[0].set_accepted()
    assert handles[0].status == GoalStatus.PENDING


def test_bad_results_and_feedback_raise_typed_errors(world: ddes.World) -> None:
    node = world.create_node("server")
    handles: list[ServerGoalHandle] = []
    server = ActionServer(node, "act", RefAction, handles.append)
    server.start()
    client = ActionClient(world.create_node("client"), "act", RefAction)
    world.run(until=0.1)
    client.send_goal(RefGoal(0))
    world.run(until=0.2)
    gh = handles[0]
    gh.set_accepted()
    with pytest.raises(ROSActionException, match="actionlib/TestResult"):
        gh.set_succeeded(RefFeedback(1))
    with pytest.raises(ROSActionException, match="actionlib/TestFeedback"):
        gh.publish_feedback(RefResult(1))
    assert gh.status == GoalStatus.ACTIVE
    gh.set_succeeded(RefResult(2))
    gh.publish_feedback(RefFeedback(3))  # ROS publishes it; ddes also records a warning
    warn = world.trace.filter(kind="action.misuse")[-1]
    assert "after its terminal state SUCCEEDED" in warn.details["text"]


def test_not_an_action_spec(world: ddes.World) -> None:
    node = world.create_node("n")
    with pytest.raises(ROSActionException, match="Type is not an action spec"):
        ActionServer(node, "act", get_message_class("std_msgs/String"), lambda gh: None)
    with pytest.raises(ROSActionException, match="Type is not an action spec"):
        ActionClient(node, "act", "no_such_pkg/NopeAction")
    client = ActionClient(node, "act", "actionlib/TestAction")  # a name works too
    assert client.ActionGoal._type == "actionlib/TestActionGoal"


def test_server_goal_handles_compare_by_id(world: ddes.World) -> None:
    node = world.create_node("server")
    handles: list[ServerGoalHandle] = []
    server = ActionServer(node, "act", RefAction, handles.append)
    server.start()
    client = ActionClient(world.create_node("client"), "act", RefAction)
    world.run(until=0.1)
    client.send_goal(RefGoal(0))
    client.send_goal(RefGoal(0))
    world.run(until=0.2)
    empty = ServerGoalHandle.uninitialized(server)
    assert handles[0] != handles[1] and handles[0] == handles[0]
    assert empty != empty and len({handles[0], handles[0]}) == 1
    assert handles[0].get_goal_id().id == "/client-1-0.100"
    assert empty.get_goal_id().id == ""


def test_shutdown_of_the_node_stops_the_server(world: ddes.World) -> None:
    server_node = world.create_node("server")
    server = ActionServer(server_node, "act", RefAction, lambda gh: None)
    server.start()
    server_node.shutdown()
    assert not server.started
    assert "/act/status" not in dict(world.master.get_published_topics())


def test_handles_of_stopped_tracking_goals_stop_updating(world: ddes.World) -> None:
    _, client = ref(world)
    gh = client.send_goal(RefGoal(4))
    world.run_for(0.5)
    gh.stop_tracking()
    assert client.goal_handles == []
    client.send_goal(RefGoal(5))
    world.run_for(0.5)
    assert gh.get_goal_status() == GoalStatus.ACTIVE  # the SUCCEEDED was not applied


def test_cancel_before_the_ack_marks_the_goal_lost_as_rospy_does(world: ddes.World) -> None:
    """rospy's LOST rule does not exempt WAITING_FOR_CANCEL_ACK: a goal cancelled before the
    server acknowledged it is LOST on the next status array that does not list it yet."""
    _, client = ref(world)
    world.set_link("/reference_action/goal", latency=0.3)
    world.set_link("/reference_action/cancel", latency=0.3)
    gh = client.send_goal(RefGoal(4))
    gh.cancel()
    world.run_for(0.25)  # a periodic status array (without the goal) arrives at 0.2 s
    assert gh.get_comm_state() == CommState.DONE
    assert gh.get_goal_status() == GoalStatus.LOST
    world.run_for(1.0)
    # the server got the goal, then the cancel: the goal was PREEMPTING when the client gave up
    assert [e.details["after"] for e in world.trace.filter(kind="action.server.transition")] == [
        "ACTIVE", "PREEMPTING"]
