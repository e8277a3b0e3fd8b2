"""Client callbacks that are generators go through the node's one callback runner.

docs/graph.md: on the default ``spinner="single"`` a generator callback holds
the spinner while it takes simulated time, and the node's other callbacks
wait.  An action client's callbacks are no exception: a generator
``feedback_cb`` / ``done_cb`` / ``transition_cb`` runs as part of the
subscriber callback that received the message, so another subscriber of the
same node is served only when it has ended.
"""

from __future__ import annotations

from collections.abc import Generator
from typing import Any

import pytest

import ddes
from ddes.actionlib import (
    ActionClient,
    ClientGoalHandle,
    CommState,
    GoalStatus,
    SimpleActionClient,
    SimpleActionServer,
    SimpleGoalState,
)
from ddes.msg import get_message_class

Fibonacci = get_message_class("actionlib_tutorials/FibonacciAction")
Goal = get_message_class("actionlib_tutorials/FibonacciGoal")
Feedback = get_message_class("actionlib_tutorials/FibonacciFeedback")
Result = get_message_class("actionlib_tutorials/FibonacciResult")
String = get_message_class("std_msgs/String")

HOLD = 0.3  # how long each generator callback takes (s of simulated time)


def fibonacci_server(world: ddes.World) -> SimpleActionServer:
    node = world.create_node("fibonacci")

    def execute(goal: Any) -> Generator[Any, Any, None]:
        for i in range(goal.order):
            server.publish_feedback(Feedback(sequence=list(range(i + 1))))
            yield node.sleep(1.0)
        server.set_succeeded(Result(sequence=list(range(goal.order))))

    server = SimpleActionServer(node, "fibonacci", Fibonacci, execute, auto_start=False)
    server.start()
    return server


class Scene:
    """A client node that also subscribes to ``/chatter``; a talker that publishes to it."""

    def __init__(self, world: ddes.World, spinner: str | int = "single") -> None:
        self.world = world
        fibonacci_server(world)
        self.user = world.create_node("user", spinner=spinner)
        self.talker = world.create_node("talker")
        self.pub = self.talker.advertise("/chatter", String, queue_size=10)
        self.log: list[tuple[str, float]] = []
        self.user.subscribe("/chatter", String, self.on_chatter)

    def now(self) -> float:
        return self.user.get_time()

    def on_chatter(self, msg: Any) -> None:
        self.log.append((f"chatter {msg.data}", self.now()))

    def slow(self, name: str) -> Generator[Any, Any, None]:
        """A generator callback: it makes the talker speak, then takes HOLD seconds."""
        self.log.append((f"{name} start", self.now()))
        self.pub.publish(String(data=name))  # arrives at the user while this callback runs
        yield self.user.sleep(HOLD)
        self.log.append((f"{name} end", self.now()))

    def times(self, label: str) -> list[float]:
        return [t for what, t in self.log if what == label]


def _check_held(scene: Scene, name: str) -> None:
    """Every ``name`` callback held the spinner: its chatter waited until it ended."""
    starts, ends = scene.times(f"{name} start"), scene.times(f"{name} end")
    chatter = scene.times(f"chatter {name}")
    assert starts and len(starts) == len(ends) == len(chatter)
    for start, end, heard in zip(starts, ends, chatter):
        assert end == pytest.approx(start + HOLD)
        assert heard >= end  # queued behind the generator, served once it (and any before) ended


def test_generator_feedback_and_done_callbacks_hold_the_single_spinner(
        world: ddes.World) -> None:
    scene = Scene(world)
    client = SimpleActionClient(scene.user, "fibonacci", Fibonacci)
    states: list[SimpleGoalState] = []

    def feedback_cb(feedback: Any) -> Generator[Any, Any, None]:
        yield from scene.slow("feedback")

    def done_cb(state: int, result: Any) -> Generator[Any, Any, None]:
        states.append(client.simple_state)  # done_cb runs before the state is DONE
        yield from scene.slow("done")
        states.append(client.simple_state)

    def main() -> Generator[Any, Any, None]:
        assert (yield client.wait_for_server(5.0))
        client.send_goal(Goal(order=3), done_cb=done_cb, feedback_cb=feedback_cb)
        assert (yield client.wait_for_result())
        scene.log.append(("waiter", scene.now()))

    scene.user.process(main())
    world.run(until=10.0)
    _check_held(scene, "feedback")
    _check_held(scene, "done")
    assert len(scene.times("feedback start")) == 3
    assert scene.times("chatter done") == [pytest.approx(scene.times("done end")[0])]
    # ros/actionlib#190 for a generator done_cb: the waiter resumes once it has ended
    assert scene.times("waiter") == [pytest.approx(scene.times("done end")[0])]
    assert states == [SimpleGoalState.ACTIVE, SimpleGoalState.ACTIVE]
    assert client.simple_state is SimpleGoalState.DONE
    assert client.get_state() == GoalStatus.SUCCEEDED
    assert world.callback_errors == []


def test_with_two_threads_the_other_subscriber_runs_alongside(world: ddes.World) -> None:
    scene = Scene(world, spinner=2)  # roscpp AsyncSpinner(2): the chatter needs no wait
    client = SimpleActionClient(scene.user, "fibonacci", Fibonacci)

    def feedback_cb(feedback: Any) -> Generator[Any, Any, None]:
        yield from scene.slow("feedback")

    def main() -> Generator[Any, Any, None]:
        assert (yield client.wait_for_server(5.0))
        client.send_goal(Goal(order=2), feedback_cb=feedback_cb)
        yield client.wait_for_result()

    scene.user.process(main())
    world.run(until=10.0)
    for start, end, heard in zip(scene.times("feedback start"), scene.times("feedback end"),
                                 scene.times("chatter feedback"), strict=True):
        assert start <= heard < end


def test_action_client_generator_callbacks_run_in_order(world: ddes.World) -> None:
    """ActionClient: generator transition/feedback callbacks hold the spinner; the callbacks
    after one (the later transitions of the same message) run when it has ended."""
    scene = Scene(world)
    client = ActionClient(scene.user, "fibonacci", Fibonacci)
    entered: list[tuple[str, float]] = []

    def transition_cb(gh: ClientGoalHandle) -> Generator[Any, Any, None] | None:
        state = gh.get_comm_state()
        entered.append((state.name, scene.now()))
        if state in (CommState.ACTIVE, CommState.WAITING_FOR_RESULT):
            return scene.slow(state.name)
        return None

    def feedback_cb(gh: ClientGoalHandle, feedback: Any) -> Generator[Any, Any, None]:
        yield from scene.slow("feedback")

    def main() -> Generator[Any, Any, None]:
        assert (yield client.wait_for_server(5.0))
        client.send_goal(Goal(order=2), transition_cb, feedback_cb)

    scene.user.process(main())
    world.run(until=10.0)
    _check_held(scene, "ACTIVE")
    _check_held(scene, "WAITING_FOR_RESULT")
    _check_held(scene, "feedback")
    # the result message passes WAITING_FOR_RESULT and DONE: the DONE callback waits for the
    # generator callback of WAITING_FOR_RESULT
    (wait_name, wait_t), (done_name, done_t) = entered[-2:]
    assert (wait_name, done_name) == ("WAITING_FOR_RESULT", "DONE")
    assert done_t == pytest.approx(wait_t + HOLD)
    assert world.callback_errors == []


def test_cancel_with_a_generator_transition_callback_queues_it(world: ddes.World) -> None:
    """gh.cancel() is called by the user, not by a callback: a generator transition callback
    it triggers is handed to the node's callback queue, where it holds the spinner."""
    scene = Scene(world)
    client = ActionClient(scene.user, "fibonacci", Fibonacci)

    def transition_cb(gh: ClientGoalHandle) -> Generator[Any, Any, None] | None:
        if gh.get_comm_state() is CommState.WAITING_FOR_CANCEL_ACK:
            return scene.slow("cancel")
        return None

    def main() -> Generator[Any, Any, None]:
        assert (yield client.wait_for_server(5.0))
        gh = client.send_goal(Goal(order=5), transition_cb)
        yield scene.user.sleep(1.5)
        gh.cancel()

    scene.user.process(main())
    world.run(until=10.0)
    assert scene.times("cancel start") == [pytest.approx(1.501)]  # the spinner was free
    _check_held(scene, "cancel")
    assert world.callback_errors == []
