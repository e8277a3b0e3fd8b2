"""Fast helpers for the ROS 1 wire format of whole messages."""

from __future__ import annotations

from typing import TypeVar

from ddes.msg.message import Message, serialize_checked

__all__ = ["deserialize_message", "serialize_message"]

M = TypeVar("M", bound=Message)


def serialize_message(msg: Message) -> bytes:
    """The ROS 1 wire bytes of ``msg`` (what ``msg.serialize(buff)`` writes).

    A bad field raises :class:`~ddes.errors.ROSSerializationException`
    naming the field, its type and the value.
    """
    return serialize_checked(msg)


def deserialize_message(cls: type[M], data: bytes | bytearray | memoryview) -> M:
    """A new ``cls`` instance read from ROS 1 wire bytes.

    Truncated data raises :class:`~ddes.errors.DeserializationError`.
    """
    msg = object.__new__(cls)
    return msg._deserialize_from(data if type(data) is bytes else bytes(data))
