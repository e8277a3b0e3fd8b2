"""Records of the ROS bag v2.0 format, and the connection records they carry.

A record is ``header_len (u32) | header | data_len (u32) | data``; the
header is a run of ``field_len (u32) | name=value`` fields.  Integers are
little-endian; a time is ``u32 secs | u32 nsecs``.  The op codes and field
names are those of rosbag's ``bag.py`` (``_OP_*``, ``_write_*_record``).

Every parse goes through :class:`Cursor`, which checks each length against
the bytes that are really there, so a truncated or corrupt file raises
:class:`~ddes.errors.ROSBagFormatException` naming the file, the offset and
what was wrong, and never reads past the end or loops.
"""

from __future__ import annotations

import struct
from dataclasses import dataclass, field

from ddes.errors import ROSBagFormatException

__all__ = [
    "FILE_HEADER_LENGTH",
    "MAGIC",
    "OP_CHUNK",
    "OP_CHUNK_INFO",
    "OP_CONNECTION",
    "OP_FILE_HEADER",
    "OP_INDEX_DATA",
    "OP_MSG_DATA",
    "OP_MSG_DEF",
    "OP_NAMES",
    "ConnectionInfo",
    "Cursor",
    "Record",
    "canonicalize_topic",
    "decode_header",
    "encode_header",
    "encode_record",
    "header_from_fields",
    "pack_time",
]

MAGIC = b"#ROSBAG V2.0\n"
FILE_HEADER_LENGTH = 4096

OP_MSG_DEF = 0x01
OP_MSG_DATA = 0x02
OP_FILE_HEADER = 0x03
OP_INDEX_DATA = 0x04
OP_CHUNK = 0x05
OP_CHUNK_INFO = 0x06
OP_CONNECTION = 0x07

OP_NAMES = {
    OP_MSG_DEF: "MSG_DEF",
    OP_MSG_DATA: "MSG_DATA",
    OP_FILE_HEADER: "FILE_HEADER",
    OP_INDEX_DATA: "INDEX_DATA",
    OP_CHUNK: "CHUNK",
    OP_CHUNK_INFO: "CHUNK_INFO",
    OP_CONNECTION: "CONNECTION",
}

_U32 = struct.Struct("<L")
_U64 = struct.Struct("<Q")
_TIME = struct.Struct("<LL")
_NS = 1_000_000_000


def pack_time(ns: int) -> bytes:
    """``u32 secs | u32 nsecs`` of an integer-nanosecond time."""
    return _TIME.pack(*divmod(ns, _NS))


def encode_header(fields: dict[str, bytes]) -> bytes:
    """The header bytes (without their length prefix) of ``fields``, in dict order."""
    parts = []
    for name, value in fields.items():
        item = name.encode() + b"=" + value
        parts.append(_U32.pack(len(item)))
        parts.append(item)
    return b"".join(parts)


def encode_record(fields: dict[str, bytes], data: bytes) -> bytes:
    """A whole record: sized header, then sized data."""
    header = encode_header(fields)
    return b"".join((_U32.pack(len(header)), header, _U32.pack(len(data)), data))


def decode_header(raw: bytes, where: str) -> dict[str, bytes]:
    """Parse header bytes into ``{name: value}`` (the last of repeated names wins)."""
    fields: dict[str, bytes] = {}
    pos, end = 0, len(raw)
    while pos < end:
        if end - pos < 4:
            raise ROSBagFormatException(f"{where}: a header field length is cut short "
                                        f"({end - pos} of 4 bytes)")
        (size,) = _U32.unpack_from(raw, pos)
        pos += 4
        if size > end - pos:
            raise ROSBagFormatException(f"{where}: a header field claims {size} bytes but only "
                                        f"{end - pos} are left in the header")
        name, sep, value = raw[pos:pos + size].partition(b"=")
        if not sep:
            raise ROSBagFormatException(f"{where}: header field {raw[pos:pos + size][:40]!r} "
                                        "has no '='")
        try:
            key = name.decode()
        except UnicodeDecodeError:
            raise ROSBagFormatException(f"{where}: header field name {name[:40]!r} is not "
                                        "UTF-8") from None
        fields[key] = value
        pos += size
    return fields


@dataclass
class Record:
    """One parsed record: its header fields and where its data lies in the buffer."""

    pos: int
    fields: dict[str, bytes]
    data_pos: int
    data_len: int
    where: str

    @property
    def end(self) -> int:
        """Offset of the next record."""
        return self.data_pos + self.data_len

    def op(self) -> int:
        return self.u8("op")

    def _value(self, name: str, size: int) -> bytes:
        try:
            value = self.fields[name]
        except KeyError:
            raise ROSBagFormatException(
                f"{self.where}: required field '{name}' is missing from the record header "
                f"(fields present: {sorted(self.fields)})") from None
        if size and len(value) != size:
            raise ROSBagFormatException(
                f"{self.where}: field '{name}' has {len(value)} bytes, expected {size}")
        return value

    def u8(self, name: str) -> int:
        return self._value(name, 1)[0]

    def u32(self, name: str) -> int:
        return int(_U32.unpack(self._value(name, 4))[0])

    def u64(self, name: str) -> int:
        return int(_U64.unpack(self._value(name, 8))[0])

    def time(self, name: str) -> int:
        secs, nsecs = _TIME.unpack(self._value(name, 8))
        return int(secs) * _NS + int(nsecs)

    def text(self, name: str) -> str:
        return self._value(name, 0).decode("utf-8", "surrogateescape")

    def expect(self, op: int) -> Record:
        """This record, after checking that its op code is ``op``."""
        have = self.op()
        if have != op:
            raise ROSBagFormatException(
                f"{self.where}: expected a {OP_NAMES[op]} record (op {op:#04x}), found "
                f"{OP_NAMES.get(have, 'an unknown record')} (op {have:#04x})")
        return self


class Cursor:
    """Bounds-checked reading of records from a byte buffer.

    ``origin`` names the buffer in messages (``"x.bag"``, or
    ``"x.bag chunk at offset 4117"`` for a decompressed chunk, whose offsets
    are relative to the chunk data).
    """

    __slots__ = ("buf", "origin", "size")

    def __init__(self, buf: bytes, origin: str) -> None:
        self.buf = buf
        self.origin = origin
        self.size = len(buf)

    def u32_at(self, pos: int, what: str) -> int:
        if pos < 0 or self.size - pos < 4:
            raise ROSBagFormatException(
                f"{self.origin}: offset {pos}: {what} is cut short (the data ends at "
                f"{self.size}); the file is truncated or the offset is corrupt")
        return int(_U32.unpack_from(self.buf, pos)[0])

    def record(self, pos: int, what: str = "record") -> Record:
        """Parse the record starting at ``pos``."""
        where = f"{self.origin}: {what} at offset {pos}"
        header_len = self.u32_at(pos, f"the header length of the {what}")
        start = pos + 4
        if header_len > self.size - start:
            raise ROSBagFormatException(
                f"{where}: the header claims {header_len} bytes but only {self.size - start} "
                "are left; the file is truncated or corrupt")
        fields = decode_header(self.buf[start:start + header_len], where)
        data_len = self.u32_at(start + header_len, f"the data length of the {what}")
        data_pos = start + header_len + 4
        if data_len > self.size - data_pos:
            raise ROSBagFormatException(
                f"{where}: the data claims {data_len} bytes but only {self.size - data_pos} "
                "are left; the file is truncated or corrupt")
        return Record(pos, fields, data_pos, data_len, where)

    def data(self, rec: Record) -> bytes:
        return self.buf[rec.data_pos:rec.end]


def canonicalize_topic(name: str) -> str:
    """roslib's ``canonicalize_name``: no repeated or trailing slashes."""
    if not name or name == "/":
        return name
    lead = "/" if name[0] == "/" else ""
    return lead + "/".join(part for part in name.split("/") if part)


@dataclass(eq=False)
class ConnectionInfo:
    """A connection of a bag: ``id``, ``topic`` and its connection header.

    ``header`` holds the fields as text (``type``, ``md5sum``,
    ``message_definition``, and for recorded topics ``callerid`` and
    ``latching``); rosbag returns them as bytes under Python 3, ddes as
    ``str`` (as ``AnyMsg._connection_header``).  Header bytes that are not
    UTF-8 survive a round trip (they are decoded with ``surrogateescape``).
    """

    id: int
    topic: str
    header: dict[str, str]
    datatype: str = field(init=False)
    md5sum: str = field(init=False)
    msg_def: str = field(init=False)

    def __post_init__(self) -> None:
        for name in ("type", "md5sum", "message_definition"):
            if name not in self.header:
                raise ROSBagFormatException(
                    f"connection {self.id} on topic {self.topic}: connection header field "
                    f"{name} not found (header fields: {sorted(self.header)})")
        self.datatype = self.header["type"]
        self.md5sum = self.header["md5sum"]
        self.msg_def = self.header["message_definition"]

    @property
    def latching(self) -> bool:
        """Whether the publisher was latched (header ``latching: 1``)."""
        return self.header.get("latching") == "1"

    @property
    def callerid(self) -> str:
        """The publishing node (header ``callerid``), or ``""``."""
        return self.header.get("callerid", "")

    def encoded_header(self) -> bytes:
        return encode_header({k: v.encode("utf-8", "surrogateescape")
                              for k, v in self.header.items()})

    def __repr__(self) -> str:
        return f"ConnectionInfo(id={self.id}, topic={self.topic!r}, type={self.datatype!r})"


def header_from_fields(fields: dict[str, bytes]) -> dict[str, str]:
    """Decode a connection header's byte values as text (lossless)."""
    return {k: v.decode("utf-8", "surrogateescape") for k, v in fields.items()}
