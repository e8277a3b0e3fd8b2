"""``actionlib.action_client``: ``ActionClient``, ``ClientGoalHandle``, ``CommState``...

* ``ActionClient(ns, ActionSpec)`` is :class:`ddes.actionlib.ActionClient` on the node of the
  running script; ``wait_for_server(timeout)`` (and its old name
  ``wait_for_action_server_to_start``) blocks that node only;
* ``ClientGoalHandle`` is :class:`ddes.actionlib.ClientGoalHandle` and ``CommStateMachine`` the
  state machine behind it (:mod:`ddes.actionlib.client`);
* ``CommState``, ``TerminalState``, ``NO_TRANSITION`` (-1) and ``INVALID_TRANSITION`` (-2) are
  actionlib's plain int constants, with ``to_string`` (``get_name_of_constant``); importing
  actionlib gives the world's ``actionlib_msgs/GoalStatus`` its ``to_string`` too, as in ROS;
* ``GoalID``, ``GoalStatus``, ``GoalStatusArray`` and ``Header`` are the world's message
  classes, ``g_goal_id`` the id count the node's next goal gets (ROS: the process's).

``GoalManager`` is the one name without a ddes counterpart to use on its own: ddes's
ActionClient keeps its goals itself (``client.goal_handles()``); making one raises
``ActionException`` saying so.
"""

from __future__ import annotations

from typing import Any

from ddes.actionlib import ActionClient as _ActionClient
from ddes.actionlib import ClientGoalHandle
from ddes.actionlib.client import _CommStateMachine as CommStateMachine
from ddes.actionlib.states import GoalStatus as _Status
from ddes.compat import rospy
from ddes.compat import threads as _threads
from ddes.compat.actionlib._lazy import ROSPY_CONSTANT_NAMES, install_to_string, module_getattr
from ddes.compat.actionlib.exceptions import ActionException
from ddes.compat.rospy import _node
from ddes.graph.blocking import wait
from ddes.msg.message import Message
from ddes.time.rostime import Duration

#: The names answered when read (:mod:`ddes.compat.actionlib._lazy`).
_LAZY = ("GoalID", "GoalStatus", "GoalStatusArray", "Header", "g_goal_id", "time", "weakref")
__all__ = ["ActionClient", "ActionException", "ClientGoalHandle", "CommState", "CommStateMachine",
           "GoalManager", "INVALID_TRANSITION", "NO_TRANSITION", "TerminalState",
           "get_name_of_constant", "rospy", "threading", *_LAZY]

threading = _threads.module()

_lazy_attr = module_getattr(__name__, _LAZY)


def __getattr__(name: str) -> Any:
    return _lazy_attr(name)

_script_imported = install_to_string

#: actionlib's markers in its comm-state table (ddes: :data:`ddes.actionlib.NO_TRANSITION`).
NO_TRANSITION = -1
INVALID_TRANSITION = -2

#: actionlib's default timeout, ``rospy.Duration()``: wait for ever.
_FOR_EVER = Duration()


def get_name_of_constant(C: Any, n: int) -> str:  # noqa: N803 - actionlib's name
    """The name of the int constant ``n`` of the class ``C`` (the first in its ``__dict__``),
    else ``NO_SUCH_STATE_<n>``, as actionlib's: ``GoalStatus.to_string(0)`` is ``_has_header``
    (a message class's ``_has_header = False`` comes first, in genpy's classes and here)."""
    items: Any = C.__dict__.items()
    if isinstance(C, type) and issubclass(C, Message):  # ddes's own int attributes left out
        items = [(k, v) for k, v in items if not k.startswith("_") or k in ROSPY_CONSTANT_NAMES]
    for k, v in items:
        if isinstance(v, int) and v == n:
            return str(k)
    return f"NO_SUCH_STATE_{n:d}"


class CommState:
    """actionlib's client comm states (ddes: the IntEnum :class:`ddes.actionlib.CommState`)."""

    WAITING_FOR_GOAL_ACK = 0
    PENDING = 1
    ACTIVE = 2
    WAITING_FOR_RESULT = 3
    WAITING_FOR_CANCEL_ACK = 4
    RECALLING = 5
    PREEMPTING = 6
    DONE = 7
    LOST = 8
    to_string = classmethod(get_name_of_constant)


class TerminalState:
    """The statuses a goal ends in (``GoalStatus``'s values)."""

    RECALLED = int(_Status.RECALLED)
    REJECTED = int(_Status.REJECTED)
    PREEMPTED = int(_Status.PREEMPTED)
    ABORTED = int(_Status.ABORTED)
    SUCCEEDED = int(_Status.SUCCEEDED)
    LOST = int(_Status.LOST)
    to_string = classmethod(get_name_of_constant)


class GoalManager:
    """actionlib's ``GoalManager(ActionSpec)``: not made in ddes (see the module docstring)."""

    def __init__(self, ActionSpec: Any) -> None:  # noqa: N803 - actionlib's name
        raise ActionException(
            "actionlib.action_client.GoalManager is not provided: ddes's ActionClient keeps "
            "its goals itself. Use ActionClient(ns, ActionSpec): send_goal(goal) returns a "
            "ClientGoalHandle, client.goal_handles() lists those it follows")


class ActionClient:
    """actionlib's ``ActionClient(ns, ActionSpec)``: ``wait_for_server`` blocks this node."""

    def __init__(self, ns: str, ActionSpec: Any) -> None:  # noqa: N803 - actionlib's name
        self._client = _ActionClient(_node(), ns, ActionSpec)

    def wait_for_server(self, timeout: Any = _FOR_EVER) -> bool:
        """Block until the server is connected (or ``timeout``; 0: for ever); True if it is."""
        return bool(wait(self._client.wait_for_server(timeout), "client.wait_for_server()"))

    def wait_for_action_server_to_start(self, timeout: Any = _FOR_EVER) -> bool:
        """actionlib's old name of :meth:`wait_for_server`."""
        return self.wait_for_server(timeout)

    def __getattr__(self, name: str) -> Any:
        return getattr(self._client, name)
