"""``actionlib.simple_action_server``: ``SimpleActionServer``, one goal at a time.

``SimpleActionServer(name, ActionSpec, execute_cb=None, auto_start=True)`` is
:class:`ddes.actionlib.SimpleActionServer` on the node of the running script.  The execute
callback is plain blocking code (``rate.sleep()``, ``rospy.sleep()``, ``time.sleep()``)
running on a greenlet of its own, as actionlib runs it on a thread of its own; one that raises
aborts the goal, as actionlib's does.  ``action_server`` is the script's
:class:`~ddes.compat.actionlib.action_server.ActionServer` (``status_list``, ``lock``) and
``current_goal`` / ``next_goal`` are
:class:`~ddes.compat.actionlib.server_goal_handle.ServerGoalHandle`\\ s, so a subclass may
replace ``current_goal`` with ``ServerGoalHandle()`` as actionlib's tests do.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from ddes.actionlib import SimpleActionServer as _SimpleActionServer
from ddes.compat import rospy
from ddes.compat import threads as _threads
from ddes.compat.actionlib._lazy import install_to_string, module_getattr
from ddes.compat.actionlib.action_server import ActionServer
from ddes.compat.actionlib.server_goal_handle import ServerGoalHandle
from ddes.compat.rospy import _node
from ddes.graph.blocking import spawn

#: The names answered when read (:mod:`ddes.compat.actionlib._lazy`).
_LAZY = ("GoalStatus", "traceback")
__all__ = ["ActionServer", "ServerGoalHandle", "SimpleActionServer", "nop_cb", "rospy",
           "threading", *_LAZY]

threading = _threads.module()

_lazy_attr = module_getattr(__name__, _LAZY)


def __getattr__(name: str) -> Any:
    return _lazy_attr(name)

_script_imported = install_to_string


def nop_cb(goal_handle: Any) -> None:
    """actionlib's ``simple_action_server.nop_cb``: does nothing."""


def _on_greenlet(node: Any, execute_cb: Callable[[Any], object] | None
                 ) -> Callable[[Any], Any] | None:
    """An execute callback written as blocking code, run on its own greenlet.

    ddes's server runs its execute loop as a kernel process; this generator starts the
    callback on a greenlet and waits for its end, so its errors reach the server as
    actionlib's would (the goal is aborted, the error logged).
    """
    if execute_cb is None:
        return None
    cb = execute_cb

    def execute(goal: Any) -> Any:
        done = spawn(node.world, cb, (goal,), node=node)
        return (yield done)

    execute.__qualname__ = getattr(cb, "__qualname__", "execute_cb")
    return execute


class SimpleActionServer(_SimpleActionServer):
    """actionlib's ``SimpleActionServer(name, ActionSpec, execute_cb=None, auto_start=True)``."""

    def __init__(self, name: str, ActionSpec: Any,  # noqa: N803 - actionlib's name
                 execute_cb: Callable[[Any], object] | None = None,
                 auto_start: bool = True) -> None:
        node = _node()
        super().__init__(node, name, ActionSpec, _on_greenlet(node, execute_cb), auto_start)
        server = ActionServer._adopt(self.action_server)
        self.action_server = server
        self.current_goal = ServerGoalHandle.uninitialized(server)
        self.next_goal = ServerGoalHandle.uninitialized(server)
