"""actionlib's Python API on simulated time: ``import actionlib`` in a rospy script.

The package has actionlib's modules, each with the names actionlib's has (docs/actionlib.md,
"actionlib's modules in a script"), over ddes's actionlib (:mod:`ddes.actionlib`: the same state
machines and topics) on the node of the running script (:mod:`ddes.compat.rospy`):

=============================  ====================================================================
module                         what
=============================  ====================================================================
``action_client``              ``ActionClient``, ``ClientGoalHandle``, ``CommState``,
                               ``TerminalState``, ``get_name_of_constant``...
``simple_action_client``       ``SimpleActionClient``, ``SimpleGoalState``
``action_server``              ``ActionServer`` (``status_list``, ``lock``), ``nop_cb``
``simple_action_server``       ``SimpleActionServer`` (its execute callback on a greenlet)
``server_goal_handle``         ``ServerGoalHandle``
``goal_id_generator``          ``GoalIDGenerator`` (the node's count, as ROS's process count)
``status_tracker``             ``StatusTracker``
``handle_tracker_deleter``     ``HandleTrackerDeleter``
``exceptions``                 ``ActionException`` (ddes's ROSActionException)
=============================  ====================================================================

``import actionlib`` holds what actionlib's ``__init__`` star-imports from the first four.
What blocks in actionlib blocks here, only the calling node: ``client.wait_for_server()``,
``client.wait_for_result()``, ``client.send_goal_and_wait(goal)``.  An execute callback is
plain blocking code (``rate.sleep()``, ``rospy.sleep()``) running on a greenlet of its own, as
actionlib runs it on a thread of its own.  ``GoalStatus`` (and ``GoalID``, ``GoalStatusArray``,
``Header``) is the world's message class, as ``from actionlib_msgs.msg import GoalStatus``
gives it.
"""

from __future__ import annotations

from typing import Any

from ddes.compat.actionlib import (
    action_client,
    action_server,
    exceptions,
    goal_id_generator,
    handle_tracker_deleter,
    server_goal_handle,
    simple_action_client,
    simple_action_server,
    status_tracker,
)
from ddes.compat.actionlib._lazy import MESSAGES, current_world, install_to_string, message_class
from ddes.compat.actionlib.action_client import (
    INVALID_TRANSITION,
    NO_TRANSITION,
    ActionClient,
    ClientGoalHandle,
    CommState,
    CommStateMachine,
    GoalManager,
    TerminalState,
    get_name_of_constant,
    rospy,
    threading,
    weakref,
)
from ddes.compat.actionlib.action_server import ActionServer
from ddes.compat.actionlib.exceptions import ActionException
from ddes.compat.actionlib.goal_id_generator import GoalIDGenerator
from ddes.compat.actionlib.handle_tracker_deleter import HandleTrackerDeleter
from ddes.compat.actionlib.server_goal_handle import ServerGoalHandle
from ddes.compat.actionlib.simple_action_client import SimpleActionClient, SimpleGoalState
from ddes.compat.actionlib.simple_action_server import SimpleActionServer, nop_cb, traceback
from ddes.compat.actionlib.status_tracker import StatusTracker

__all__ = ["ActionClient", "ActionException", "ActionServer", "ClientGoalHandle", "CommState",
           "CommStateMachine", "GoalID", "GoalIDGenerator", "GoalManager", "GoalStatus",
           "GoalStatusArray", "HandleTrackerDeleter", "Header", "INVALID_TRANSITION",
           "NO_TRANSITION", "ServerGoalHandle", "SimpleActionClient", "SimpleActionServer",
           "SimpleGoalState", "StatusTracker", "TerminalState", "action_client", "action_server",
           "exceptions", "g_goal_id", "get_name_of_constant", "goal_id_generator",
           "handle_tracker_deleter", "nop_cb", "rospy", "server_goal_handle",
           "simple_action_client", "simple_action_server", "status_tracker", "threading", "time",
           "traceback", "weakref"]

#: actionlib's ``__init__`` star-imports ``g_goal_id`` once: its first value, for ever.
g_goal_id = 1

_script_imported = install_to_string


def __getattr__(name: str) -> Any:
    if name in MESSAGES:
        return message_class(MESSAGES[name])
    if name == "time":
        return action_client.time
    if name == "msg":  # ``actionlib.msg``, as Python sets it once actionlib.msg is imported
        from ddes.compat.scripts import _message_package

        world = current_world()
        pkg = _message_package(world, "actionlib") if world is not None else None
        if pkg is not None:
            return pkg.msg
    raise AttributeError(f"module 'actionlib' has no attribute '{name}'")
