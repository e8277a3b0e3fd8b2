"""actionlib's Python API on simulated time: ``import actionlib`` in a rospy script.

``SimpleActionServer``, ``SimpleActionClient``, ``ActionServer`` and
``ActionClient`` as actionlib's, on the node of the running script
(:mod:`ddes.compat.rospy`), over ddes's actionlib (:mod:`ddes.actionlib`: the
same state machines and topics).  What blocks in actionlib blocks here, only
the calling node: ``client.wait_for_server()``, ``client.wait_for_result()``,
``client.send_goal_and_wait(goal)``.  An execute callback is plain blocking
code (``rate.sleep()``, ``rospy.sleep()``) running on a greenlet of its own,
as actionlib runs it on a thread of its own.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from ddes.actionlib import ActionClient as _ActionClient
from ddes.actionlib import ActionServer as _ActionServer
from ddes.actionlib import GoalStatus
from ddes.actionlib import SimpleActionClient as _SimpleActionClient
from ddes.actionlib import SimpleActionServer as _SimpleActionServer
from ddes.actionlib.simple_client import SimpleGoalState
from ddes.compat.rospy import _node
from ddes.graph.blocking import spawn, wait
from ddes.time.rostime import Duration

#: actionlib's default timeout, ``rospy.Duration()``: wait for ever.
_FOR_EVER = Duration()

__all__ = ["ActionClient", "ActionServer", "GoalStatus", "SimpleActionClient",
           "SimpleActionServer", "SimpleGoalState"]


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
    """actionlib.SimpleActionServer(name, ActionSpec, execute_cb=None, auto_start=True)."""

    def __init__(self, name: str, ActionSpec: Any,  # noqa: N803 - actionlib's name
                 execute_cb: Callable[[Any], object] | None = None,
                 auto_start: bool = True) -> None:
        node = _node()
        super().__init__(node, name, ActionSpec, _on_greenlet(node, execute_cb), auto_start)


class ActionServer(_ActionServer):
    """actionlib.ActionServer(ns, ActionSpec, goal_cb, cancel_cb=nop, auto_start=True)."""

    def __init__(self, ns: str, ActionSpec: Any, goal_cb: Callable[..., object],  # noqa: N803
                 cancel_cb: Callable[..., object] | None = None,
                 auto_start: bool = True) -> None:
        super().__init__(_node(), ns, ActionSpec, goal_cb, cancel_cb, auto_start=auto_start)


class SimpleActionClient:
    """actionlib.SimpleActionClient(ns, ActionSpec): its waits block this node."""

    def __init__(self, ns: str, ActionSpec: Any) -> None:  # noqa: N803 - actionlib's name
        self._client = _SimpleActionClient(_node(), ns, ActionSpec)
        self.action_client = self._client.action_client

    def wait_for_server(self, timeout: Any = _FOR_EVER) -> bool:
        """Block until the server is connected (or ``timeout``; 0: for ever); True if it is."""
        return bool(wait(self._client.wait_for_server(timeout), "client.wait_for_server()"))

    def wait_for_result(self, timeout: Any = _FOR_EVER) -> bool:
        """Block until the goal is done (or ``timeout``; 0: for ever); True if it is."""
        return bool(wait(self._client.wait_for_result(timeout), "client.wait_for_result()"))

    def send_goal_and_wait(self, goal: Any, execute_timeout: Any = _FOR_EVER,
                           preempt_timeout: Any = _FOR_EVER) -> int:
        """Send ``goal``, block until it is done (cancelling it after ``execute_timeout``)."""
        return int(wait(self._client.send_goal_and_wait(goal, execute_timeout, preempt_timeout),
                        "client.send_goal_and_wait()"))

    def __getattr__(self, name: str) -> Any:
        return getattr(self._client, name)


class ActionClient:
    """actionlib.ActionClient(ns, ActionSpec): ``wait_for_server`` blocks this node."""

    def __init__(self, ns: str, ActionSpec: Any) -> None:  # noqa: N803 - actionlib's name
        self._client = _ActionClient(_node(), ns, ActionSpec)

    def wait_for_server(self, timeout: Any = _FOR_EVER) -> bool:
        return bool(wait(self._client.wait_for_server(timeout), "client.wait_for_server()"))

    def __getattr__(self, name: str) -> Any:
        return getattr(self._client, name)
