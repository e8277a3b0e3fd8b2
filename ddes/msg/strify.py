"""The YAML-like text of a message, as ``rostopic echo`` prints it.

:func:`strify_message` reproduces genpy's ``strify_message`` character for
character (it is what ``str(msg)`` returns in rospy): ``field: value`` lines,
nested messages indented two spaces, times as ``secs``/``nsecs`` (nsecs
right-aligned in 9 columns), numeric lists in Python list syntax, strings
through ``yaml.dump`` with double quotes, lists of messages as ``- ``
items, ``uint8[]`` data shown as a list of ints.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable
from typing import Any

import yaml

from ddes.time.rostime import Time, TVal

__all__ = ["strify_message"]


def _field_value(msg: Any, name: str, type_: str) -> Any:
    val = getattr(msg, name)
    if "uint8[" in type_:
        if isinstance(val, str):
            return [ord(c) for c in val]
        if isinstance(val, bytes | bytearray):
            return list(val)
    return val


def strify_message(val: Any, indent: str = "", time_offset: Time | None = None,
                   current_time: Time | None = None,
                   field_filter: Callable[[Any], Iterable[str]] | None = None,
                   fixed_numeric_width: int | None = None) -> str:
    """Text of ``val`` (a message, or any field value) in rostopic-echo layout.

    ``time_offset`` prints Time values relative to it; ``field_filter(msg)``
    selects the fields printed; ``fixed_numeric_width`` pads numbers (rostopic
    ``--fixed-numeric-width``).  ``current_time`` is accepted for API
    compatibility and unused, as in genpy.
    """
    from ddes.msg.message import Message

    kind = type(val)
    if kind in (int, float) and fixed_numeric_width is not None:
        if kind is float:
            text: str = ("%." + str(fixed_numeric_width) + "f") % val
            return text[:max(text.find("."), fixed_numeric_width)]
        padded: str = ("%" + str(fixed_numeric_width) + "d") % val
        return padded
    if kind in (int, float, bool):
        return str(val)
    if isinstance(val, str):
        if not val:
            return "''"
        return yaml.dump(val, default_style='"').rstrip("\n")
    if isinstance(val, TVal):
        if time_offset is not None and isinstance(val, Time):
            val = val - time_offset
        if fixed_numeric_width is not None:
            fmt = "%" + str(fixed_numeric_width) + "d"
            return f"\n{indent}secs: {fmt % val.secs}\n{indent}nsecs: {fmt % val.nsecs}"
        return f"\n{indent}secs: {val.secs}\n{indent}nsecs: {val.nsecs:9d}"
    if kind in (list, tuple):
        if not val:
            return "[]"
        first = val[0]
        if type(first) in (int, float) and fixed_numeric_width is not None:
            inner = "".join(
                strify_message(v, indent, time_offset, current_time, field_filter,
                               fixed_numeric_width) + ", " for v in val
            )
            return "[" + inner.rstrip(", ") + "]"
        if isinstance(first, str):
            text = yaml.dump(val).rstrip("\n")
            if text[0] == "[":
                return text
            return "\n" + "\n".join(indent + line for line in text.splitlines())
        if type(first) in (int, float, bool):
            return str(list(val))
        prefix = indent + "- "
        sub = indent + "  "
        return "\n" + "\n".join(
            prefix + strify_message(v, sub, time_offset, current_time, field_filter,
                                    fixed_numeric_width)
            for v in val
        )
    if isinstance(val, Message):
        slots = val.__slots__
        wanted = list(field_filter(val)) if field_filter is not None else slots
        sub = "  " + indent
        text = "\n".join(
            f"{indent}{name}: "
            + strify_message(_field_value(val, name, type_), sub, time_offset,
                             current_time, field_filter, fixed_numeric_width)
            for name, type_ in zip(slots, val._slot_types)
            if name in wanted
        )
        return "\n" + text if indent else text
    return str(val)
