"""``rosgraph.names``: ROS name functions (:mod:`ddes.graph.names`, which follows rosgraph's)."""

from __future__ import annotations

from ddes.graph.names import (
    ANYTYPE,
    GLOBALNS,
    PRIV_NAME,
    REMAP,
    SEP,
    canonicalize_name,
    get_ros_namespace,
    is_global,
    is_legal_base_name,
    is_legal_name,
    is_legal_remap,
    is_private,
    load_mappings,
    make_caller_id,
    make_global_ns,
    namespace,
    ns_join,
    resolve_name,
)
from ddes.graph.names import anonymous_name as _anonymous_name

__all__ = ["ANYTYPE", "GLOBALNS", "PRIV_NAME", "REMAP", "SEP", "anonymous_name",
           "canonicalize_name", "get_ros_namespace", "is_global", "is_legal_base_name",
           "is_legal_name", "is_legal_remap", "is_private", "load_mappings", "make_caller_id",
           "make_global_ns", "namespace", "ns_join", "resolve_name"]


def anonymous_name(id: str) -> str:  # noqa: A002 - rosgraph's parameter name
    """rosgraph's ``anonymous_name(id)``: a unique name, here ``<id>_<n>`` counted by the
    script's world (rosgraph adds host, pid and a random number)."""
    from ddes.graph.blocking import current_task

    task = current_task()
    n = task.world.next_id("anonymous") if task is not None else 0
    return _anonymous_name(id, n)
