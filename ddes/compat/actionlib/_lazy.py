"""What the ``actionlib.*`` modules of a script resolve when a name is read, not at import.

actionlib's modules hold, besides their classes, the message classes they import
(``GoalID``, ``GoalStatus``, ``GoalStatusArray``, ``Header``), the modules they import
(``rospy``, ``threading``, ``time``, ``actionlib_msgs``...) and their process-wide goal
counters (``g_goal_id``, ``s_goalcount``).  The ddes modules are shared by every world of the
process, so these names are answered for the script that reads them (its world's message
classes, its ``time``, its node's counters) by each module's ``__getattr__``.
"""

from __future__ import annotations

import traceback
import weakref
from collections.abc import Callable
from types import SimpleNamespace
from typing import TYPE_CHECKING, Any

from ddes.graph.blocking import current_task

if TYPE_CHECKING:
    from ddes.graph.world import World

__all__ = ["ROSPY_CONSTANT_NAMES", "current_world", "install_to_string", "message_class",
           "module_getattr", "node_counter"]

#: The message classes actionlib's modules import, by name.
MESSAGES = {"GoalID": "actionlib_msgs/GoalID", "GoalStatus": "actionlib_msgs/GoalStatus",
            "GoalStatusArray": "actionlib_msgs/GoalStatusArray", "Header": "std_msgs/Header"}

#: Names of a generated message class that genpy also has and that ``get_name_of_constant``
#: may find (ddes's classes hold more int attributes of their own: ``_wire_min``...).
ROSPY_CONSTANT_NAMES = ("_has_header",)


def current_world() -> World | None:
    """The world of the script running now (None outside any script)."""
    task = current_task()
    return task.world if task is not None else None


def message_class(type_name: str) -> Any:
    """The message class ``type_name`` of the running script's world (else ddes's registry)."""
    world = current_world()
    if world is not None:
        return world.messages.get_message_class(type_name)
    from ddes.msg import get_message_class

    return get_message_class(type_name)


def node_counter(kind: str) -> int:
    """How many goal ids the running script's node has made in ``kind`` ("server", "client"):
    the node stands for ROS's process, whose module-level counter this is."""
    task = current_task()
    if task is None or task.node is None:
        return 0
    ids: dict[str, int] = getattr(task.world, "_ids", {})
    return ids.get(f"actionlib.goal_id.{kind}:{task.node.name}", 0)


def _script_module(name: str) -> Any:
    """The module ``name`` as the running script imports it (its ``time``, its message
    package ``actionlib_msgs``), else the real one."""
    world = current_world()
    if name == "time":
        if world is not None:
            from ddes.compat import walltime

            return walltime.module(world)
        import time

        return time
    if name == "actionlib_msgs":
        from ddes.compat.scripts import _message_package

        if world is not None:
            pkg = _message_package(world, "actionlib_msgs")
            if pkg is not None:
                return pkg
        from ddes.compat.scripts import _MessagePackage
        from ddes.msg.registry import default_registry

        plain: Any = SimpleNamespace(messages=default_registry())  # a world's one attribute used
        return _MessagePackage(plain, "actionlib_msgs")
    raise AttributeError(name)


def module_getattr(module: str, lazy: tuple[str, ...]) -> Callable[[str], Any]:
    """A module's ``__getattr__`` answering the names ``lazy`` (a message class, ``time``,
    ``actionlib_msgs``, a counter) for the running script; others raise AttributeError."""
    names = frozenset(lazy)

    def __getattr__(name: str) -> Any:  # noqa: N807 - the module hook's name
        if name in names:
            if name in MESSAGES:
                return message_class(MESSAGES[name])
            if name == "g_goal_id":  # the client id the next goal gets
                return node_counter("client") + 1
            if name == "s_goalcount":  # server ids made so far
                return node_counter("server")
            if name == "traceback":
                return traceback
            if name == "weakref":
                return weakref
            return _script_module(name)
        raise AttributeError(f"module '{module}' has no attribute '{name}'")

    return __getattr__


def install_to_string(world: World) -> None:
    """actionlib's ``GoalStatus.to_string = classmethod(get_name_of_constant)``, on the world's
    ``actionlib_msgs/GoalStatus`` (importing actionlib does it to the message class in ROS)."""
    cls = world.messages.get_message_class("actionlib_msgs/GoalStatus")
    if "to_string" not in cls.__dict__:
        from ddes.compat.actionlib.action_client import get_name_of_constant

        cls.to_string = classmethod(get_name_of_constant)  # type: ignore[attr-defined]
