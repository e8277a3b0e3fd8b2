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

from ddes.actionlib import ActionServer, ServerGoalHandle, SimpleActionServer
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
                                         g.last_cancel, g.status_list_timeout, g.created)
            server.current_goal = ServerGoalHandle.uninitialized(aserver)
        else:
            node.logerr(f"Don't know how to terminate as {status}")
            server.set_aborted(None, f"Don't know how to terminate as {status}")
