"""``rosnode`` of ROS Noetic as a module, for a test node: list and kill the world's nodes.

actionlib's deadlock test calls ``rosnode.get_node_names()`` and ``rosnode.kill_nodes(names)``
from inside its node. Here both act on the master of the running script's world:
:func:`get_node_names` the sorted names of the live nodes (under ``namespace``, as ``rosnode
list NS``); :func:`kill_nodes` shuts each named node down, as ``rosnode kill`` does (rospy's
reason ``user request``), and returns ``(killed, failed)``: a name no node has fails. The
command-line parts (``rosnodemain``, ``rosnode_ping`` …) are the console's ``rosnode``.
"""

from __future__ import annotations

from collections.abc import Iterable
from typing import TYPE_CHECKING

from ddes.errors import ROSException
from ddes.graph.names import make_global_ns

if TYPE_CHECKING:
    from ddes.graph.world import World

__all__ = ["ROSNodeException", "get_node_names", "kill_nodes"]


class ROSNodeException(ROSException):
    """rosnode's error (ddes: outside a ddes script there is no master to ask)."""


def _world() -> World:
    from ddes.graph.blocking import current_task

    task = current_task()
    if task is None:
        raise ROSNodeException("rosnode: no ROS master here (call it from a node run by ddes)")
    return task.world


def get_node_names(namespace: str | None = None) -> list[str]:
    """The names of the live nodes (under ``namespace``), sorted."""
    names = _world().master.node_names()
    if namespace:
        ns = make_global_ns(namespace)
        names = [n for n in names if n.startswith(ns) or n == namespace]
    return sorted(names)


def kill_nodes(node_names: Iterable[str]) -> tuple[list[str], list[str]]:
    """Shut the named nodes down; ``(killed, failed)``."""
    world = _world()
    killed: list[str] = []
    failed: list[str] = []
    for name in node_names:
        node = world.master.lookup_node(name)
        if node is None:
            failed.append(name)
            continue
        node.shutdown("user request")
        killed.append(name)
    return killed, failed
