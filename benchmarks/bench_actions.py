"""Complete action goals per second against a raw SimPy model of the same messages.

One complete goal is five messages: the client's goal, the server's status
array (ACTIVE), one feedback, the result and the status array (SUCCEEDED).
ddes does, per goal: build the ActionGoal and a goal id, publish it, run the
server's pure core (receive_goal, two apply_goal_event), build and publish
four messages (serialize once, deserialize per subscriber), run the client's
comm-state table for each, trace every step, and call the user's callbacks.

The baseline is a hand-written SimPy model with the same message count: per
goal one event whose callback schedules four more, each with a callback.

``<ns>/status_list_timeout`` is 0 here so the status array holds only the
goals of the current instant (ROS's default of 5 s would make every array
carry the last 5 s of goals: that cost is the array's size, not the protocol).
"""

from __future__ import annotations

import sys
from pathlib import Path
from typing import Any

import simpy

sys.path.insert(0, str(Path(__file__).resolve().parent))

from common import compare, row  # noqa: E402

import ddes  # noqa: E402
from ddes.actionlib import ActionClient, ActionServer, CommState  # noqa: E402
from ddes.msg import get_message_class  # noqa: E402

N = 2_000
MESSAGES_PER_GOAL = 5
Action = get_message_class("actionlib_tutorials/FibonacciAction")
Goal = get_message_class("actionlib_tutorials/FibonacciGoal")
Feedback = get_message_class("actionlib_tutorials/FibonacciFeedback")
Result = get_message_class("actionlib_tutorials/FibonacciResult")


def raw() -> int:
    env = simpy.Environment()
    done = [0]

    def finished(_ev: Any) -> None:
        done[0] += 1

    def nothing(_ev: Any) -> None:
        pass

    def server(ev: Any) -> None:
        for last in (False, False, False, True):  # status, feedback, result, status
            env.timeout(0, ev.value).callbacks.append(finished if last else nothing)

    def client() -> Any:
        for i in range(N):
            env.timeout(0, i).callbacks.append(server)
            yield env.timeout(1_000_000)

    env.process(client())
    env.run()
    return done[0]


def ddes_goals() -> int:
    world = ddes.World()
    world.params.set_param("/fibonacci/status_list_timeout", 0.0)
    snode = world.create_node("fibonacci_server", disable_rosout=True)
    feedback, result = Feedback(sequence=[0, 1]), Result(sequence=[0, 1, 1])

    def goal_cb(gh: Any) -> None:
        gh.set_accepted()
        gh.publish_feedback(feedback)
        gh.set_succeeded(result)

    server = ActionServer(snode, "fibonacci", Action, goal_cb)
    server.start()
    cnode = world.create_node("fibonacci_client", disable_rosout=True)
    client = ActionClient(cnode, "fibonacci", Action)
    done = [0]

    def transition(gh: Any) -> None:
        if gh.get_comm_state() == CommState.DONE:
            done[0] += 1
            gh.stop_tracking()

    def loop() -> Any:
        yield client.wait_for_server()
        goal = Goal(order=3)
        for _ in range(N):
            client.send_goal(goal, transition)
            yield world.env.timeout(1_000_000)

    cnode.process(loop())
    world.run(until=(N + 10) * 0.001)
    assert done[0] == N, done[0]
    return done[0]


def benchmarks() -> list[dict[str, Any]]:
    value, base = compare(ddes_goals, raw, repeat=3)
    return [row("action_goals", value, "goals/s", base,
                f"simpy: {MESSAGES_PER_GOAL} events + callbacks per goal", n=N,
                messages_per_goal=MESSAGES_PER_GOAL)]


if __name__ == "__main__":
    import json

    for r in benchmarks():
        print(json.dumps(r))
