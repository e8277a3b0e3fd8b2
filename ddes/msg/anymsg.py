"""rospy.AnyMsg: subscribe to any type and receive the serialized bytes."""

from __future__ import annotations

from typing import Any

__all__ = ["AnyMsg"]


class AnyMsg:
    """Subscribe to any type and receive the serialized bytes (rospy.AnyMsg).

    ``_buff`` holds the wire bytes; ``_connection_header`` has ``type``,
    ``md5sum``, ``message_definition``, ``callerid`` and ``latching``.
    """

    _type = "*"
    _md5sum = "*"
    _full_text = ""
    _has_header = False
    __slots__ = ("_buff", "_connection_header")

    def __init__(self, buff: bytes = b"", connection_header: dict[str, str] | None = None) -> None:
        self._buff = buff
        self._connection_header = connection_header or {}

    def serialize(self, buff: Any) -> None:
        buff.write(self._buff)

    def _serialize_to_bytes(self) -> bytes:
        return self._buff

    def deserialize(self, data: bytes) -> AnyMsg:
        self._buff = bytes(data)
        return self
