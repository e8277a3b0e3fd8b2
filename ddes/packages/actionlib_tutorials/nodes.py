"""Node types of ``actionlib_tutorials`` (``rosrun actionlib_tutorials fibonacci_server``).

Each mirrors the tutorial of the same name in ros/common_tutorials
(``actionlib_tutorials/scripts/*.py`` and ``src/*.cpp``): same node names,
action names, goals and log texts, on simulated time.

* ``fibonacci_server`` (``scripts/fibonacci_server.py``): a SimpleActionServer
  named after the node (``/fibonacci``) whose execute callback computes the
  sequence at 1 Hz, checking for preemption at every step;
* ``fibonacci_client`` (``scripts/fibonacci_client.py``): sends order 20,
  waits, and logs ``Result: 0, 1, 1, 2, ...`` (the script prints it);
* ``averaging_server`` (``src/averaging_server.cpp``, roscpp log style): a
  SimpleActionServer with goal and preempt callbacks; it averages
  ``/random_number`` samples and ends SUCCEEDED when the mean is at least 5,
  ABORTED otherwise;
* ``averaging_client`` (``src/averaging_client.cpp``): 100 samples, waits 30 s;
* ``gen_numbers`` (``scripts/gen_numbers.py``): publishes N(5, 1) numbers on
  ``random_number`` every 0.05 s, from the world's seeded generator.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

from ddes.actionlib import GoalStatus, SimpleActionClient, SimpleActionServer
from ddes.msg import get_message_class
from ddes.nodes import NodeType

if TYPE_CHECKING:
    from simpy.events import ProcessGenerator

    from ddes.graph.node import Node
    from ddes.msg.message import Message


class FibonacciServer:
    """``FibonacciAction`` of scripts/fibonacci_server.py."""

    def __init__(self, node: Node, name: str) -> None:
        self.node = node
        self._feedback = get_message_class("actionlib_tutorials/FibonacciFeedback")()
        self._result = get_message_class("actionlib_tutorials/FibonacciResult")()
        self._action_name = name
        self._as = SimpleActionServer(node, self._action_name,
                                      get_message_class("actionlib_tutorials/FibonacciAction"),
                                      execute_cb=self.execute_cb, auto_start=False)
        self._as.start()

    def execute_cb(self, goal: Message) -> ProcessGenerator:
        node = self.node
        r = node.create_rate(1)
        success = True
        self._feedback.sequence = [0, 1]
        node.loginfo("%s: Executing, creating fibonacci sequence of order %i with seeds %i, %i",
                     self._action_name, goal.order, self._feedback.sequence[0],
                     self._feedback.sequence[1])
        for i in range(1, goal.order):
            if self._as.is_preempt_requested():
                node.loginfo("%s: Preempted", self._action_name)
                self._as.set_preempted()
                success = False
                break
            self._feedback.sequence.append(self._feedback.sequence[i]
                                           + self._feedback.sequence[i - 1])
            self._as.publish_feedback(self._feedback)
            yield r.sleep()
        if success:
            self._result.sequence = self._feedback.sequence
            node.loginfo("%s: Succeeded", self._action_name)
            self._as.set_succeeded(self._result)


def fibonacci_server(node: Node) -> None:
    """Serve the ``fibonacci`` action under the node's name (then spin)."""
    FibonacciServer(node, node.get_name())


def fibonacci_client(node: Node) -> ProcessGenerator:
    """Send ``FibonacciGoal(order=20)``, wait for the result and log it."""
    client = SimpleActionClient(node, "fibonacci",
                                get_message_class("actionlib_tutorials/FibonacciAction"))
    yield client.wait_for_server()
    goal = get_message_class("actionlib_tutorials/FibonacciGoal")(order=20)
    client.send_goal(goal)
    yield client.wait_for_result()
    result = client.get_result()
    node.loginfo("Result: " + ", ".join([str(n) for n in result.sequence]))
    return 0


class AveragingServer:
    """``AveragingAction`` of src/averaging_server.cpp."""

    def __init__(self, node: Node, name: str) -> None:
        self.node = node
        self.action_name = name
        self.feedback = get_message_class("actionlib_tutorials/AveragingFeedback")()
        self.result = get_message_class("actionlib_tutorials/AveragingResult")()
        self.data_count = self.goal = 0
        self.sum = self.sum_sq = 0.0
        self.as_ = SimpleActionServer(node, name,
                                      get_message_class("actionlib_tutorials/AveragingAction"),
                                      auto_start=False)
        self.as_.register_goal_callback(self.goal_cb)
        self.as_.register_preempt_callback(self.preempt_cb)
        self.sub = node.subscribe("/random_number", get_message_class("std_msgs/Float32"),
                                  self.analysis_cb, queue_size=1)
        self.as_.start()

    def goal_cb(self) -> None:
        self.data_count = 0
        self.sum = self.sum_sq = 0.0
        self.goal = self.as_.accept_new_goal().samples

    def preempt_cb(self) -> None:
        self.node.loginfo("%s: Preempted", self.action_name)
        self.as_.set_preempted()

    def analysis_cb(self, msg: Message) -> None:
        if not self.as_.is_active():
            return
        self.data_count += 1
        fb = self.feedback
        fb.sample = self.data_count
        fb.data = msg.data
        self.sum += msg.data
        fb.mean = self.sum / self.data_count
        self.sum_sq += msg.data ** 2
        fb.std_dev = math.sqrt(abs(self.sum_sq / self.data_count - fb.mean ** 2))
        self.as_.publish_feedback(fb)
        if self.data_count > self.goal:
            self.result.mean = fb.mean
            self.result.std_dev = fb.std_dev
            if self.result.mean < 5.0:
                self.node.loginfo("%s: Aborted", self.action_name)
                self.as_.set_aborted(self.result)
            else:
                self.node.loginfo("%s: Succeeded", self.action_name)
                self.as_.set_succeeded(self.result)


def averaging_server(node: Node) -> None:
    """Serve the ``averaging`` action under the node's name (then spin)."""
    AveragingServer(node, node.get_name())


def averaging_client(node: Node) -> ProcessGenerator:
    """Ask for the average of 100 samples; wait up to 30 s; log the final state."""
    ac = SimpleActionClient(node, "averaging",
                            get_message_class("actionlib_tutorials/AveragingAction"))
    node.loginfo("Waiting for action server to start.")
    yield ac.wait_for_server()
    node.loginfo("Action server started, sending goal.")
    goal = get_message_class("actionlib_tutorials/AveragingGoal")(samples=100)
    ac.send_goal(goal)
    finished_before_timeout = yield ac.wait_for_result(30.0)
    if finished_before_timeout:
        state = ac.get_state()
        node.loginfo("Action finished: %s", GoalStatus(state).name)
    else:
        node.loginfo("Action did not finish before the time out.")
    return 0


def gen_numbers(node: Node) -> ProcessGenerator:
    """Publish N(5, 1) samples on ``random_number`` every 0.05 s (seeded per world and node)."""
    pub = node.advertise("random_number", get_message_class("std_msgs/Float32"))
    rng = node.world.rng_for(f"gen_numbers:{node.name}")
    node.loginfo("Generating random numbers")
    while not node.is_shutdown():
        pub.publish(rng.normalvariate(5, 1))
        yield node.sleep(0.05)


NODES = {
    "fibonacci_server": NodeType(fibonacci_server, name="fibonacci",
                                 doc="scripts/fibonacci_server.py"),
    "fibonacci_client": NodeType(fibonacci_client, name="fibonacci_client_py",
                                 doc="scripts/fibonacci_client.py"),
    "averaging_server": NodeType(averaging_server, name="averaging", log_style="roscpp",
                                 doc="src/averaging_server.cpp"),
    "averaging_client": NodeType(averaging_client, name="test_averaging", log_style="roscpp",
                                 doc="src/averaging_client.cpp"),
    "gen_numbers": NodeType(gen_numbers, name="random_number_generator",
                            doc="scripts/gen_numbers.py"),
}
