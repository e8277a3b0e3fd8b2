"""``Bag``: rosbag's Python API over an in-memory store, .bag v2.0 and MCAP files.

A bag holds serialized messages, each with its time (integer ns) and its
connection (topic + connection header with type, md5sum and
message_definition).  It lives in memory; a file is read whole when the bag
opens and written whole when it closes:

* ``Bag()`` — an in-memory bag (mode ``'w'``);
* ``Bag("x.bag")`` / ``Bag("x.mcap")`` — read a ROS bag v2.0 or MCAP file
  (the format is told by the first bytes);
* ``Bag("x.bag", "w")`` — write on close: the file is written as
  ``x.bag.active`` (created at once, so a bad path fails early) and renamed
  to ``x.bag`` when complete, as ``rosbag record`` does;
* ``Bag("x.bag", "a")`` — load ``x.bag`` if it exists, add messages, and
  rewrite it on close.

Semantics follow rosbag's ``bag.py``: ``write`` uses one connection per
topic; indexes are kept sorted with ``insort_right`` (equal stamps keep
write order); ``read_messages`` merges connections by time (ties in
connection order) with both bounds inclusive and a zero ``Time`` meaning no
bound; ``get_start_time``/``get_end_time`` are float seconds.

Deviations (see docs/bags.md): ``write(t=None)`` uses the bag's ``clock``
(a node, world or clock passed to the constructor) because ddes has no wall
clock, and raises without one; connection header values are ``str``;
the raw ``position`` is None; a file object given as ``f`` is not closed.
"""

from __future__ import annotations

import bisect
import datetime
import functools
import heapq
import io
import os
import stat
import warnings
from collections.abc import Callable, Iterable, Iterator
from operator import itemgetter
from types import TracebackType
from typing import (
    IO,
    TYPE_CHECKING,
    Literal,
    NamedTuple,
    Protocol,
    TypedDict,
    Union,
    cast,
    overload,
)

from ddes.errors import (
    DdesError,
    DdesTypeError,
    DdesValueError,
    InvalidMsgSpec,
    MsgNotFound,
    ResourceLimitError,
    ROSBagException,
    ROSBagFormatException,
)
from ddes.msg.anymsg import AnyMsg
from ddes.rosbag.bagfile import (
    COMPRESSIONS,
    Decoded,
    Entry,
    FileStats,
    active_placeholder,
    decode,
    encode,
    read_file,
)
from ddes.rosbag.info import (
    BagSummary,
    TopicRow,
    info_text,
    info_yaml,
    shown,
    to_sec,
    topic_rows,
)
from ddes.rosbag.mcapfile import MCAP_MAGIC, decode_mcap, encode_mcap
from ddes.rosbag.records import ConnectionInfo, canonicalize_topic
from ddes.time.rostime import Time
from ddes.time.units import HasNsec, to_ns

if TYPE_CHECKING:
    from ddes.msg.message import Message
    from ddes.msg.registry import MessageRegistry

__all__ = [
    "Bag",
    "BagClock",
    "BagMessage",
    "BagMessageWithConnectionHeader",
    "BagOptions",
    "Compression",
    "CompressionTuple",
    "ConnectionFilter",
    "MAX_REBUILT_FIELDS",
    "RawMessage",
    "TopicTuple",
    "TypesAndTopicsTuple",
    "open_active",
    "write_target",
]

_time_key = itemgetter(0)
_NS = 1_000_000_000
_TIME_LIMIT = to_ns(2**32)  # a bag stores u32 seconds

#: The fields (nested types inlined, as code generation writes them) that the classes one Bag
#: rebuilds from its connections' ``message_definition`` may hold in all.  Generating a class
#: costs about 65 us a field: a hostile file of thousands of definitions, each just under the
#: codegen limit of ddes.msg.codegen.MAX_FLAT_FIELDS, would take hours; real bags need a few
#: thousand (the largest bundled type has 76).
MAX_REBUILT_FIELDS = 50_000


class Compression:
    """Chunk compressions (rosbag.Compression)."""

    NONE = "none"
    BZ2 = "bz2"
    LZ4 = "lz4"


#: A message as ``read_messages(raw=True)`` gives it and ``write(..., raw=True)`` takes it:
#: ``(datatype, bytes, md5sum, position, pytype)``; ``write`` also takes the 4-tuple without
#: ``position``.
RawMessage = Union[
    "tuple[str, bytes, str, int | None, type[Message] | None]",
    "tuple[str, bytes, str, type[Message] | None]",
]
#: ``connection_filter(topic, datatype, md5sum, msg_def, header) -> bool``.
ConnectionFilter = Callable[[str, str, str, str, "dict[str, str]"], bool]
#: Topics to select: one topic, several, or None for all.
Topics = str | Iterable[str] | None


class _RosTimeSource(Protocol):
    def get_rostime(self) -> Time: ...


class _TimeSource(Protocol):
    def time(self) -> Time: ...


#: Where ``write(t=None)`` takes the time: a node or a clock (``get_rostime()``), a world
#: (``time()``), or a function returning a Time.
BagClock = _RosTimeSource | _TimeSource | Callable[[], Time]


class BagOptions(TypedDict, total=False):
    """``Bag(options=...)`` and :attr:`Bag.options`."""

    compression: str
    chunk_threshold: int


class BagMessage(NamedTuple):
    """One message read from a bag (``message`` is a :data:`RawMessage` with ``raw=True``)."""

    topic: str
    message: Message | RawMessage
    timestamp: Time


class BagMessageWithConnectionHeader(NamedTuple):
    """One message read with ``return_connection_header=True``."""

    topic: str
    message: Message | RawMessage
    timestamp: Time
    connection_header: dict[str, str]


class TopicTuple(NamedTuple):
    """Per-topic summary of :meth:`Bag.get_type_and_topic_info`."""

    msg_type: str
    message_count: int
    connections: int
    frequency: float | None


class TypesAndTopicsTuple(NamedTuple):
    """``msg_types`` ({type: md5}) and ``topics`` ({topic: TopicTuple})."""

    msg_types: dict[str, str]
    topics: dict[str, TopicTuple]


class CompressionTuple(NamedTuple):
    """Main compression and total sizes (rosbag's ``get_compression_info``)."""

    compression: str
    uncompressed: int
    compressed: int


def _stamp_ns(t: Time | HasNsec, what: str) -> int:
    """A message time in ns: rosbag takes a Time, never bare seconds, within the u32 range."""
    if isinstance(t, (int, float)) or not isinstance(t, HasNsec):
        raise DdesTypeError(
            f"{what} must be a Time (e.g. Time(secs, nsecs) or node.get_rostime()), got {t!r}")
    ns = to_ns(t, what)
    if not 0 <= ns < _TIME_LIMIT:
        raise DdesValueError(f"{what} {t!r} is outside the ROS 1 time range a bag can hold "
                             "(0 to 2**32 seconds)")
    return ns


def _bound(t: Time | HasNsec | None, what: str) -> int | None:
    if t is None:
        return None
    if not isinstance(t, HasNsec):
        raise DdesTypeError(f"{what} must be a Time or None, got {t!r}")
    return None if not t else to_ns(t, what)


_KINDS = ((stat.S_ISDIR, "a directory"), (stat.S_ISFIFO, "a FIFO (named pipe)"),
          (stat.S_ISCHR, "a character device"), (stat.S_ISBLK, "a block device"),
          (stat.S_ISSOCK, "a socket"))


def write_target(path: str) -> str:
    """The file a bag written to ``path`` lands in: a symlink is followed (its target gets the
    bag, the link stays); a directory, FIFO, device or socket is refused with ROSBagException."""
    target = os.path.realpath(path) if os.path.islink(path) else path
    try:
        mode = os.stat(target).st_mode
    except FileNotFoundError:
        return target
    except OSError as exc:
        raise ROSBagException(f"{path}: cannot write the bag there ({exc.strerror})") from None
    for test, what in _KINDS:
        if test(mode):
            shown_path = path if target == path else f"{path} (a link to {target})"
            raise ROSBagException(f"{shown_path} is {what}, not a regular file: a bag is written "
                                  "only to a regular file; give a file name such as run.bag")
    return target


def open_active(path: str) -> IO[bytes]:
    """Open the temporary file ``path`` (a ``.active`` name) for writing, fresh.

    A symlink or other non-regular file of that name is ddes's temporary name taken by
    something else: a link is removed (the bag never writes through it), anything else refused.
    """
    if os.path.islink(path):
        os.unlink(path)
    write_target(path)
    return open(path, "wb")


def _is_mcap_name(f: str | os.PathLike[str]) -> bool:
    return str(os.fspath(f)).lower().endswith(".mcap")


class Bag:
    """A ROS 1 bag (rosbag.Bag), in memory, with .bag v2.0 and MCAP files.

    Parameters
    ----------
    f:
        None (in memory), a path, or a binary file object.
    mode:
        ``'r'``, ``'w'`` or ``'a'``; default ``'r'`` for a file, ``'w'`` in memory.
    compression:
        Chunk compression used when the bag is written: ``'none'``, ``'bz2'``, ``'lz4'``.
    chunk_threshold:
        Uncompressed bytes after which a chunk closes (rosbag's 768 KB).
    allow_unindexed:
        Read an unindexed or truncated .bag by recovering its complete chunks
        (what ``rosbag reindex`` keeps); :attr:`recovered` says what was dropped.
    skip_index:
        As rosbag: no message-index statistics (frequencies) in ``str(bag)``.
    clock:
        Where ``write(t=None)`` takes the time: a node, a world, a clock, or a
        function returning a Time.
    format:
        ``'bag'`` or ``'mcap'`` for writing (default from the file name).
    registry:
        Message registry used to turn connections into classes (default: the
        package path); types it lacks are rebuilt from ``message_definition``.
    max_chunk_size:
        Reading a hostile file: by default a compressed chunk may declare at
        most 256 MiB uncompressed and all of a file's compressed chunks together
        at most 1000x the file's size (at least 64 MiB); past that ddes raises
        ResourceLimitError before decompressing.  An int trusts each chunk up
        to that many bytes instead (for genuine, very compressible bags).
    filename:
        The name the bag goes by (:attr:`filename`, ``rosbag info``'s
        ``path:``, error messages) when it is not ``f`` itself: a program
        opening ``x.bag`` in its own directory passes the joined path as
        ``f`` and ``"x.bag"`` here.
    """

    def __init__(self, f: str | os.PathLike[str] | IO[bytes] | None = None,
                 mode: str | None = None, compression: str = "none",
                 chunk_threshold: int = 768 * 1024, allow_unindexed: bool = False,
                 options: BagOptions | None = None, skip_index: bool = False, *,
                 clock: BagClock | None = None, format: str | None = None,
                 registry: MessageRegistry | None = None,
                 max_chunk_size: int | None = None, filename: str | None = None) -> None:
        if options is not None:
            if not isinstance(options, dict):
                raise DdesTypeError(f"options must be a dict, got {options!r}")
            compression = options.get("compression", compression)
            chunk_threshold = options.get("chunk_threshold", chunk_threshold)
        if mode is None:
            mode = "w" if f is None else "r"
        if mode not in ("r", "w", "a"):
            raise DdesValueError(f"mode {mode!r} is invalid: use 'r', 'w' or 'a'")
        if f is None and mode == "r":
            raise DdesValueError("an in-memory bag (f=None) is written to: use mode 'w' (the "
                                 "default) or open a file with Bag(path)")
        if format not in (None, "bag", "mcap"):
            raise DdesValueError(f"format {format!r} is invalid: use 'bag' or 'mcap'")
        self._mode = mode
        self._compression = Compression.NONE
        self._chunk_threshold = 768 * 1024
        self.compression = compression
        self.chunk_threshold = chunk_threshold
        self._skip_index = bool(skip_index)
        self._clock = clock
        self._registry = registry
        self._connections: dict[int, ConnectionInfo] = {}
        self._indexes: dict[int, list[Entry]] = {}
        self._log: list[Entry] = []
        self._topic_connections: dict[str, int] = {}
        self._header_connections: dict[tuple[str, str], list[tuple[dict[str, str], int]]] = {}
        self._next_id = 0
        self._classes: dict[int, type[Message]] = {}
        self._rebuilt: dict[tuple[str, str], int] = {}  # definitions costed: their fields
        self._rebuilt_total = 0
        self._loaded: FileStats | None = None
        self._encoded: tuple[bytes, FileStats] | None = None
        self._closed = False
        #: What recovering an unindexed file dropped (``allow_unindexed``), else None.
        self.recovered: str | None = None
        self._filename: str | None = None
        self._file: IO[bytes] | None = None
        self._path: str | None = None
        self._format = format
        self._mcap_loaded = False
        self._file_pos = 0
        self._max_chunk_size = max_chunk_size
        if f is None:
            return
        if not isinstance(f, (str, os.PathLike)):  # a file object (has read or write)
            self._file = f
            self._file_pos = f.tell()
            if mode in ("r", "a"):
                data = f.read()
                if mode == "r" or data:
                    self._load(data, "<file object>", allow_unindexed)
            return
        path = os.fspath(f)
        self._path = str(path)
        self._filename = self._path if filename is None else filename
        if self._format is None:
            self._format = "mcap" if _is_mcap_name(path) else "bag"
        if mode == "r" or (mode == "a" and os.path.exists(path)):
            try:
                data = read_file(path)
            except ROSBagException as exc:
                text = str(exc)
                if filename is None or not text.startswith(f"{path}: "):
                    raise
                raise type(exc)(f"{filename}: {text[len(str(path)) + 2:]}") from None
            self._load(data, self._filename, allow_unindexed)
        if mode in ("w", "a"):
            self._start_active()

    # -- loading and saving ------------------------------------------------------------------
    def _load(self, data: bytes, name: str, allow_unindexed: bool) -> None:
        decoded: Decoded
        try:
            if data.startswith(MCAP_MAGIC):
                decoded = decode_mcap(data, name, max_chunk_size=self._max_chunk_size)
            else:
                decoded = decode(data, name, allow_unindexed=allow_unindexed,
                                 max_chunk_size=self._max_chunk_size)
        except DdesError as exc:  # a hostile name in the message must not break printing it
            text = str(exc)
            if text.isprintable():
                raise
            raise type(exc)(shown(text)) from None
        self._connections = dict(decoded.connections)
        self._indexes = decoded.indexes
        self._log = decoded.log
        self._loaded = decoded.stats
        self.recovered = decoded.recovered
        self._next_id = max(self._connections, default=-1) + 1
        for cid, conn in self._connections.items():
            self._topic_connections.setdefault(conn.topic, cid)
            self._header_connections.setdefault((conn.topic, conn.callerid), []).append(
                (conn.header, cid))
        self._mcap_loaded = data.startswith(MCAP_MAGIC)

    def _start_active(self) -> None:
        assert self._path is not None
        target = write_target(self._path)  # refuse a directory, FIFO or device at once
        active = target + ".active"
        try:
            with open_active(active) as out:
                if self._format == "bag":
                    out.write(active_placeholder())  # what an open rosbag file starts with
        except OSError as exc:
            raise ROSBagException(f"{self._path}: cannot create {active} ({exc.strerror})") from None

    def to_bytes(self, format: str = "bag", compression: str | None = None) -> bytes:
        """The bag as .bag v2.0 (``format='bag'``) or MCAP (``'mcap'``) bytes."""
        out = io.BytesIO()
        self._write_to(out, format, compression)
        return out.getvalue()

    @classmethod
    def from_bytes(cls, data: bytes, *, allow_unindexed: bool = False, compression: str = "none",
                   chunk_threshold: int = 768 * 1024, options: BagOptions | None = None,
                   skip_index: bool = False, clock: BagClock | None = None,
                   format: str | None = None, registry: MessageRegistry | None = None,
                   max_chunk_size: int | None = None) -> Bag:
        """An in-memory bag holding the messages of .bag or MCAP ``data`` (the other keywords
        are the constructor's)."""
        bag = cls(None, "w", compression, chunk_threshold, options=options, skip_index=skip_index,
                  clock=clock, format=format, registry=registry, max_chunk_size=max_chunk_size)
        bag._load(bytes(data), "<bytes>", allow_unindexed)
        return bag

    def save(self, f: str | os.PathLike[str] | IO[bytes], *, format: str | None = None,
             compression: str | None = None) -> None:
        """Write the bag to a path or a file object.

        A path is written atomically: into ``NAME.active`` in the same folder, flushed to
        disk, then renamed over ``NAME`` (``os.replace``), so ``NAME`` is always the old or
        the new bag, never half of one.  A symlink is followed (the target gets the bag and
        the link stays); a directory, FIFO, device or socket is refused with ROSBagException.
        """
        if not isinstance(f, (str, os.PathLike)):  # a file object
            self._write_to(f, format or "bag", compression)
            return
        path = str(os.fspath(f))
        fmt = format or ("mcap" if _is_mcap_name(path) else "bag")
        target = write_target(path)
        active = target + ".active"
        try:
            with open_active(active) as out:
                self._write_to(out, fmt, compression)
                out.flush()
                os.fsync(out.fileno())
            os.replace(active, target)
        except OSError as exc:
            raise ROSBagException(f"{path}: cannot write the bag ({exc.strerror}); the file "
                                  f"{path} is unchanged") from None

    def _write_to(self, out: IO[bytes], fmt: str, compression: str | None) -> None:
        if fmt == "mcap":
            encode_mcap(self._connections, self._indexes, out,
                        compression="lz4" if compression is None else compression)
        elif fmt == "bag":
            kind = self._compression if compression is None else compression
            if kind == self._compression and self._encoded is not None:
                out.write(self._encoded[0])
                return
            encode(self._connections, self._log, out, compression=kind,
                   chunk_threshold=self._chunk_threshold)
        else:
            raise DdesValueError(f"format {fmt!r} is invalid: use 'bag' or 'mcap'")

    def _encoding(self) -> tuple[bytes, FileStats]:
        if self._encoded is None:
            out = io.BytesIO()
            stats = encode(self._connections, self._log, out, compression=self._compression,
                           chunk_threshold=self._chunk_threshold)
            self._encoded = (out.getvalue(), stats)
        return self._encoded

    def flush(self) -> None:
        """Check the bag is open (data reaches the file on :meth:`close`)."""
        self._check_open()

    def close(self) -> None:
        """Write the file (modes ``'w'``/``'a'``) and close; closing twice does nothing."""
        if self._closed:
            return
        self._closed = True
        if self._mode == "r":
            return
        if self._path is not None:
            self.save(self._path, format=self._format)
        elif self._file is not None:
            self._file.seek(self._file_pos)
            self._write_to(self._file, self._format or "bag", None)
            self._file.truncate()

    def __enter__(self) -> Bag:
        return self

    def __exit__(self, exc_type: type[BaseException] | None, exc: BaseException | None,
                 tb: TracebackType | None) -> None:
        self.close()

    def _check_open(self) -> None:
        if self._closed:
            raise DdesValueError("I/O operation on closed bag")

    # -- properties ------------------------------------------------------------------------------
    @property
    def filename(self) -> str | None:
        """The file's path (None in memory or for a file object)."""
        return self._filename

    @property
    def mode(self) -> str:
        return self._mode

    @property
    def version(self) -> int:
        """200 (bag format 2.0)."""
        return 200

    @property
    def options(self) -> BagOptions:
        return {"compression": self._compression, "chunk_threshold": self._chunk_threshold}

    @property
    def compression(self) -> str:
        """The compression used when the bag is written."""
        return self._compression

    @compression.setter
    def compression(self, value: str) -> None:
        if value not in COMPRESSIONS:
            raise DdesValueError(f"compression must be one of: {', '.join(COMPRESSIONS)} "
                                 f"(got {value!r})")
        if value != self._compression:
            self._compression = value
            self._encoded = None

    @property
    def chunk_threshold(self) -> int:
        return self._chunk_threshold

    @chunk_threshold.setter
    def chunk_threshold(self, value: int) -> None:
        if isinstance(value, bool) or not isinstance(value, int) or value < 0:
            raise DdesValueError(f"chunk_threshold must be an int >= 0, got {value!r}")
        if value != self._chunk_threshold:
            self._chunk_threshold = value
            self._encoded = None

    @property
    def size(self) -> int:
        """Bytes of the file read, or of the .bag file the bag would be written as."""
        self._check_open()
        if self._loaded is not None:
            return self._loaded.size
        return len(self._encoding()[0])

    # -- writing ---------------------------------------------------------------------------------
    def _modified(self) -> None:
        self._loaded = None
        self._encoded = None

    def _append(self, cid: int, t: int, data: bytes) -> None:
        entry = (t, cid, data)
        self._log.append(entry)
        index = self._indexes[cid]
        if not index or t >= index[-1][0]:
            index.append(entry)
        else:
            bisect.insort_right(index, entry, key=_time_key)
        if self._loaded is not None or self._encoded is not None:
            self._modified()

    def _new_connection(self, topic: str, header: dict[str, str]) -> int:
        cid = self._next_id
        self._next_id += 1
        self._connections[cid] = ConnectionInfo(cid, topic, header)
        self._indexes[cid] = []
        return cid

    def _now(self) -> Time:
        clock = self._clock
        if clock is None:
            raise DdesValueError(
                "write() needs t: ddes has no wall clock. Pass t=node.get_rostime(), or bind "
                "the bag to a clock with Bag(..., clock=node)")
        for name in ("get_rostime", "time"):
            fn = getattr(clock, name, None)
            if callable(fn):
                now: Time = fn()
                return now
        if callable(clock):
            return clock()
        raise DdesTypeError(f"clock must be a node, world, clock or function, got {clock!r}")

    def _check_writable(self) -> None:
        self._check_open()
        if self._mode == "r":
            raise DdesValueError(f"bag {self._filename or ''} is open for reading ('r'); "
                                 "open it with mode 'a' to add messages")

    def write(self, topic: str, msg: Message | AnyMsg | RawMessage, t: Time | None = None,
              raw: bool = False, connection_header: dict[str, str] | None = None) -> None:
        """Write ``msg`` on ``topic`` at ``t`` (rosbag.Bag.write).

        ``raw=True`` takes ``msg`` as ``(type, bytes, md5sum[, position], pytype)``.
        An ``AnyMsg`` is written raw with its own connection header.  The first
        write on a topic creates its connection from ``connection_header`` (or
        the message class); later writes on that topic reuse it.
        """
        if self._closed or self._mode == "r":
            self._check_writable()
        if not topic or not isinstance(topic, str):
            raise DdesValueError(f"topic is invalid: {topic!r}")
        if msg is None:
            raise DdesValueError("msg is invalid: None")
        if type(t) is Time and t.secs < 4294967296:
            ns = t.secs * _NS + t.nsecs  # the common case: a Time within the u32 range
            if type(ns) is not int:
                ns = int(ns)
        else:
            ns = _stamp_ns(self._now() if t is None else t, "t")
        if raw and type(msg) is tuple and 4 <= len(msg) <= 5:
            # the common raw case, on a known topic: rosbag's checks, then _append
            data = msg[1]
            if type(data) is not bytes:
                if not isinstance(data, (bytes, bytearray, memoryview)):
                    raise DdesTypeError(f"raw message data must be bytes, got "
                                        f"{type(data).__name__}")
                data = bytes(data)
            cid = self._topic_connections.get(topic)
            if cid is not None:
                self._append(cid, ns, data)
                return
        if isinstance(msg, AnyMsg):
            data = bytes(msg._buff)
            header = dict(msg._connection_header)
            if connection_header is not None:
                header = dict(connection_header)
            cid = self._topic_connections.get(topic)
            if cid is None:
                cid = self._new_connection(topic, header)
                self._topic_connections[topic] = cid
            self._append(cid, ns, data)
            return
        if raw:
            if not isinstance(msg, tuple) or len(msg) not in (4, 5):
                raise DdesValueError("msg must be of length 4 or 5 when raw=True: "
                                     "(type, bytes, md5sum[, position], pytype)")
            datatype, data, md5sum = msg[0], msg[1], msg[2]
            pytype = msg[-1]
            if not isinstance(data, (bytes, bytearray, memoryview)):
                raise DdesTypeError(f"raw message data must be bytes, got {type(data).__name__}")
            data = bytes(data)
        else:
            if isinstance(msg, tuple) or not hasattr(type(msg), "_md5sum") \
                    or not hasattr(msg, "_serialize_to_bytes"):
                raise DdesTypeError(f"msg must be a ROS message, got {msg!r}")
            from ddes.msg.message import serialize_checked

            data = serialize_checked(msg)
            cls = type(msg)
        cid = self._topic_connections.get(topic)
        if cid is None:
            if connection_header is not None:
                header = dict(connection_header)
            elif raw:
                if pytype is None:
                    pytype = self._lookup_class(datatype)
                if pytype._md5sum != md5sum:
                    warnings.warn(f"md5sum of loaded type [{datatype}] does not match that "
                                  "specified", stacklevel=2)
                header = {"topic": topic, "type": datatype, "md5sum": md5sum,
                          "message_definition": pytype._full_text}
            else:
                header = {"topic": topic, "type": cls._type, "md5sum": cls._md5sum,
                          "message_definition": cls._full_text}
            cid = self._new_connection(topic, header)
            self._topic_connections[topic] = cid
        self._append(cid, ns, data)

    def _write_raw(self, topic: str, header: dict[str, str], data: bytes, t_ns: int) -> None:
        """roscpp's ``Bag::write`` with a connection header: one connection per distinct header."""
        self._check_writable()
        candidates = self._header_connections.setdefault((topic, header.get("callerid", "")), [])
        for known, found in candidates:
            if known == header:
                cid = found
                break
        else:
            cid = self._new_connection(topic, dict(sorted(header.items())))
            candidates.append((self._connections[cid].header, cid))
            self._topic_connections.setdefault(topic, cid)
        self._append(cid, t_ns, data)

    # -- reading ---------------------------------------------------------------------------------
    def _lookup_class(self, datatype: str) -> type[Message]:
        from ddes.msg import get_message_class

        try:
            return get_message_class(datatype, self._registry)
        except (MsgNotFound, InvalidMsgSpec) as exc:
            raise ROSBagException(f"cannot locate message class and no message class provided "
                                  f"for [{datatype}]: {exc}") from None

    def message_class(self, conn: ConnectionInfo) -> type[Message]:
        """The class of the messages of ``conn`` (the registry's, or rebuilt from the bag)."""
        cls = self._classes.get(conn.id)
        if cls is not None:
            return cls
        from ddes.msg import default_registry, get_message_class, message_class_from_definition

        registry = self._registry or default_registry()
        where = shown(f"{self._filename or 'bag'}: connection {conn.id} ({conn.topic})")
        if not conn.datatype.isprintable() or not conn.datatype.isascii():
            raise ROSBagFormatException(
                f"{where}: the message type {shown(conn.datatype)!r} in the connection header is "
                "not a ROS type name (bytes that are not printable ASCII); the bag is corrupt")
        if conn.msg_def:
            # bytes that are not UTF-8 (say Latin-1 comments of an old .msg) read as U+FFFD;
            # they cannot reach the md5, which ignores comments, and elsewhere the parser refuses
            definition = "".join("\ufffd" if "\ud800" <= c <= "\udfff" else c
                                 for c in conn.msg_def) if not conn.msg_def.isascii() \
                else conn.msg_def
            self._charge_rebuild(conn, definition, where)
            try:
                cls = message_class_from_definition(conn.datatype, definition, registry=registry)
            except DdesError as exc:
                raise ROSBagFormatException(f"{where}: cannot rebuild [{conn.datatype}] from its "
                                            f"message_definition: {shown(str(exc))}") from None
        else:
            try:
                cls = get_message_class(conn.datatype, registry)
            except (MsgNotFound, InvalidMsgSpec):
                raise ROSBagException(
                    f"Cannot deserialize messages of type [{conn.datatype}]: {where} has no "
                    "message_definition and the type is not on the package path") from None
        self._classes[conn.id] = cls
        return cls

    def _charge_rebuild(self, conn: ConnectionInfo, definition: str, where: str) -> None:
        """Refuse a definition whose classes would take the Bag past MAX_REBUILT_FIELDS."""
        from ddes.msg.registry import definition_facts

        key = (conn.datatype, definition)
        if key in self._rebuilt:
            return
        try:
            cost = definition_facts(conn.datatype, definition)[1]
        except DdesError as exc:
            raise ROSBagFormatException(f"{where}: cannot rebuild [{conn.datatype}] from its "
                                        f"message_definition: {shown(str(exc))}") from None
        total = self._rebuilt_total + cost
        if total > MAX_REBUILT_FIELDS:
            raise ResourceLimitError(shown(
                f"{where}: rebuilding [{conn.datatype}] from its message_definition takes "
                f"{cost} fields (nested types inlined), {total} with the classes this bag "
                f"rebuilt before, more than ddes.rosbag.bag.MAX_REBUILT_FIELDS "
                f"({MAX_REBUILT_FIELDS}): definitions whose types hold each other many times "
                "(a hostile or corrupt bag); raise the limit if the bag is genuine"))
        self._rebuilt[key] = cost
        self._rebuilt_total = total

    def _deserialize(self, conn: ConnectionInfo, t: int, data: bytes) -> Message:
        cls = self.message_class(conn)
        try:
            return cls.__new__(cls)._deserialize_from(data)
        except DdesError as exc:
            raise ROSBagFormatException(shown(
                f"{self._filename or 'bag'}: message at {to_sec(t):.9f} on {conn.topic} "
                f"(connection {conn.id}, {conn.datatype}) cannot be deserialized: {exc}"
            )) from None

    def _select(self, topics: Topics = None, connection_filter: ConnectionFilter | None = None,
                ) -> list[ConnectionInfo]:
        if topics and isinstance(topics, str):
            topics = [topics]
        wanted = {canonicalize_topic(t) for t in topics} if topics else None
        out = []
        for c in self._connections.values():
            if wanted is not None and c.topic not in wanted \
                    and canonicalize_topic(c.topic) not in wanted:
                continue
            if connection_filter is not None and not connection_filter(
                    c.topic, c.datatype, c.md5sum, c.msg_def, c.header):
                continue
            out.append(c)
        return out

    def _entries(self, conns: Iterable[ConnectionInfo], start: int | None = None,
                 end: int | None = None) -> Iterator[Entry]:
        for entry in heapq.merge(*(self._indexes[c.id] for c in conns), key=_time_key):
            if start is not None and entry[0] < start:
                continue
            if end is not None and entry[0] > end:
                return
            yield entry

    @overload
    def read_messages(self, topics: Topics = None, start_time: Time | None = None,
                      end_time: Time | None = None,
                      connection_filter: ConnectionFilter | None = None, raw: bool = False,
                      return_connection_header: Literal[False] = False) -> Iterator[BagMessage]:
        ...

    @overload
    def read_messages(self, topics: Topics = None, start_time: Time | None = None,
                      end_time: Time | None = None,
                      connection_filter: ConnectionFilter | None = None, raw: bool = False, *,
                      return_connection_header: Literal[True],
                      ) -> Iterator[BagMessageWithConnectionHeader]:
        ...

    def read_messages(self, topics: Topics = None, start_time: Time | None = None,
                      end_time: Time | None = None,
                      connection_filter: ConnectionFilter | None = None, raw: bool = False,
                      return_connection_header: bool = False,
                      ) -> Iterator[BagMessage] | Iterator[BagMessageWithConnectionHeader]:
        """Messages in time order as ``BagMessage(topic, message, timestamp)``.

        ``topics`` is a topic or a list; ``start_time``/``end_time`` are
        inclusive Time bounds (a zero Time is no bound); ``connection_filter``
        is ``f(topic, datatype, md5sum, msg_def, header) -> bool``.  With
        ``raw=True`` the message is ``(datatype, bytes, md5sum, None, pytype)``.
        """
        self._check_open()
        conns = self._select(topics, connection_filter)
        start, end = _bound(start_time, "start_time"), _bound(end_time, "end_time")
        messages = self._read(conns, start, end, raw, return_connection_header)
        return cast("Iterator[BagMessage] | Iterator[BagMessageWithConnectionHeader]", messages)

    def _read(self, conns: list[ConnectionInfo], start: int | None, end: int | None, raw: bool,
              with_header: bool) -> Iterator[BagMessage | BagMessageWithConnectionHeader]:
        by_id = {c.id: c for c in conns}
        # one connection with no bounds is its index as it is (no merge, no bound checks)
        entries: Iterable[Entry] = (
            self._indexes[conns[0].id] if len(conns) == 1 and start is None and end is None
            else self._entries(conns, start, end))
        pytypes: dict[int, type[Message] | None] = {}  # raw: each connection's class, once
        for t, cid, data in entries:
            conn = by_id[cid]
            if raw:
                if cid in pytypes:
                    pytype = pytypes[cid]
                else:
                    try:
                        pytype = self.message_class(conn)
                    except ROSBagException:
                        pytype = None
                    pytypes[cid] = pytype
                msg: Message | RawMessage = (conn.datatype, data, conn.md5sum, None, pytype)
            else:
                msg = self._deserialize(conn, t, data)
            stamp = _new_time(Time)  # Time._from_ns(t), written out: a bag's times are >= 0
            stamp.secs, stamp.nsecs = divmod(t, _NS)
            if with_header:
                yield BagMessageWithConnectionHeader(conn.topic, msg, stamp, conn.header)
            else:
                yield _bag_message((conn.topic, msg, stamp))

    def __iter__(self) -> Iterator[BagMessage]:
        return self.read_messages()

    def get_connections(self, topics: Topics = None,
                        connection_filter: ConnectionFilter | None = None) -> list[ConnectionInfo]:
        """The connections (on ``topics``, passing ``connection_filter``), in bag order."""
        self._check_open()
        return self._select(topics, connection_filter)

    def get_message_count(self, topic_filters: str | list[str] | None = None) -> int:
        """Number of messages, optionally only on the given topic(s)."""
        self._check_open()
        if topic_filters is not None:
            return sum(t.message_count for t in self.get_type_and_topic_info(topic_filters)
                       .topics.values())
        return sum(len(ix) for ix in self._indexes.values())

    def _span(self) -> tuple[int, int]:
        if self._loaded is not None and self._loaded.chunks:
            return self._loaded.chunks[0].start, self._loaded.chunks[-1].end
        heads = [ix for ix in self._indexes.values() if ix]
        if not heads:
            raise ROSBagException("Bag contains no message")
        return min(ix[0][0] for ix in heads), max(ix[-1][0] for ix in heads)

    def get_start_time(self) -> float:
        """Time of the earliest message, float seconds (ROSBagException on an empty bag)."""
        self._check_open()
        return to_sec(self._span()[0])

    def get_end_time(self) -> float:
        """Time of the latest message, float seconds (ROSBagException on an empty bag)."""
        self._check_open()
        return to_sec(self._span()[1])

    def _summary(self) -> BagSummary:
        stats = self._loaded
        if stats is None or self._mcap_loaded:
            stats = self._encoding()[1]
        size = self._loaded.size if self._loaded is not None else stats.size
        return BagSummary(self._filename, size, stats.chunks, list(self._connections.values()),
                          self._indexes)

    def get_type_and_topic_info(self, topic_filters: str | list[str] | None = None,
                                ) -> TypesAndTopicsTuple:
        """Types with their md5 and, per topic, type, count, connections and frequency."""
        self._check_open()
        summary = BagSummary(self._filename, 0, [], list(self._connections.values()),
                             self._indexes)
        types = {t: md5 for t, md5, _ in summary.types()}
        if topic_filters is not None and not isinstance(topic_filters, list):
            topic_filters = [topic_filters]
        rows: list[TopicRow] = topic_rows(summary, not self._skip_index, topic_filters)
        return TypesAndTopicsTuple(types, {r.topic: TopicTuple(r.datatype, r.count, r.connections,
                                                                r.frequency) for r in rows})

    def get_compression_info(self) -> CompressionTuple:
        """The main compression and total uncompressed/compressed chunk bytes."""
        self._check_open()
        chunks = self._summary().chunks
        if not chunks:
            return CompressionTuple(self._compression, 0, 0)
        counts: dict[str, int] = {}
        for c in chunks:
            counts[c.compression] = counts.get(c.compression, 0) + 1
        main = max((v, k) for k, v in counts.items())[1]
        return CompressionTuple(main, sum(c.uncompressed_size for c in chunks),
                                sum(c.compressed_size for c in chunks))

    def info(self, freq: bool | None = None, tz: datetime.tzinfo | None = None) -> str:
        """The text ``rosbag info`` prints (``freq`` adds frequencies; ``tz`` a time zone)."""
        self._check_open()
        return info_text(self._summary(), freq=not self._skip_index if freq is None else freq,
                         tz=tz)

    def yaml_info(self, key: str | None = None, freq: bool = False) -> str:
        """The text ``rosbag info -y [-k KEY]`` prints (DdesKeyError for an unknown key)."""
        self._check_open()
        return info_yaml(self._summary(), freq=freq, key=key)

    def __str__(self) -> str:
        return self.info()

    def reindex(self) -> Iterator[int]:
        """Offsets of the chunks of the (rebuilt) index; recovery happens on opening with
        ``allow_unindexed=True``, so there is nothing left to do but report them."""
        self._check_open()
        return iter([c.pos for c in self._summary().chunks])

    def __repr__(self) -> str:
        where = self._filename or "memory"
        state = "closed" if self._closed else self._mode
        return (f"<Bag {where} ({state}) {len(self._connections)} connections "
                f"{sum(len(ix) for ix in self._indexes.values())} messages>")

    def _repr_html_(self) -> str:
        """What ``rosbag info`` shows, as HTML tables for notebooks (every name escaped).

        Path, version, duration, start and end (local time and seconds), size,
        messages and compression, then one row per type (md5) and per topic
        (messages, frequency, type, connections).  A closed bag shows its repr.
        """
        from ddes.display.tables import html_table, html_text, key_value_table
        from ddes.rosbag.info import (
            _compression_rows,
            _duration_str,
            human_readable_frequency,
            human_readable_size,
            time_to_str,
        )

        if self._closed:
            return f"<p><code>{html_text(repr(self))}</code></p>"
        summary = self._summary()
        rows: list[tuple[str, object]] = [("path", shown(summary.path or "(in memory)")),
                                          ("version", "2.0")]
        span = summary.span()
        if span is not None:
            start, end = span
            rows += [("duration", _duration_str(end - start)),
                     ("start", f"{time_to_str(start)} ({start:.2f})"),
                     ("end", f"{time_to_str(end)} ({end:.2f})")]
        rows += [("size", human_readable_size(summary.size)),
                 ("messages", summary.message_count())]
        if span is not None:
            rows += _compression_rows(summary.chunks, span[1] - span[0])
        out = [key_value_table(rows, caption="bag")]
        if span is not None:
            out.append(html_table(
                ("type", "md5sum"), ((shown(t), shown(md5)) for t, md5, _ in summary.types()),
                caption="types", mono=(0, 1), limit=10_000))
            topics = topic_rows(summary, not self._skip_index)
            out.append(html_table(
                ("topic", "messages", "frequency", "type", "connections"),
                ((shown(r.topic), r.count,
                  "" if r.frequency is None else human_readable_frequency(r.frequency),
                  shown(r.datatype), r.connections) for r in topics),
                caption="topics", mono=(0, 3), limit=10_000))
        return "".join(out)


# Bag._read: Time._from_ns and BagMessage(...) without their Python-level calls
_new_time = Time.__new__
_bag_message = functools.partial(tuple.__new__, BagMessage)
