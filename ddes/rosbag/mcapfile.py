"""MCAP files in the ``ros1`` profile, so recordings open in Foxglove.

Layout written (with the ``mcap`` library): profile ``ros1``; one schema
per message type and definition (encoding ``ros1msg``, name ``pkg/Type``,
data the ``message_definition``); one channel per bag connection (message
encoding ``ros1``); one message per bag message with ``log_time`` =
``publish_time`` = the bag time in nanoseconds, in bag read order.

Channel metadata carries the connection header, so a bag survives
bag → MCAP → bag exactly: every header field except ``message_definition``
(which is the schema), with ``latching`` written as the profile's
``"true"``/``"false"`` for ``"1"``/``"0"``.  MCAP files written by other
tools (``mcap convert``, ``mcap_ros1.writer``) have channels without a
``type``/``md5sum``: their header is rebuilt as rosbag's Python writer
would write it (topic, type, md5sum computed from the definition,
message_definition) plus ``callerid``/``latching`` when present.
"""

from __future__ import annotations

import dataclasses
import heapq
import io
from collections.abc import Mapping
from operator import itemgetter
from typing import IO, TYPE_CHECKING

from ddes.errors import DdesError, ROSBagException, ROSBagFormatException
from ddes.rosbag.bagfile import Decoded, Entry, FileStats, InflateBudget, inflate
from ddes.rosbag.records import ConnectionInfo
from ddes.time.units import to_ns

if TYPE_CHECKING:
    from mcap.records import Channel, Chunk, McapRecord, Schema
    from mcap.writer import CompressionType

__all__ = ["MCAP_MAGIC", "decode_mcap", "encode_mcap"]

MCAP_MAGIC = b"\x89MCAP0\r\n"
_time_key = itemgetter(0)
_TIME_LIMIT = to_ns(2**32)  # ROS 1 times are u32 seconds
_LATCH_OUT: dict[str, str] = {"1": "true", "0": "false"}
_LATCH_IN: dict[str, str] = {"true": "1", "false": "0"}
_READ_COMPRESSIONS = ("none", "lz4", "zstd")


def _compression(kind: str) -> CompressionType:
    from mcap.writer import CompressionType

    table = {"none": CompressionType.NONE, "lz4": CompressionType.LZ4,
             "zstd": CompressionType.ZSTD}
    if kind not in table:
        raise ROSBagException(f"unsupported MCAP compression {kind!r}: use 'none', 'lz4' or 'zstd'")
    return table[kind]


def encode_mcap(connections: Mapping[int, ConnectionInfo], indexes: Mapping[int, list[Entry]],
                out: IO[bytes], *, compression: str = "lz4", chunk_size: int = 1024 * 1024) -> None:
    """Write the bag (its connections and per-connection indexes) as MCAP to ``out``."""
    from mcap.exceptions import McapError
    from mcap.writer import Writer

    from ddes._version import __version__

    try:
        writer = Writer(out, chunk_size=chunk_size, compression=_compression(compression))
    except McapError as exc:
        raise ROSBagException(f"cannot write MCAP with {compression} compression: {exc}") from None
    writer.start(profile="ros1", library=f"ddes/{__version__}")
    schemas: dict[tuple[str, str], int] = {}
    channels: dict[int, int] = {}
    for cid, conn in connections.items():
        if not indexes.get(cid):
            continue
        key = (conn.datatype, conn.msg_def)
        if key not in schemas:
            schemas[key] = writer.register_schema(
                name=conn.datatype, encoding="ros1msg",
                data=conn.msg_def.encode("utf-8", "surrogateescape"))
        metadata = {k: (_LATCH_OUT.get(v, v) if k == "latching" else v)
                    for k, v in conn.header.items() if k != "message_definition"}
        channels[cid] = writer.register_channel(topic=conn.topic, message_encoding="ros1",
                                                schema_id=schemas[key], metadata=metadata)
    sequence = dict.fromkeys(channels, 0)
    for t, cid, data in heapq.merge(*(indexes[cid] for cid in channels), key=_time_key):
        writer.add_message(channel_id=channels[cid], log_time=t, data=data, publish_time=t,
                           sequence=sequence[cid])
        sequence[cid] += 1
    writer.finish()  # type: ignore[no-untyped-call,unused-ignore]  # mcap's writer is untyped


def _header(channel: Channel, schema: Schema, definition: str) -> dict[str, str]:
    meta: dict[str, str] = {str(k): str(v) for k, v in channel.metadata.items()}
    if "type" in meta and "md5sum" in meta:  # written by ddes: the header itself
        header = {k: (_LATCH_IN.get(v, v) if k == "latching" else v) for k, v in meta.items()}
        header["message_definition"] = definition
        return header
    from ddes.msg.registry import definition_facts

    try:  # the md5 alone: no class is generated to read a file (rosbag info)
        md5 = definition_facts(schema.name, definition)[0]
    except DdesError as exc:
        raise ROSBagFormatException(
            f"channel {channel.id} ({channel.topic}): cannot compute the md5sum of "
            f"{schema.name} from its schema: {exc}") from None
    header = {"topic": channel.topic, "type": schema.name, "md5sum": md5,
              "message_definition": definition}
    if "callerid" in meta:
        header["callerid"] = meta["callerid"]
    if "latching" in meta:
        header["latching"] = _LATCH_IN.get(meta["latching"], meta["latching"])
    return header


def _chunk_records(chunk: Chunk, at: int, name: str, budget: InflateBudget) -> list[McapRecord]:
    """The records of ``chunk``, decompressed by ddes with the declared size as a hard cap.

    The mcap library inflates lz4 chunks without any bound; ddes checks the
    chunk's ``uncompressed_size`` against the budget first, then inflates at
    most that many bytes (:func:`~ddes.rosbag.bagfile.inflate`).
    """
    from mcap.stream_reader import breakup_chunk

    where = f"{name}: chunk at offset {at}"
    kind = chunk.compression or "none"
    if kind not in _READ_COMPRESSIONS:
        raise ROSBagException(f"{where}: unsupported MCAP compression {kind[:40]!r}; ddes reads "
                              "'' (none), 'lz4' and 'zstd'")
    if kind == "none":
        raw = bytes(chunk.data)
    else:
        budget.take(chunk.uncompressed_size, len(chunk.data), kind, where)
        raw = inflate(kind, bytes(chunk.data), chunk.uncompressed_size, where)
    return list(breakup_chunk(dataclasses.replace(chunk, compression="", data=raw),
                              validate_crc=True))


def decode_mcap(buf: bytes, name: str, *, max_chunk_size: int | None = None) -> Decoded:
    """Read an MCAP file of the ``ros1`` profile (``name`` names it in errors).

    ``max_chunk_size`` bounds what compressed chunks may inflate to (see
    :class:`~ddes.rosbag.bagfile.InflateBudget`).
    """
    from mcap.records import Channel, Chunk, Message, Schema
    from mcap.stream_reader import StreamReader

    budget = InflateBudget(len(buf), max_chunk_size)
    if not buf.startswith(MCAP_MAGIC):
        raise ROSBagFormatException(f"{name}: not an MCAP file (it starts with {buf[:8]!r})")
    schemas: dict[int, Schema] = {}
    chans: dict[int, Channel] = {}
    messages: list[tuple[int, int, bytes]] = []
    try:
        stream = io.BytesIO(buf)
        reader = StreamReader(stream, validate_crcs=True, record_size_limit=len(buf),
                              emit_chunks=True)
        for top in reader.records:
            if isinstance(top, Chunk):
                # the chunk record ends where the stream stands: opcode, length, 5 fixed fields,
                # the compression string and the records (ddes and mcap write no padding)
                at = stream.tell() - (9 + 40 + len(top.compression.encode()) + len(top.data))
                inner: list[McapRecord] = _chunk_records(top, at, name, budget)
            else:
                inner = [top]
            for record in inner:
                if isinstance(record, Schema):
                    schemas[record.id] = record
                elif isinstance(record, Channel):
                    chans.setdefault(record.id, record)
                elif isinstance(record, Message):
                    messages.append((record.log_time, record.channel_id, bytes(record.data)))
    except DdesError:
        raise
    except Exception as exc:  # noqa: BLE001 - the mcap library raises many kinds on bad input
        raise ROSBagFormatException(f"{name}: corrupt or truncated MCAP file "
                                    f"({type(exc).__name__}: {exc})") from None
    used = sorted({m[1] for m in messages})
    conn_of: dict[int, int] = {}
    connections: dict[int, ConnectionInfo] = {}
    for chan_id in used:
        chan = chans.get(chan_id)
        if chan is None:
            raise ROSBagFormatException(f"{name}: a message refers to channel {chan_id}, which "
                                        "the file never defines")
        if chan.message_encoding not in ("ros1", "ros"):
            raise ROSBagFormatException(
                f"{name}: channel {chan_id} ({chan.topic}) has message encoding "
                f"{chan.message_encoding!r}; ddes reads only the ros1 profile")
        schema = schemas.get(chan.schema_id)
        if schema is None or schema.encoding != "ros1msg":
            raise ROSBagFormatException(
                f"{name}: channel {chan_id} ({chan.topic}) needs a ros1msg schema, found "
                f"{'none' if schema is None else repr(schema.encoding)}")
        definition = bytes(schema.data).decode("utf-8", "surrogateescape")
        cid = len(connections)
        conn_of[chan_id] = cid
        try:
            connections[cid] = ConnectionInfo(cid, chan.topic, _header(chan, schema, definition))
        except ROSBagFormatException as exc:
            raise ROSBagFormatException(f"{name}: {exc}") from None
    log: list[Entry] = []
    indexes: dict[int, list[Entry]] = {cid: [] for cid in connections}
    for t, chan_id, data in messages:
        if t >= _TIME_LIMIT:
            raise ROSBagFormatException(
                f"{name}: a message of channel {chan_id} has log_time {t} ns, beyond the ROS 1 "
                "time range (u32 seconds)")
        entry = (t, conn_of[chan_id], data)
        log.append(entry)
        indexes[entry[1]].append(entry)
    for index in indexes.values():
        index.sort(key=_time_key)  # stable: equal times keep file order
    return Decoded(connections, log, indexes, FileStats(len(buf), []), None)

