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
* ``/tf`` is received as bytes (a TFMessage subclass that keeps them, reading ``transforms`` when
  used) and parsed straight into the buffer, with no message objects (one transform between the
  frames of the last one: only its stamp and values are read); a transform that a check or the
  cache refuses, an unparsable message, a Buffer whose
  ``set_transform`` or a listener whose ``callback`` is overridden go the message way
  (``callback(msg)``, ``set_transform``), so results, logs and order are the same.
* ``TransformBroadcaster`` publishes on ``/tf`` (queue 100); ``sendTransform`` takes one
  TransformStamped or a list.
* ``StaticTransformBroadcaster`` publishes latched on ``/tf_static`` (queue 100) and, as the C++
  broadcaster does, keeps every transform it was sent (a later one with the same child frame
  replaces the earlier) and publishes them all each time, so a late subscriber gets all of them.
"""

from __future__ import annotations

import struct
from typing import TYPE_CHECKING, Any

from ddes.errors import DdesTypeError
from ddes.graph.topics import Publisher, Subscriber
from ddes.time.rospy_calls import is_node_like
from ddes.time.rostime import Time

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
        self.tf_sub = Subscriber(node, "/tf", _lazy_class(tf_message), self._on_tf,
                                 queue_size=queue_size, buff_size=buff_size,
                                 tcp_nodelay=tcp_nodelay)
        self.tf_static_sub = Subscriber(node, "/tf_static", tf_message, self.static_callback,
                                        queue_size=queue_size, buff_size=buff_size,
                                        tcp_nodelay=tcp_nodelay)

    def unregister(self) -> None:
        """Unsubscribe both topics."""
        self.tf_sub.unregister()
        self.tf_static_sub.unregister()

    @property
    def last_update(self) -> Time:
        """The ROS time of the last message (rospy's attribute)."""
        return Time._from_ns(self._last_ns)

    @last_update.setter
    def last_update(self, value: Time) -> None:
        self._last_ns = value.secs * 1_000_000_000 + value.nsecs

    def check_for_reset(self) -> None:
        """Clear the buffer when ROS time went back since the last message (rospy's text)."""
        try:
            now_ns = self.node.clock.now_ns()
        except AttributeError:  # a node-like without a clock
            t = self.node.get_rostime()
            now_ns = t.secs * 1_000_000_000 + t.nsecs
        if now_ns < self._last_ns:
            now = Time._from_ns(now_ns)
            if self.node.client_library == "roscpp":
                self.node.logwarn("Detected jump back in time. Clearing TF buffer.")
            else:
                self.node.logwarn("Detected jump back in time of %fs. Clearing TF buffer.",
                                  (self.last_update - now).to_sec())
            self.buffer.clear()
        self._last_ns = now_ns

    def callback(self, data: Any) -> None:
        """/tf: each transform into the buffer, the publisher's caller id as authority."""
        self.check_for_reset()
        who = _authority(data)
        for transform in data.transforms:
            self.buffer.set_transform(transform, who)

    # the last one-transform /tf message's frames: (their bytes, frame_id, child_frame_id, the
    # buffer, BufferCore._fast_slot for them there or None)
    _names: tuple[bytes, str, str, Any, Any] | None = None

    def _on_tf(self, data: Any) -> None:
        """/tf as bytes: parsed straight into the buffer when nothing is overridden."""
        buf = self.buffer
        if type(self).callback is not TransformListener.callback or not _plain(buf):
            self.callback(data)  # its transforms are read from the bytes when used
            return
        raw = data._buff
        names = self._names
        if (names is not None and names[3] is buf and raw[:4] == _ONE
                and raw[16:-56] == names[0]):
            # one transform between the same frames as last time into the same buffer (a
            # broadcaster's steady stream): only the stamp and the values are read; the names,
            # and where they go in the buffer, are the last ones
            secs, nsecs = _STAMP.unpack_from(raw, 8)
            values = _SEVEN.unpack_from(raw, len(raw) - 56)
            self.check_for_reset()
            who = _authority(data)
            slot = names[4]
            if slot is None:
                slot = buf._fast_slot(names[1], names[2])
                if slot is not None:
                    self._names = (names[0], names[1], names[2], buf, slot)
            if slot is None or not buf._insert_fast(slot, secs * 1_000_000_000 + nsecs, *values,
                                                    who):
                buf.set_transform(data.transforms[0], who)
            return
        items = _parse_tf(raw)
        if items is None:
            self.callback(data)  # the message way raises what is wrong
            return
        if len(items) == 1:
            self._names = (raw[16:-56], items[0][0], items[0][1], buf, None)
        self.check_for_reset()
        who = _authority(data)
        fast = buf._set_transform_fast
        for k, item in enumerate(items):
            if not fast(*item, who):
                buf.set_transform(data.transforms[k], who)

    def static_callback(self, data: Any) -> None:
        """/tf_static: each transform into the buffer's static store."""
        self.check_for_reset()
        who = _authority(data)
        for transform in data.transforms:
            self.buffer.set_transform_static(transform, who)


_U32 = struct.Struct("<I")
_HEADER = struct.Struct("<3II")
_SEVEN = struct.Struct("<7d")
_STAMP = struct.Struct("<2I")
_ONE = _U32.pack(1)


def _parse_tf(data: bytes) -> list[tuple[str, str, int, float, float, float, float, float,
                                          float, float]] | None:
    """A TFMessage's transforms as (frame_id, child, stamp ns, tx, ty, tz, qx, qy, qz, qw); None
    when the bytes do not parse exactly (trailing bytes included)."""
    try:
        (count,), o = _U32.unpack_from(data, 0), 4
        out: list[Any] = []
        for _ in range(count):
            _seq, secs, nsecs, n = _HEADER.unpack_from(data, o)
            o += 16
            if o + n > len(data):
                return None
            frame = data[o:o + n].decode("utf-8", "replace")
            o += n
            (n,) = _U32.unpack_from(data, o)
            o += 4
            if o + n > len(data):
                return None
            child = data[o:o + n].decode("utf-8", "replace")
            o += n
            out.append((frame, child, secs * 1_000_000_000 + nsecs) + _SEVEN.unpack_from(data, o))
            o += 56
    except struct.error:
        return None
    return out if o == len(data) else None


_PLAIN: list[object] = []


def _plain(buf: Any) -> bool:
    """True for a BufferCore/Buffer whose ``set_transform`` is not overridden."""
    if not _PLAIN:
        from ddes.tf2 import BufferCore
        from ddes.tf2_ros.buffer import Buffer

        _PLAIN.extend((Buffer.set_transform, BufferCore.set_transform))
    return (getattr(type(buf), "set_transform", None) in _PLAIN
            and "set_transform" not in getattr(buf, "__dict__", ()))


_LAZY: dict[type, type] = {}


def _lazy_class(tf_message: type) -> type:
    """A subclass of ``tf_message`` whose instances keep their wire bytes: ``transforms`` is read
    from them when first used, and until it is set they serialize as those bytes."""
    lazy = _LAZY.get(tf_message)
    if lazy is None:
        base_deserialize = tf_message._deserialize_from  # type: ignore[attr-defined]
        base_serialize = tf_message._serialize_to_bytes  # type: ignore[attr-defined]
        slot = tf_message.__dict__["transforms"]

        def deserialize_from(self: Any, data: bytes) -> Any:
            self._buff = bytes(data)
            return self

        def getattr_(self: Any, name: str) -> Any:
            # reached only for an unset slot: `transforms` of a message kept as bytes
            if name == "transforms":
                try:
                    buff = object.__getattribute__(self, "_buff")
                except AttributeError:
                    raise AttributeError(name) from None
                base_deserialize(self, buff)
                return slot.__get__(self, None)
            raise AttributeError(name)

        def serialize_to_bytes(self: Any) -> bytes:
            try:
                slot.__get__(self, None)
            except AttributeError:  # never read or set: the bytes as received
                return object.__getattribute__(self, "_buff")  # type: ignore[no-any-return]
            return base_serialize(self)  # type: ignore[no-any-return]

        lazy = type(tf_message)("TFMessageBytes", (tf_message,), {
            "__slots__": ("_buff",), "__module__": __name__,
            "_deserialize_from": deserialize_from, "__getattr__": getattr_,
            "_serialize_to_bytes": serialize_to_bytes})
        _LAZY[tf_message] = lazy
    return lazy


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
