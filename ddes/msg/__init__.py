"""ROS 1 messages: .msg/.srv/.action parsing, md5 + full text, generated classes, wire format.

Quick start::

    from ddes.msg import get_message_class, serialize_message, deserialize_message

    String = get_message_class("std_msgs/String")
    data = serialize_message(String(data="hi"))      # ROS 1 wire bytes
    assert deserialize_message(String, data).data == "hi"

Types are looked up on a package path by a :class:`MessageRegistry`, one
per world, layered over the shared, immutable bundled registry
(:func:`default_registry`, ddes's own packages), which the module-level
functions use.  No environment variable is read unless you call
:meth:`MessageRegistry.from_environment`.  See docs/messages.md.
"""

from ddes.msg.convert import (
    default_keys,
    dict_to_message,
    fill_message_args,
    get_printable_message_args,
    message_to_dict,
    message_to_yaml,
    yaml_to_message,
)
from ddes.msg.message import FieldInfo, Message, ServiceDefinition
from ddes.msg.registry import (
    MessageRegistry,
    default_registry,
    get_message_class,
    get_service_class,
    message_class_from_definition,
    parse_definition,
)
from ddes.msg.strify import strify_message
from ddes.msg.wire import deserialize_message, serialize_message

__all__ = [
    "FieldInfo",
    "Message",
    "MessageRegistry",
    "ServiceDefinition",
    "default_keys",
    "default_registry",
    "deserialize_message",
    "dict_to_message",
    "fill_message_args",
    "get_message_class",
    "get_printable_message_args",
    "get_service_class",
    "message_class_from_definition",
    "message_to_dict",
    "message_to_yaml",
    "parse_definition",
    "serialize_message",
    "strify_message",
    "yaml_to_message",
]
