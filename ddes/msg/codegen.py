"""Generate a specialised Python class per message type and ``exec`` it.

For each :class:`~ddes.msg.spec.MsgSpec` this module writes the source of
three functions -- ``__init__``, ``_serialize_to_bytes`` and
``_deserialize_from`` -- and compiles them once.  Like genpy's generator, the
code is *flattened*: nested messages, times and durations are inlined, and
runs of fixed-size primitives (including the length prefixes of strings and
arrays that follow them) are packed or unpacked with one precompiled
little-endian ``struct.Struct``.

The wire format is ROS 1's: little-endian primitives; ``bool`` as one byte;
``string`` and variable-length arrays prefixed by a uint32 count (strings in
UTF-8); fixed-length arrays without a prefix; ``uint8[]``/``char[]`` held as
``bytes``; ``time`` as uint32 secs + uint32 nsecs, ``duration`` as int32 +
int32.  Deserialized primitive arrays are tuples (``bool[]`` lists of bool),
as genpy returns them.  Times and durations read from the wire are always
canonicalised (genpy does this only for top-level fields).
"""

from __future__ import annotations

import struct
from collections.abc import Callable
from typing import Any

from ddes.errors import DdesAttributeError, DdesTypeError, DeserializationError, InvalidMsgSpec
from ddes.msg.message import FieldInfo, Message
from ddes.msg.spec import SIMPLE_STRUCT, MsgSpec, parse_type, python_safe_name
from ddes.time.rostime import Duration, Time

__all__ = [
    "MAX_DEFAULT_ELEMENTS",
    "MAX_FLAT_FIELDS",
    "MAX_ZERO_SIZE_ELEMENTS",
    "field_infos",
    "generate_message_class",
]

#: Most fields one generated class may inline (nested messages are flattened, so a type
#: that uses ``B`` ten times, where ``B`` uses ``C`` ten times ... grows exponentially).
MAX_FLAT_FIELDS = 20_000
#: Most elements (summed over fixed-length arrays, nested ones multiplied) a default
#: instance of one type may hold: ``int32[4000000000] x`` would otherwise allocate 32 GB.
MAX_DEFAULT_ELEMENTS = 1 << 22
#: Most elements a variable-length array of a type with no wire bytes (``std_msgs/Empty[]``)
#: may declare on the wire: such a count is not bounded by the data's length.
MAX_ZERO_SIZE_ELEMENTS = 1 << 20

_INT_RANGES = {
    "int8": (-(2**7), 2**7 - 1), "byte": (-(2**7), 2**7 - 1), "uint8": (0, 2**8 - 1),
    "char": (0, 2**8 - 1), "bool": (0, 2**8 - 1), "int16": (-(2**15), 2**15 - 1),
    "uint16": (0, 2**16 - 1), "int32": (-(2**31), 2**31 - 1), "uint32": (0, 2**32 - 1),
    "int64": (-(2**63), 2**63 - 1), "uint64": (0, 2**64 - 1),
}
_STRUCT_I = struct.Struct("<I")


def _kind(base: str) -> str:
    if base in ("float32", "float64"):
        return "float"
    if base == "bool":
        return "bool"
    if base in _INT_RANGES:
        return "int"
    if base in ("string", "time", "duration"):
        return base
    return "message"


def field_infos(spec: MsgSpec, resolve: Callable[[str], type[Message]]) -> tuple[FieldInfo, ...]:
    """One :class:`FieldInfo` per field of ``spec``; ``resolve`` maps a type name to its class."""
    infos = []
    for f in spec.fields:
        base, is_array, length = parse_type(f.type)
        kind = _kind(base)
        cls: Any = None
        if kind == "message":
            cls = resolve(base)
        elif kind == "time":
            cls = Time
        elif kind == "duration":
            cls = Duration
        if is_array and base in ("uint8", "char"):
            kind = "bytes"
        low, high = _INT_RANGES.get(base, (0, 0))
        infos.append(FieldInfo(python_safe_name(f.name), f.type, base, is_array, length,
                               kind, cls, low, high))
    return tuple(infos)


def _trunc(msg: Message, needed: int, have: int) -> DeserializationError:
    return DeserializationError(
        f"cannot deserialize {msg._type}: the data is truncated (needs at least {needed} "
        f"bytes, got {have}); check that the bytes are a serialized {msg._type} and "
        "that the md5sums match"
    )


def _struct_failure(msg: Message, exc: Exception) -> DeserializationError:
    return DeserializationError(
        f"cannot deserialize {msg._type}: the data is truncated or corrupt ({exc}); "
        f"check that the bytes are a serialized {msg._type} and that the md5sums match"
    )


def _too_many(msg: Message, count: int, elem_size: int, have: int) -> DeserializationError:
    if elem_size:
        return DeserializationError(
            f"cannot deserialize {msg._type}: an array declares {count} elements of at least "
            f"{elem_size} bytes each, but only {have} bytes remain; the data is truncated or "
            f"corrupt (check that the bytes are a serialized {msg._type} and that the md5sums "
            "match)"
        )
    return DeserializationError(
        f"cannot deserialize {msg._type}: an array of a type with no fields declares {count} "
        f"elements, more than ddes.msg.codegen.MAX_ZERO_SIZE_ELEMENTS ({MAX_ZERO_SIZE_ELEMENTS}); "
        "the data is probably corrupt (raise the limit if it is genuine)"
    )


def _check_zero(msg: Message, count: int) -> None:
    if count > MAX_ZERO_SIZE_ELEMENTS:
        raise _too_many(msg, count, 0, 0)


def _fixed_len_error(path: str, want: int, got: int) -> ValueError:
    return ValueError(f"field {path} needs exactly {want} elements, got {got}")


def _to_bytes(value: Any) -> bytes:
    if isinstance(value, str):
        raise TypeError("uint8[] data must be bytes or a list of ints, not str")
    return bytes(value)


def _pack_array(code: str, seq: Any) -> bytes:
    return struct.pack(f"<{len(seq)}{code}", *seq)


def _make_time(secs: int, nsecs: int) -> Time:
    t = object.__new__(Time)
    t.secs = secs
    t.nsecs = nsecs
    if nsecs >= 1_000_000_000:
        t.canon()
    return t


def _make_duration(secs: int, nsecs: int) -> Duration:
    d = object.__new__(Duration)
    d.secs = secs
    d.nsecs = nsecs
    if not 0 <= nsecs < 1_000_000_000:
        d.canon()
    return d


class _Source:
    """Lines of generated code plus the objects they reference."""

    def __init__(self, numpy: Any = None) -> None:
        self.numpy = numpy  # the numpy module for numpy_msg classes, else None
        self.lines: list[str] = []
        self.ns: dict[str, Any] = {
            "_struct": struct, "_I": _STRUCT_I, "_Time": Time, "_Duration": Duration,
            "_new": object.__new__, "_mkT": _make_time, "_mkD": _make_duration,
            "_to_bytes": _to_bytes, "_pack_array": _pack_array, "_unpack_from":
            struct.unpack_from, "_trunc": _trunc, "_flen": _fixed_len_error,
            "_TypeErr": DdesTypeError, "_AttrErr": DdesAttributeError,
            "_many": _too_many, "_zero": _check_zero, "_np": numpy,
        }
        self._counter = 0
        self._structs: dict[str, str] = {}

    def var(self, prefix: str = "_v") -> str:
        self._counter += 1
        return f"{prefix}{self._counter}"

    def obj(self, value: Any, prefix: str = "_c") -> str:
        for key, existing in self.ns.items():
            if existing is value and key.startswith(prefix):
                return key
        name = self.var(prefix)
        self.ns[name] = value
        return name

    def struct(self, fmt: str) -> str:
        if fmt not in self._structs:
            name = self.var("_S")
            self.ns[name] = struct.Struct("<" + fmt)
            self._structs[fmt] = name
        return self._structs[fmt]

    def emit(self, indent: int, line: str) -> None:
        self.lines.append("    " * indent + line)


def _infos_of(cls: type[Message]) -> tuple[FieldInfo, ...]:
    return cls._fields_info


_SCALAR_MIN = {"string": 4, "time": 8, "duration": 8}


def _elem_min_size(info: FieldInfo) -> int:
    """Fewest wire bytes one (non-array) value of ``info``'s type takes."""
    if info.kind in ("int", "float", "bool", "bytes"):
        return struct.calcsize("<" + SIMPLE_STRUCT[info.base_type])
    if info.kind in _SCALAR_MIN:
        return _SCALAR_MIN[info.kind]
    return int(getattr(info.cls, "_wire_min", 0))


def _measure(infos: tuple[FieldInfo, ...]) -> tuple[int, int, int]:
    """(fewest wire bytes, fields inlined by codegen, elements of a default instance)."""
    wire = flat = elems = 0
    for info in infos:
        nested = info.kind == "message"
        sub_flat = int(getattr(info.cls, "_flat_fields", 1)) if nested else 1
        sub_elems = int(getattr(info.cls, "_default_elements", 1)) if nested else 1
        flat += sub_flat
        if not info.is_array:
            wire += _elem_min_size(info)
            elems += sub_elems
        elif info.array_len is None:
            wire += 4
            elems += 1
        else:
            wire += info.array_len * _elem_min_size(info)
            elems += info.array_len * max(sub_elems, 1)
    return wire, flat, elems


# --- serialization ---------------------------------------------------------------------


class _Packer:
    """Accumulates fixed-size values and packs each run with one Struct."""

    def __init__(self, src: _Source) -> None:
        self.src = src
        self.codes: list[str] = []
        self.exprs: list[str] = []

    def add(self, code: str, expr: str) -> None:
        self.codes.append(code)
        self.exprs.append(expr)

    def flush(self, indent: int) -> None:
        if not self.codes:
            return
        name = self.src.struct("".join(self.codes))
        self.src.emit(indent, f"_w({name}.pack({', '.join(self.exprs)}))")
        self.codes, self.exprs = [], []


def _ser_fields(src: _Source, pk: _Packer, infos: tuple[FieldInfo, ...], ctx: str,
                indent: int, path: str) -> None:
    for info in infos:
        ref = f"{ctx}.{info.name}"
        where = path + info.name
        if not info.is_array:
            _ser_scalar(src, pk, info, ref, indent, where)
            continue
        tmp = src.var()
        src.emit(indent, f"{tmp} = {ref}")
        n = info.array_len
        if info.kind == "bytes":
            src.emit(indent, f"if {tmp}.__class__ is not bytes: {tmp} = _to_bytes({tmp})")
            if n is None:
                pk.add("I", f"len({tmp})")
            else:
                src.emit(indent, f"if len({tmp}) != {n}: raise _flen({where!r}, {n}, len({tmp}))")
            pk.flush(indent)
            src.emit(indent, f"_w({tmp})")
            continue
        if n is None:
            pk.add("I", f"len({tmp})")
        elif info.kind == "bool" or (info.kind in ("int", "float") and src.numpy is None):
            pk.add(f"{n}{SIMPLE_STRUCT[info.base_type]}", f"*{tmp}")
            continue
        else:
            src.emit(indent, f"if len({tmp}) != {n}: raise _flen({where!r}, {n}, len({tmp}))")
        if info.kind in ("int", "float") and src.numpy is not None:
            pk.flush(indent)
            dt = "<" + SIMPLE_STRUCT[info.base_type]
            src.emit(indent, f"_w(_np.asarray({tmp}, {dt!r}).tobytes())")
            continue
        if info.kind in ("int", "float", "bool"):
            pk.flush(indent)
            src.emit(indent, f"_w(_pack_array({SIMPLE_STRUCT[info.base_type]!r}, {tmp}))")
            continue
        pk.flush(indent)
        item = src.var("_e")
        src.emit(indent, f"for {item} in {tmp}:")
        inner = _Packer(src)
        elem = info._replace(is_array=False, array_len=None)
        body_start = len(src.lines)
        _ser_scalar(src, inner, elem, item, indent + 1, where + "[]", bare=True)
        inner.flush(indent + 1)
        if len(src.lines) == body_start:  # a type with no fields: the count, then nothing
            src.emit(indent + 1, "pass")


def _ser_scalar(src: _Source, pk: _Packer, info: FieldInfo, ref: str, indent: int,
                where: str, bare: bool = False) -> None:
    kind = info.kind
    if kind in ("int", "float", "bool"):
        pk.add(SIMPLE_STRUCT[info.base_type], ref)
    elif kind in ("time", "duration"):
        tmp = ref if bare else src.var()
        if not bare:
            src.emit(indent, f"{tmp} = {ref}")
        code = "I" if kind == "time" else "i"
        pk.add(code, f"{tmp}.secs")
        pk.add(code, f"{tmp}.nsecs")
    elif kind == "string":
        tmp = src.var()
        src.emit(indent, f"{tmp} = {ref}")
        src.emit(indent, f"if {tmp}.__class__ is str: {tmp} = {tmp}.encode()")
        pk.add("I", f"len({tmp})")
        pk.flush(indent)
        src.emit(indent, f"_w({tmp})")
    else:  # nested message
        tmp = ref if bare else src.var()
        if not bare:
            src.emit(indent, f"{tmp} = {ref}")
        _ser_fields(src, pk, _infos_of(info.cls), tmp, indent, where + ".")


# --- deserialization -------------------------------------------------------------------


class _Unpacker:
    """Accumulates fixed-size targets and unpacks each run with one Struct."""

    def __init__(self, src: _Source) -> None:
        self.src = src
        self.codes: list[str] = []
        self.targets: list[str] = []
        self.post: list[str] = []

    def add(self, code: str, target: str) -> None:
        self.codes.append(code)
        self.targets.append(target)

    def flush(self, indent: int) -> None:
        if not self.codes:
            return
        fmt = "".join(self.codes)
        name = self.src.struct(fmt)
        size = struct.calcsize("<" + fmt)
        targets = ", ".join(self.targets)
        self.src.emit(indent, f"{targets}, = {name}.unpack_from(_d, _o)")
        self.src.emit(indent, f"_o += {size}")
        for line in self.post:
            self.src.emit(indent, line)
        self.codes, self.targets, self.post = [], [], []


def _check_room(src: _Source, indent: int, end: str) -> None:
    src.emit(indent, f"if {end} > _n: raise _trunc(self, {end}, _n)")


def _de_fields(src: _Source, up: _Unpacker, infos: tuple[FieldInfo, ...], ctx: str,
               indent: int) -> None:
    for info in infos:
        ref = f"{ctx}.{info.name}"
        if not info.is_array:
            _de_scalar(src, up, info, ref, indent)
            continue
        n = info.array_len
        base = info.base_type
        if info.kind == "bytes":
            if n is None:
                length = src.var("_l")
                up.add("I", length)
                up.flush(indent)
            else:
                up.flush(indent)
                length = str(n)
            src.emit(indent, f"_e = _o + {length}")
            _check_room(src, indent, "_e")
            src.emit(indent, f"{ref} = _d[_o:_e]")
            src.emit(indent, "_o = _e")
            continue
        if info.kind in ("int", "float", "bool"):
            code = SIMPLE_STRUCT[base]
            size = struct.calcsize("<" + code)
            if n is None:
                length = src.var("_l")
                up.add("I", length)
                up.flush(indent)
                src.emit(indent, f"_e = _o + {length} * {size}")
                _check_room(src, indent, "_e")
                value = f"_unpack_from('<%d{code}' % {length}, _d, _o)"
                if src.numpy is not None and info.kind != "bool":
                    value = f"_np.frombuffer(_d, '<{code}', {length}, _o)"
            else:
                up.flush(indent)
                sname = src.struct(f"{n}{code}")
                src.emit(indent, f"_e = _o + {n * size}")
                _check_room(src, indent, "_e")
                value = f"{sname}.unpack_from(_d, _o)"
                if src.numpy is not None and info.kind != "bool":
                    value = f"_np.frombuffer(_d, '<{code}', {n}, _o)"
            if info.kind == "bool":
                value = f"[bool(_b) for _b in {value}]"
            src.emit(indent, f"{ref} = {value}")
            src.emit(indent, "_o = _e")
            continue
        if n is None:
            length = src.var("_l")
            up.add("I", length)
        else:
            length = str(n)
        up.flush(indent)
        if n is None:
            # reject a huge count before building anything: each element needs bytes
            size = _elem_min_size(info)
            if size:
                src.emit(indent, f"if _o + {length} * {size} > _n: "
                                 f"raise _many(self, {length}, {size}, _n - _o)")
            else:
                src.emit(indent, f"_zero(self, {length})")
        lst = src.var("_a")
        src.emit(indent, f"{ref} = {lst} = []")
        src.emit(indent, f"for _ in range({length}):")
        inner = _Unpacker(src)
        item = src.var("_e")
        elem = info._replace(is_array=False, array_len=None)
        _de_scalar(src, inner, elem, item, indent + 1)
        inner.flush(indent + 1)
        src.emit(indent + 1, f"{lst}.append({item})")


def _de_scalar(src: _Source, up: _Unpacker, info: FieldInfo, ref: str, indent: int) -> None:
    kind = info.kind
    if kind in ("int", "float"):
        up.add(SIMPLE_STRUCT[info.base_type], ref)
    elif kind == "bool":
        tmp = src.var("_t")
        up.add("B", tmp)
        up.post.append(f"{ref} = {tmp} != 0")
    elif kind in ("time", "duration"):
        s, ns = src.var("_t"), src.var("_t")
        code = "I" if kind == "time" else "i"
        up.add(code, s)
        up.add(code, ns)
        maker = "_mkT" if kind == "time" else "_mkD"
        up.post.append(f"{ref} = {maker}({s}, {ns})")
    elif kind == "string":
        length = src.var("_l")
        up.add("I", length)
        up.flush(indent)
        src.emit(indent, f"_e = _o + {length}")
        _check_room(src, indent, "_e")
        src.emit(indent, f"{ref} = _d[_o:_e].decode('utf-8', 'replace')")
        src.emit(indent, "_o = _e")
    else:
        cname = src.obj(info.cls)
        tmp = src.var()
        src.emit(indent, f"{tmp} = {ref} = _new({cname})")
        _de_fields(src, up, _infos_of(info.cls), tmp, indent)


# --- __init__ ----------------------------------------------------------------------------


def _default_expr(src: _Source, info: FieldInfo) -> str:
    n = info.array_len
    if info.kind == "bytes":
        return "b''" if n is None else f"b'\\x00' * {n}"
    if info.is_array and n is None:
        return "[]"
    scalar = {"int": "0", "float": "0.0", "bool": "False", "string": "''"}.get(info.kind)
    if scalar is not None:
        return scalar if not info.is_array else f"[{scalar}] * {n}"
    ctor = f"{src.obj(info.cls)}()"
    return ctor if not info.is_array else f"[{ctor} for _ in range({n})]"


def _init_source(src: _Source, cls_name: str, infos: tuple[FieldInfo, ...]) -> None:
    names = [i.name for i in infos]
    pct = cls_name.replace("%", "%%")  # the messages below are %-formatted
    src.ns["_SLOTS"] = frozenset(names)
    src.emit(0, "def __init__(self, *args, **kwds):")
    if not infos:
        src.emit(1, "if args or kwds:")
        src.emit(2, "if args and kwds: raise _TypeErr("
                    "'Message constructor may only use args OR keywords, not both')")
        src.ns["_NARGS"] = ("Invalid number of arguments, args should be [] args are%s; "
                            f"{pct} has no fields")
        src.ns["_NOATTR"] = f"%s is not an attribute of {pct}; it has no fields"
        src.emit(2, "if args: raise _TypeErr(_NARGS % (args,))")
        src.emit(2, "raise _AttrErr(_NOATTR % (next(iter(kwds)),))")
        return
    local = [f"_a{i}" for i in range(len(infos))]
    src.emit(1, "if args:")
    src.emit(2, "if kwds: raise _TypeErr("
                "'Message constructor may only use args OR keywords, not both')")
    src.ns["_NARGS"] = (f"Invalid number of arguments, args should be {names!r} args are%s; "
                        f"pass all {len(infos)} fields in order, or use keyword arguments")
    src.emit(2, f"if len(args) != {len(infos)}: raise _TypeErr(_NARGS % (args,))")
    src.emit(2, f"{', '.join(local)}, = args")
    src.emit(1, "elif kwds:")
    src.ns["_NOATTR"] = f"%s is not an attribute of {pct}; its fields are {', '.join(names)}"
    src.emit(2, "for _k in kwds:")
    src.emit(3, "if _k not in _SLOTS: raise _AttrErr(_NOATTR % (_k,))")
    src.emit(2, "_get = kwds.get")
    for var, name in zip(local, names):
        src.emit(2, f"{var} = _get({name!r})")
    src.emit(1, "else:")
    for info in infos:
        src.emit(2, f"self.{info.name} = {_default_expr(src, info)}")
    src.emit(2, "return")
    for var, info in zip(local, infos):
        src.emit(1, f"self.{info.name} = {_default_expr(src, info)} if {var} is None else {var}")


def generate_message_class(spec: MsgSpec, md5sum: str, full_text: str,
                           resolve: Callable[[str], type[Message]],
                           numpy: Any = None) -> type[Message]:
    """Build the Message subclass for ``spec`` (nested types via ``resolve``).

    ``numpy`` (the numpy module) builds the :func:`ddes.msg.numpy_msg` form:
    numeric arrays (not bool, not uint8/char) read as read-only
    ``numpy.frombuffer`` views and written with ``numpy.asarray(...).tobytes()``.

    ``resolve(type_name)`` must return the already built class of each
    nested message type.
    """
    infos = field_infos(spec, resolve)
    wire_min, flat, elems = _measure(infos)
    if flat > MAX_FLAT_FIELDS:
        raise InvalidMsgSpec(
            f"{spec.filename or spec.full_name}: {spec.full_name} has {flat} fields once its "
            f"nested types are expanded, more than ddes.msg.codegen.MAX_FLAT_FIELDS "
            f"({MAX_FLAT_FIELDS}); the definition nests types too often (raise the limit if "
            "it is genuine)"
        )
    if elems > MAX_DEFAULT_ELEMENTS:
        raise InvalidMsgSpec(
            f"{spec.filename or spec.full_name}: a default {spec.full_name} holds {elems} "
            f"array elements (fixed-length arrays, nested ones multiplied), more than "
            f"ddes.msg.codegen.MAX_DEFAULT_ELEMENTS ({MAX_DEFAULT_ELEMENTS}); use a "
            "variable-length array T[] (or raise the limit if it is genuine)"
        )
    src = _Source(numpy)
    cls_name = spec.short_name
    _init_source(src, cls_name, infos)

    src.emit(0, "def _serialize_to_bytes(self):")
    src.emit(1, "_parts = []")
    src.emit(1, "_w = _parts.append")
    pk = _Packer(src)
    _ser_fields(src, pk, infos, "self", 1, "")
    pk.flush(1)
    src.emit(1, "return b''.join(_parts)")

    src.emit(0, "def _deserialize_from(self, _d):")
    src.emit(1, "_n = len(_d)")
    src.emit(1, "_o = 0")
    src.emit(1, "try:")
    up = _Unpacker(src)
    body_start = len(src.lines)
    _de_fields(src, up, infos, "self", 2)
    up.flush(2)
    if len(src.lines) == body_start:
        src.emit(2, "pass")
    src.emit(1, "except _struct.error as exc:")
    src.emit(2, "raise _struct_failure(self, exc) from None")
    src.emit(1, "return self")
    src.ns["_struct_failure"] = _struct_failure

    code = "\n".join(src.lines) + "\n"
    ns = src.ns
    try:
        compiled = compile(code, f"<ddes.msg generated {spec.full_name}>", "exec")
    except (SyntaxError, ValueError, RecursionError, MemoryError) as exc:
        # the parser only lets legal names through, so this is a ddes bug or a hostile spec
        raise InvalidMsgSpec(
            f"{spec.filename or spec.full_name}: cannot generate a class for "
            f"{spec.full_name!r}: {type(exc).__name__}: {exc}; check its field names and "
            "types (letters, digits and '_' only)"
        ) from None
    exec(compiled, ns)  # noqa: S102

    attrs: dict[str, Any] = {
        "__slots__": tuple(i.name for i in infos),
        "__module__": "ddes.msg.generated",
        "__qualname__": cls_name,
        "__doc__": f"Message {spec.full_name} (generated by ddes from its definition).\n\n"
                   f"{spec.text}",
        "_type": spec.full_name,
        "_md5sum": md5sum,
        "_full_text": full_text,
        "_has_header": spec.has_header(),
        "_slot_types": [f.type for f in spec.fields],
        "_spec": spec,
        "_fields_info": infos,
        "_generated_source": code,
        "_wire_min": wire_min,
        "_flat_fields": flat,
        "_default_elements": elems,
        "__init__": ns["__init__"],
        "_serialize_to_bytes": ns["_serialize_to_bytes"],
        "_deserialize_from": ns["_deserialize_from"],
    }
    for c in spec.constants:
        attrs[python_safe_name(c.name)] = c.val
    return type(cls_name, (Message,), attrs)
