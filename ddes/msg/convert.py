"""Messages to and from dicts and YAML, and genpy's ``fill_message_args``.

* :func:`message_to_dict` / :func:`dict_to_message`: nested plain data
  (dicts, lists, numbers, strings); times and durations as
  ``{"secs": s, "nsecs": n}``; ``uint8[]``/``char[]`` as lists of ints.
  ``dict_to_message`` checks field names and value types and says which
  field is wrong; it accepts what ``yaml.safe_load`` makes of
  ``str(msg)``, so YAML round-trips (floats written as ``1e+16``, ``inf``
  or ``nan``, which YAML reads as strings, are converted back).
* :func:`fill_message_args`: the rules ``rostopic pub`` and
  ``rosservice call`` use (genpy), with genpy's error texts.
"""

from __future__ import annotations

import copy
import numbers
from collections.abc import Mapping
from typing import Any, TypeVar

import yaml

from ddes.errors import ROSMessageException
from ddes.msg.message import FieldInfo, Message
from ddes.msg.strify import strify_message
from ddes.time.rostime import Duration, Time, TVal

__all__ = [
    "default_keys",
    "dict_to_message",
    "fill_message_args",
    "get_printable_message_args",
    "message_to_dict",
    "message_to_yaml",
    "yaml_to_message",
]

M = TypeVar("M", bound=Message)


# --- to plain data -----------------------------------------------------------------------


def _plain(info: FieldInfo, value: Any) -> Any:
    kind = info.kind
    if kind == "message":
        return message_to_dict(value)
    if kind in ("time", "duration"):
        return {"secs": value.secs, "nsecs": value.nsecs}
    return value


def message_to_dict(msg: Message) -> dict[str, Any]:
    """Nested dict of ``msg``'s fields (in field order)."""
    out: dict[str, Any] = {}
    for info in type(msg)._fields_info:
        value = getattr(msg, info.name)
        if info.kind == "bytes":
            out[info.name] = list(value.encode() if isinstance(value, str) else value)
        elif info.is_array:
            out[info.name] = [_plain(info, v) for v in value]
        else:
            out[info.name] = _plain(info, value)
    return out


def message_to_yaml(msg: Message) -> str:
    """The YAML text ``rostopic echo`` prints for ``msg`` (same as ``str(msg)``)."""
    return strify_message(msg)


# --- from plain data -------------------------------------------------------------------------


def _bad(path: str, info: FieldInfo, value: Any, want: str) -> ROSMessageException:
    return ROSMessageException(
        f"field {path} ({info.type}) cannot take {value!r} ({type(value).__name__}): "
        f"expected {want}"
    )


def _to_time(path: str, info: FieldInfo, value: Any) -> TVal:
    cls = Time if info.kind == "time" else Duration
    if isinstance(value, cls):
        return copy.copy(value)
    if isinstance(value, Mapping):
        unknown = set(value) - {"secs", "nsecs"}
        if unknown:
            raise ROSMessageException(
                f"field {path} ({info.type}): unknown keys {sorted(unknown)}; use secs and nsecs"
            )
        secs, nsecs = value.get("secs", 0), value.get("nsecs", 0)
        if not all(isinstance(v, int) and not isinstance(v, bool) for v in (secs, nsecs)):
            raise _bad(path, info, value, "integer secs and nsecs")
        try:
            return cls(secs, nsecs)
        except (TypeError, ValueError) as exc:
            raise ROSMessageException(f"field {path} ({info.type}): {exc}") from None
    if isinstance(value, int) and not isinstance(value, bool):
        try:
            return cls.from_nsec(value)
        except (TypeError, ValueError) as exc:
            raise ROSMessageException(f"field {path} ({info.type}): {exc}") from None
    raise _bad(path, info, value, "{secs: s, nsecs: n} or integer nanoseconds")


def _scalar(path: str, info: FieldInfo, value: Any) -> Any:
    kind = info.kind
    if kind == "message":
        if isinstance(value, Message) and value._type == info.cls._type:
            return value
        if value is None or isinstance(value, Mapping):
            return _from_dict(info.cls, value, path + ".")
        raise _bad(path, info, value, f"a dict of {info.cls._type} fields")
    if kind in ("time", "duration"):
        return _to_time(path, info, value)
    if kind == "string":
        if value is None:
            return ""
        if not isinstance(value, str):
            raise _bad(path, info, value, "a string")
        return value
    if kind == "float":
        if isinstance(value, str):
            try:
                return float(value)
            except ValueError:
                raise _bad(path, info, value, "a number") from None
        if isinstance(value, bool) or not isinstance(value, numbers.Real):
            raise _bad(path, info, value, "a number")
        return float(value)
    if kind == "bool":
        if value in (True, False) and isinstance(value, int):
            return bool(value)
        raise _bad(path, info, value, "true or false")
    if isinstance(value, bool) or not isinstance(value, numbers.Integral):
        raise _bad(path, info, value, "an integer")
    if not info.low <= int(value) <= info.high:
        raise _bad(path, info, value, f"an integer in [{info.low}, {info.high}]")
    return int(value)


def _field_value(path: str, info: FieldInfo, value: Any) -> Any:
    if not info.is_array:
        return _scalar(path, info, value)
    if value is None:
        value = []
    if info.kind == "bytes" and isinstance(value, bytes | bytearray):
        items: Any = bytes(value)
    elif isinstance(value, list | tuple):
        items = value
    else:
        raise _bad(path, info, value, "a list")
    if info.array_len is not None and len(items) != info.array_len:
        raise ROSMessageException(
            f"field {path} ({info.type}) has {len(items)} elements; it needs exactly "
            f"{info.array_len}"
        )
    if info.kind == "bytes":
        if isinstance(items, bytes):
            return items
        elem = info._replace(kind="int", low=0, high=255)
        return bytes(_scalar(f"{path}[{i}]", elem, v) for i, v in enumerate(items))
    return [_scalar(f"{path}[{i}]", info, v) for i, v in enumerate(items)]


def _from_dict(cls: type[M], data: Any, prefix: str) -> M:
    msg = cls()
    if data is None:
        return msg
    if not isinstance(data, Mapping):
        raise ROSMessageException(
            f"{cls._type}{' at ' + prefix[:-1] if prefix else ''}: expected a dict of fields, "
            f"got {data!r} ({type(data).__name__})"
        )
    infos = {i.name: i for i in cls._fields_info}
    for key, value in data.items():
        info = infos.get(key)
        if info is None:
            raise ROSMessageException(
                f"No field name [{prefix}{key}]; {cls._type} has fields "
                f"{', '.join(infos) or '(none)'}"
            )
        setattr(msg, key, _field_value(prefix + key, info, value))
    return msg


def dict_to_message(cls: type[M], data: Mapping[str, Any] | None) -> M:
    """A new ``cls`` message from a (nested) dict such as :func:`message_to_dict` gives.

    Missing fields keep their zero values; unknown fields and values of the
    wrong type raise :class:`~ddes.errors.ROSMessageException` naming the field.
    """
    return _from_dict(cls, data, "")


def yaml_to_message(cls: type[M], text: str) -> M:
    """A new ``cls`` message from YAML text (e.g. what ``rostopic echo`` printed)."""
    try:
        data = yaml.safe_load(text)
    except yaml.YAMLError as exc:
        raise ROSMessageException(f"invalid YAML for {cls._type}: {exc}") from None
    return _from_dict(cls, data, "")


# --- genpy's fill_message_args ------------------------------------------------------------


def _slots(obj: Any) -> list[str]:
    if isinstance(obj, TVal):
        return ["secs", "nsecs"]
    return list(obj.__slots__)


def _info(msg: Any, name: str) -> FieldInfo | None:
    if isinstance(msg, Message):
        for info in type(msg)._fields_info:
            if info.name == name:
                return info
    return None


def _time_from_ns(target: TVal, value: int) -> TVal:
    # genpy converts through float seconds (lossy); kept for identical results
    return type(target).from_sec(value / 1e9)


def _fill_val(msg: Any, name: str, value: Any, keys: Mapping[str, Any], prefix: str) -> None:
    if name not in _slots(msg):
        raise ROSMessageException(f"No field name [{prefix}{name}]")
    current = getattr(msg, name)
    info = _info(msg, name)
    if isinstance(current, Message | TVal):
        if type(value) is str:
            if value not in keys:
                raise ROSMessageException(f"No key named [{value}]")
            setattr(msg, name, copy.deepcopy(keys[value]))
        elif isinstance(current, TVal) and type(value) is int:
            setattr(msg, name, _time_from_ns(current, value))
        else:
            _fill(current, value, keys, prefix + name + ".")
    elif info is not None and info.is_array and info.kind != "bytes":
        if type(value) not in (list, tuple):
            raise ROSMessageException(
                f"Field [{prefix}{name}] must be a list or tuple instead of: "
                f"{type(value).__name__}"
            )
        if info.array_len is not None and len(value) != info.array_len:
            raise ROSMessageException(
                f"Field [{prefix}{name}] has incorrect number of elements: "
                f"{len(value)} != {info.array_len}"
            )
        if info.kind not in ("message", "time", "duration"):
            setattr(msg, name, value)
            return
        items = []
        for element in value:
            inner = info.cls()
            if isinstance(inner, TVal) and type(element) is int:
                inner = _time_from_ns(inner, element)
            else:
                _fill(inner, element, keys, prefix)
            items.append(inner)
        setattr(msg, name, items)
    else:
        setattr(msg, name, value)


def _fill(msg: Any, args: Any, keys: Mapping[str, Any], prefix: str) -> None:
    if not isinstance(msg, Message | TVal):
        raise ROSMessageException(f"msg must be a Message instance: {msg!r}")
    if type(args) is dict:
        for name, value in args.items():
            _fill_val(msg, name, "" if value is None else value, keys, prefix)
    elif type(args) is list:
        slots = _slots(msg)
        if len(args) > len(slots):
            raise ROSMessageException(
                f"Too many arguments:\n * Given: {args}\n * Expected: {slots}")
        if len(args) < len(slots):
            raise ROSMessageException(
                f"Not enough arguments:\n * Given: {args}\n * Expected: {slots}")
        for name, value in zip(slots, args):
            _fill_val(msg, name, value, keys, prefix)
    else:
        raise ROSMessageException(f"invalid msg_args type: {args}")
    if isinstance(msg, TVal):
        msg.canon()


def fill_message_args(msg: Message, msg_args: list[Any] | None,
                      keys: Mapping[str, Any] | None = None) -> None:
    """Fill ``msg`` from command-line style arguments (genpy ``fill_message_args``).

    ``msg_args`` is a list of YAML-parsed values.  A single dict fills fields
    by name; otherwise the values are positional and their number must
    equal the number of fields ("Too many arguments" / "Not enough
    arguments").  Nested messages take lists or dicts.  A time, duration or
    message field given a string looks it up in ``keys`` (``now``, ``auto``:
    see :func:`default_keys`; else "No key named [x]"); a time or duration
    given an int takes it as nanoseconds.  Fixed-size arrays need exactly
    their length.  Errors are :class:`~ddes.errors.ROSMessageException`.
    """
    args = [] if msg_args is None else msg_args
    use_keys = keys if keys is not None else {}
    if len(args) == 1 and type(args[0]) is dict:
        _fill(msg, args[0], use_keys, "")
    else:
        _fill(msg, args, use_keys, "")


def default_keys(now: Time, header_class: type[Message] | None = None) -> dict[str, Any]:
    """The substitution keys of rostopic/rosservice: ``now`` and ``auto`` (a Header).

    ``header_class`` defaults to the default registry's std_msgs/Header.
    """
    if header_class is None:
        from ddes.msg.registry import get_message_class

        header_class = get_message_class("std_msgs/Header")
    return {"now": now, "auto": header_class(stamp=now)}


def get_printable_message_args(msg: Message, prefix: str = "") -> str:
    """Field names of ``msg``, nested ones dotted (``rosservice args``)."""
    parts: list[str] = []

    def walk(m: Message, pre: str) -> None:
        for name in m.__slots__:
            value = getattr(m, name)
            if isinstance(value, Message):
                walk(value, pre + name + ".")
            else:
                parts.append(pre + name)

    walk(msg, prefix)
    return " ".join(parts)
