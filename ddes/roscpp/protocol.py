"""The frames of the external-node protocol, version 1 (docs/external-nodes.md).

A frame is ``b"DX"``, one byte of kind, a little-endian ``u32`` payload length and the
payload.  :class:`Reader` takes a payload apart field by field, checking every length against
what is left (a bad frame is a :class:`~ddes.errors.ProtocolError` naming the field);
:class:`Writer` builds one.  Nothing read is evaluated: strings are UTF-8 text, values
(parameters) a small tagged tree of bounded depth.
"""

from __future__ import annotations

import struct
from typing import Any

from ddes.errors import ProtocolError

__all__ = ["KINDS", "MAGIC", "MAX_PAYLOAD", "MAX_STR", "VERSION", "Reader", "Writer",
           "frame", "split_header"]

#: The protocol version this ddes speaks.
VERSION = 1
MAGIC = b"DX"
#: The largest payload (a message) and the longest string a frame may hold.
MAX_PAYLOAD = 256 * 1024 * 1024
MAX_STR = 1024 * 1024
#: The deepest parameter value (arrays and structs inside each other) a frame may hold.
MAX_VALUE_DEPTH = 64

# process -> world
HELLO, RESOLVE, ADVERTISE, PUBLISH, UNADVERTISE, SUBSCRIBE, UNSUBSCRIBE = range(1, 8)
ADVERTISE_SERVICE, UNADVERTISE_SERVICE, CALL, SERVICE_EXISTS, WAIT_FOR_SERVICE = range(8, 13)
NUM_SUBSCRIBERS, NUM_PUBLISHERS, PUBLISH_ONE = 0x0D, 0x0E, 0x0F
PARAM_GET, PARAM_SET, PARAM_HAS, PARAM_DELETE, PARAM_SEARCH, PARAM_NAMES = range(0x10, 0x16)
SLEEP_UNTIL, SPIN, SPIN_ONCE, TIMER_CREATE, TIMER_CONTROL, SPINNER, WAIT_FOR_MESSAGE = range(
    0x20, 0x27)
LOG, LOGGER_LEVEL = 0x30, 0x31
SHUTDOWN, REQUEST_SHUTDOWN, CB_DONE = 0x40, 0x41, 0x42
# world -> process
REPLY, CALLBACK, SHUTDOWN_NOTICE = 0x81, 0x90, 0x91

#: Every kind by number, for messages.
KINDS = {
    HELLO: "HELLO", RESOLVE: "RESOLVE", ADVERTISE: "ADVERTISE", PUBLISH: "PUBLISH",
    UNADVERTISE: "UNADVERTISE", SUBSCRIBE: "SUBSCRIBE", UNSUBSCRIBE: "UNSUBSCRIBE",
    ADVERTISE_SERVICE: "ADVERTISE_SERVICE", UNADVERTISE_SERVICE: "UNADVERTISE_SERVICE",
    CALL: "CALL", SERVICE_EXISTS: "SERVICE_EXISTS", WAIT_FOR_SERVICE: "WAIT_FOR_SERVICE",
    NUM_SUBSCRIBERS: "NUM_SUBSCRIBERS", NUM_PUBLISHERS: "NUM_PUBLISHERS",
    PUBLISH_ONE: "PUBLISH_ONE",
    PARAM_GET: "PARAM_GET", PARAM_SET: "PARAM_SET", PARAM_HAS: "PARAM_HAS",
    PARAM_DELETE: "PARAM_DELETE", PARAM_SEARCH: "PARAM_SEARCH", PARAM_NAMES: "PARAM_NAMES",
    SLEEP_UNTIL: "SLEEP_UNTIL", SPIN: "SPIN", SPIN_ONCE: "SPIN_ONCE",
    TIMER_CREATE: "TIMER_CREATE", TIMER_CONTROL: "TIMER_CONTROL", SPINNER: "SPINNER",
    WAIT_FOR_MESSAGE: "WAIT_FOR_MESSAGE", LOG: "LOG", LOGGER_LEVEL: "LOGGER_LEVEL",
    SHUTDOWN: "SHUTDOWN", REQUEST_SHUTDOWN: "REQUEST_SHUTDOWN", CB_DONE: "CB_DONE",
    REPLY: "REPLY", CALLBACK: "CALLBACK", SHUTDOWN_NOTICE: "SHUTDOWN_NOTICE",
}

# CALLBACK kinds
CB_MESSAGE, CB_TIMER, CB_SERVICE, CB_PEER_SUBSCRIBED, CB_PEER_UNSUBSCRIBED = range(1, 6)

_HEAD = struct.Struct("<2sBI")
_U32 = struct.Struct("<I")
_I32 = struct.Struct("<i")
_I64 = struct.Struct("<q")
_F64 = struct.Struct("<d")
HEADER_SIZE = _HEAD.size


def frame(kind: int, payload: bytes) -> bytes:
    """One frame of ``kind`` around ``payload``."""
    if len(payload) > MAX_PAYLOAD:
        raise ProtocolError(f"a {KINDS.get(kind, kind)} frame of {len(payload)} bytes is over "
                            f"the protocol's {MAX_PAYLOAD} bytes")
    return _HEAD.pack(MAGIC, kind, len(payload)) + payload


def split_header(head: bytes) -> tuple[int, int]:
    """``(kind, payload length)`` of a frame's 7 header bytes (checked)."""
    magic, kind, size = _HEAD.unpack(head)
    if magic != MAGIC:
        raise ProtocolError(f"protocol error: a frame must start with b'DX', got {magic!r}")
    if kind not in KINDS:
        raise ProtocolError(f"protocol error: unknown frame kind 0x{kind:02x}")
    if size > MAX_PAYLOAD:
        raise ProtocolError(f"protocol error: a {KINDS[kind]} frame of {size} bytes is over the "
                            f"protocol's {MAX_PAYLOAD} bytes")
    return kind, size


class Reader:
    """Fields of one payload, read in order; every length checked against what is left."""

    __slots__ = ("data", "pos", "what")

    def __init__(self, data: bytes, what: str) -> None:
        self.data = data
        self.pos = 0
        self.what = what

    def _take(self, n: int, field: str) -> bytes:
        end = self.pos + n
        if end > len(self.data):
            raise ProtocolError(f"protocol error: {self.what} frame ends inside its {field}")
        out = self.data[self.pos:end]
        self.pos = end
        return out

    def u8(self, field: str = "u8") -> int:
        return self._take(1, field)[0]

    def u32(self, field: str = "u32") -> int:
        return int(_U32.unpack(self._take(4, field))[0])

    def i32(self, field: str = "i32") -> int:
        return int(_I32.unpack(self._take(4, field))[0])

    def i64(self, field: str = "i64") -> int:
        return int(_I64.unpack(self._take(8, field))[0])

    def f64(self, field: str = "f64") -> float:
        return float(_F64.unpack(self._take(8, field))[0])

    def blob(self, field: str = "blob") -> bytes:
        n = self.u32(field)
        return bytes(self._take(n, field))

    def string(self, field: str = "str") -> str:
        n = self.u32(field)
        if n > MAX_STR:
            raise ProtocolError(f"protocol error: {self.what}'s {field} of {n} bytes is over "
                                f"the protocol's {MAX_STR} bytes for a string")
        raw = self._take(n, field)
        try:
            return raw.decode("utf-8")
        except UnicodeDecodeError:
            raise ProtocolError(f"protocol error: {self.what}'s {field} is not UTF-8") from None

    def value(self, field: str = "value", depth: int = 0) -> Any:
        """A parameter value (docs/external-nodes.md, "Values")."""
        if depth > MAX_VALUE_DEPTH:
            raise ProtocolError(f"protocol error: {self.what}'s {field} nests deeper than "
                                f"{MAX_VALUE_DEPTH} levels")
        tag = self.u8(field)
        if tag == 0:
            return None
        if tag == 1:
            return bool(self.u8(field))
        if tag == 2:
            return self.i32(field)
        if tag == 3:
            return self.f64(field)
        if tag == 4:
            return self.string(field)
        if tag == 5:
            n = self.u32(field)
            if n > len(self.data) - self.pos:
                raise ProtocolError(f"protocol error: {self.what}'s {field} claims {n} items")
            return [self.value(field, depth + 1) for _ in range(n)]
        if tag == 6:
            n = self.u32(field)
            if n > len(self.data) - self.pos:
                raise ProtocolError(f"protocol error: {self.what}'s {field} claims {n} members")
            out: dict[str, Any] = {}
            for _ in range(n):
                key = self.string(field)
                out[key] = self.value(field, depth + 1)
            return out
        if tag == 7:
            return self.blob(field)
        raise ProtocolError(f"protocol error: {self.what}'s {field} has unknown value tag {tag}")

    def end(self) -> None:
        if self.pos != len(self.data):
            raise ProtocolError(f"protocol error: {len(self.data) - self.pos} bytes left over "
                                f"after {self.what}'s fields")


class Writer:
    """A payload, field by field."""

    __slots__ = ("parts",)

    def __init__(self) -> None:
        self.parts: list[bytes] = []

    def u8(self, v: int) -> Writer:
        self.parts.append(bytes((v & 0xFF,)))
        return self

    def u32(self, v: int) -> Writer:
        self.parts.append(_U32.pack(v))
        return self

    def i32(self, v: int) -> Writer:
        self.parts.append(_I32.pack(v))
        return self

    def i64(self, v: int) -> Writer:
        self.parts.append(_I64.pack(v))
        return self

    def f64(self, v: float) -> Writer:
        self.parts.append(_F64.pack(v))
        return self

    def blob(self, v: bytes) -> Writer:
        self.parts.append(_U32.pack(len(v)))
        self.parts.append(bytes(v))
        return self

    def string(self, v: str) -> Writer:
        raw = v.encode("utf-8", "replace")
        self.parts.append(_U32.pack(len(raw)))
        self.parts.append(raw)
        return self

    def value(self, v: Any, depth: int = 0) -> Writer:
        """A parameter value: bool, int (i32, else sent as a double), float, str, list, dict
        (keys sorted), bytes; anything else (None) as the invalid value."""
        if depth > MAX_VALUE_DEPTH:
            raise ProtocolError(f"a parameter value nests deeper than {MAX_VALUE_DEPTH} levels")
        if isinstance(v, bool):
            return self.u8(1).u8(1 if v else 0)
        if isinstance(v, int):
            if -(2**31) <= v < 2**31:
                return self.u8(2).i32(v)
            return self.u8(3).f64(float(v))
        if isinstance(v, float):
            return self.u8(3).f64(v)
        if isinstance(v, str):
            return self.u8(4).string(v)
        if isinstance(v, (list, tuple)):
            self.u8(5).u32(len(v))
            for item in v:
                self.value(item, depth + 1)
            return self
        if isinstance(v, dict):
            self.u8(6).u32(len(v))
            for key in sorted(v, key=str):
                self.string(str(key))
                self.value(v[key], depth + 1)
            return self
        if isinstance(v, (bytes, bytearray)):
            return self.u8(7).blob(bytes(v))
        return self.u8(0)

    def payload(self) -> bytes:
        return b"".join(self.parts)

    def frame(self, kind: int) -> bytes:
        return frame(kind, self.payload())
