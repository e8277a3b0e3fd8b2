"""tf2_ros's TransformListener, TransformBroadcaster and StaticTransformBroadcaster on a node.

As everywhere in ddes the node comes first: ``TransformListener(node, buffer)``,
``TransformBroadcaster(node)``, ``StaticTransformBroadcaster(node)``; in a rospy script
``tf2_ros.TransformListener(buffer)`` (:mod:`ddes.compat.tf2_ros`) takes the script's node.

* The listener subscribes ``/tf`` and ``/tf_static`` (tf2_msgs/TFMessage) and puts every
  transform into the buffer with ``set_transform``/``set_transform_static``, the authority being
  the publisher's caller id (``msg._connection_header['callerid']``, ``default_authority``
  without one), as ``transform_listener.py`` does.  When the node's ROS time has gone back since
  the last message (``rosbag play --loop``, a ``/clock`` restart) it logs ``Detected jump back in
  time of %fs. Clearing TF buffer.`` (rospy's text; a roscpp node logs tf2_ros C++'s ``Detected
  jump back in time. Clearing TF buffer.``) and clears the buffer first.
* ``TransformBroadcaster`` publishes on ``/tf`` (queue 100); ``sendTransform`` takes one
  TransformStamped or a list.
* ``StaticTransformBroadcaster`` publishes latched on ``/tf_static`` (queue 100) and, as the C++
  broadcaster does, keeps every transform it was sent (a later one with the same child frame
  replaces the earlier) and publishes them all each time, so a late subscriber gets all of them.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from ddes.errors import DdesTypeError
from ddes.graph.topics import Publisher, Subscriber
from ddes.time.rospy_calls import is_node_like

if TYPE_CHECKING:
    from ddes.graph.node import Node
    from ddes.tf2_ros.buffer import Buffer

__all__ = ["StaticTransformBroadcaster", "TransformBroadcaster", "TransformListener"]


def _need_node(cls: str, node: object, rest: str) -> None:
    if not is_node_like(node):
        raise DdesTypeError(
            f"ddes.tf2_ros.{cls}({rest}) takes the node first, got {node!r}: write "
            f"ddes.tf2_ros.{cls}(node{', ' + rest if rest else ''}) (in a rospy script, "
            f"`import tf2_ros` and tf2_ros.{cls}({rest}) take the script's node)")


class TransformListener:
    """``TransformListener(node, buffer, queue_size=None)``: fills ``buffer`` from /tf, /tf_static."""

    def __init__(self, node: Node, buffer: Buffer, queue_size: int | None = None,
                 buff_size: int = 65536, tcp_nodelay: bool = False) -> None:
        _need_node("TransformListener", node, "buffer")
        if not callable(getattr(buffer, "set_transform", None)):
            raise DdesTypeError(f"TransformListener(node, buffer) needs a tf2_ros Buffer, got "
                                f"{buffer!r}")
        self.node = node
        self.buffer = buffer
        attach = getattr(buffer, "attach", None)
        if callable(attach) and getattr(buffer, "node", None) is None:
            attach(node)
        tf_message = node.world.messages.get_message_class("tf2_msgs/TFMessage")
        self.last_update = node.get_rostime()
        self.tf_sub = Subscriber(node, "/tf", tf_message, self.callback, queue_size=queue_size,
                                 buff_size=buff_size, tcp_nodelay=tcp_nodelay)
        self.tf_static_sub = Subscriber(node, "/tf_static", tf_message, self.static_callback,
                                        queue_size=queue_size, buff_size=buff_size,
                                        tcp_nodelay=tcp_nodelay)

    def unregister(self) -> None:
        """Unsubscribe both topics."""
        self.tf_sub.unregister()
        self.tf_static_sub.unregister()

    def check_for_reset(self) -> None:
        """Clear the buffer when ROS time went back since the last message (rospy's text)."""
        now = self.node.get_rostime()
        if now < self.last_update:
            if self.node.client_library == "roscpp":
                self.node.logwarn("Detected jump back in time. Clearing TF buffer.")
            else:
                self.node.logwarn("Detected jump back in time of %fs. Clearing TF buffer.",
                                  (self.last_update - now).to_sec())
            self.buffer.clear()
        self.last_update = now

    def callback(self, data: Any) -> None:
        """/tf: each transform into the buffer, the publisher's caller id as authority."""
        self.check_for_reset()
        who = _authority(data)
        for transform in data.transforms:
            self.buffer.set_transform(transform, who)

    def static_callback(self, data: Any) -> None:
        """/tf_static: each transform into the buffer's static store."""
        self.check_for_reset()
        who = _authority(data)
        for transform in data.transforms:
            self.buffer.set_transform_static(transform, who)


def _authority(data: Any) -> str:
    header = getattr(data, "_connection_header", None)
    if isinstance(header, dict):
        return str(header.get("callerid", "default_authority"))
    return "default_authority"


class TransformBroadcaster:
    """``TransformBroadcaster(node)``: ``sendTransform(t)`` publishes on /tf (queue 100)."""

    def __init__(self, node: Node) -> None:
        _need_node("TransformBroadcaster", node, "")
        self.node = node
        self._msg = node.world.messages.get_message_class("tf2_msgs/TFMessage")
        self.pub_tf = Publisher(node, "/tf", self._msg, queue_size=100)

    def sendTransform(self, transform: Any) -> None:  # noqa: N802 - tf2_ros's name
        """Publish one TransformStamped, or a list of them, in one TFMessage."""
        if not isinstance(transform, list):
            transform = [transform]
        self.pub_tf.publish(self._msg(transform))

    send_transform = sendTransform


class StaticTransformBroadcaster:
    """``StaticTransformBroadcaster(node)``: latched /tf_static holding every transform sent."""

    def __init__(self, node: Node) -> None:
        _need_node("StaticTransformBroadcaster", node, "")
        self.node = node
        self._msg = node.world.messages.get_message_class("tf2_msgs/TFMessage")
        self.pub_tf = Publisher(node, "/tf_static", self._msg, queue_size=100, latch=True)
        self._transforms: list[Any] = []

    def sendTransform(self, transform: Any) -> None:  # noqa: N802 - tf2_ros's name
        """Add one TransformStamped (or a list) and publish all of them (C++ tf2_ros's rule)."""
        if not isinstance(transform, list):
            transform = [transform]
        for t in transform:
            for i, old in enumerate(self._transforms):
                if old.child_frame_id == t.child_frame_id:
                    self._transforms[i] = t
                    break
            else:
                self._transforms.append(t)
        self.pub_tf.publish(self._msg(list(self._transforms)))

    send_transform = sendTransform
