"""ddes ports of actionlib's own test servers (``actionlib/test/``), used by several tests.

* :class:`RefServer`: ``ref_server.py`` (an ActionServer on ``actionlib/Test``;
  goal 1 succeeds, 2 aborts, 3 rejects, 4 is saved and accepted, 5/6 finish
  the saved goals (succeed/abort), 7 sends them feedback, 8 succeeds/aborts
  them alternately with results);
* :class:`SimpleTester`: ``simple_tester_server.py`` (a SimpleActionServer on
  ``actionlib/TestRequest`` whose goal says how to end: succeed, abort,
  drop, raise, lose, after ``delay_terminate``, ignoring cancels or not).
  The execute callback polls every 20 ms of simulated time, as ROS's sleeps 20 ms.
"""

from __future__ import annotations

from collections.abc import Generator
from typing import Any

from ddes.actionlib import ActionServer, GoalStatus, ServerGoalHandle, SimpleActionServer
from ddes.actionlib.cancel import ServerGoals
from ddes.graph.node import Node
from ddes.msg import get_message_class

RefAction = get_message_class("actionlib/TestAction")
RefGoal = get_message_class("actionlib/TestGoal")
RefFeedback = get_message_class("actionlib/TestFeedback")
RefResult = get_message_class("actionlib/TestResult")
RequestAction = get_message_class("actionlib/TestRequestAction")
RequestGoal = get_message_class("actionlib/TestRequestGoal")
RequestResult = get_message_class("actionlib/TestRequestResult")


class RefServer:
    """``ref_server.py`` on ``reference_action``."""

    def __init__(self, node: Node, name: str = "reference_action") -> None:
        self.node = node
        self.saved_goals: list[ServerGoalHandle] = []
        self.server = ActionServer(node, name, RefAction, self.goal_cb, self.cancel_cb)
        self.server.start()
        node.loginfo("Creating ActionServer [%s]\n", name)

    def goal_cb(self, gh: ServerGoalHandle) -> None:
        goal = gh.get_goal().goal
        self.node.loginfo("Got goal %d", int(goal))
        if goal == 1:
            gh.set_accepted()
            gh.set_succeeded(None, "The ref server has succeeded")
        elif goal == 2:
            gh.set_accepted()
            gh.set_aborted(None, "The ref server has aborted")
        elif goal == 3:
            gh.set_rejected(None, "The ref server has rejected")
        elif goal == 4:
            self.saved_goals.append(gh)
            gh.set_accepted()
        elif goal in (5, 6):
            gh.set_accepted()
            for g in self.saved_goals:
                if goal == 5:
                    g.set_succeeded()
                else:
                    g.set_aborted()
            self.saved_goals = []
            gh.set_succeeded()
        elif goal == 7:
            gh.set_accepted()
            n = len(self.saved_goals)
            for i, g in enumerate(self.saved_goals):
                g.publish_feedback(RefFeedback(n - i))
            gh.set_succeeded()
        elif goal == 8:
            gh.set_accepted()
            n = len(self.saved_goals)
            for i, g in enumerate(self.saved_goals):
                if i % 2 == 0:
                    g.set_succeeded(RefResult(n - i), "The ref server has succeeded")
                else:
                    g.set_aborted(RefResult(n - i), "The ref server has aborted")
            self.saved_goals = []
            gh.set_succeeded()

    def cancel_cb(self, gh: ServerGoalHandle) -> None:
        pass


class SimpleTester:
    """``simple_tester_server.py`` on ``test_request_action``."""

    def __init__(self, node: Node, name: str = "test_request_action") -> None:
        self.node = node
        self.server = SimpleActionServer(node, name, RequestAction, self.execute_cb, False)
        self.server.start()

    def execute_cb(self, goal: Any) -> Generator[Any, Any, None]:
        node, server = self.node, self.server
        result = RequestResult(goal.the_result, True)
        terminate_at = node.get_rostime() + goal.delay_terminate
        while node.get_rostime() < terminate_at:
            yield node.sleep(0.02)
            if not goal.ignore_cancel and server.is_preempt_requested():
                server.set_preempted(result, goal.result_text)
                return
        status = goal.terminate_status
        if status == RequestGoal.TERMINATE_SUCCESS:
            server.set_succeeded(result, goal.result_text)
        elif status == RequestGoal.TERMINATE_ABORTED:
            server.set_aborted(result, goal.result_text)
        elif status == RequestGoal.TERMINATE_REJECTED:
            node.logerr("Simple action server cannot reject goals")
            server.set_aborted(None, "Simple action server cannot reject goals")
        elif status == RequestGoal.TERMINATE_DROP:
            node.loginfo("About to drop the goal.  This should produce an error message.")
            return
        elif status == RequestGoal.TERMINATE_EXCEPTION:
            node.loginfo("About to throw an exception.  This should produce an error message.")
            raise RuntimeError("Terminating by throwing an exception")
        elif status == RequestGoal.TERMINATE_LOSE:
            # As in ROS, losing a goal means messing with the server's innards.
            aserver = server.action_server
            lost = server.current_goal.tracker
            assert lost is not None
            g = aserver._goals
            aserver._goals = ServerGoals(tuple(t for t in g.trackers if t.serial != lost.serial),
                                         g.last_cancel_ns, g.status_list_timeout_ns, g.created)
            server.current_goal = ServerGoalHandle.uninitialized(aserver)
        else:
            node.logerr(f"Don't know how to terminate as {status}")
            server.set_aborted(None, f"Don't know how to terminate as {status}")


# -- reference servers for the protocol machine ------------------------------------------------

def make_tester(world: Any, node: Node) -> SimpleActionServer:
    """The SimpleActionServer port of simple_tester_server.py (execute-callback mode)."""
    return SimpleTester(node).server


class TimedServer:
    """An ActionServer on ``actionlib/Test``: goal ``g`` is rejected when ``g % 4 == 0``, else
    accepted after 50 ms and finished ``(g % 10) * 0.1`` s later (odd: SUCCEEDED, even:
    ABORTED); a cancel request cancels at once (RECALLED or PREEMPTED)."""

    def __init__(self, node: Node, name: str = "timed") -> None:
        self.node = node
        self.server = ActionServer(node, name, RefAction, self.goal_cb, self.cancel_cb)
        self.server.start()

    def goal_cb(self, gh: ServerGoalHandle) -> None:
        self.node.process(self.run(gh))

    def run(self, gh: ServerGoalHandle) -> Generator[Any, Any, None]:
        g = gh.get_goal().goal
        yield self.node.sleep(0.05)
        if gh.status not in (GoalStatus.PENDING, GoalStatus.RECALLING):
            return  # cancelled meanwhile
        if g % 4 == 0:
            gh.set_rejected(None, "rejected")
            return
        gh.set_accepted()
        yield self.node.sleep((g % 10) * 0.1)
        if gh.status not in (GoalStatus.ACTIVE, GoalStatus.PREEMPTING):
            return
        if g % 2:
            gh.set_succeeded(RefResult(g), "done")
        else:
            gh.set_aborted(RefResult(g), "failed")

    def cancel_cb(self, gh: ServerGoalHandle) -> None:
        gh.set_canceled(None, "canceled")


def make_timed(world: Any, node: Node) -> ActionServer:
    return TimedServer(node).server


class SamplingServer:
    """A SimpleActionServer in goal/preempt-callback mode (like the averaging tutorial): a
    10 Hz timer takes samples for the active goal; ``goal`` samples finish it (SUCCEEDED).
    ``forget_preempt=True`` plants a bug: a preempted goal is never set to a terminal state."""

    def __init__(self, node: Node, name: str = "sampling", forget_preempt: bool = False) -> None:
        self.node = node
        self.forget_preempt = forget_preempt
        self.count = 0
        self.target = 0
        self.server = SimpleActionServer(node, name, RefAction, auto_start=False)
        self.server.register_goal_callback(self.goal_cb)
        self.server.register_preempt_callback(self.preempt_cb)
        node.create_timer(0.1, self.sample)
        self.server.start()

    def goal_cb(self) -> None:
        self.count = 0
        self.target = abs(self.server.accept_new_goal().goal) % 8

    def preempt_cb(self) -> None:
        if not self.forget_preempt:
            self.server.set_preempted()

    def sample(self, _event: Any) -> None:
        if not self.server.is_active() or self.server.is_preempt_requested():
            return
        self.count += 1
        self.server.publish_feedback(RefFeedback(self.count))
        if self.count > self.target:
            self.server.set_succeeded(RefResult(self.count))


def make_sampling(world: Any, node: Node) -> SimpleActionServer:
    return SamplingServer(node).server


def make_sampling_forgetful(world: Any, node: Node) -> SimpleActionServer:
    return SamplingServer(node, forget_preempt=True).server


RefFibonacciAction = get_message_class("actionlib_tutorials/FibonacciAction")
FibFeedback = get_message_class("actionlib_tutorials/FibonacciFeedback")
FibResult = get_message_class("actionlib_tutorials/FibonacciResult")


def make_leaky_fibonacci(world: Any, node: Node) -> SimpleActionServer:
    """A classic student bug: no ``return`` after ``set_preempted()``, so the loop goes on and
    ends with ``set_succeeded()`` on a goal already PREEMPTED (an illegal transition)."""

    def execute(goal: Any) -> Generator[Any, Any, None]:
        seq = [0, 1]
        for i in range(1, min(goal.order, 5)):
            if server.is_preempt_requested():
                server.set_preempted()
            seq.append(seq[i] + seq[i - 1])
            server.publish_feedback(FibFeedback(sequence=seq))
            yield node.sleep(0.2)
        server.set_succeeded(FibResult(sequence=seq))

    server = SimpleActionServer(node, "fibonacci", RefFibonacciAction, execute, auto_start=False)
    server.start()
    return server
