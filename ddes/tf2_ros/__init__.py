"""tf2_ros on simulated time: Buffer, TransformListener and the broadcasters (docs/tf.md).

tf2's semantics (caches, lookups, texts, exceptions) are :mod:`ddes.tf2`'s ``BufferCore``; this
room is the ROS side: the Buffer's waits as events (or blocking calls in rospy code), the
listener and broadcasters on ``/tf`` and ``/tf_static``, ``Buffer.transform`` for the stamped
geometry_msgs types, the tools' texts (``tf_echo``, ``view_frames``) and a drawing of the tree
(:func:`plot_frames`, matplotlib, loaded only when called).
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from ddes.tf2 import (
    ConnectivityException,
    ExtrapolationException,
    InvalidArgumentException,
    LookupException,
    TimeoutException,
    TransformException,
)
from ddes.tf2_ros.buffer import DEFAULT_CAN_TRANSFORM_POLLING_SCALE, Buffer
from ddes.tf2_ros.geometry import TypeException
from ddes.tf2_ros.listener import (
    StaticTransformBroadcaster,
    TransformBroadcaster,
    TransformListener,
)

if TYPE_CHECKING:
    from ddes.tf2_ros.plot import plot_frames

__all__ = ["DEFAULT_CAN_TRANSFORM_POLLING_SCALE", "Buffer", "ConnectivityException",
           "ExtrapolationException", "InvalidArgumentException", "LookupException",
           "StaticTransformBroadcaster", "TimeoutException", "TransformBroadcaster",
           "TransformException", "TransformListener", "TypeException", "plot_frames"]


def __getattr__(name: str) -> Any:
    if name == "plot_frames":  # matplotlib only when a tree is drawn
        from ddes.tf2_ros.plot import plot_frames

        return plot_frames
    raise AttributeError(f"module 'ddes.tf2_ros' has no attribute {name!r}")
