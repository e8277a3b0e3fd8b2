"""``actionlib.goal_id_generator``: ``GoalIDGenerator``, goal ids in the action server's format.

``GoalIDGenerator(name=None)`` names its ids after ``name`` (default: the node's name,
``rospy.get_name()``); ``generate_ID()`` returns an ``actionlib_msgs/GoalID`` stamped with the
node's ROS time, its id ``"<name>-<count>-<secs>.<nsecs>"``.  As in actionlib the count is the
process's, shared by every generator and by the node's action servers: in ddes the node's
(:class:`ddes.actionlib._common.NodeGoalIds`), so ids stay unique within a node and two worlds
never interfere.  ``s_goalcount`` reads that count; ``s_goalcount_lock`` is a lock of
:mod:`ddes.compat.threads` (the count needs none: greenlets never interleave inside a call).
"""

from __future__ import annotations

from typing import Any

from ddes.actionlib._common import NodeGoalIds
from ddes.actionlib.goal_id import GoalIdStyle
from ddes.compat import rospy
from ddes.compat import threads as _threads
from ddes.compat.actionlib._lazy import install_to_string, message_class, module_getattr
from ddes.time.rostime import Time

#: The names answered when read (:mod:`ddes.compat.actionlib._lazy`).
_LAZY = ("GoalID", "s_goalcount")
__all__ = ["GoalIDGenerator", "rospy", "s_goalcount_lock", "threading", *_LAZY]

threading = _threads.module()
s_goalcount_lock = _threads.Lock()

_lazy_attr = module_getattr(__name__, _LAZY)


def __getattr__(name: str) -> Any:
    return _lazy_attr(name)

_script_imported = install_to_string


class GoalIDGenerator:
    """actionlib's ``GoalIDGenerator(name=None)``: ``generate_ID()`` makes unique GoalIDs."""

    def __init__(self, name: str | None = None) -> None:
        self.name: str = ""
        self.set_name(rospy.get_name() if name is None else name)

    def set_name(self, name: str) -> None:
        """The name the ids start with (usually the node's fully qualified name)."""
        self.name = name

    def generate_ID(self) -> Any:  # noqa: N802 - actionlib's name
        """A new ``actionlib_msgs/GoalID``: ``<name>-<count>-<secs>.<nsecs>``, stamped now."""
        now = rospy.Time.now()  # before init_node: rospy's "time is not initialized"
        ids = NodeGoalIds(rospy._node(), GoalIdStyle.SERVER)
        ids.name = self.name
        made = ids.generate_id(now.to_nsec())
        return message_class("actionlib_msgs/GoalID")(stamp=Time._from_ns(made.stamp_ns),
                                                      id=made.id)
