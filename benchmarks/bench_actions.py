"""Complete action goals per second against a raw SimPy model of the same messages.

One complete goal is five messages: the client's goal, the server's status
array (ACTIVE), one feedback, the result and the status array (SUCCEEDED).
ddes does, per goal: build the ActionGoal and a goal id, publish it, run the
server's pure core (receive_goal, two apply_goal_event), build and publish
four messages (serialize once, deserialize per subscriber), run the client's
comm-state table for each, trace every step, and call the user's callbacks.

The raw baseline is a hand-written SimPy model with the same message count:
per goal one event whose callback schedules four more, each with a callback.
The fair baseline is the *message-only floor*: the same events carrying the
five real messages (FibonacciActionGoal, GoalStatusArray ×2,
FibonacciActionFeedback, FibonacciActionResult), each built, serialized,
deserialized, with its publish and deliver trace rows.  Where real ROS is
installed, ``action_goals_vs_actionlib`` runs real actionlib (rospy, a live
rosmaster, loopback TCPROS) under the system Python, one goal at a time, in
wall-clock goals/s (its work is spread over threads and the master's process,
so CPU time of one process would flatter it).

``<ns>/status_list_timeout`` is 0 here so the status array holds only the
goals of the current instant (ROS's default of 5 s would make every array
carry the last 5 s of goals: that cost is the array's size, not the protocol).
"""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path
from typing import Any

import simpy

sys.path.insert(0, str(Path(__file__).resolve().parent))

from common import TINY, compare, result, row, size  # noqa: E402

import ddes  # noqa: E402
from ddes.actionlib import ActionClient, ActionServer, CommState  # noqa: E402
from ddes.kernel.trace import Trace  # noqa: E402
from ddes.msg import get_message_class  # noqa: E402

N = size(2_000)
MESSAGES_PER_GOAL = 5
Action = get_message_class("actionlib_tutorials/FibonacciAction")
Goal = get_message_class("actionlib_tutorials/FibonacciGoal")
Feedback = get_message_class("actionlib_tutorials/FibonacciFeedback")
Result = get_message_class("actionlib_tutorials/FibonacciResult")
ActionGoal = get_message_class("actionlib_tutorials/FibonacciActionGoal")
ActionFeedback = get_message_class("actionlib_tutorials/FibonacciActionFeedback")
ActionResult = get_message_class("actionlib_tutorials/FibonacciActionResult")
GoalStatusArray = get_message_class("actionlib_msgs/GoalStatusArray")
GoalStatus = get_message_class("actionlib_msgs/GoalStatus")
GoalID = get_message_class("actionlib_msgs/GoalID")


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


def fair() -> int:
    """The message-only floor: five real messages per goal, serialized, deserialized, traced."""
    env = simpy.Environment()
    trace = Trace()
    append = trace.append_row
    pub_keys, deliver_keys = ("topic", "seq", "connections", "data"), ("topic", "publisher", "seq")
    done = [0]
    feedback, result = Feedback(sequence=[0, 1]), Result(sequence=[0, 1, 1])

    def hop(topic: str, msg: Any, seq: int, cb: Any) -> None:
        data = msg._serialize_to_bytes()
        append((env.now, "topic.publish", "/node", pub_keys, topic, seq, 1, data))
        env.timeout(0, (type(msg), data, topic, seq)).callbacks.append(cb)

    def receive(ev: Any) -> Any:
        cls, data, topic, seq = ev.value
        append((env.now, "topic.deliver", "/node", deliver_keys, topic, "/node", seq))
        return cls.__new__(cls)._deserialize_from(data)

    def client_got(ev: Any) -> None:
        msg = receive(ev)
        if type(msg) is ActionResult:
            done[0] += 1

    def server(ev: Any) -> None:
        goal = receive(ev)
        gid = goal.goal_id
        seq = ev.value[3]
        active = GoalStatusArray(status_list=[GoalStatus(goal_id=gid, status=GoalStatus.ACTIVE)])
        hop("/fibonacci/status", active, seq, client_got)
        hop("/fibonacci/feedback", ActionFeedback(status=GoalStatus(goal_id=gid, status=1),
                                                  feedback=feedback), seq, client_got)
        hop("/fibonacci/result", ActionResult(status=GoalStatus(goal_id=gid, status=3),
                                              result=result), seq, client_got)
        done_status = GoalStatusArray(status_list=[GoalStatus(goal_id=gid, status=3)])
        hop("/fibonacci/status", done_status, seq, client_got)

    def client() -> Any:
        goal = Goal(order=3)
        for i in range(N):
            gid = GoalID(id=f"/fibonacci_client-{i + 1}-{env.now}")
            hop("/fibonacci/goal", ActionGoal(goal_id=gid, goal=goal), i, server)
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


REAL_SCRIPT = Path(__file__).resolve().parent / "real_actionlib.py"
SYSTEM_PYTHON = "/usr/bin/python3"


def real_actionlib(n: int) -> float | None:
    """Goals/s (wall clock) of real actionlib under the system Python, or None if not installed."""
    if not Path(SYSTEM_PYTHON).exists():
        return None
    probe = subprocess.run([SYSTEM_PYTHON, "-c", "import actionlib, rospy"], capture_output=True)
    if probe.returncode != 0:
        return None
    out = subprocess.run([SYSTEM_PYTHON, str(REAL_SCRIPT), str(n)], capture_output=True,
                         text=True, timeout=300)
    if out.returncode != 0:
        raise RuntimeError(f"real actionlib benchmark failed: {out.stderr[-2000:]}")
    return float(json.loads(out.stdout.strip().splitlines()[-1])["goals_per_s"])


def benchmarks() -> list[dict[str, Any]]:
    c = compare(ddes_goals, raw, repeat=5, fair_fn=fair)
    out = [result("action_goals", c, "goals/s",
                  f"simpy: {MESSAGES_PER_GOAL} events + callbacks per goal",
                  "message-only floor: the 5 real messages built, (de)serialized, traced",
                  n=N, messages_per_goal=MESSAGES_PER_GOAL)]
    real = None if TINY else real_actionlib(300)
    if real is not None:
        out.append(row("action_goals_vs_actionlib", c[0], "goals/s", real,
                       "real actionlib (rospy, live rosmaster), wall clock, one goal at a time"))
    return out


if __name__ == "__main__":
    for r in benchmarks():
        print(json.dumps(r))
