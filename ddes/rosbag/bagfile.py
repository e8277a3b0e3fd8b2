"""Reading and writing ROS bag v2.0 files (the layout of rosbag's ``bag.py``).

A file is the line ``#ROSBAG V2.0``, a file-header record padded with
spaces to 4096 header+data bytes, then *chunks* and, at ``index_pos``, the
index: one connection record per connection and one chunk-info record per
chunk.  A chunk record holds (possibly bz2/lz4-compressed) connection and
message-data records and is followed by one index-data record per
connection it contains.

:func:`encode` writes records in the order and with the field order of
rosbag's Python writer, chunk boundaries at the same ``chunk_threshold``;
for uncompressed and bz2 bags the bytes are the ones rosbag writes for the
same sequence of writes.  :func:`decode` reads a whole file, checking every
length, op code, index entry and count against what is really there: a
truncated, corrupt or unindexed file raises a typed error naming the file,
the offset and what is wrong.  With ``allow_unindexed`` it instead recovers
every complete chunk, as ``rosbag reindex`` does.

Messages are ``(time_ns, conn_id, data)`` tuples (an *entry*); a decoded
bag is its connections, its entries in file order, and per connection the
entries in index order.
"""

from __future__ import annotations

import bisect
import bz2
import os
import stat
import struct
from collections.abc import Iterable, Iterator, Mapping
from dataclasses import dataclass, field
from itertools import chain
from operator import itemgetter
from typing import IO

from ddes.errors import (
    DdesError,
    DdesTypeError,
    DdesValueError,
    ResourceLimitError,
    ROSBagEncryptNotSupportedException,
    ROSBagException,
    ROSBagFormatException,
    ROSBagUnindexedException,
)
from ddes.rosbag.records import (
    FILE_HEADER_LENGTH,
    MAGIC,
    OP_CHUNK,
    OP_CHUNK_INFO,
    OP_CONNECTION,
    OP_FILE_HEADER,
    OP_INDEX_DATA,
    OP_MSG_DATA,
    OP_NAMES,
    ConnectionInfo,
    Cursor,
    Record,
    decode_header,
    encode_header,
    encode_record,
    header_from_fields,
    pack_time,
)

__all__ = ["COMPRESSIONS", "INFLATE_FLOOR", "INFLATE_RATIO", "MAX_CHUNK_SIZE", "MAX_FILE_SIZE",
           "ChunkStat",
           "Decoded", "Entry", "FileStats", "InflateBudget", "StreamWriter", "active_placeholder",
           "decode", "encode", "inflate", "read_file"]

#: ``(time_ns, connection id, serialized message)``.
Entry = tuple[int, int, bytes]

#: Chunk compressions ddes reads and writes (rosbag's ``Compression``).
COMPRESSIONS = ("none", "bz2", "lz4")

_U32 = struct.Struct("<L")
_U64 = struct.Struct("<Q")
_B = struct.Struct("<B")
_IDX = struct.Struct("<LLL")
_PAIR = struct.Struct("<LL")
_NS = 1_000_000_000
_DATA_START = len(MAGIC)
_time_key = itemgetter(0)
# A message-data record: header length 38, then op=0x02, conn=<u32>, time=<u32 u32>, data.
_MSG_PREFIX = struct.pack("<LL", 38, 4) + b"op=\x02" + struct.pack("<L", 9) + b"conn="
_OP_CONN = struct.pack("<L", 4) + b"op=\x02" + struct.pack("<L", 9) + b"conn="  # rosbag (Python)
_CONN_OP = struct.pack("<L", 9) + b"conn="  # roscpp writes the fields sorted: conn, op, time
_OP_AFTER = struct.pack("<L", 4) + b"op=\x02"
_TIME_FIELD = struct.pack("<L", 13) + b"time="
_MSG_HEAD = struct.Struct(f"<{len(_MSG_PREFIX)}sL{len(_TIME_FIELD)}sLLL")
_secs_nsecs = itemgetter(0, 1)
_FAST = struct.Struct("<L")
_FAST_TAIL = struct.Struct("<LLL")


@dataclass
class ChunkStat:
    """What ``rosbag info`` needs of one chunk."""

    pos: int
    compression: str
    compressed_size: int
    uncompressed_size: int
    start: int
    end: int
    counts: dict[int, int] = field(default_factory=dict)


@dataclass
class FileStats:
    """Size and chunk layout of an encoded bag."""

    size: int
    chunks: list[ChunkStat]


@dataclass
class Decoded:
    """A bag file read into memory."""

    connections: dict[int, ConnectionInfo]
    log: list[Entry]
    indexes: dict[int, list[Entry]]
    stats: FileStats
    #: What recovery of an unindexed file dropped, or None.
    recovered: str | None = None


# -- writing ---------------------------------------------------------------------------------

def _compress(kind: str, data: bytes) -> bytes:
    if kind == "none":
        return data
    if kind == "bz2":
        return bz2.compress(data, 9)
    if kind == "lz4":
        import lz4.frame  # type: ignore[import-untyped,unused-ignore]  # stubs vary by version

        return bytes(lz4.frame.compress(data, block_size=lz4.frame.BLOCKSIZE_MAX1MB,
                                        content_checksum=True, store_size=False))
    raise ROSBagException(f"unsupported compression type: {kind}; use one of {', '.join(COMPRESSIONS)}")


def _file_header(index_pos: int, conn_count: int, chunk_count: int) -> bytes:
    fields = {"op": _B.pack(OP_FILE_HEADER), "index_pos": _U64.pack(index_pos),
              "conn_count": _U32.pack(conn_count), "chunk_count": _U32.pack(chunk_count)}
    header = encode_header(fields)
    pad = b" " * max(0, FILE_HEADER_LENGTH - len(header))
    return b"".join((_U32.pack(len(header)), header, _U32.pack(len(pad)), pad))


def active_placeholder() -> bytes:
    """The start of a bag being written: magic and a file header with no index yet."""
    return MAGIC + _file_header(0, 0, 0)


def _connection_record(conn: ConnectionInfo) -> bytes:
    fields = {"op": _B.pack(OP_CONNECTION), "topic": conn.topic.encode("utf-8", "surrogateescape"),
              "conn": _U32.pack(conn.id)}
    return encode_record(fields, conn.encoded_header())


class _ChunkWriter:
    """Accumulates one chunk's records and its per-connection index.

    ``index`` maps a connection to ``[latest time, secs, nsecs, offset, secs, nsecs,
    offset, ...]``: the u32 triples of its index record in write order; a connection
    in ``unsorted`` got a message older than its latest, and its triples are sorted
    (stably, by time: what inserting each one in order gives) when the chunk closes.
    """

    __slots__ = ("buf", "end", "index", "start", "unsorted")

    def __init__(self, t: int) -> None:
        self.buf = bytearray()
        self.start = self.end = t
        self.index: dict[int, list[int]] = {}
        self.unsorted: set[int] = set()

    def add(self, t: int, cid: int, data: bytes) -> None:
        buf = self.buf
        offset = len(buf)
        secs, nsecs = divmod(t, _NS)
        # header fields op, conn, time: rosbag's order
        buf += _MSG_HEAD.pack(_MSG_PREFIX, cid, _TIME_FIELD, secs, nsecs, len(data))
        buf += data
        entries = self.index.get(cid)
        if entries is None:
            self.index[cid] = [t, secs, nsecs, offset]
        else:
            if t >= entries[0]:
                entries[0] = t
            else:
                self.unsorted.add(cid)
            entries += (secs, nsecs, offset)
        if t > self.end:
            self.end = t
        elif t < self.start:
            self.start = t

    def fill(self, it: Iterator[Entry], threshold: int, seen: set[int],
             connections: Mapping[int, ConnectionInfo]) -> bool:
        """:meth:`add` the entries of ``it`` (a connection's record before its first
        message) until the chunk holds more than ``threshold`` bytes; False once ``it``
        is exhausted."""
        buf = self.buf
        add = self.add
        for t, cid, data in it:
            if cid not in seen:
                seen.add(cid)
                buf += _connection_record(connections[cid])
            add(t, cid, data)
            if len(buf) > threshold:
                return True
        return False

    def counts(self) -> dict[int, int]:
        """Messages per connection, in first-message order."""
        return {cid: (len(e) - 1) // 3 for cid, e in self.index.items()}

    def index_body(self, cid: int) -> bytes:
        """The entries of connection ``cid``'s index record: ``secs | nsecs | offset``."""
        flat = self.index[cid][1:]
        if cid in self.unsorted:
            triples = sorted(zip(flat[0::3], flat[1::3], flat[2::3]), key=_secs_nsecs)
            flat = [v for triple in triples for v in triple]
        return struct.pack(f"<{len(flat)}L", *flat)


def encode(connections: Mapping[int, ConnectionInfo], log: Iterable[Entry], out: IO[bytes], *,
           compression: str = "none", chunk_threshold: int = 768 * 1024) -> FileStats:
    """Write a v2.0 bag of ``log`` (entries in write order) to the seekable ``out``.

    Connection records go into the chunk of their first message and again
    into the index; a chunk closes once it holds more than
    ``chunk_threshold`` uncompressed bytes, as in rosbag.
    """
    if compression not in COMPRESSIONS:
        raise ROSBagException(f"unsupported compression type: {compression}; use one of "
                              f"{', '.join(COMPRESSIONS)}")
    base = out.tell()
    out.write(MAGIC)
    out.write(_file_header(0, 0, 0))
    pos = out.tell() - base
    chunks: list[ChunkStat] = []
    seen: set[int] = set()
    it = iter(log)
    more = True
    while more:
        first = next(it, None)
        if first is None:
            break
        chunk = _ChunkWriter(first[0])
        more = chunk.fill(chain((first,), it), chunk_threshold, seen, connections)
        blob, packed_size, raw_size = _chunk_blob(chunk, compression)
        out.write(blob)
        chunks.append(ChunkStat(pos, compression, packed_size, raw_size, chunk.start, chunk.end,
                                chunk.counts()))
        pos += len(blob)
    index_pos = pos
    tail = [_connection_record(conn) for cid, conn in connections.items() if cid in seen]
    conn_count = len(tail)
    for ch in chunks:
        fields = {"op": _B.pack(OP_CHUNK_INFO), "ver": _U32.pack(1), "chunk_pos": _U64.pack(ch.pos),
                  "start_time": pack_time(ch.start), "end_time": pack_time(ch.end),
                  "count": _U32.pack(len(ch.counts))}
        tail.append(encode_record(fields, b"".join(_PAIR.pack(c, n) for c, n in ch.counts.items())))
    blob = b"".join(tail)
    out.write(blob)
    end = out.tell()
    out.seek(base + _DATA_START)
    out.write(_file_header(index_pos, conn_count, len(chunks)))
    out.seek(end)
    return FileStats(index_pos + len(blob), chunks)


# -- reading ---------------------------------------------------------------------------------

#: The most uncompressed bytes one chunk may declare (256 MiB), unless ``Bag(max_chunk_size=N)``
#: says otherwise.  rosbag closes a chunk past 768 KiB, so only a single message larger than
#: that makes a larger chunk; a chunk costs about twice its size in memory while it is read.
MAX_CHUNK_SIZE = 256 << 20
#: Without ``max_chunk_size``, the compressed chunks of a file together may inflate to at most
#: ``INFLATE_RATIO`` times the file's size, and never less than ``INFLATE_FLOOR`` bytes allowed.
INFLATE_RATIO = 1000
INFLATE_FLOOR = 64 << 20


def _mib(n: int) -> str:
    return f"{n / (1 << 20):.1f} MiB"


class InflateBudget:
    """How many bytes the compressed chunks of one file may inflate to.

    A chunk declares its uncompressed size; ddes checks the declaration
    *before* decompressing (so a 5 KB file cannot make ddes allocate 2 GB)
    and then decompresses with that size as a hard cap (see :func:`inflate`).
    With ``max_chunk_size=None`` a chunk may declare at most
    :data:`MAX_CHUNK_SIZE` and all compressed chunks together at most
    ``max(INFLATE_FLOOR, INFLATE_RATIO * file_size)``; an explicit
    ``max_chunk_size`` trusts each chunk up to that size, with no ratio.
    """

    __slots__ = ("file_size", "limit", "ratio_budget", "used")

    def __init__(self, file_size: int, max_chunk_size: int | None = None) -> None:
        if max_chunk_size is not None and (isinstance(max_chunk_size, bool)
                                           or not isinstance(max_chunk_size, int)):
            raise DdesTypeError(f"max_chunk_size must be an int (bytes) or None, got "
                                f"{max_chunk_size!r}")
        if max_chunk_size is not None and max_chunk_size < 1:
            raise DdesValueError(f"max_chunk_size must be at least 1 byte, got {max_chunk_size}")
        self.file_size = file_size
        self.limit = MAX_CHUNK_SIZE if max_chunk_size is None else max_chunk_size
        self.ratio_budget: int | None = (max(INFLATE_FLOOR, INFLATE_RATIO * file_size)
                                         if max_chunk_size is None else None)
        self.used = 0

    def take(self, declared: int, compressed: int, kind: str, where: str) -> None:
        """Account for a chunk of ``compressed`` bytes of ``kind`` declaring ``declared``."""
        if declared > self.limit:
            raise ResourceLimitError(
                f"{where}: the chunk declares {declared} bytes ({_mib(declared)}) uncompressed "
                f"from {compressed} bytes of {kind} data, over the limit max_chunk_size="
                f"{self.limit} ({_mib(self.limit)}): a decompression bomb or a corrupt chunk "
                f"header; if the bag is genuine, open it with Bag(path, max_chunk_size="
                f"{declared})")
        if self.ratio_budget is not None and self.used + declared > self.ratio_budget:
            raise ResourceLimitError(
                f"{where}: the chunk declares {declared} bytes ({_mib(declared)}) uncompressed "
                f"from {compressed} bytes of {kind} data, which takes the file's compressed "
                f"chunks past {self.ratio_budget} bytes inflated ({INFLATE_RATIO}x the file's "
                f"{self.file_size} bytes, at least {_mib(INFLATE_FLOOR)}): a decompression bomb "
                f"or a corrupt chunk header; if the bag is genuine, open it with "
                f"Bag(path, max_chunk_size={max(declared, 1)}) to trust each chunk's declared "
                "size up to that many bytes")
        self.used += declared


def _zstd_inflate(data: bytes, cap: int) -> bytes:
    import zstandard

    parts: list[bytes] = []
    got = 0
    with zstandard.ZstdDecompressor().stream_reader(data) as reader:
        while got < cap:
            part = reader.read(min(cap - got, 1 << 20))
            if not part:
                break
            parts.append(part)
            got += len(part)
    return b"".join(parts)


def inflate(kind: str, data: bytes, size: int, where: str) -> bytes:
    """Decompress ``data`` (``none``, ``bz2``, ``lz4``, ``zstd``) to exactly ``size`` bytes.

    Decompression stops one byte past ``size``, so data that inflates further
    (a bomb, or a lying header) costs at most ``size + 1`` bytes and raises
    :class:`~ddes.errors.ROSBagFormatException`.
    """
    try:
        if kind == "none":
            out = data
        elif kind == "bz2":
            out = bz2.BZ2Decompressor().decompress(data, max_length=size + 1)
        elif kind == "lz4":
            import lz4.frame

            out = lz4.frame.LZ4FrameDecompressor().decompress(data, max_length=size + 1)
        elif kind == "zstd":
            out = _zstd_inflate(data, size + 1)
        else:
            raise ROSBagException(f"{where}: unsupported compression type: {kind[:40]!r} (ddes "
                                  f"reads {', '.join(COMPRESSIONS)})")
    except DdesError:
        raise
    except Exception as exc:  # noqa: BLE001 - each codec raises its own kinds on bad data
        raise ROSBagFormatException(f"{where}: the {kind} data of the chunk is corrupt "
                                    f"({type(exc).__name__}: {exc})") from None
    if len(out) > size:
        raise ROSBagFormatException(
            f"{where}: the chunk header says {size} bytes uncompressed but its {kind} data "
            "inflates past that (ddes stops at the declared size): a decompression bomb or a "
            "corrupt chunk")
    if len(out) != size:
        raise ROSBagFormatException(
            f"{where}: the chunk header says {size} bytes uncompressed but its {kind} data "
            f"holds {len(out)}; the chunk is truncated or corrupt")
    return bytes(out)


def _connection(cur: Cursor, rec: Record) -> ConnectionInfo:
    rec.expect(OP_CONNECTION)
    cid = rec.u32("conn")
    topic = rec.text("topic")
    fields = decode_header(cur.data(rec), f"{rec.where} (connection header)")
    try:
        return ConnectionInfo(cid, topic, header_from_fields(fields))
    except ROSBagFormatException as exc:
        raise ROSBagFormatException(f"{rec.where}: {exc}") from None


@dataclass
class _Chunk:
    rec: Record
    compression: str
    size: int
    order: list[Entry]
    at: dict[int, Entry]
    conns: list[ConnectionInfo]


def _read_chunk(cur: Cursor, pos: int, name: str, budget: InflateBudget) -> _Chunk:
    rec = cur.record(pos, "chunk").expect(OP_CHUNK)
    compression = rec.text("compression")
    size = rec.u32("size")
    if compression not in COMPRESSIONS:
        shown = compression[:40]
        if not (shown.isascii() and shown.isprintable()):
            shown = repr(shown)
        raise ROSBagException(f"{rec.where}: unsupported compression type: {shown} "
                              f"(ddes reads {', '.join(COMPRESSIONS)})")
    if compression != "none":
        budget.take(size, rec.data_len, compression, rec.where)
    raw = inflate(compression, cur.data(rec), size, rec.where)
    inner = Cursor(raw, f"{name}: chunk at offset {pos}, uncompressed data")
    order: list[Entry] = []
    at: dict[int, Entry] = {}
    conns: list[ConnectionInfo] = []
    p = 0
    n = len(raw)
    while p < n:
        entry_at = _fast_message(raw, p, n)
        if entry_at is not None:
            entry, end = entry_at
            order.append(entry)
            at[p] = entry
            p = end
            continue
        r = inner.record(p)
        op = r.op()
        if op == OP_MSG_DATA:
            entry = (r.time("time"), r.u32("conn"), inner.data(r))
            order.append(entry)
            at[p] = entry
        elif op == OP_CONNECTION:
            conns.append(_connection(inner, r))
        else:
            raise ROSBagFormatException(
                f"{r.where}: a chunk holds only CONNECTION and MSG_DATA records, found "
                f"{OP_NAMES.get(op, 'unknown')} (op {op:#04x})")
        p = r.end
    return _Chunk(rec, compression, size, order, at, conns)


def _fast_message(raw: bytes, p: int, n: int) -> tuple[Entry, int] | None:
    """A standard 38-byte-header message record at ``p`` (either field order), else None."""
    if n - p < 46 or _FAST.unpack_from(raw, p)[0] != 38:
        return None
    if raw.startswith(_OP_CONN, p + 4):  # op, conn, time
        cid = _FAST.unpack_from(raw, p + 21)[0]
        if not raw.startswith(_TIME_FIELD, p + 25):
            return None
    elif raw.startswith(_CONN_OP, p + 4) and raw.startswith(_OP_AFTER, p + 17) \
            and raw.startswith(_TIME_FIELD, p + 25):  # conn, op, time
        cid = _FAST.unpack_from(raw, p + 13)[0]
    else:
        return None
    secs, nsecs, size = _FAST_TAIL.unpack_from(raw, p + 34)
    end = p + 46 + size
    if end > n:
        return None  # let the checked path name the problem
    return (secs * _NS + nsecs, cid, raw[p + 46:end]), end


def _read_index_records(cur: Cursor, chunk: _Chunk, count: int,
                        indexes: dict[int, list[Entry]]) -> tuple[int, dict[int, int]]:
    """Read ``count`` index records after ``chunk``; check each entry against the chunk."""
    pos = chunk.rec.end
    counts: dict[int, int] = {}
    indexed = 0
    for _ in range(count):
        rec = cur.record(pos, "index record").expect(OP_INDEX_DATA)
        ver = rec.u32("ver")
        if ver != 1:
            raise ROSBagFormatException(f"{rec.where}: expecting index version 1, got {ver}")
        cid, n = rec.u32("conn"), rec.u32("count")
        if rec.data_len != 12 * n:
            raise ROSBagFormatException(
                f"{rec.where}: count {n} needs {12 * n} bytes of entries, the record has "
                f"{rec.data_len}")
        target = indexes.setdefault(cid, [])
        for k in range(n):
            secs, nsecs, offset = _IDX.unpack_from(cur.buf, rec.data_pos + 12 * k)
            entry = chunk.at.get(offset)
            if entry is None or entry[1] != cid or entry[0] != secs * _NS + nsecs:
                raise ROSBagFormatException(
                    f"{rec.where}: entry {k} of connection {cid} points to offset {offset} of "
                    f"the chunk at {chunk.rec.pos}, which holds no message of that connection "
                    "and time; the index is corrupt (rosbag reindex rebuilds it)")
            target.append(entry)
        counts[cid] = counts.get(cid, 0) + n
        indexed += n
        pos = rec.end
    if indexed != len(chunk.order):
        raise ROSBagFormatException(
            f"{cur.origin}: the chunk at offset {chunk.rec.pos} holds {len(chunk.order)} messages "
            f"but its index lists {indexed}; the index is corrupt (rosbag reindex rebuilds it)")
    return pos, counts


def _read_magic(buf: bytes, name: str) -> None:
    if not buf:
        raise ROSBagFormatException(f"{name}: empty file (0 bytes), not a bag")
    line = buf[:64].split(b"\n", 1)[0]
    if buf.startswith(MAGIC):
        return
    if line.startswith(b"#ROSBAG V"):
        raise ROSBagFormatException(
            f"{name}: bag format {line[9:].decode('ascii', 'replace')!r} is not supported; "
            "ddes reads version 2.0 (convert older bags with ROS's rosbag fix)")
    if buf.startswith(b"\x89MCAP"):
        raise ROSBagFormatException(f"{name}: this is an MCAP file, not a ROS 1 bag; open it "
                                    "with Bag(path) on a '.mcap' name or format='mcap'")
    raise ROSBagFormatException(f"{name}: this does not appear to be a bag file (it starts "
                                f"with {line[:20]!r}, not {MAGIC.strip()!r})")


def decode(buf: bytes, name: str, *, allow_unindexed: bool = False,
           max_chunk_size: int | None = None) -> Decoded:
    """Read a whole v2.0 bag from ``buf`` (``name`` names it in error messages).

    ``max_chunk_size`` bounds what compressed chunks may inflate to (see
    :class:`InflateBudget`).
    """
    budget = InflateBudget(len(buf), max_chunk_size)
    _read_magic(buf, name)
    cur = Cursor(buf, name)
    head = cur.record(_DATA_START, "file header").expect(OP_FILE_HEADER)
    encryptor = head.fields.get("encryptor", b"").decode("utf-8", "replace")
    if encryptor and encryptor != "rosbag/NoEncryptor":
        raise ROSBagEncryptNotSupportedException(
            f"{name}: the bag is encrypted with {encryptor}, which ddes cannot read; decrypt it "
            "with ROS's rosbag decrypt")
    index_pos = head.u64("index_pos")
    conn_count, chunk_count = head.u32("conn_count"), head.u32("chunk_count")
    first = head.end
    if index_pos == 0 or index_pos > len(buf):
        why = ("its index position is 0: it was not closed properly" if index_pos == 0 else
               f"its index position {index_pos} lies beyond the end of the file ({len(buf)} "
               "bytes): the file is truncated")
        if allow_unindexed:
            return _recover(cur, first, name, why, budget)
        raise ROSBagUnindexedException(f"{name}: bag unindexed ({why}); run rosbag reindex")
    if index_pos < first:
        raise ROSBagFormatException(f"{name}: the index position {index_pos} points into the "
                                    f"file header (records start at {first}); the file is corrupt")
    connections: dict[int, ConnectionInfo] = {}
    pos = index_pos
    for _ in range(conn_count):
        rec = cur.record(pos, "index connection record")
        conn = _connection(cur, rec)
        connections[conn.id] = conn
        pos = rec.end
    infos: list[tuple[int, int, int, dict[int, int]]] = []
    for _ in range(chunk_count):
        rec = cur.record(pos, "chunk info record").expect(OP_CHUNK_INFO)
        ver = rec.u32("ver")
        if ver != 1:
            raise ROSBagFormatException(f"{rec.where}: unknown chunk info record version: {ver}")
        n = rec.u32("count")
        if rec.data_len != 8 * n:
            raise ROSBagFormatException(f"{rec.where}: count {n} needs {8 * n} bytes, the "
                                        f"record has {rec.data_len}")
        counts = dict(_PAIR.unpack_from(buf, rec.data_pos + 8 * k) for k in range(n))
        infos.append((rec.u64("chunk_pos"), rec.time("start_time"), rec.time("end_time"), counts))
        pos = rec.end
    log: list[Entry] = []
    indexes: dict[int, list[Entry]] = {cid: [] for cid in connections}
    stats: list[ChunkStat] = []
    for chunk_pos, start, end, counts in infos:
        if not first <= chunk_pos < index_pos:
            raise ROSBagFormatException(f"{name}: a chunk info record points to offset "
                                        f"{chunk_pos}, outside the chunk section "
                                        f"[{first}, {index_pos}); the index is corrupt")
        chunk = _read_chunk(cur, chunk_pos, name, budget)
        _, found = _read_index_records(cur, chunk, len(counts), indexes)
        if found != counts:
            raise ROSBagFormatException(
                f"{name}: the chunk info of the chunk at offset {chunk_pos} counts {counts} "
                f"messages per connection, its index records {found}; the index is corrupt")
        for entry in chunk.order:
            if entry[1] not in connections:
                raise ROSBagFormatException(
                    f"{name}: the chunk at offset {chunk_pos} holds a message of connection "
                    f"{entry[1]}, which the index does not define")
        log.extend(chunk.order)
        stats.append(ChunkStat(chunk_pos, chunk.compression, chunk.rec.data_len, chunk.size,
                               start, end, counts))
    for index in indexes.values():
        # rosbag concatenates the chunk indexes; a stable sort by time keeps that order for
        # bags written in time order and gives write order to equal stamps otherwise
        index.sort(key=_time_key)
    return _finish(connections, log, indexes, FileStats(len(buf), stats), None)


def _finish(connections: dict[int, ConnectionInfo], log: list[Entry],
            indexes: dict[int, list[Entry]], stats: FileStats, note: str | None) -> Decoded:
    # rosbag drops connections without messages
    live = {cid: c for cid, c in connections.items() if indexes.get(cid)}
    return Decoded(live, log, {cid: indexes[cid] for cid in live}, stats, note)


def _recover(cur: Cursor, pos: int, name: str, why: str, budget: InflateBudget) -> Decoded:
    """Rebuild the index from the chunks, as ``rosbag reindex`` does."""
    connections: dict[int, ConnectionInfo] = {}
    log: list[Entry] = []
    indexes: dict[int, list[Entry]] = {}
    stats: list[ChunkStat] = []
    stop: str | None = None
    while pos < cur.size:
        try:
            rec = cur.record(pos)
            op = rec.op()
            if op == OP_CHUNK:
                chunk = _read_chunk(cur, pos, name, budget)
                for conn in chunk.conns:
                    connections.setdefault(conn.id, conn)
                for entry in chunk.order:
                    if entry[1] not in connections:
                        raise ROSBagFormatException(
                            f"{name}: the chunk at offset {pos} holds a message of connection "
                            f"{entry[1]} with no connection record before it")
            elif op == OP_CONNECTION:
                conn = _connection(cur, rec)
                connections.setdefault(conn.id, conn)
            elif op not in (OP_INDEX_DATA, OP_CHUNK_INFO):
                raise ROSBagFormatException(f"{rec.where}: unexpected "
                                            f"{OP_NAMES.get(op, 'unknown')} record (op {op:#04x})")
        except ROSBagFormatException as exc:
            stop = f"recovery stopped at offset {pos}: {exc}"
            break
        if op == OP_CHUNK:
            counts: dict[int, int] = {}
            for entry in chunk.order:
                cid = entry[1]
                counts[cid] = counts.get(cid, 0) + 1
                bisect.insort_right(indexes.setdefault(cid, []), entry, key=_time_key)
            log.extend(chunk.order)
            times = [e[0] for e in chunk.order] or [0]
            stats.append(ChunkStat(pos, chunk.compression, rec.data_len, chunk.size, min(times),
                                   max(times), counts))
        pos = rec.end
    note = f"{name}: {why}; recovered {len(log)} messages in {len(stats)} chunks"
    if stop is not None:
        note += f"; {stop}"
    return _finish(connections, log, indexes, FileStats(cur.size, stats), note)


#: The largest bag file ddes reads (8 GiB): a bag is read into memory whole.
MAX_FILE_SIZE = 8 << 30


def read_file(path: str | os.PathLike[str], limit: int | None = None) -> bytes:
    """The bytes of the bag file at ``path``, or ROSBagException naming it.

    Only a regular file is opened: a directory, a FIFO, a device (``/dev/zero``)
    or a socket is refused first (``rosbag info /dev/zero`` read until memory ran
    out), and a file larger than ``limit`` (default :data:`MAX_FILE_SIZE`) raises
    :class:`~ddes.errors.ResourceLimitError`, checked on ``stat`` and while reading.
    """
    limit = MAX_FILE_SIZE if limit is None else limit
    try:
        st = os.stat(path)
    except FileNotFoundError:
        raise ROSBagException(f"{path}: no such bag file") from None
    except (OSError, ValueError) as exc:
        raise ROSBagException(f"{path}: cannot read the bag file "
                              f"({getattr(exc, 'strerror', None) or exc})") from None
    if stat.S_ISDIR(st.st_mode):
        raise ROSBagException(f"{path}: is a directory, not a bag file")
    if not stat.S_ISREG(st.st_mode):
        kind = ("a FIFO (named pipe)" if stat.S_ISFIFO(st.st_mode) else
                "a device" if stat.S_ISCHR(st.st_mode) or stat.S_ISBLK(st.st_mode) else
                "a socket" if stat.S_ISSOCK(st.st_mode) else "not a regular file")
        raise ROSBagException(f"{path}: is {kind}, not a bag file; give the path of a bag file")
    too_big = (f"{path}: the bag file is larger than {limit} bytes ({_mib(limit)}), the most "
               "ddes reads (ddes.rosbag.bagfile.MAX_FILE_SIZE); split it with rosbag filter")
    if st.st_size > limit:
        raise ResourceLimitError(f"{too_big} (it is {st.st_size} bytes)")
    try:
        with open(path, "rb") as f:
            data = f.read(limit + 1)
    except IsADirectoryError:
        raise ROSBagException(f"{path}: is a directory, not a bag file") from None
    except OSError as exc:
        raise ROSBagException(f"{path}: cannot read the bag file ({exc.strerror})") from None
    if len(data) > limit:
        raise ResourceLimitError(too_big)
    return data


# -- writing as you go (rosbag record) ---------------------------------------------------------

def _chunk_blob(ch: _ChunkWriter, compression: str) -> tuple[bytes, int, int]:
    """A closed chunk record and its index records, as :func:`encode` writes them."""
    raw = bytes(ch.buf)
    packed = _compress(compression, raw)
    head = encode_header({"op": _B.pack(OP_CHUNK), "compression": compression.encode(),
                          "size": _U32.pack(len(raw))})
    parts = [_U32.pack(len(head)), head, _U32.pack(len(packed)), packed]
    for cid, entries in ch.index.items():
        parts.append(encode_record({"op": _B.pack(OP_INDEX_DATA), "conn": _U32.pack(cid),
                                    "ver": _U32.pack(1),
                                    "count": _U32.pack((len(entries) - 1) // 3)},
                                   ch.index_body(cid)))
    return b"".join(parts), len(packed), len(raw)


class StreamWriter:
    """A v2.0 bag written as it grows, the way ``rosbag record`` writes ``NAME.bag.active``.

    The file starts with the magic and a file header whose index position is
    0 (unindexed).  :meth:`add` appends a message to the open chunk; a chunk
    holding more than ``chunk_threshold`` uncompressed bytes is written out
    at once, and :meth:`flush` writes the open chunk whatever its size (and
    flushes the file to the operating system).  What was written survives a
    killed process: ``rosbag reindex`` (ddes's or ROS's) rebuilds the index
    from the chunks.  :meth:`close` writes the index and the final file
    header.  Without :meth:`flush` calls the bytes equal :func:`encode`'s
    for the same messages.
    """

    def __init__(self, out: IO[bytes], *, compression: str = "none",
                 chunk_threshold: int = 768 * 1024) -> None:
        if compression not in COMPRESSIONS:
            raise ROSBagException(f"unsupported compression type: {compression}; use one of "
                                  f"{', '.join(COMPRESSIONS)}")
        self.out = out
        self.compression = compression
        self.chunk_threshold = chunk_threshold
        self.base = out.tell()
        out.write(MAGIC)
        out.write(_file_header(0, 0, 0))
        self.pos = out.tell() - self.base
        self.chunks: list[ChunkStat] = []
        self.connections: dict[int, ConnectionInfo] = {}
        self._chunk: _ChunkWriter | None = None
        self.closed = False
        out.flush()

    def add(self, t: int, conn: ConnectionInfo, data: bytes) -> None:
        """Append one message (``t`` in ns) of connection ``conn``."""
        chunk = self._chunk
        if chunk is None:
            chunk = self._chunk = _ChunkWriter(t)
        if conn.id not in self.connections:
            self.connections[conn.id] = conn
            chunk.buf += _connection_record(conn)
        chunk.add(t, conn.id, data)
        if len(chunk.buf) > self.chunk_threshold:
            self._write_chunk()
            self.out.flush()

    def _write_chunk(self) -> None:
        ch = self._chunk
        if ch is None:
            return
        self._chunk = None
        blob, packed, raw = _chunk_blob(ch, self.compression)
        self.out.write(blob)
        self.chunks.append(ChunkStat(self.pos, self.compression, packed, raw, ch.start, ch.end,
                                     ch.counts()))
        self.pos += len(blob)

    def flush(self) -> None:
        """Write the open chunk (if any) and hand the bytes to the operating system."""
        if self.closed:
            return
        self._write_chunk()
        self.out.flush()

    def close(self) -> FileStats:
        """Write the open chunk, the index and the final file header."""
        self._write_chunk()
        self.closed = True
        out = self.out
        index_pos = self.pos
        tail = [_connection_record(conn) for conn in self.connections.values()]
        for ch in self.chunks:
            fields = {"op": _B.pack(OP_CHUNK_INFO), "ver": _U32.pack(1),
                      "chunk_pos": _U64.pack(ch.pos), "start_time": pack_time(ch.start),
                      "end_time": pack_time(ch.end), "count": _U32.pack(len(ch.counts))}
            tail.append(encode_record(fields, b"".join(_PAIR.pack(c, n)
                                                       for c, n in ch.counts.items())))
        blob = b"".join(tail)
        out.write(blob)
        end = out.tell()
        out.seek(self.base + _DATA_START)
        out.write(_file_header(index_pos, len(self.connections), len(self.chunks)))
        out.seek(end)
        out.flush()
        return FileStats(index_pos + len(blob), self.chunks)
