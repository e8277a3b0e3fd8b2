"""rosbag's Python API for plain scripts: ``import rosbag`` in a rospy script.

``rosbag.Bag(f, mode='r', compression=Compression.NONE, chunk_threshold=768 * 1024,
allow_unindexed=False, options=None, skip_index=False)`` with rosbag's signature, argument
checks, exception types and texts, over :class:`ddes.rosbag.Bag` (the same .bag v2.0 reader and
writer: a file written here is byte for byte what ``ddes.rosbag`` writes, and real rosbag reads
it).  What differs from :class:`ddes.rosbag.Bag`:

* ``write(topic, msg)`` without ``t`` stamps the message with the ROS time of the running
  script's node (``rospy.get_rostime()``); outside a node it raises rospy's ``time is not
  initialized`` error (real rosbag reads the wall clock, which ddes has none of);
* rosbag's errors: ``mode "x" is invalid``, ``filename (or stream) is invalid``, a missing file
  is a ``FileNotFoundError`` (:class:`ddes.errors.BagNotFoundError`), a file still being
  written (``x.bag`` while only ``x.bag.active`` exists) is ``ROSBagUnindexedException('Unindexed
  bag')``, a write to a bag opened for reading is an ``io.UnsupportedOperation``
  (:class:`ddes.errors.BagReadOnlyError`), options that are not a dict, a negative
  chunk_threshold and an unknown compression give rosbag's ``ValueError`` texts;
* a closed bag still answers ``get_message_count``, ``get_start_time``, ``get_end_time``,
  ``get_type_and_topic_info`` and ``get_compression_info`` from its index, as rosbag's does;
* a bag open for writing (``'w'``) reports no frequencies in ``get_type_and_topic_info``
  (rosbag computes them only from an index it has read);
* a file read indexes each connection chunk by chunk, as rosbag does (a message written out of
  time order into a later chunk is read there, not where its stamp sorts);
* appending (``'a'``) starts a new connection for each topic written (rosbag's 2.0 reader keeps
  no topic table).  Deviation: ddes rewrites the whole file on close, in chunks of the
  appending bag's compression and threshold; rosbag keeps the old chunks and adds new ones.

The exceptions are ddes's (:mod:`ddes.errors`), under rosbag's names. See docs/rospy.md.
"""

from __future__ import annotations

import errno
import os
import sys
from collections.abc import Iterator
from contextlib import contextmanager
from operator import itemgetter
from typing import IO, Any

from ddes.errors import (
    BagNotFoundError,
    BagReadOnlyError,
    DdesValueError,
    ROSBagEncryptNotSupportedException,
    ROSBagException,
    ROSBagFormatException,
    ROSBagUnindexedException,
)
from ddes.rosbag.bag import Bag as _Bag
from ddes.rosbag.bag import (
    BagMessage,
    BagMessageWithConnectionHeader,
    Compression,
    CompressionTuple,
    TopicTuple,
    TypesAndTopicsTuple,
)
from ddes.rosbag.bagfile import Entry
from ddes.time.rostime import Time

__all__ = [
    "Bag", "BagMessage", "BagMessageWithConnectionHeader", "Compression", "CompressionTuple",
    "ROSBagEncryptNotSupportedException", "ROSBagException", "ROSBagFormatException",
    "ROSBagUnindexedException", "TopicTuple", "TypesAndTopicsTuple",
]

#: ``from rosbag.bag import Bag``: the submodule is this module.
bag = sys.modules[__name__]

_COMPRESSIONS = (Compression.NONE, Compression.BZ2, Compression.LZ4)


def _script_time() -> Time:
    """``write(t=None)``: the ROS time of the running script's node (rospy's rule)."""
    from ddes.compat import rospy

    return rospy.get_rostime()


class Bag(_Bag):
    """rosbag.Bag: a .bag v2.0 file to read (``'r'``), write (``'w'``) or append to (``'a'``)."""

    def __init__(self, f: str | os.PathLike[str] | IO[bytes], mode: str = "r",
                 compression: str = Compression.NONE, chunk_threshold: int = 768 * 1024,
                 allow_unindexed: bool = False, options: dict[str, Any] | None = None,
                 skip_index: bool = False) -> None:
        if options is not None:  # rosbag's checks, in rosbag's order and with its texts
            if type(options) is not dict:
                raise DdesValueError("options must be of type dict")
            compression = options.get("compression", compression)
            chunk_threshold = options.get("chunk_threshold", chunk_threshold)
        if compression not in _COMPRESSIONS:
            raise DdesValueError("compression must be one of: " + ", ".join(_COMPRESSIONS))
        if chunk_threshold < 0:
            raise DdesValueError("chunk_threshold must be greater than or equal to zero")
        if not f:
            raise DdesValueError("filename (or stream) is invalid")
        if mode not in ("r", "w", "a"):
            raise DdesValueError(f'mode "{mode}" is invalid')
        source: str | os.PathLike[str] | IO[bytes] = f
        name: str | None = None
        if mode == "r" and isinstance(f, (str, os.PathLike)) and not os.path.exists(f):
            active = os.fspath(f) + ".active"
            if not os.path.exists(active):
                raise BagNotFoundError(errno.ENOENT, os.strerror(errno.ENOENT), f)
            # the file of a bag still being written (ddes writes NAME.active, then renames it;
            # rosbag's file has no index until it is closed)
            if not allow_unindexed:
                raise ROSBagUnindexedException("Unindexed bag")
            source, name = active, os.fspath(f)
        super().__init__(source, mode, compression, chunk_threshold, allow_unindexed, None,
                         skip_index, clock=_script_time, filename=name)
        if mode == "r":
            self._chunk_order()
        elif mode == "a":
            # rosbag's 2.0 reader does not fill its topic table: the first write on a topic
            # after opening for appending starts a new connection
            self._topic_connections.clear()

    def _chunk_order(self) -> None:
        """Index each connection as rosbag does: its chunks' index records one after the
        other (each sorted by time), not sorted over the whole bag. The two differ only for a
        message written out of time order into a later chunk; rosbag then reads it later."""
        stats = self._loaded
        if stats is None or self._mcap_loaded or not stats.chunks:
            return
        indexes: dict[int, list[Entry]] = {cid: [] for cid in self._indexes}
        pos = 0
        for chunk in stats.chunks:
            n = sum(chunk.counts.values())
            part = self._log[pos:pos + n]
            pos += n
            for cid in chunk.counts:
                if cid in indexes:
                    indexes[cid].extend(sorted((e for e in part if e[1] == cid),
                                               key=itemgetter(0)))
        if pos == len(self._log) and all(len(indexes[c]) == len(ix)
                                         for c, ix in self._indexes.items()):
            self._indexes = indexes

    # -- rosbag's behaviour where it differs from ddes.rosbag.Bag ------------------------------
    def write(self, topic: str, msg: Any, t: Time | None = None, raw: bool = False,
              connection_header: dict[str, str] | None = None) -> None:
        """rosbag.Bag.write: ``msg`` on ``topic`` at ``t`` (default: the node's ROS time)."""
        if not self._closed and self._mode == "r":
            raise BagReadOnlyError(
                "write: the bag is open for reading (rosbag: io.UnsupportedOperation); open it "
                "with mode 'a' to add messages")
        if not self._closed:
            if not topic:
                raise DdesValueError("topic is invalid")
            if not msg:
                raise DdesValueError("msg is invalid")
        super().write(topic, msg, t, raw, connection_header)

    @contextmanager
    def _index(self) -> Iterator[None]:
        """Answer from the index even when closed (rosbag keeps its index after close)."""
        closed = self._closed
        self._closed = False
        try:
            yield
        finally:
            self._closed = closed

    def get_message_count(self, topic_filters: str | list[str] | None = None) -> int:
        with self._index():
            return super().get_message_count(topic_filters)

    def get_start_time(self) -> float:
        with self._index():
            return super().get_start_time()

    def get_end_time(self) -> float:
        with self._index():
            return super().get_end_time()

    def get_type_and_topic_info(self, topic_filters: str | list[str] | None = None,
                                ) -> TypesAndTopicsTuple:
        with self._index():
            info = super().get_type_and_topic_info(topic_filters)
        if self._mode != "w":
            return info
        return TypesAndTopicsTuple(info.msg_types, {
            topic: row._replace(frequency=None) for topic, row in info.topics.items()})

    def get_compression_info(self) -> CompressionTuple:
        with self._index():
            return super().get_compression_info()

    def __str__(self) -> str:
        self._check_open()
        return super().__str__()
