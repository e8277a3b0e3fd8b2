"""tf's ``broadcaster.py`` (Noetic): ``tf.TransformBroadcaster`` over tf2_ros's broadcaster.

``TransformBroadcaster(queue_size=100)`` publishes on ``/tf`` from the running script's node
(:class:`ddes.compat.tf2_ros.TransformBroadcaster`); ``sendTransform(translation, rotation,
time, child, parent)`` builds the geometry_msgs/TransformStamped (header ``parent`` and
``time``, ``child_frame_id`` ``child``) and ``sendTransformMessage(transform)`` sends one as a
one-element TFMessage, as Noetic does.  Like Noetic's, ``queue_size`` is ignored (tf2_ros's
broadcaster uses 100).  No deviation.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

from ddes.compat import tf2_ros

__all__ = ["TransformBroadcaster"]


class TransformBroadcaster:
    """tf.TransformBroadcaster(queue_size=100): /tf of the script's node."""

    def __init__(self, queue_size: int = 100) -> None:
        self.tf2_broadcaster = tf2_ros.TransformBroadcaster()

    def sendTransform(self, translation: Sequence[float], rotation: Sequence[float],  # noqa: N802
                      time: Any, child: str, parent: str) -> None:
        """Broadcast the transform of frame ``child`` in frame ``parent`` at ``time``."""
        cls = self.tf2_broadcaster.node.world.messages.get_message_class(
            "geometry_msgs/TransformStamped")
        t = cls()
        t.header.frame_id = parent
        t.header.stamp = time
        t.child_frame_id = child
        t.transform.translation.x = translation[0]
        t.transform.translation.y = translation[1]
        t.transform.translation.z = translation[2]
        t.transform.rotation.x = rotation[0]
        t.transform.rotation.y = rotation[1]
        t.transform.rotation.z = rotation[2]
        t.transform.rotation.w = rotation[3]
        self.sendTransformMessage(t)

    def sendTransformMessage(self, transform: Any) -> None:  # noqa: N802 - tf's name
        """Broadcast one geometry_msgs/TransformStamped."""
        self.tf2_broadcaster.sendTransform([transform])
