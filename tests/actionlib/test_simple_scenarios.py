"""SimpleActionServer/Client scenarios: actionlib's own tests, each ending in the state ROS reaches.

``exercise_simple_client.py`` against ``simple_tester_server.py`` (ported in
``servers.py``), plus the single-goal policy, send_goal_and_wait timeouts,
the callbacks' order (ros/actionlib#190) and bad input.
"""

from __future__ import annotations

from collections.abc import Callable, Generator
from typing import Any

import pytest

import ddes
from ddes.actionlib import GoalStatus, SimpleActionClient, SimpleActionServer, SimpleGoalState
from ddes.actionlib.simple_server import NO_TERMINAL_STATE_TEXT, NO_TERMINAL_STATE_WARNING
from ddes.errors import ROSActionException
from ddes.msg import get_message_class

from .servers import RequestAction, RequestGoal, SimpleTester

Duration = ddes.Duration
FibonacciAction = get_message_class("actionlib_tutorials/FibonacciAction")
FibonacciGoal = get_message_class("actionlib_tutorials/FibonacciGoal")


def make_tester(world: ddes.World) -> tuple[SimpleTester, SimpleActionClient]:
    server = SimpleTester(world.create_node("ref_simple_server"))
    client = SimpleActionClient(world.create_node("exercise_simple_server"), "test_request_action",
                                RequestAction)
    return server, client


def drive(world: ddes.World, client: SimpleActionClient,
          body: Callable[[], Generator[Any, Any, Any]], until: float = 60.0) -> Any:
    """Run ``body`` as the client node's main, after wait_for_server(5 s); its return value."""
    out: dict[str, Any] = {}

    def main() -> Generator[Any, Any, None]:
        assert (yield client.wait_for_server(Duration(5)))
        out["value"] = yield from body()

    proc = client.node.process(main())
    world.run(until=until)
    assert proc.triggered, "the scenario did not finish"
    return out.get("value")


def misuse_texts(world: ddes.World) -> list[str]:
    return [e.details["text"] for e in world.trace.filter(kind="action.misuse")]


def test_just_succeed(world: ddes.World) -> None:
    _, client = make_tester(world)

    def body() -> Generator[Any, Any, None]:
        client.send_goal(RequestGoal(terminate_status=RequestGoal.TERMINATE_SUCCESS,
                                         the_result=42))
        assert (yield client.wait_for_result(Duration(5)))

    drive(world, client, body)
    assert client.get_state() == GoalStatus.SUCCEEDED
    assert client.get_result().the_result == 42
    assert client.get_result().is_simple_server is True


def test_just_abort(world: ddes.World) -> None:
    _, client = make_tester(world)

    def body() -> Generator[Any, Any, None]:
        client.send_goal(RequestGoal(terminate_status=RequestGoal.TERMINATE_ABORTED,
                                         the_result=42, result_text="no"))
        yield client.wait_for_result(Duration(5))

    drive(world, client, body)
    assert client.get_state() == GoalStatus.ABORTED
    assert client.get_result().the_result == 42
    assert client.get_goal_status_text() == "no"


def test_just_preempt(world: ddes.World) -> None:
    _, client = make_tester(world)

    def body() -> Generator[Any, Any, None]:
        client.send_goal(RequestGoal(terminate_status=RequestGoal.TERMINATE_SUCCESS,
                                         delay_terminate=Duration(100000), the_result=42))
        client.cancel_goal()
        yield client.wait_for_result(Duration(5))

    drive(world, client, body)
    assert client.get_state() == GoalStatus.PREEMPTED
    assert client.get_result().the_result == 42


def test_drop_aborts_with_ros_text(world: ddes.World) -> None:
    _, client = make_tester(world)

    def body() -> Generator[Any, Any, None]:
        client.send_goal(RequestGoal(terminate_status=RequestGoal.TERMINATE_DROP,
                                         the_result=42))
        yield client.wait_for_result(Duration(5))

    drive(world, client, body)
    assert client.get_state() == GoalStatus.ABORTED
    assert client.get_result().the_result == 0
    assert client.get_goal_status_text() == NO_TERMINAL_STATE_TEXT == "No terminal state was set."
    assert NO_TERMINAL_STATE_WARNING in misuse_texts(world)
    assert "did not set the goal to a terminal status" in NO_TERMINAL_STATE_WARNING


def test_exception_aborts_with_ros_text(world: ddes.World) -> None:
    _, client = make_tester(world)

    def body() -> Generator[Any, Any, None]:
        client.send_goal(RequestGoal(terminate_status=RequestGoal.TERMINATE_EXCEPTION,
                                         the_result=42))
        yield client.wait_for_result(Duration(5))

    drive(world, client, body)
    assert client.get_state() == GoalStatus.ABORTED
    assert client.get_result().the_result == 0
    assert client.get_goal_status_text() == (
        "Exception in execute callback: Terminating by throwing an exception")
    assert any(t.startswith("Exception in your execute callback: Terminating by throwing")
               for t in misuse_texts(world))
    assert world.callback_errors == []  # handled by the server, as in ROS


def test_ignore_cancel_and_succeed(world: ddes.World) -> None:
    _, client = make_tester(world)

    def body() -> Generator[Any, Any, None]:
        client.send_goal(RequestGoal(terminate_status=RequestGoal.TERMINATE_SUCCESS,
                                         delay_terminate=Duration(2), ignore_cancel=True,
                                         the_result=42))
        client.cancel_goal()
        yield client.wait_for_result(Duration(5))

    drive(world, client, body)
    assert client.get_state() == GoalStatus.SUCCEEDED
    assert client.get_result().the_result == 42
    # Goal and cancel reach the server in the same instant, before the execute
    # loop accepts the goal: PENDING -> RECALLING, then accepted -> PREEMPTING.
    afters = [e.details["after"] for e in world.trace.filter(kind="action.server.transition")]
    assert afters == ["RECALLING", "PREEMPTING", "SUCCEEDED"]


def test_lose(world: ddes.World) -> None:
    _, client = make_tester(world)

    def body() -> Generator[Any, Any, None]:
        client.send_goal(RequestGoal(terminate_status=RequestGoal.TERMINATE_LOSE,
                                         the_result=42))
        yield client.wait_for_result(Duration(10))

    drive(world, client, body)
    assert client.get_state() == GoalStatus.LOST
    assert client.action_client.lost_goals == 1
    assert [e.details["state"] for e in world.trace.filter(kind="action.client.lost")] == ["ACTIVE"]


def test_cancel_before_accept_is_recalled(world: ddes.World) -> None:
    """A cancel that reaches the server before the goal leaves a RECALLING placeholder."""
    _, client = make_tester(world)
    world.set_link("/test_request_action/goal", latency=0.5)

    def body() -> Generator[Any, Any, None]:
        client.send_goal(RequestGoal(delay_terminate=Duration(1)))
        client.cancel_goal()
        yield client.wait_for_result(Duration(5))

    drive(world, client, body)
    assert client.get_state() == GoalStatus.RECALLED
    cancel = world.trace.filter(kind="action.server.cancel")[0]
    assert cancel.details["placeholder"] is True
    assert [e.details["arrival"] for e in world.trace.filter(kind="action.server.goal")] == [
        "duplicate_recalled"]


def test_newer_goal_preempts_the_current_one(world: ddes.World) -> None:
    _, client = make_tester(world)
    ends: list[tuple[int, Any]] = []

    def body() -> Generator[Any, Any, None]:
        client.send_goal(RequestGoal(delay_terminate=Duration(10), the_result=1),
                         done_cb=lambda s, r: ends.append((s, r.the_result)))
        first = client.gh
        yield client.node.sleep(1.0)
        client.send_goal(RequestGoal(delay_terminate=Duration(1), the_result=2))
        assert (yield client.wait_for_result(Duration(5)))
        assert first is not None
        return first.get_goal_status()

    first_status = drive(world, client, body)
    assert client.get_state() == GoalStatus.SUCCEEDED
    assert client.get_result().the_result == 2
    # The first goal stopped being tracked (send_goal forgets it): no done_cb for it ...
    assert ends == []
    assert first_status == GoalStatus.ACTIVE
    # ... but the server preempted it because of the newer goal.
    preempts = world.trace.filter(kind="action.simple.preempt_request")
    assert [e.details["reason"] for e in preempts] == ["new goal"]
    finals = [(e.details["before"], e.details["after"])
              for e in world.trace.filter(kind="action.server.transition")]
    assert ("ACTIVE", "PREEMPTED") in finals


def test_next_goal_replaced_before_acceptance_is_recalled(world: ddes.World) -> None:
    """Two goals arrive while a third runs: the first of them is RECALLED (next-goal replacement)."""
    node = world.create_node("server")
    accepted: list[int] = []
    server = SimpleActionServer(node, "fib", FibonacciAction, auto_start=False)

    def goal_cb() -> None:
        if not server.is_active():
            accepted.append(server.accept_new_goal().order)

    server.register_goal_callback(goal_cb)
    server.start()
    client_node = world.create_node("client")
    from ddes.actionlib import ActionClient

    client = ActionClient(client_node, "fib", FibonacciAction)
    handles: list[Any] = []

    def main() -> Generator[Any, Any, None]:
        yield client.wait_for_server()
        handles.append(client.send_goal(FibonacciGoal(order=1)))
        yield client_node.sleep(0.1)
        handles.append(client.send_goal(FibonacciGoal(order=2)))
        handles.append(client.send_goal(FibonacciGoal(order=3)))
        yield client_node.sleep(0.1)
        server.set_succeeded()
        accepted.append(server.accept_new_goal().order)
        server.set_succeeded()

    client_node.process(main())
    world.run(until=2.0)
    assert accepted == [1, 3]
    assert [h.get_goal_status() for h in handles] == [GoalStatus.SUCCEEDED, GoalStatus.RECALLED,
                                                      GoalStatus.SUCCEEDED]
    assert handles[1].get_goal_status_text() == (
        "This goal was canceled because another goal was received by the simple action server")


def test_older_goal_is_recalled_at_once(world: ddes.World) -> None:
    """A goal stamped before the current one is set_canceled on arrival: RECALLED."""
    from ddes.actionlib import ActionClient

    node = world.create_node("server")
    server = SimpleActionServer(node, "fib", FibonacciAction, auto_start=False)
    server.register_goal_callback(lambda: server.accept_new_goal())
    server.start()
    client = ActionClient(world.create_node("client"), "fib", FibonacciAction)
    world.set_link("/fib/goal", publisher="/client", latency=1.0)
    world.run(until=0.5)
    late = client.send_goal(FibonacciGoal(order=1))  # stamped 0.5, arrives at 1.5
    other = ActionClient(world.create_node("other"), "fib", FibonacciAction)
    world.run(until=1.0)
    newer = other.send_goal(FibonacciGoal(order=2))  # stamped 1.0, arrives at 1.0
    world.run(until=3.0)
    assert newer.get_goal_status() == GoalStatus.ACTIVE
    assert late.get_goal_status() == GoalStatus.RECALLED


def test_send_goal_and_wait_times_out_and_preempts(world: ddes.World) -> None:
    _, client = make_tester(world)

    def body() -> Generator[Any, Any, int]:
        t0 = client.node.get_time()
        state = yield client.send_goal_and_wait(
            RequestGoal(delay_terminate=Duration(100)), Duration(1.0), Duration(1.0))
        return state, client.node.get_time() - t0

    state, took = drive(world, client, body)
    assert state == GoalStatus.PREEMPTED
    assert 1.0 <= took < 1.1  # cancelled at 1 s, preempted at the next 20 ms poll


def test_send_goal_and_wait_preempt_timeout_expires(world: ddes.World) -> None:
    _, client = make_tester(world)

    def body() -> Generator[Any, Any, int]:
        t0 = client.node.get_time()
        state = yield client.send_goal_and_wait(
            RequestGoal(delay_terminate=Duration(100), ignore_cancel=True),
            Duration(1.0), Duration(0.5))
        return state, client.node.get_time() - t0

    state, took = drive(world, client, body)
    assert state == GoalStatus.ACTIVE  # PREEMPTING, as get_state() reports it
    assert client.gh is not None and client.gh.get_goal_status() == GoalStatus.PREEMPTING
    assert took == pytest.approx(1.5)


def test_wait_for_result_times_out_on_ros_time(world: ddes.World) -> None:
    _, client = make_tester(world)

    def body() -> Generator[Any, Any, Any]:
        client.send_goal(RequestGoal(delay_terminate=Duration(3)))
        a = yield client.wait_for_result(Duration(1))
        ta = client.node.get_time()
        b = yield client.wait_for_result()  # zero: for ever
        return a, ta, b, client.node.get_time()

    a, ta, b, tb = drive(world, client, body)
    assert (a, b) == (False, True)
    assert ta == pytest.approx(1.001)
    assert 3.0 < tb < 3.1


def test_done_cb_runs_before_the_state_is_done(world: ddes.World) -> None:
    """ros/actionlib#190: whoever waits for the result resumes after done_cb returned."""
    _, client = make_tester(world)
    seen: list[Any] = []

    def done_cb(state: int, result: Any) -> None:
        seen.append(("done_cb", state, client.simple_state))

    def body() -> Generator[Any, Any, None]:
        client.send_goal(RequestGoal(the_result=7), done_cb=done_cb,
                         active_cb=lambda: seen.append(("active_cb", client.simple_state)),
                         feedback_cb=lambda fb: seen.append("feedback"))
        yield client.wait_for_result()
        seen.append(("waiter", client.simple_state))

    drive(world, client, body)
    assert seen == [("active_cb", SimpleGoalState.ACTIVE),
                    ("done_cb", GoalStatus.SUCCEEDED, SimpleGoalState.ACTIVE),
                    ("waiter", SimpleGoalState.DONE)]


def test_calls_without_a_goal_are_logged_not_raised(world: ddes.World) -> None:
    _, client = make_tester(world)
    assert client.get_state() == GoalStatus.LOST
    assert client.get_result() is None
    assert client.get_goal_status_text() == (
        "ERROR: Called get_goal_status_text when no goal is running")
    ev = client.wait_for_result()
    world.run(until=ev)
    assert ev.value is False
    client.cancel_goal()  # nothing to cancel: no message
    assert misuse_texts(world) == ["Called get_result when no goal is running",
                                   "Called get_goal_status_text when no goal is running",
                                   "Called wait_for_result when no goal exists"]
    assert world.trace.filter(kind="action.client.cancel") == []


def test_goal_of_the_wrong_type_raises(world: ddes.World) -> None:
    _, client = make_tester(world)
    with pytest.raises(ROSActionException, match="actionlib/TestRequestGoal"):
        client.send_goal(FibonacciGoal(order=3))
    assert client.simple_state == SimpleGoalState.DONE
    assert client.gh is None


def test_server_methods_without_a_goal_log_ros_errors(world: ddes.World) -> None:
    node = world.create_node("server")
    server = SimpleActionServer(node, "fib", FibonacciAction, auto_start=False)
    server.set_succeeded()
    server.publish_feedback(get_message_class("actionlib_tutorials/FibonacciFeedback")())
    assert server.accept_new_goal() is None
    assert not server.is_active()
    server.register_preempt_callback(lambda: None)
    goal_id = "Attempt to get a goal id on an uninitialized ServerGoalHandle"
    assert misuse_texts(world) == [  # rospy's debug line asks for the goal id twice first
        goal_id, goal_id, "Attempt to set status on an uninitialized ServerGoalHandle",
        goal_id, goal_id, "Attempt to publish feedback on an uninitialized ServerGoalHandle",
        "Attempting to accept the next goal when a new goal is not available",
    ]


def test_register_goal_callback_refused_with_an_execute_callback(world: ddes.World) -> None:
    node = world.create_node("server")
    server = SimpleActionServer(node, "fib", FibonacciAction, lambda goal: None, auto_start=False)
    server.register_goal_callback(lambda: None)
    assert server.goal_callback is None
    assert misuse_texts(world) == [
        "Cannot call SimpleActionServer.register_goal_callback() because an executeCallback "
        "exists. Not going to register it."]


def test_auto_start_warns_as_ros_does(world: ddes.World) -> None:
    node = world.create_node("server")
    server = SimpleActionServer(node, "fib", FibonacciAction, lambda goal: None)
    assert server.action_server.started
    assert misuse_texts(world) == [
        "You've passed in true for auto_start to the python action server, you should always "
        "pass in false to avoid race conditions."]


def test_goal_callback_exception_is_logged_as_ros_does(world: ddes.World) -> None:
    node = world.create_node("server")
    server = SimpleActionServer(node, "fib", FibonacciAction, auto_start=False)

    def goal_cb() -> None:
        raise ValueError("boom")

    server.register_goal_callback(goal_cb)
    server.start()
    client = SimpleActionClient(world.create_node("client"), "fib", FibonacciAction)
    world.run(until=0.5)
    client.send_goal(FibonacciGoal(order=1))
    world.run(until=1.0)
    assert "SimpleActionServer.internal_goal_callback - exception boom" in misuse_texts(world)
    assert server.is_new_goal_available()
    assert client.get_state() == GoalStatus.PENDING


def test_execute_loop_picks_a_queued_goal_up_after_0_1_s(world: ddes.World) -> None:
    """A goal that arrives while execute runs is accepted 0.1 s (kernel) after it returns."""
    node = world.create_node("server")
    starts: list[int] = []

    def execute(goal: Any) -> Generator[Any, Any, None]:
        starts.append(world.now)
        while not server.is_preempt_requested():
            yield node.sleep(0.25)
        server.set_preempted()

    server = SimpleActionServer(node, "fib", FibonacciAction, execute, auto_start=False)
    server.start()
    client = SimpleActionClient(world.create_node("client"), "fib", FibonacciAction)
    world.run(until=0.5)
    client.send_goal(FibonacciGoal(order=1))
    world.run(until=1.1)
    client.send_goal(FibonacciGoal(order=2))  # arrives at 1.1 while execute sleeps
    world.run(until=3.0)
    assert starts == [500_000_000, 1_350_000_000]  # preempt seen at 1.25, +0.1 s
