"""rospy.AnyMsg: subscribe to any type and receive the serialized bytes."""

from __future__ import annotations

from typing import TYPE_CHECKING, ClassVar

if TYPE_CHECKING:
    from ddes.msg.message import BytesWriter

__all__ = ["AnyMsg"]


class AnyMsg:
    """Subscribe to any type and receive the serialized bytes (rospy.AnyMsg).

    ``_buff`` holds the wire bytes; ``_connection_header`` has ``type``,
    ``md5sum``, ``message_definition``, ``callerid`` and ``latching``.
    """

    _type: ClassVar[str] = "*"
    _md5sum: ClassVar[str] = "*"
    _full_text: ClassVar[str] = ""
    _has_header: ClassVar[bool] = False
    __slots__ = ("_buff", "_connection_header")

    def __init__(self, buff: bytes = b"", connection_header: dict[str, str] | None = None) -> None:
        self._buff = buff
        self._connection_header = connection_header or {}

    def serialize(self, buff: BytesWriter) -> None:
        buff.write(self._buff)

    def _serialize_to_bytes(self) -> bytes:
        return self._buff

    def _deserialize_from(self, data: bytes) -> AnyMsg:
        self._buff = data
        return self

    def deserialize(self, data: bytes) -> AnyMsg:
        self._buff = bytes(data)
        return self
