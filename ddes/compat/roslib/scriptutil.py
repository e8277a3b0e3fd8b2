"""``roslib.scriptutil`` of ROS Noetic (deprecated there, still imported by rospy_tutorials' tests).

:func:`script_resolve_name` resolves a name as a script does (global stays, ``~name`` under
``/script_name``, a relative one in the script's namespace: the running node's, else
``ROS_NAMESPACE``'s root ``/``), with Noetic's ``DeprecationWarning``. :func:`get_master` and
:func:`get_param_server` return XML-RPC proxies in Noetic; ddes has no XML-RPC master, so they
raise :class:`~ddes.errors.ROSException` saying what to use instead.
"""

from __future__ import annotations

import warnings

from ddes.errors import ROSException
from ddes.graph.names import make_caller_id, ns_join

__all__ = ["get_master", "get_param_server", "script_resolve_name"]

_GLOBAL_CALLER_ID = "/script"


def _namespace() -> str:
    from ddes.graph.blocking import current_node

    node = current_node()
    return node.namespace if node is not None else "/"


def script_resolve_name(script_name: str, name: str) -> str:
    """Noetic's ``script_resolve_name`` (no remappings)."""
    warnings.warn("Call to deprecated function script_resolve_name.", DeprecationWarning,
                  stacklevel=2)
    if not name:
        return _namespace()
    if name.startswith("/"):
        return name
    if name.startswith("~"):
        return ns_join(make_caller_id(script_name), name[1:])
    return _namespace() + name


def get_master() -> object:
    """Noetic: an XML-RPC proxy of the master. ddes: :class:`ROSException` (no XML-RPC)."""
    raise ROSException("roslib.scriptutil.get_master(): ddes has no XML-RPC master; use rospy "
                       "(get_published_topics, get_param ...) or rostest.is_publisher")


def get_param_server() -> object:
    """Noetic: an XML-RPC proxy of the parameter server. ddes: :class:`ROSException`."""
    raise ROSException("roslib.scriptutil.get_param_server(): ddes has no XML-RPC master; use "
                       "rospy.get_param / rospy.set_param")
