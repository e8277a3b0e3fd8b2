"""``rosgraph`` of ROS Noetic for rospy scripts: the master's API on the running world.

``rosgraph.Master(caller_id)`` asks the master of the script's world what rosgraph's XML-RPC
proxy asks rosmaster, with rosgraph's return values (lists, as XML-RPC gives them) and
``MasterError`` texts: ``getSystemState()``, ``getTopicTypes()``, ``getPublishedTopics(subgraph)``,
``lookupNode(name)``, ``lookupService(name)``, ``getParam``/``setParam``/``hasParam``/
``deleteParam``/``searchParam``/``getParamNames``, ``getUri()``, ``getPid()``, ``is_online()``;
``rosgraph.names`` is rosgraph's name functions (:mod:`ddes.graph.names`);
``is_master_online()``, ``get_master_uri()``, ``myargv``.

ddes nodes have no XML-RPC servers: a node's URI is the synthetic one ROS tools show in ddes
(``http://localhost:PORT/``, from its name alone, as ``rosnode info`` prints it), a service's
its ``rosrpc://`` one, the master's ``http://localhost:11311/``.
"""

from __future__ import annotations

import hashlib
from typing import TYPE_CHECKING, Any

from ddes.compat.rosgraph import names
from ddes.errors import DdesError, ROSException

if TYPE_CHECKING:
    from ddes.graph.world import World

__all__ = ["Master", "MasterError", "MasterException", "MasterFailure", "ROS_MASTER_URI",
           "get_master_uri", "is_master_online", "myargv", "names"]

ROS_MASTER_URI = "ROS_MASTER_URI"
_MASTER_URI = "http://localhost:11311"


class MasterException(ROSException):
    """rosgraph's base of master errors."""


class MasterFailure(MasterException):
    """The master failed to answer (rosgraph's ``MasterFailure``)."""


class MasterError(MasterException):
    """The master refused a call (rosgraph's ``MasterError``: its status message)."""


def _world() -> World:
    from ddes.graph.blocking import current_task

    task = current_task()
    if task is None:
        raise MasterFailure("rosgraph: no master here (ddes: call it from a script node run "
                            "by ddes, where the master is its world's)")
    return task.world


def node_uri(name: str) -> str:
    """The URI ddes's ROS tools show for node ``name`` (``ddes.launch.runtime.node_uri``)."""
    digest = int.from_bytes(hashlib.sha256(name.encode("utf-8")).digest()[:8], "big")
    return f"http://localhost:{32768 + digest % 28000}/"


def get_master_uri(env: Any = None, argv: Any = None) -> str:
    """The master's URI (ddes: the one ``roslaunch`` prints)."""
    return _MASTER_URI


def is_master_online(master_uri: str | None = None) -> bool:
    """True where a script runs: its world is its master."""
    from ddes.graph.blocking import current_task

    return current_task() is not None


def myargv(argv: list[str] | None = None) -> list[str]:
    """The command line without remapping arguments."""
    from ddes.compat import rospy

    return rospy.myargv(argv)


class Master:
    """rosgraph.Master: the master's API for ``caller_id`` (see the module docstring)."""

    def __init__(self, caller_id: str, master_uri: str | None = None) -> None:
        if not caller_id:
            raise ValueError("caller_id must be a non-empty string")
        self.caller_id = names.make_caller_id(caller_id)
        self.master_uri = master_uri or _MASTER_URI

    def is_online(self) -> bool:
        return is_master_online()

    def getUri(self) -> str:  # noqa: N802 - rosgraph's name
        return self.master_uri.rstrip("/") + "/"

    def getPid(self) -> int:  # noqa: N802
        return 1000 + int.from_bytes(hashlib.sha256(b"/master").digest()[:8], "big") % 30000

    def getSystemState(self) -> list[list[list[Any]]]:  # noqa: N802
        pubs, subs, srvs = _world().master.get_system_state()
        return [[[t, list(n)] for t, n in part] for part in (pubs, subs, srvs)]

    def getTopicTypes(self) -> list[list[str]]:  # noqa: N802
        return [[t, ty] for t, ty in _world().master.get_topic_types()]

    def getPublishedTopics(self, subgraph: str) -> list[list[str]]:  # noqa: N802
        return [[t, ty] for t, ty in _world().master.get_published_topics(subgraph)]

    def lookupNode(self, node_name: str) -> str:  # noqa: N802
        if _world().master.lookup_node(node_name) is None:
            raise MasterError(f"unknown node [{node_name}]")
        return node_uri(node_name)

    def lookupService(self, service: str) -> str:  # noqa: N802
        from ddes.services.network import network_of

        world = _world()
        entry = world.master.lookup_service(service)
        if entry is None:
            raise MasterError("no provider")
        return network_of(world).uri_for(entry.node)

    # -- parameters (keys resolved for the caller, as rosmaster resolves them) -------------
    def _key(self, key: str) -> str:
        ns = names.namespace(self.caller_id)
        if key.startswith("~"):
            return names.canonicalize_name(self.caller_id + "/" + key[1:])
        return names.canonicalize_name(key if key.startswith("/") else names.ns_join(ns, key))

    def getParam(self, key: str) -> Any:  # noqa: N802
        params = _world().master.params
        full = self._key(key)
        if not params.has_param(full):
            raise MasterError(f"Parameter [{full}] is not set")
        return params.get_param(full)

    def setParam(self, key: str, value: Any) -> int:  # noqa: N802
        _world().master.params.set_param(self._key(key), value, caller_id=self.caller_id)
        return 0

    def hasParam(self, key: str) -> bool:  # noqa: N802
        return bool(_world().master.params.has_param(self._key(key)))

    def deleteParam(self, key: str) -> int:  # noqa: N802
        params = _world().master.params
        full = self._key(key)
        try:
            params.delete_param(full)
        except (KeyError, DdesError):
            raise MasterError(f"parameter [{full}] is not set") from None
        return 0

    def searchParam(self, key: str) -> str:  # noqa: N802
        found = _world().master.params.search_param(self.caller_id, key)
        if found is None:
            raise MasterError(f"Cannot find parameter [{key}] in an upwards search")
        return str(found)

    def getParamNames(self) -> list[str]:  # noqa: N802
        return list(_world().master.params.get_param_names())
