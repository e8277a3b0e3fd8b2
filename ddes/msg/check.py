"""Diagnose why a message cannot be serialized (genpy's ``check_type``).

Serialization runs fast generated code; only when it fails does
:func:`check_message` walk the message to name the bad field, its type and
its value in a :class:`~ddes.errors.ROSSerializationException`.
"""

from __future__ import annotations

import math
import numbers
import struct
from typing import Any

from ddes.errors import ROSSerializationException
from ddes.msg.message import FieldInfo, Message
from ddes.time.rostime import Duration, Time

__all__ = ["check_message", "find_problem"]

_FLT_MAX = 3.4028234663852886e38
_MISSING = object()


def _short(value: Any) -> str:
    if isinstance(value, Message):
        return f"<{value._type} message>"
    text = repr(value)
    return text if len(text) <= 80 else text[:77] + "..."


def _scalar_problem(info: FieldInfo, value: Any) -> str | None:
    kind = info.kind
    if kind in ("int", "bool"):
        if not isinstance(value, numbers.Integral):
            return f"must be an integer, not {type(value).__name__}"
        if not info.low <= int(value) <= info.high:
            return f"is out of range for {info.base_type} [{info.low}, {info.high}]"
        return None
    if kind == "float":
        if not isinstance(value, numbers.Real):
            return f"must be a float, not {type(value).__name__}"
        if info.base_type == "float32" and math.isfinite(value) and abs(float(value)) > _FLT_MAX:
            try:
                struct.pack("<f", value)
            except OverflowError:
                return "is too large for a float32"
        return None
    if kind == "string":
        if isinstance(value, bytes | bytearray):
            return None
        if not isinstance(value, str):
            return f"must be a str (or bytes), not {type(value).__name__}"
        try:
            value.encode("utf-8")
        except UnicodeEncodeError as exc:
            return f"cannot be encoded as UTF-8 ({exc.reason})"
        return None
    if kind in ("time", "duration"):
        want = Time if kind == "time" else Duration
        if not isinstance(value, want):
            return f"must be a ddes.{want.__name__}, not {type(value).__name__}"
        lo, hi = (0, 2**32 - 1) if kind == "time" else (-(2**31), 2**31 - 1)
        if not lo <= value.secs <= hi:
            return f"has secs={value.secs} outside the {kind} range [{lo}, {hi}]"
        if not 0 <= value.nsecs < 2**31:
            return f"has nsecs={value.nsecs} out of range"
        return None
    if kind == "message":
        if not isinstance(value, Message):
            return f"must be a {info.base_type} message, not {type(value).__name__}"
        if value._type != info.base_type:
            return f"must be a {info.base_type} message, not a {value._type}"
        return None
    return None  # pragma: no cover - every kind is handled above


def _array_problem(info: FieldInfo, value: Any) -> str | None:
    if info.kind == "bytes":
        if isinstance(value, bytes | bytearray | memoryview):
            n = len(value)
        elif isinstance(value, list | tuple):
            for i, v in enumerate(value):
                if not isinstance(v, numbers.Integral) or not 0 <= int(v) <= 255:
                    return f"has element [{i}] = {_short(v)}, not a byte (int in [0, 255])"
            n = len(value)
        elif hasattr(value, "tobytes"):
            n = len(value)
        else:
            return f"must be bytes or a list of ints, not {type(value).__name__}"
    else:
        if isinstance(value, str | bytes) or not hasattr(value, "__len__"):
            return f"must be a list or tuple, not {type(value).__name__}"
        n = len(value)
    if info.array_len is not None and n != info.array_len:
        return f"has {n} elements; this fixed-size array needs exactly {info.array_len}"
    return None


def find_problem(msg: Any, prefix: str = "") -> str | None:
    """Text naming the first field of ``msg`` that cannot be serialized, or None."""
    for info in type(msg)._fields_info:
        path = prefix + info.name
        value: Any = getattr(msg, info.name, _MISSING)
        if value is _MISSING:
            return f"field {path} ({info.type}) is not set; assign it or construct the message"
        if info.is_array:
            reason = _array_problem(info, value)
            if reason:
                return f"field {path} ({info.type}) has invalid value {_short(value)}: {reason}"
            if info.kind == "bytes":
                continue
            for i, item in enumerate(value):
                reason = _scalar_problem(info, item)
                if reason:
                    return (f"field {path}[{i}] ({info.base_type}) has invalid value "
                            f"{_short(item)}: {reason}")
                if info.kind == "message":
                    inner = find_problem(item, f"{path}[{i}].")
                    if inner:
                        return inner
        else:
            reason = _scalar_problem(info, value)
            if reason:
                return f"field {path} ({info.type}) has invalid value {_short(value)}: {reason}"
            if info.kind == "message":
                inner = find_problem(value, path + ".")
                if inner:
                    return inner
    return None


def check_message(msg: Message, exc: BaseException | None = None) -> None:
    """Raise ROSSerializationException for the first bad field of ``msg``.

    With ``exc`` (the error the serializer hit) it always raises: if no
    field is found at fault, the message names ``exc``.
    """
    problem = find_problem(msg)
    if problem:
        raise ROSSerializationException(
            f"cannot serialize {msg._type}: {problem}"
        ) from exc
    if exc is not None:
        raise ROSSerializationException(
            f"cannot serialize {msg._type}: {type(exc).__name__}: {exc}"
        ) from exc
