"""Property tests: every bundled type round-trips through the wire format, dicts and YAML."""

from __future__ import annotations

import copy
import pickle

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from ddes.errors import DeserializationError
from ddes.msg import (
    Message,
    default_registry,
    deserialize_message,
    dict_to_message,
    message_class_from_definition,
    message_to_dict,
    serialize_message,
    yaml_to_message,
)
from ddes.testing import messages

_REG = default_registry()
MSG_TYPES = list(_REG.iter_types("msg"))
SRV_PARTS = [(t, part) for t in _REG.iter_types("srv") for part in ("request", "response")]

_SETTINGS = settings(max_examples=12, deadline=None,
                     suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])


def _check_round_trips(msg: Message) -> None:
    cls = type(msg)
    data = serialize_message(msg)
    back = deserialize_message(cls, data)
    assert back == msg
    assert serialize_message(back) == data
    assert dict_to_message(cls, message_to_dict(msg)) == msg
    assert yaml_to_message(cls, str(msg)) == msg
    assert copy.deepcopy(msg) == msg
    assert pickle.loads(pickle.dumps(msg)) == msg


def test_every_bundled_package_has_types() -> None:
    assert len(MSG_TYPES) > 150
    assert len(SRV_PARTS) > 20


@pytest.mark.parametrize("type_name", MSG_TYPES)
def test_message_round_trips(type_name: str) -> None:
    cls = _REG.get_message_class(type_name)

    @_SETTINGS
    @given(messages(cls))
    def check(msg: Message) -> None:
        _check_round_trips(msg)

    check()


@pytest.mark.parametrize(("type_name", "part"), SRV_PARTS)
def test_service_parts_round_trip(type_name: str, part: str) -> None:
    srv = _REG.get_service_class(type_name)
    cls = srv._request_class if part == "request" else srv._response_class

    @_SETTINGS
    @given(messages(cls))
    def check(msg: Message) -> None:
        _check_round_trips(msg)

    check()


@settings(max_examples=30, deadline=None)
@given(st.sampled_from(MSG_TYPES), st.data())
def test_class_from_definition_reads_registry_bytes(type_name: str, data: st.DataObject) -> None:
    cls = _REG.get_message_class(type_name)
    msg = data.draw(messages(cls))
    other = message_class_from_definition(type_name, cls._full_text)
    assert other is not cls
    assert other._md5sum == cls._md5sum
    back = deserialize_message(other, serialize_message(msg))
    assert back == msg
    assert serialize_message(back) == serialize_message(msg)
    assert str(back) == str(msg)


@settings(max_examples=200, deadline=None)
@given(st.sampled_from(MSG_TYPES), st.data())
def test_every_truncation_is_a_deserialization_error(type_name: str, data: st.DataObject) -> None:
    cls = _REG.get_message_class(type_name)
    raw = serialize_message(data.draw(messages(cls)))
    if not raw:
        return
    cut = data.draw(st.integers(0, len(raw) - 1))
    with pytest.raises(DeserializationError):
        deserialize_message(cls, raw[:cut])


@settings(max_examples=200, deadline=None)
@given(st.sampled_from(MSG_TYPES), st.binary(max_size=64))
def test_garbage_gives_a_message_or_a_deserialization_error(type_name: str, raw: bytes) -> None:
    cls = _REG.get_message_class(type_name)
    try:
        msg = deserialize_message(cls, raw)
    except DeserializationError:
        return
    assert isinstance(msg, cls)
