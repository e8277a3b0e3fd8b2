"""tf2_ros's Python API in a rospy script: ``import tf2_ros`` (docs/tf.md).

As in tf2_ros the objects take no node: ``tf2_ros.TransformListener(buffer)``,
``tf2_ros.TransformBroadcaster()``, ``tf2_ros.StaticTransformBroadcaster()`` act on the node of
the running script (:mod:`ddes.compat.rospy`).  ``tf2_ros.Buffer(cache_time=None, debug=True)``
is :class:`ddes.tf2_ros.Buffer` with tf2_ros's default ``debug=True`` (it advertises
``~tf2_frames`` once the script has a node); its ``lookup_transform(..., timeout)``,
``can_transform(..., timeout)`` and ``transform(..., timeout)`` block the calling node on
simulated time until the transform is available or the timeout has passed, then answer as
tf2_ros does.  The exceptions are tf2's.
"""

from __future__ import annotations

from typing import Any

from ddes.compat.rospy import _node
from ddes.graph.blocking import current_node
from ddes.tf2_ros import (
    DEFAULT_CAN_TRANSFORM_POLLING_SCALE,
    ConnectivityException,
    ExtrapolationException,
    InvalidArgumentException,
    LookupException,
    TimeoutException,
    TransformException,
    TypeException,
)
from ddes.tf2_ros import Buffer as _Buffer
from ddes.tf2_ros import StaticTransformBroadcaster as _StaticTransformBroadcaster
from ddes.tf2_ros import TransformBroadcaster as _TransformBroadcaster
from ddes.tf2_ros import TransformListener as _TransformListener

__all__ = ["DEFAULT_CAN_TRANSFORM_POLLING_SCALE", "Buffer", "ConnectivityException",
           "ExtrapolationException", "InvalidArgumentException", "LookupException",
           "StaticTransformBroadcaster", "TimeoutException", "TransformBroadcaster",
           "TransformException", "TransformListener", "TypeException"]


class Buffer(_Buffer):
    """tf2_ros.Buffer(cache_time=None, debug=True): waits block the script's node."""

    def __init__(self, cache_time: Any = None, debug: bool = True) -> None:
        super().__init__(cache_time, debug, node=current_node())


class TransformListener(_TransformListener):
    """tf2_ros.TransformListener(buffer, queue_size=None, buff_size=65536, tcp_nodelay=False)."""

    def __init__(self, buffer: Any, queue_size: int | None = None, buff_size: int = 65536,
                 tcp_nodelay: bool = False) -> None:
        super().__init__(_node(), buffer, queue_size, buff_size, tcp_nodelay)


class TransformBroadcaster(_TransformBroadcaster):
    """tf2_ros.TransformBroadcaster(): /tf of the script's node."""

    def __init__(self) -> None:
        super().__init__(_node())


class StaticTransformBroadcaster(_StaticTransformBroadcaster):
    """tf2_ros.StaticTransformBroadcaster(): latched /tf_static of the script's node."""

    def __init__(self) -> None:
        super().__init__(_node())
