"""``actionlib.simple_action_client``: ``SimpleActionClient`` and ``SimpleGoalState``.

``SimpleActionClient(ns, ActionSpec)`` is :class:`ddes.actionlib.SimpleActionClient` on the node
of the running script: ``wait_for_server(timeout)``, ``wait_for_result(timeout)`` and
``send_goal_and_wait(goal, execute_timeout, preempt_timeout)`` block that node only and return
what actionlib returns.  ``SimpleGoalState`` is actionlib's plain int constants (PENDING 0,
ACTIVE 1, DONE 2) with ``to_string``.
"""

from __future__ import annotations

from typing import Any

from ddes.actionlib import SimpleActionClient as _SimpleActionClient
from ddes.compat import rospy
from ddes.compat import threads as _threads
from ddes.compat.actionlib._lazy import install_to_string, module_getattr
from ddes.compat.actionlib.action_client import (
    ActionClient,
    CommState,
    get_name_of_constant,
)
from ddes.compat.rospy import _node
from ddes.graph.blocking import current_task, wait, wait_ns
from ddes.time.rostime import Duration

#: The names answered when read (:mod:`ddes.compat.actionlib._lazy`).
_LAZY = ("GoalStatus",)
__all__ = ["ActionClient", "CommState", "SimpleActionClient", "SimpleGoalState",
           "get_name_of_constant", "rospy", "threading", *_LAZY]

threading = _threads.module()

_lazy_attr = module_getattr(__name__, _LAZY)


def __getattr__(name: str) -> Any:
    return _lazy_attr(name)

_script_imported = install_to_string

#: actionlib's default timeout, ``rospy.Duration()``: wait for ever.
_FOR_EVER = Duration()


class SimpleGoalState:
    """actionlib's simple goal states (ddes: the IntEnum
    :class:`ddes.actionlib.SimpleGoalState`)."""

    PENDING = 0
    ACTIVE = 1
    DONE = 2
    to_string = classmethod(get_name_of_constant)


class SimpleActionClient:
    """actionlib's ``SimpleActionClient(ns, ActionSpec)``: its waits block this node."""

    def __init__(self, ns: str, ActionSpec: Any) -> None:  # noqa: N803 - actionlib's name
        self._client = _SimpleActionClient(_node(), ns, ActionSpec)
        self.action_client = self._client.action_client
        self._last_poll: tuple[int, int] | None = None

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

    def get_state(self) -> int:
        """The goal's state (a ``GoalStatus`` value, as actionlib's).

        A script polling it in a loop that never blocks (``while ...: if client.get_state() !=
        GoalStatus.PENDING: break``, as actionlib's own tests do) would hold simulated time
        still for ever; so a second call at one instant that finds the state unchanged gives
        way until the world's next event, as the polling thread gives way to the ones that
        receive the status in ROS.
        """
        state = self._client.get_state()
        env = self._client.node.world.env
        if self._last_poll == (env.now, state) and current_task() is not None:
            nxt = env.peek()
            if nxt != float("inf"):
                wait_ns(env, max(int(nxt) - int(env.now), 0), "client.get_state()")
                state = self._client.get_state()
        self._last_poll = (env.now, state)
        return int(state)

    def __getattr__(self, name: str) -> Any:
        return getattr(self._client, name)
