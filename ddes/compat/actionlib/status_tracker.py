"""``actionlib.status_tracker``: ``StatusTracker``, one entry of an action server's status list.

``StatusTracker(goal_id, status)`` or ``StatusTracker(goal=action_goal)`` as in actionlib: the
goal's ``actionlib_msgs/GoalStatus`` in ``status`` (a goal without an id gets one from its
``id_generator``, one without a stamp the node's time), the ``FooActionGoal`` in ``goal``, the
``handle_destruction_time``.  ddes's server keeps its status list in its pure core
(:class:`ddes.actionlib.cancel.GoalTracker`); a script reading ``server.status_list`` gets
StatusTrackers made from it (:mod:`ddes.compat.actionlib.action_server`).
"""

from __future__ import annotations

from typing import Any

from ddes.compat import rospy
from ddes.compat.actionlib import goal_id_generator
from ddes.compat.actionlib._lazy import install_to_string, message_class, module_getattr

#: The names answered when read (:mod:`ddes.compat.actionlib._lazy`).
_LAZY = ("actionlib_msgs",)
__all__ = ["StatusTracker", "goal_id_generator", "rospy", *_LAZY]

_lazy_attr = module_getattr(__name__, _LAZY)


def __getattr__(name: str) -> Any:
    return _lazy_attr(name)

_script_imported = install_to_string


class StatusTracker:
    """actionlib's ``StatusTracker(goal_id=None, status=None, goal=None)``."""

    def __init__(self, goal_id: Any = None, status: int | None = None, goal: Any = None) -> None:
        GoalStatus = message_class("actionlib_msgs/GoalStatus")  # noqa: N806 - a class
        self.goal: Any = None
        self.handle_tracker: Any = None
        self.status: Any = GoalStatus()
        self.handle_destruction_time: Any = rospy.Time()
        self.id_generator = goal_id_generator.GoalIDGenerator()
        if goal_id:
            self.status.goal_id = goal_id
            self.status.status = status
            return
        self.goal = goal
        self.status.goal_id = goal.goal_id
        self.status.status = GoalStatus.PENDING
        if self.status.goal_id.id == "":
            self.status.goal_id = self.id_generator.generate_ID()
        if self.status.goal_id.stamp == rospy.Time():
            self.status.goal_id.stamp = rospy.Time.now()
