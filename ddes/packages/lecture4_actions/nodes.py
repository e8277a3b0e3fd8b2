"""Node types of ``lecture4_actions``: the lecture's FollowPath action, served and used.

``FollowPath.action`` (lecture 4, "ROS Actions (actionlib)")::

    nav_msgs/Path path            # goal (the slide writes navigation_msgs/Path)
    ---
    bool success                  # result
    ---
    float32 remaining_distance    # feedback
    float32 initial_distance

* ``follow_path_server``: a SimpleActionServer on ``follow_path`` whose
  execute callback drives a point robot along the path at ``~speed`` m/s
  (default 0.5), sending feedback at ``~feedback_rate`` Hz (default 10) and
  checking for preemption at every step.  An empty path is ABORTED;
* ``follow_path_client``: sends a square path of side ``~side`` m (default
  2), logs the feedback once a second, and, when ``~cancel_after`` seconds
  (default 0: never) pass first, cancels the goal and waits for the server
  to stop.

    rosrun lecture4_actions follow_path_server
    rosrun lecture4_actions follow_path_client _cancel_after:=3.0
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

ACTION = "lecture4_actions/FollowPathAction"


def path_length(path: Message) -> float:
    """Length of the polyline through the poses of a ``nav_msgs/Path`` (m)."""
    pts = [(p.pose.position.x, p.pose.position.y) for p in path.poses]
    total = 0.0  # added left to right: sum() of floats rounds differently from Python 3.12 on
    for a, b in zip(pts, pts[1:]):
        total += math.dist(a, b)
    return total


class FollowPathServer:
    """The ``follow_path`` action server of ``follow_path_server``."""

    def __init__(self, node: Node, name: str = "follow_path") -> None:
        self.node = node
        self.name = name
        self.speed = float(node.get_param("~speed", 0.5))
        self.feedback_rate = float(node.get_param("~feedback_rate", 10.0))
        self.Feedback = get_message_class("lecture4_actions/FollowPathFeedback")
        self.Result = get_message_class("lecture4_actions/FollowPathResult")
        self.server = SimpleActionServer(node, name, get_message_class(ACTION),
                                         execute_cb=self.execute, auto_start=False)
        self.server.start()

    def execute(self, goal: Message) -> ProcessGenerator:
        node, server = self.node, self.server
        total = path_length(goal.path)
        if len(goal.path.poses) < 2 or total == 0.0:
            node.logwarn("%s: empty path, nothing to follow", self.name)
            server.set_aborted(self.Result(success=False), "empty path")
            return
        node.loginfo("%s: following a path of %d poses, %.2f m", self.name,
                     len(goal.path.poses), total)
        rate = node.create_rate(self.feedback_rate)
        step = self.speed / self.feedback_rate
        steps = max(1, math.ceil(round(total / step, 9)))  # no float drift in the step count
        travelled = 0.0
        for k in range(1, steps + 1):
            if server.is_preempt_requested():
                node.loginfo("%s: preempted with %.2f m to go", self.name, total - travelled)
                server.set_preempted(self.Result(success=False))
                return
            yield rate.sleep()
            travelled = min(total, k * step)
            server.publish_feedback(self.Feedback(remaining_distance=total - travelled,
                                                  initial_distance=total))
        node.loginfo("%s: reached the end of the path", self.name)
        server.set_succeeded(self.Result(success=True))


def follow_path_server(node: Node) -> None:
    """Serve ``follow_path`` (then spin)."""
    FollowPathServer(node)


def square_path(side: float, frame: str = "odom") -> Message:
    """A closed square path of ``side`` metres starting at the origin."""
    Path = get_message_class("nav_msgs/Path")
    PoseStamped = get_message_class("geometry_msgs/PoseStamped")
    path = Path()
    path.header.frame_id = frame
    for x, y in ((0, 0), (side, 0), (side, side), (0, side), (0, 0)):
        p = PoseStamped()
        p.header.frame_id = frame
        p.pose.position.x, p.pose.position.y = float(x), float(y)
        p.pose.orientation.w = 1.0
        path.poses.append(p)
    return path


def follow_path_client(node: Node) -> ProcessGenerator:
    """Send a square path, log feedback, optionally cancel after ``~cancel_after`` s."""
    client = SimpleActionClient(node, "follow_path", get_message_class(ACTION))
    side = float(node.get_param("~side", 2.0))
    cancel_after = float(node.get_param("~cancel_after", 0.0))
    node.loginfo("Waiting for the follow_path server")
    yield client.wait_for_server()
    goal = get_message_class("lecture4_actions/FollowPathGoal")(path=square_path(side))

    def feedback_cb(fb: Message) -> None:
        node.loginfo_throttle(1.0, "remaining %.2f of %.2f m", fb.remaining_distance,
                              fb.initial_distance)

    client.send_goal(goal, feedback_cb=feedback_cb,
                     active_cb=lambda: node.loginfo("The server accepted the path"))
    finished = yield client.wait_for_result(cancel_after)
    if not finished:
        node.loginfo("No result after %.1f s: cancelling", cancel_after)
        client.cancel_goal()
        yield client.wait_for_result()
    result = client.get_result()
    node.loginfo("Finished: %s, success=%s", GoalStatus(client.get_state()).name,
                 None if result is None else result.success)
    return 0


NODES = {
    "follow_path_server": NodeType(follow_path_server, name="follow_path_server",
                                   doc="serves the lecture's FollowPath action"),
    "follow_path_client": NodeType(follow_path_client, name="follow_path_client",
                                   doc="sends a square path to follow_path"),
}
