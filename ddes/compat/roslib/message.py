"""``roslib.message`` of ROS Noetic: message and service classes by type name.

Follows Noetic's ``roslib/message.py``: :func:`get_message_class` and
:func:`get_service_class` return the class of ``pkg/Type``, or None when there is no such
type; a name without package is ``std_msgs/Header`` for ``Header`` and else
``ValueError("message type is missing package name: ...")``; a name of more than two parts is
``ValueError("invalid name [...]")`` (genmsg's check).  The classes are the running world's
(``world.messages``; outside any script, ddes's bundled types).  Also the names Noetic
re-exports from genpy: ``Message``, ``Time``, ``Duration``, ``SerializationError``,
``DeserializationError``, ``fill_message_args``, ``get_printable_message_args``,
``strify_message``.

The ValueErrors are :class:`ddes.errors.DdesValueError` (a ``ValueError`` too).
Deliberate deviation: ``reload_on_error`` is accepted and ignored (a world's types do not
change while it runs), and nothing is cached here (the world's registry caches).
"""

from __future__ import annotations

from typing import Any

from ddes.errors import DdesValueError, DeserializationError, MsgNotFound
from ddes.errors import ROSSerializationException as SerializationError
from ddes.graph.blocking import current_task
from ddes.msg import (
    Message,
    MessageRegistry,
    default_registry,
    fill_message_args,
    get_printable_message_args,
    strify_message,
)
from ddes.time.rostime import Duration, Time

__all__ = ["DeserializationError", "Duration", "Message", "SerializationError", "Time",
           "fill_message_args", "get_message_class", "get_printable_message_args",
           "get_service_class", "strify_message"]


def _registry() -> MessageRegistry:
    task = current_task()
    return task.world.messages if task is not None else default_registry()


def _full_name(type_name: str) -> str | None:
    """``pkg/Type`` of a type name as genmsg splits it; None for an empty type part."""
    parts = type_name.split("/")
    if len(parts) > 2:
        raise DdesValueError(f"invalid name [{type_name}]")
    package, base = parts if len(parts) == 2 else ("", parts[0])
    if not package:
        if base != "Header":
            raise DdesValueError(f"message type is missing package name: {type_name}")
        package = "std_msgs"
    return f"{package}/{base}" if base else None


def get_message_class(message_type: str, reload_on_error: bool = False) -> Any:
    """The class of message ``pkg/Type``, or None when the world has no such type."""
    full = _full_name(message_type)
    if full is None:
        return None
    try:
        return _registry().get_message_class(full)
    except MsgNotFound:
        return None


def get_service_class(service_type: str, reload_on_error: bool = False) -> Any:
    """The class of service ``pkg/Type``, or None when the world has no such type."""
    full = _full_name(service_type)
    if full is None:
        return None
    try:
        return _registry().get_service_class(full)
    except MsgNotFound:
        return None
