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

Speed: the generated code is straight-line where the type allows it (the
serializer returns one ``b''.join`` of a tuple; a loop appears only for arrays of
messages, strings, times or durations), calls precompiled ``Struct`` methods
bound once, reads fixed offsets as constants, and, on a little-endian host,
reads ``float32``/``float64`` and writes ``float64`` runs with the native-order
Struct (``'@'``), which CPython converts faster than the standard-order one and
which gives the same bytes and values wherever it has no padding (``float32``
writes stay on ``'<'``: the native packer writes ``inf`` for a finite value too
large for a float32, where ``'<'`` raises, and scans hold real infinities, so a
check after the fact would cost more than it saves).  ``__init__`` takes the fields as keyword-only parameters, so Python
matches keywords in C.
"""

from __future__ import annotations

import re
import struct
import sys
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
#: The native-order Struct ('@') reads and writes the standard little-endian layout.
_NATIVE_LE = (sys.byteorder == "little" and struct.calcsize("@f") == 4
              and struct.calcsize("@d") == 8)
#: Lengths below this have their uint32 prefix ready-made (``_LP``).
_LEN_PREFIXES = 1024
_LEN_PREFIX = tuple(_STRUCT_I.pack(n) for n in range(_LEN_PREFIXES))
_USES_N = re.compile(r"\b_n\b")
_UNSET: Any = type("_Unset", (), {"__repr__": lambda self: "<unset>", "__slots__": ()})()


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


def _native(fmt: str, packing: bool) -> bool:
    """Whether ``'@' + fmt`` may replace ``'<' + fmt``: same bytes, same values, same errors.

    Only float codes gain (CPython already runs the native code for the
    standard-size integer codes); a padded layout or a float32 pack (the native
    one writes ``inf`` where the standard one raises OverflowError) keeps ``'<'``.
    """
    if not _NATIVE_LE or ("f" not in fmt and "d" not in fmt) or (packing and "f" in fmt):
        return False
    return struct.calcsize("@" + fmt) == struct.calcsize("<" + fmt)


class _Source:
    """Lines of generated code plus the objects they reference."""

    def __init__(self, numpy: Any = None) -> None:
        self.numpy = numpy  # the numpy module for numpy_msg classes, else None
        self.lines: list[str] = []
        self.ns: dict[str, Any] = {
            "_struct": struct, "_I": _STRUCT_I, "_Time": Time, "_Duration": Duration,
            "_new": object.__new__, "_to_bytes": _to_bytes, "_unpack_from": struct.unpack_from,
            "_trunc": _trunc, "_flen": _fixed_len_error,
            "_TypeErr": DdesTypeError, "_AttrErr": DdesAttributeError,
            "_many": _too_many, "_zero": _check_zero, "_np": numpy,
            "_spack": struct.pack, "_U": _UNSET, "_LP": _LEN_PREFIX, "_range": range,
            "_len": len, "_next": next, "_iter": iter, "_fresh_T": _fresh_time,
            "_fresh_D": _fresh_duration,
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

    def _method(self, fmt: str, packing: bool) -> str:
        """Name of the bound ``pack`` (or ``unpack_from``) of the Struct for ``fmt``."""
        order = "@" if _native(fmt, packing) else "<"
        key = ("p" if packing else "u") + order + fmt
        if key not in self._structs:
            name = self.var("_P" if packing else "_U")
            compiled = struct.Struct(order + fmt)
            self.ns[name] = compiled.pack if packing else compiled.unpack_from
            self._structs[key] = name
        return self._structs[key]

    def packer(self, fmt: str) -> str:
        return self._method(fmt, True)

    def unpacker(self, fmt: str) -> str:
        return self._method(fmt, False)

    def emit(self, indent: int, line: str) -> None:
        self.lines.append("    " * indent + line)


def _fresh_time() -> Time:
    """``Time()``, built without the argument checks."""
    t = object.__new__(Time)
    t.secs = 0
    t.nsecs = 0
    return t


def _fresh_duration() -> Duration:
    """``Duration()``, built without the argument checks."""
    d = object.__new__(Duration)
    d.secs = 0
    d.nsecs = 0
    return d


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


class _Writer:
    """Where the serializer's pieces of bytes go.

    Straight-line code keeps each piece in a local and returns one ``join`` of
    them (or ``a + b`` for two pieces of exact ``bytes``); from the first loop on,
    the pieces go to a list.  Statements stay in field order, so a bad field
    raises the same error as before.
    """

    def __init__(self, src: _Source) -> None:
        self.src = src
        self.parts: list[tuple[str, bool]] | None = []  # (local, may not be exact bytes)
        self.pending: str | None = None  # the last piece, an expression not yet bound

    def _bind(self) -> None:
        if self.pending is not None and self.parts is not None:
            name = self.src.var("_p")
            self.src.emit(1, f"{name} = {self.pending}")
            self.parts.append((name, False))
        self.pending = None

    def emit(self, indent: int, line: str) -> None:
        self._bind()
        self.src.emit(indent, line)

    def write(self, indent: int, expr: str, local: bool = False, loose: bool = False) -> None:
        """Append ``expr`` to the output; ``local``: it is a local variable that ``loose``
        says may hold something other than exact ``bytes`` (a string field's value)."""
        if self.parts is None:
            self.emit(indent, f"_w({expr})")
            return
        self._bind()
        if local:
            self.parts.append((expr, loose))
        else:
            self.pending = expr

    def loop(self) -> None:
        """Switch to a list before code that writes from a loop."""
        if self.parts is not None:
            self._bind()
            self.src.emit(1, f"_parts = [{', '.join(p for p, _ in self.parts)}]")
            self.src.emit(1, "_w = _parts.append")
            self.parts = None

    def finish(self) -> None:
        if self.parts is None:
            self.src.emit(1, "return b''.join(_parts)")
            return
        parts = list(self.parts)
        if self.pending is not None:
            parts.append((self.pending, False))
        exprs = [p for p, _ in parts]
        loose = [p for p, maybe in parts if maybe]
        if not parts:
            self.src.emit(1, "return b''")
        elif len(parts) == 1 and not loose:
            self.src.emit(1, f"return {exprs[0]}")
        elif len(parts) == 2:
            plus = f"{exprs[0]} + {exprs[1]}"
            if not loose:
                self.src.emit(1, f"return {plus}")
            else:  # join's error (and join's acceptance of bytearray) for anything else
                exact = " and ".join(f"{p}.__class__ is bytes" for p in loose)
                self.src.emit(1, f"return {plus} if {exact} else b''.join(({', '.join(exprs)}))")
        else:
            self.src.emit(1, f"return b''.join(({', '.join(exprs)},))")


class _Packer:
    """Accumulates fixed-size values and packs each run with one Struct."""

    def __init__(self, src: _Source, wr: _Writer) -> None:
        self.src = src
        self.wr = wr
        self.codes: list[str] = []
        self.exprs: list[str] = []

    def add(self, code: str, expr: str) -> None:
        self.codes.append(code)
        self.exprs.append(expr)

    def flush(self, indent: int) -> None:
        if not self.codes:
            return
        name = self.src.packer("".join(self.codes))
        expr = f"{name}({', '.join(self.exprs)})"
        if self.codes == ["I"] and self.exprs[0].startswith("len("):
            # a lone length prefix (a string or array after variable-length data): short
            # ones come from a table of ready-made prefixes
            n = self.src.var("_n")
            expr = f"(_LP[{n}] if ({n} := {self.exprs[0]}) < {_LEN_PREFIXES} else {name}({n}))"
        self.wr.write(indent, expr)
        self.codes, self.exprs = [], []


def _ser_fields(src: _Source, wr: _Writer, pk: _Packer, infos: tuple[FieldInfo, ...], ctx: str,
                indent: int, path: str) -> None:
    for info in infos:
        ref = f"{ctx}.{info.name}"
        where = path + info.name
        if not info.is_array:
            _ser_scalar(src, wr, pk, info, ref, indent, where)
            continue
        tmp = src.var()
        wr.emit(indent, f"{tmp} = {ref}")
        n = info.array_len
        if info.kind == "bytes":
            wr.emit(indent, f"if {tmp}.__class__ is not bytes: {tmp} = _to_bytes({tmp})")
            if n is None:
                pk.add("I", f"len({tmp})")
            else:
                wr.emit(indent, f"if len({tmp}) != {n}: raise _flen({where!r}, {n}, len({tmp}))")
            pk.flush(indent)
            wr.write(indent, tmp, local=True)
            continue
        if n is None:
            pk.add("I", f"len({tmp})")
        elif info.kind == "bool" or (info.kind in ("int", "float") and src.numpy is None):
            pk.add(f"{n}{SIMPLE_STRUCT[info.base_type]}", f"*{tmp}")
            continue
        else:
            wr.emit(indent, f"if len({tmp}) != {n}: raise _flen({where!r}, {n}, len({tmp}))")
        if info.kind in ("int", "float") and src.numpy is not None:
            pk.flush(indent)
            dt = "<" + SIMPLE_STRUCT[info.base_type]
            wr.write(indent, f"_np.asarray({tmp}, {dt!r}).tobytes()")
            continue
        if info.kind in ("int", "float", "bool"):
            pk.flush(indent)
            code = SIMPLE_STRUCT[info.base_type]
            order = "@" if _native(code, True) else "<"
            wr.write(indent, f"_spack('{order}%d{code}' % len({tmp}), *{tmp})")
            continue
        pk.flush(indent)
        wr.loop()
        item = src.var("_e")
        wr.emit(indent, f"for {item} in {tmp}:")
        inner = _Packer(src, wr)
        elem = info._replace(is_array=False, array_len=None)
        body_start = len(src.lines)
        _ser_scalar(src, wr, inner, elem, item, indent + 1, where + "[]", bare=True)
        inner.flush(indent + 1)
        if len(src.lines) == body_start:  # a type with no fields: the count, then nothing
            wr.emit(indent + 1, "pass")


def _ser_scalar(src: _Source, wr: _Writer, pk: _Packer, info: FieldInfo, ref: str, indent: int,
                where: str, bare: bool = False) -> None:
    kind = info.kind
    if kind in ("int", "float", "bool"):
        pk.add(SIMPLE_STRUCT[info.base_type], ref)
    elif kind in ("time", "duration"):
        tmp = ref if bare else src.var()
        if not bare:
            wr.emit(indent, f"{tmp} = {ref}")
        code = "I" if kind == "time" else "i"
        pk.add(code, f"{tmp}.secs")
        pk.add(code, f"{tmp}.nsecs")
    elif kind == "string":
        tmp = src.var()
        wr.emit(indent, f"{tmp} = {ref}")
        wr.emit(indent, f"if {tmp}.__class__ is str: {tmp} = {tmp}.encode()")
        pk.add("I", f"len({tmp})")
        pk.flush(indent)
        wr.write(indent, tmp, local=True, loose=True)
    else:  # nested message
        tmp = ref if bare else src.var()
        if not bare:
            wr.emit(indent, f"{tmp} = {ref}")
        _ser_fields(src, wr, pk, _infos_of(info.cls), tmp, indent, where + ".")


# --- deserialization -------------------------------------------------------------------


class _Offset:
    """Where the reader is: a constant while only fixed-size data was read, else ``_o`` plus
    a constant; ``_o`` is updated only where a variable-length item or a loop needs it."""

    def __init__(self, src: _Source) -> None:
        self.src = src
        self.live = False  # whether ``_o`` holds the base
        self.const = 0

    def at(self, extra: int = 0) -> str:
        k = self.const + extra
        if not self.live:
            return str(k)
        return f"_o + {k}" if k else "_o"

    def settle(self, indent: int) -> None:
        """Make ``_o`` hold the offset itself."""
        if not self.live:
            self.src.emit(indent, f"_o = {self.const}")
        elif self.const:
            self.src.emit(indent, f"_o += {self.const}")
        self.live, self.const = True, 0

    def start(self, indent: int) -> str:
        """The offset as a constant or ``_o`` (settling ``_o`` if it is ``_o + k``)."""
        if self.live and self.const:
            self.settle(indent)
        return self.at()

    def moved_to_end(self) -> None:
        """After ``_o = _e``."""
        self.live, self.const = True, 0


class _Unpacker:
    """Accumulates fixed-size targets and unpacks each run with one Struct."""

    def __init__(self, src: _Source, off: _Offset) -> None:
        self.src = src
        self.off = off
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
        name = self.src.unpacker(fmt)
        targets = ", ".join(self.targets)
        self.src.emit(indent, f"{targets}, = {name}(_d, {self.off.at()})")
        self.off.const += struct.calcsize("<" + fmt)
        for line in self.post:
            self.src.emit(indent, line)
        self.codes, self.targets, self.post = [], [], []


def _check_room(src: _Source, indent: int, end: str) -> None:
    src.emit(indent, f"if {end} > _n: raise _trunc(self, {end}, _n)")


def _end_of(start: str, count: str) -> str:
    """``start + count`` as code (folded when both are constants)."""
    if start.isdigit() and count.isdigit():
        return str(int(start) + int(count))
    return f"{count}" if start == "0" else f"{start} + {count}"


def _de_variable(src: _Source, off: _Offset, indent: int, ref: str, count: str,
                 value: str) -> None:
    """A variable-length item of ``count`` bytes at the current offset; ``value`` is the
    code for it with ``{s}`` and ``{e}`` standing for its start and end."""
    start = off.start(indent)
    src.emit(indent, f"_e = {_end_of(start, count)}")
    _check_room(src, indent, "_e")
    src.emit(indent, f"{ref} = {value.format(s=start, e='_e')}")
    src.emit(indent, "_o = _e")
    off.moved_to_end()


def _de_fixed(src: _Source, off: _Offset, indent: int, ref: str, size: int,
              value: str) -> None:
    """A fixed-length array of ``size`` bytes at the current offset (as :func:`_de_variable`)."""
    start = off.start(indent)
    end = _end_of(start, str(size))
    _check_room(src, indent, end)
    src.emit(indent, f"{ref} = {value.format(s=start, e=end)}")
    off.const += size


def _de_fields(src: _Source, up: _Unpacker, infos: tuple[FieldInfo, ...], ctx: str,
               indent: int) -> None:
    off = up.off
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
                _de_variable(src, off, indent, ref, length, "_d[{s}:{e}]")
            else:
                up.flush(indent)
                _de_fixed(src, off, indent, ref, n, "_d[{s}:{e}]")
            continue
        if info.kind in ("int", "float", "bool"):
            code = SIMPLE_STRUCT[base]
            size = struct.calcsize("<" + code)
            numpy = src.numpy is not None and info.kind != "bool"
            if n is None:
                length = src.var("_l")
                up.add("I", length)
                up.flush(indent)
                if numpy:
                    value = f"_np.frombuffer(_d, '<{code}', {length}, {{s}})"
                else:
                    order = "@" if _native(code, False) else "<"
                    value = f"_unpack_from('{order}%d{code}' % {length}, _d, {{s}})"
                if info.kind == "bool":
                    value = f"list(map(bool, {value}))"
                _de_variable(src, off, indent, ref, f"{length} * {size}", value)
            else:
                up.flush(indent)
                if numpy:
                    value = f"_np.frombuffer(_d, '<{code}', {n}, {{s}})"
                else:
                    value = f"{src.unpacker(f'{n}{code}')}(_d, {{s}})"
                if info.kind == "bool":
                    value = f"list(map(bool, {value}))"
                _de_fixed(src, off, indent, ref, n * size, value)
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
                here = off.at()
                src.emit(indent, f"if {here} + {length} * {size} > _n: "
                                 f"raise _many(self, {length}, {size}, _n - {_paren(here)})")
            else:
                src.emit(indent, f"_zero(self, {length})")
        off.settle(indent)
        lst = src.var("_a")
        src.emit(indent, f"{ref} = {lst} = []")
        src.emit(indent, f"for _ in range({length}):")
        inner = _Unpacker(src, off)
        item = src.var("_e")
        elem = info._replace(is_array=False, array_len=None)
        _de_scalar(src, inner, elem, item, indent + 1)
        inner.flush(indent + 1)
        off.settle(indent + 1)
        src.emit(indent + 1, f"{lst}.append({item})")


def _paren(expr: str) -> str:
    return f"({expr})" if " " in expr else expr


def _de_scalar(src: _Source, up: _Unpacker, info: FieldInfo, ref: str, indent: int) -> None:
    kind = info.kind
    if kind in ("int", "float"):
        up.add(SIMPLE_STRUCT[info.base_type], ref)
    elif kind == "bool":
        tmp = src.var("_t")
        up.add("B", tmp)
        up.post.append(f"{ref} = {tmp} != 0")
    elif kind in ("time", "duration"):
        # built first and filled by the unpack, then canonicalised (nsecs into [0, 1e9))
        tmp = src.var("_t")
        src.emit(indent, f"{tmp} = _new({'_Time' if kind == 'time' else '_Duration'})")
        code = "I" if kind == "time" else "i"
        up.add(code, f"{tmp}.secs")
        up.add(code, f"{tmp}.nsecs")
        wrong = (f"{tmp}.nsecs >= 1000000000" if kind == "time"
                 else f"not 0 <= {tmp}.nsecs < 1000000000")
        up.post.append(f"if {wrong}: {tmp}.canon()")
        up.post.append(f"{ref} = {tmp}")
    elif kind == "string":
        length = src.var("_l")
        up.add("I", length)
        up.flush(indent)
        # strict decoding is faster; the first invalid byte reruns the whole read with
        # 'replace' (see _tolerant_reader), so the result is as if 'replace' ran throughout
        _de_variable(src, up.off, indent, ref, length, "_d[{s}:{e}]" + _STRICT)
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
    scalar = {"int": "0", "float": "0.0", "bool": "False", "string": "''",
              "time": "_fresh_T()", "duration": "_fresh_D()"}.get(info.kind)
    if scalar is not None:
        if not info.is_array:
            return scalar
        return f"[{scalar}] * {n}" if info.kind not in ("time", "duration") else \
            f"[{scalar} for _ in _range({n})]"
    fresh = getattr(info.cls, "_ddes_fresh", None)
    ctor = f"{src.obj(fresh, '_f')}()" if fresh is not None else f"{src.obj(info.cls)}()"
    return ctor if not info.is_array else f"[{ctor} for _ in _range({n})]"


_BOTH = "'Message constructor may only use args OR keywords, not both'"


def _init_source(src: _Source, cls_name: str, infos: tuple[FieldInfo, ...]) -> None:
    names = [i.name for i in infos]
    pct = cls_name.replace("%", "%%")  # the messages below are %-formatted
    src.ns["_SLOTS"] = frozenset(names)
    if not infos:
        src.emit(0, "def __init__(self, *args, **kwds):")
        src.emit(1, "if args or kwds:")
        src.emit(2, f"if args and kwds: raise _TypeErr({_BOTH})")
        src.ns["_NARGS"] = ("Invalid number of arguments, args should be [] args are%s; "
                            f"{pct} has no fields")
        src.ns["_NOATTR"] = f"%s is not an attribute of {pct}; it has no fields"
        src.emit(2, "if args: raise _TypeErr(_NARGS % (args,))")
        src.emit(2, "raise _AttrErr(_NOATTR % (next(iter(kwds)),))")
        return
    src.ns["_NARGS"] = (f"Invalid number of arguments, args should be {names!r} args are%s; "
                        f"pass all {len(infos)} fields in order, or use keyword arguments")
    src.ns["_NOATTR"] = f"%s is not an attribute of {pct}; its fields are {', '.join(names)}"
    if len(set(names)) != len(names):  # 'from' and 'from_' both become from_: no parameters
        _init_source_generic(src, infos)
        return
    # the fields are keyword-only parameters (unset ones are _U); positional values come in
    # _a, unknown keywords in _k.  Field names start with a letter and 'self' is renamed
    # self_, so none clashes with these names or the globals (_U, _len...) used here.
    src.emit(0, f"def __init__(self, *_a, {', '.join(f'{n}=_U' for n in names)}, **_k):")
    src.emit(1, "if _a:")
    for i in range(0, len(names), 32):
        chunk = " or ".join(f"{n} is not _U" for n in names[i:i + 32])
        src.emit(2, f"if {'_k or ' if i == 0 else ''}{chunk}: raise _TypeErr({_BOTH})")
    src.emit(2, f"if _len(_a) != {len(infos)}: raise _TypeErr(_NARGS % (_a,))")
    src.emit(2, f"{', '.join(names)}, = _a")
    for info in infos:
        n = info.name
        src.emit(2, f"self.{n} = {_default_expr(src, info)} if {n} is None else {n}")
    src.emit(2, "return")
    src.emit(1, "if _k: raise _AttrErr(_NOATTR % (_next(_iter(_k)),))")
    for info in infos:
        n = info.name
        src.emit(1, f"self.{n} = {_default_expr(src, info)} if {n} is _U or {n} is None else {n}")


def _init_source_generic(src: _Source, infos: tuple[FieldInfo, ...]) -> None:
    """``__init__(self, *args, **kwds)``, for field names that cannot be parameters."""
    names = [i.name for i in infos]
    local = [f"_a{i}" for i in range(len(infos))]
    src.emit(0, "def __init__(self, *args, **kwds):")
    src.emit(1, "if args:")
    src.emit(2, f"if kwds: raise _TypeErr({_BOTH})")
    src.emit(2, f"if len(args) != {len(infos)}: raise _TypeErr(_NARGS % (args,))")
    src.emit(2, f"{', '.join(local)}, = args")
    src.emit(1, "elif kwds:")
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


_STRICT = ".decode()"
_DEAD_MOVES = ("        _o = _e", "        _o += ")
_TOLERANT = ".decode('utf-8', 'replace')"


def _tolerant_reader(code: str, ns: dict[str, Any], type_name: str) -> Callable[..., Any]:
    """The reader that decodes strings with 'replace', compiled when first needed (data with
    invalid UTF-8 is rare); it reads the whole message again, from scratch."""
    def tolerant(msg: Message, data: bytes) -> Any:
        fn = ns.get("_deserialize_tolerant")
        if fn is None:
            exec(compile(code, f"<ddes.msg generated {type_name} (tolerant)>", "exec"), ns)  # noqa: S102
            fn = ns["_deserialize_tolerant"]
        return fn(msg, data)
    return tolerant


def _fresh_source(src: _Source, infos: tuple[FieldInfo, ...]) -> None:
    """``_fresh()``: a default instance (what ``cls()`` builds), without ``__init__``'s
    argument handling and with nested messages, times and durations built inline; the
    classes that nest this one call it for their defaults."""
    src.emit(0, "def _fresh():")
    src.emit(1, "_s = _new(_CLS)")
    _fresh_fields(src, infos, "_s")
    src.emit(1, "return _s")


def _fresh_fields(src: _Source, infos: tuple[FieldInfo, ...], target: str) -> None:
    for info in infos:
        ref = f"{target}.{info.name}"
        if info.is_array:
            src.emit(1, f"{ref} = {_default_expr(src, info)}")
        elif info.kind in ("time", "duration"):
            tmp = src.var("_t")
            src.emit(1, f"{ref} = {tmp} = _new({'_Time' if info.kind == 'time' else '_Duration'})")
            src.emit(1, f"{tmp}.secs = {tmp}.nsecs = 0")
        elif info.kind == "message" and getattr(info.cls, "_ddes_fresh", None) is not None:
            tmp = src.var()
            src.emit(1, f"{ref} = {tmp} = _new({src.obj(info.cls)})")
            _fresh_fields(src, _infos_of(info.cls), tmp)
        else:
            src.emit(1, f"{ref} = {_default_expr(src, info)}")


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
    _fresh_source(src, infos)

    src.emit(0, "def _serialize_to_bytes(self):")
    wr = _Writer(src)
    pk = _Packer(src, wr)
    _ser_fields(src, wr, pk, infos, "self", 1, "")
    pk.flush(1)
    wr.finish()

    src.emit(0, "def _deserialize_from(self, _d):")
    head_at = len(src.lines)
    src.emit(1, "try:")
    up = _Unpacker(src, _Offset(src))
    body_start = len(src.lines)
    _de_fields(src, up, infos, "self", 2)
    up.flush(2)
    while len(src.lines) > body_start and src.lines[-1].startswith(_DEAD_MOVES):
        src.lines.pop()  # the offset after the last item is never read
    if len(src.lines) == body_start:
        src.emit(2, "pass")
    elif any(_USES_N.search(line) for line in src.lines[body_start:]):
        src.lines.insert(head_at, "    _n = len(_d)")
    src.emit(1, "except _struct.error as exc:")
    src.emit(2, "raise _struct_failure(self, exc) from None")
    reader = src.lines[head_at - 1:]
    if any(_STRICT in line for line in reader):
        src.emit(1, "except UnicodeDecodeError:")
        src.emit(2, "return _tolerant(self, _d)")
        tolerant = [line.replace(_STRICT, _TOLERANT) for line in reader]
        tolerant[0] = "def _deserialize_tolerant(self, _d):"
        src.ns["_tolerant"] = _tolerant_reader("\n".join(tolerant) + "\n    return self\n",
                                               src.ns, spec.full_name)
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
        "_ddes_fresh": staticmethod(ns["_fresh"]),
    }
    for c in spec.constants:
        attrs[python_safe_name(c.name)] = c.val
    cls = type(cls_name, (Message,), attrs)
    ns["_CLS"] = cls
    return cls
