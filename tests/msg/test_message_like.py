"""MessageLike: what topics need of a message class, met by generated classes and AnyMsg."""

from __future__ import annotations

import io

from ddes.msg import get_message_class
from ddes.msg.anymsg import AnyMsg
from ddes.msg.message import MessageLike

String = get_message_class("std_msgs/String")
_MEMBERS = ("_type", "_md5sum", "_full_text", "_has_header", "_serialize_to_bytes",
            "_deserialize_from")


def test_generated_classes_and_anymsg_have_every_member() -> None:
    for cls in (String, AnyMsg):
        for name in _MEMBERS:
            assert hasattr(cls, name), (cls, name)
    assert all(name in MessageLike.__dict__ or name in MessageLike.__annotations__
               for name in _MEMBERS)


def test_anymsg_deserialize_from_keeps_the_bytes() -> None:
    data = String("hello")._serialize_to_bytes()
    msg = AnyMsg()
    assert msg._deserialize_from(data) is msg
    assert msg._buff == data and msg._serialize_to_bytes() == data
    buff = io.BytesIO()
    msg.serialize(buff)
    assert buff.getvalue() == data
    copy = String.__new__(String)._deserialize_from(msg._buff)
    assert copy == String("hello")
