"""Hypothesis strategies for ROS messages.

``messages(cls)`` draws valid instances of any generated message class:
integers within their type's range, float32 values representable in 32 bits,
UTF-8-encodable strings, canonical times and durations, fixed-size arrays of
exactly their size, nested messages drawn recursively.  Every instance
serializes, and survives serialize/deserialize and dict/YAML round trips.

    from hypothesis import given
    from ddes.msg import get_message_class
    from ddes.testing import messages

    @given(messages(get_message_class("sensor_msgs/LaserScan")))
    def test_scan(scan): ...
"""

from __future__ import annotations

from typing import TypeAlias, TypeVar

from hypothesis import strategies as st

from ddes.msg.message import FieldInfo, Message
from ddes.time.rostime import Duration, Time

__all__ = ["FieldValue", "durations", "field_values", "messages", "times"]

M = TypeVar("M", bound=Message)

#: A field's value: a scalar, a Time/Duration, a nested message, bytes (``uint8[]``), or a list.
FieldValue: TypeAlias = (
    bool | int | float | str | bytes | Time | Duration | Message | list["FieldValue"]
)

_MAX_NSECS = 999_999_999  # canonical nsecs of a Time/Duration on the wire


def times() -> st.SearchStrategy[Time]:
    """Any Time the wire format can carry (secs in uint32, canonical nsecs)."""
    return st.builds(Time, st.integers(0, 2**32 - 1), st.integers(0, _MAX_NSECS))


def durations() -> st.SearchStrategy[Duration]:
    """Any Duration the wire format can carry (secs in int32, canonical nsecs)."""
    return st.builds(Duration, st.integers(-(2**31), 2**31 - 1), st.integers(0, _MAX_NSECS))


def _scalar(info: FieldInfo, max_size: int, allow_nan: bool,
            allow_infinity: bool) -> st.SearchStrategy[FieldValue]:
    kind = info.kind
    if kind in ("int", "bytes"):
        return st.integers(info.low, info.high)
    if kind == "bool":
        return st.booleans()
    if kind == "float":
        if info.base_type == "float32":
            return st.floats(width=32, allow_nan=allow_nan, allow_infinity=allow_infinity)
        return st.floats(allow_nan=allow_nan, allow_infinity=allow_infinity)
    if kind == "string":
        return st.text(st.characters(codec="utf-8"), max_size=max_size)
    if kind == "time":
        return times()
    if kind == "duration":
        return durations()
    return messages(info.cls, max_size=max_size, allow_nan=allow_nan,
                    allow_infinity=allow_infinity)


def field_values(info: FieldInfo, *, max_size: int = 4, allow_nan: bool = False,
                 allow_infinity: bool = True) -> st.SearchStrategy[FieldValue]:
    """Valid values of one field (arrays as lists, ``uint8[]`` as bytes)."""
    n = info.array_len
    if info.kind == "bytes":
        if n is None:
            return st.binary(max_size=max_size)
        return st.binary(min_size=n, max_size=n)
    element = _scalar(info, max_size, allow_nan, allow_infinity)
    if not info.is_array:
        return element
    if n is None:
        return st.lists(element, max_size=max_size)
    return st.lists(element, min_size=n, max_size=n)


def messages(cls: type[M], *, max_size: int = 4, allow_nan: bool = False,
             allow_infinity: bool = True) -> st.SearchStrategy[M]:
    """Valid instances of message class ``cls``.

    ``max_size`` bounds variable-length arrays and strings.  NaN is off by
    default because ``nan != nan`` would break equality-based round trips.
    """
    fields = {
        info.name: field_values(info, max_size=max_size, allow_nan=allow_nan,
                                allow_infinity=allow_infinity)
        for info in cls._fields_info
    }
    return st.fixed_dictionaries(fields).map(lambda values: cls(**values))
