"""The parsed form of .msg/.srv/.action definitions (genmsg's MsgSpec and friends).

These are plain immutable records; :mod:`ddes.msg.parser` builds them from
text and :mod:`ddes.msg.gentools` computes md5 sums and full definition text
from them.  Field types are stored *resolved* the way genmsg stores them:
``Header`` becomes ``std_msgs/Header`` and a package-relative ``Point``
inside ``geometry_msgs`` becomes ``geometry_msgs/Point``; builtins
(``int32``, ``string``, ``time`` ...) keep their names, array suffixes kept
(``float32[]``, ``geometry_msgs/Point[3]``).
"""

from __future__ import annotations

import keyword
import re
from dataclasses import dataclass, field
from typing import Any

__all__ = [
    "BUILTIN_TYPES",
    "HEADER",
    "HEADER_FULL_NAME",
    "PRIMITIVE_TYPES",
    "SIMPLE_STRUCT",
    "ActionSpec",
    "Constant",
    "Field",
    "MsgSpec",
    "SrvSpec",
    "bare_msg_type",
    "is_builtin",
    "is_legal_base_name",
    "is_legal_resource_name",
    "package_resource_name",
    "parse_type",
    "python_safe_name",
    "resolve_type",
]

HEADER = "Header"
HEADER_FULL_NAME = "std_msgs/Header"

#: Types allowed for constants (genmsg PRIMITIVE_TYPES; ``char``/``byte`` deprecated).
PRIMITIVE_TYPES = (
    "int8", "uint8", "int16", "uint16", "int32", "uint32", "int64", "uint64",
    "float32", "float64", "string", "bool", "char", "byte",
)
#: Primitives plus ``time`` and ``duration``.
BUILTIN_TYPES = PRIMITIVE_TYPES + ("time", "duration")

#: Fixed-size primitives and their little-endian ``struct`` codes (genpy's table:
#: ``byte`` is a signed int8, ``char`` an unsigned uint8, ``bool`` a uint8).
SIMPLE_STRUCT: dict[str, str] = {
    "int8": "b", "uint8": "B", "bool": "B", "int16": "h", "uint16": "H",
    "int32": "i", "uint32": "I", "int64": "q", "uint64": "Q",
    "float32": "f", "float64": "d", "char": "B", "byte": "b",
}

_RESOURCE_RE = re.compile(r"[A-Za-z][\w/]*\Z")  # \Z: '$' would accept a trailing newline
_BASE_RE = re.compile(r"[A-Za-z]\w*\Z")


def is_legal_resource_name(name: str) -> bool:
    """``pkg/Type`` or ``Type``: a letter, then letters, digits, ``_`` or ``/`` (no ``//``)."""
    return bool(_RESOURCE_RE.match(name)) and "//" not in name and name.isascii()


def is_legal_base_name(name: str) -> bool:
    """A field, constant or type base name: a letter, then letters, digits or ``_``."""
    return bool(_BASE_RE.match(name)) and name.isascii()


def package_resource_name(name: str) -> tuple[str, str]:
    """Split ``pkg/Type`` into ``("pkg", "Type")``; a bare ``Type`` gives ``("", "Type")``."""
    if "/" in name:
        pkg, _, base = name.partition("/")
        return pkg, base
    return "", name


def bare_msg_type(type_: str) -> str:
    """The type without its array suffix: ``Point[3]`` -> ``Point``."""
    idx = type_.find("[")
    return type_ if idx < 0 else type_[:idx]


def is_builtin(type_: str) -> bool:
    """True for primitives, ``time`` and ``duration`` (no array suffix)."""
    return type_ in BUILTIN_TYPES


def parse_type(type_: str) -> tuple[str, bool, int | None]:
    """``(base_type, is_array, array_len)`` of a field type (genmsg.msgs.parse_type).

    Raises ValueError for multi-dimensional or non-numeric array suffixes.
    """
    if "[" not in type_:
        return type_, False, None
    parts = type_.split("[")
    if len(parts) > 2:
        raise ValueError(f"only 1-dimensional array types are supported: {type_}")
    if type_.endswith("[]"):
        return type_[:-2], True, None
    inner = parts[1][:-1] if parts[1].endswith("]") else parts[1]
    if not (inner.isdigit() and inner.isascii()) or not type_.endswith("]"):
        raise ValueError(f"invalid array dimension: [{inner}]")
    return parts[0], True, int(inner)


def resolve_type(type_: str, package: str) -> str:
    """Resolve a field type against the package it appears in (genmsg semantics)."""
    base = bare_msg_type(type_)
    if base in BUILTIN_TYPES:
        return type_
    if base == HEADER:
        return HEADER_FULL_NAME + type_[len(base):]
    if "/" in base or not package:
        return type_
    return f"{package}/{type_}"


def python_safe_name(name: str) -> str:
    """genpy's remapping of Python keywords (and ``self``) by appending ``_``."""
    if keyword.iskeyword(name) or name == "self":
        return name + "_"
    return name


@dataclass(frozen=True)
class Constant:
    """``type NAME=value``: ``val`` is the Python value, ``val_text`` the text hashed."""

    type: str
    name: str
    val: Any
    val_text: str
    line: int = 0


@dataclass(frozen=True)
class Field:
    """One field: ``type`` is resolved (``std_msgs/Header``, ``float32[]``)."""

    type: str
    name: str
    line: int = 0

    @property
    def base_type(self) -> str:
        """Type without array suffix."""
        return bare_msg_type(self.type)

    @property
    def is_array(self) -> bool:
        """True for ``T[]`` and ``T[n]``."""
        return "[" in self.type

    @property
    def array_len(self) -> int | None:
        """``n`` for ``T[n]``, None for variable-length arrays and scalars."""
        return parse_type(self.type)[2]

    @property
    def is_builtin(self) -> bool:
        """True if the base type is a primitive, ``time`` or ``duration``."""
        return self.base_type in BUILTIN_TYPES


@dataclass(frozen=True)
class MsgSpec:
    """A parsed message: fields and constants in file order, and the exact text."""

    full_name: str
    text: str
    fields: tuple[Field, ...]
    constants: tuple[Constant, ...] = ()
    filename: str = ""

    @property
    def package(self) -> str:
        """The package part of ``full_name``."""
        return package_resource_name(self.full_name)[0]

    @property
    def short_name(self) -> str:
        """The type part of ``full_name``."""
        return package_resource_name(self.full_name)[1]

    @property
    def types(self) -> list[str]:
        """Field types (resolved), in order."""
        return [f.type for f in self.fields]

    @property
    def names(self) -> list[str]:
        """Field names, in order (as in the file, not Python-safe)."""
        return [f.name for f in self.fields]

    def has_header(self) -> bool:
        """True if the first field is ``Header header`` (genmsg ``has_header``)."""
        return bool(self.fields) and self.fields[0].type == HEADER_FULL_NAME \
            and self.fields[0].name == "header"


@dataclass(frozen=True)
class SrvSpec:
    """A parsed service: request and response message specs plus the .srv text."""

    full_name: str
    text: str
    request: MsgSpec
    response: MsgSpec
    filename: str = ""

    @property
    def package(self) -> str:
        """The package part of ``full_name``."""
        return package_resource_name(self.full_name)[0]

    @property
    def short_name(self) -> str:
        """The type part of ``full_name``."""
        return package_resource_name(self.full_name)[1]


@dataclass(frozen=True)
class ActionSpec:
    """A parsed action: the seven generated message specs, keyed by suffix."""

    full_name: str
    text: str
    messages: dict[str, MsgSpec] = field(default_factory=dict)
    filename: str = ""
