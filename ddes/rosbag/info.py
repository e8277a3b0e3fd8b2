# ruff: noqa: UP031 - printf formats with '*' widths reproduce rosbag's text exactly
"""The text of ``rosbag info`` (``Bag.__str__``), its YAML form (``-y``) and keys (``-k``).

Every row, width, number format and quirk follows rosbag's ``bag.py``
(``__str__``, ``_get_yaml_info``, ``_human_readable_size``,
``_human_readable_frequency``, ``_time_to_str``, ``_median``): keys padded
to the longest key plus a colon, the duration as ``%.1fs`` / ``m:ss`` /
``h m:ss``, start and end in the local time zone as ``%b %d %Y
%H:%M:%S.ff (secs.ff)``, sizes in 1024-based units starting at KB, types
sorted with their md5, topics sorted with counts, optional median-period
frequencies and connection counts.

Start and end come from the chunk infos (first chunk's start, last chunk's
end) when the bag has chunks, else from the message indexes, as in rosbag.
``tz`` (a :class:`datetime.tzinfo`) formats dates in that zone instead of
the local one; the local zone is read from the process (``TZ``), never the
wall clock.
"""

from __future__ import annotations

import dataclasses
import datetime
import heapq
import json
import re
import time
from collections.abc import Sequence
from dataclasses import dataclass
from operator import itemgetter

import yaml

from ddes.errors import DdesKeyError, ROSBagFormatException
from ddes.rosbag.bagfile import ChunkStat, Entry
from ddes.rosbag.records import ConnectionInfo

__all__ = [
    "BagSummary",
    "TopicRow",
    "human_readable_frequency",
    "human_readable_size",
    "info_text",
    "info_yaml",
    "median",
    "time_to_str",
    "to_sec",
    "topic_rows",
]

_NS = 1_000_000_000
_time_key = itemgetter(0)


def to_sec(ns: int) -> float:
    """Float seconds as genpy's ``Time.to_sec`` computes them (secs + nsecs/1e9).

    Not :func:`ddes.time.units.ns_to_sec` (``ns / 1e9``): the two differ in the last bit for
    about a quarter of epoch-sized stamps, and ``get_start_time``, the frequencies and the
    ``rosbag info`` text follow rosbag, which reads genpy Times.
    """
    secs, nsecs = divmod(ns, _NS)
    return float(secs) + float(nsecs) / 1e9


def human_readable_size(size: float) -> str:
    """rosbag's size text: divided by 1024 at least once (``500`` → ``0.5 KB``)."""
    for suffix in ("KB", "MB", "GB", "TB", "PB", "EB", "ZB", "YB"):
        size /= 1024.0
        if size < 1024.0:
            return f"{size:.1f} {suffix}"
    return "-"


def human_readable_frequency(freq: float) -> str:
    """rosbag's frequency text (``10.0 Hz``, ``1.2 kHz`` ...)."""
    for suffix in ("Hz", "kHz", "MHz", "GHz", "THz", "PHz", "EHz", "ZHz", "YHz"):
        if freq < 1000.0:
            return f"{freq:.1f} {suffix}"
        freq /= 1000.0
    return "-"


def median(values: Sequence[float]) -> float:
    """The median as rosbag computes it (mean of the middle two for an even count)."""
    n = len(values)
    if n == 0:
        return float("nan")
    ordered = sorted(values)
    if n % 2 == 1:
        return ordered[n // 2]
    return float(ordered[n // 2 - 1] + ordered[n // 2]) / 2


def time_to_str(secs: float, tz: datetime.tzinfo | None = None) -> str:
    """``Mon DD YYYY HH:MM:SS.ff`` of float seconds since the epoch, in ``tz`` (default local)."""
    frac = f"{secs - int(secs):.2f}"[1:]
    if tz is None:
        return time.strftime("%b %d %Y %H:%M:%S", time.localtime(secs)) + frac
    moment = datetime.datetime.fromtimestamp(int(secs), tz)
    return moment.strftime("%b %d %Y %H:%M:%S") + frac


def _duration_str(duration: float) -> str:
    dur_secs = duration % 60
    dur_mins = int(duration / 60)
    dur_hrs = int(dur_mins / 60)
    if dur_hrs > 0:
        return "%dhr %d:%02ds (%ds)" % (dur_hrs, dur_mins % 60, dur_secs, duration)
    if dur_mins > 0:
        return "%d:%02ds (%ds)" % (dur_mins, dur_secs, duration)
    return f"{duration:.1f}s"


@dataclass
class BagSummary:
    """What ``rosbag info`` reads of a bag: its file stats, connections and indexes."""

    path: str | None
    size: int
    chunks: list[ChunkStat]
    connections: list[ConnectionInfo]
    indexes: dict[int, list[Entry]]

    def span(self) -> tuple[float, float] | None:
        """(start, end) float seconds, or None for a bag without messages."""
        if self.chunks:
            return to_sec(self.chunks[0].start), to_sec(self.chunks[-1].end)
        heads = [ix for ix in self.indexes.values() if ix]
        if not heads:
            return None
        return to_sec(min(ix[0][0] for ix in heads)), to_sec(max(ix[-1][0] for ix in heads))

    def message_count(self) -> int:
        if self.chunks:
            return sum(sum(c.counts.values()) for c in self.chunks)
        return sum(len(ix) for ix in self.indexes.values())

    def count_of(self, conn: ConnectionInfo) -> int:
        if self.chunks:
            return sum(c.counts.get(conn.id, 0) for c in self.chunks)
        return len(self.indexes.get(conn.id, ()))

    def types(self) -> list[tuple[str, str, str]]:
        """(datatype, md5sum, msg_def) of the first connection of each type, sorted."""
        seen: dict[str, tuple[str, str, str]] = {}
        for c in self.connections:
            seen.setdefault(c.datatype, (c.datatype, c.md5sum, c.msg_def))
        return sorted(seen.values())


@dataclass
class TopicRow:
    """One topic of the summary."""

    topic: str
    datatype: str
    count: int
    connections: int
    frequency: float | None


def topic_frequency(indexes: dict[int, list[Entry]], conns: list[ConnectionInfo]) -> float | None:
    """1 / median period of the topic's merged stamps, or None (rosbag's rule)."""
    stamps = [to_sec(e[0]) for e in heapq.merge(*(indexes.get(c.id, []) for c in conns),
                                                key=_time_key)]
    if len(stamps) <= 1:
        return None
    med = median([b - a for a, b in zip(stamps[:-1], stamps[1:])])
    return 1.0 / med if med > 0.0 else None


def topic_rows(summary: BagSummary, freq: bool, topics: Sequence[str] | None = None) -> list[TopicRow]:
    """Rows of the topics (all, or the given ones that exist), sorted by name."""
    from ddes.rosbag.records import canonicalize_topic

    names = sorted(set(topics if topics is not None else (c.topic for c in summary.connections)))
    rows = []
    for name in names:
        canon = canonicalize_topic(name)
        conns = [c for c in summary.connections
                 if c.topic == name or canonicalize_topic(c.topic) == canon]
        if not conns:
            continue
        rows.append(TopicRow(name, conns[0].datatype, sum(summary.count_of(c) for c in conns),
                             len(conns), topic_frequency(summary.indexes, conns) if freq else None))
    return rows


def _compression_rows(chunks: list[ChunkStat], duration: float) -> list[tuple[str, str]]:
    if not chunks:
        return [("compression", "none")]
    counts: dict[str, int] = {}
    raw: dict[str, int] = {}
    packed: dict[str, int] = {}
    for c in chunks:
        counts[c.compression] = counts.get(c.compression, 0) + 1
        raw[c.compression] = raw.get(c.compression, 0) + c.uncompressed_size
        packed[c.compression] = packed.get(c.compression, 0) + c.compressed_size
    parts = []
    for count, kind in sorted(((v, k) for k, v in counts.items()), reverse=True):
        if kind != "none":
            parts.append("%s [%d/%d chunks; %.2f%%]" % (kind, count, len(chunks),
                                                         100.0 * packed[kind] / raw[kind]))
        else:
            parts.append("%s [%d/%d chunks]" % (kind, count, len(chunks)))
    rows = [("compression", ", ".join(parts))]
    if any(k != "none" for k in counts):
        total_raw = sum(c.uncompressed_size for c in chunks)
        total_packed = sum(c.compressed_size for c in chunks)
        raw_s, packed_s = human_readable_size(total_raw), human_readable_size(total_packed)
        width = max(len(raw_s), len(packed_s))
        if duration > 0:
            raw_rate = human_readable_size(total_raw / duration)
            packed_rate = human_readable_size(total_packed / duration)
            rate_w = max(len(raw_rate), len(packed_rate))
            rows.append(("uncompressed", "%*s @ %*s/s" % (width, raw_s, rate_w, raw_rate)))
            rows.append(("compressed", "%*s @ %*s/s (%.2f%%)" % (
                width, packed_s, rate_w, packed_rate, 100.0 * total_packed / total_raw)))
        else:
            rows.append(("uncompressed", "%*s" % (width, raw_s)))
            rows.append(("compressed", "%*s" % (width, packed_s)))
    return rows


def shown(text: str) -> str:
    """``text`` safe to print: undecodable bytes as ``\\xNN``, control characters escaped.

    Header bytes that are not UTF-8 are kept as surrogates (``surrogateescape``)
    so they round-trip; printing them raw would raise UnicodeEncodeError, and a
    control character in a hostile topic name could drive the terminal.
    """
    if text.isprintable():
        return text
    out = []
    for c in text:
        if c.isprintable():
            out.append(c)
        elif "\udc80" <= c <= "\udcff":
            out.append(f"\\x{ord(c) - 0xDC00:02x}")
        else:
            out.append(c.encode("unicode_escape").decode("ascii"))
    return "".join(out)


_PLAIN = re.compile(r"[A-Za-z0-9_/.~+][A-Za-z0-9_/.~+@ -]*")


def _yaml_str(text: str) -> str:
    """``text`` as rosbag writes it when plain, else a double-quoted YAML scalar."""
    text = shown(text)
    if _PLAIN.fullmatch(text) and not text.endswith(" "):
        return text
    return json.dumps(text)  # a JSON string is a double-quoted YAML scalar


def info_text(summary: BagSummary, *, freq: bool = False, tz: datetime.tzinfo | None = None) -> str:
    """What ``rosbag info [--freq] BAG`` prints for the bag (``str(bag)``).

    Names are passed through :func:`shown` (a deviation only for names with
    bytes that are not printable UTF-8, where rosbag fails or prints them raw).
    """
    rows: list[tuple[str, str]] = []
    if summary.path:
        rows.append(("path", shown(summary.path)))
    rows.append(("version", "2.0"))
    span = summary.span()
    if span is None:
        rows.append(("size", human_readable_size(summary.size)))
    else:
        start, end = span
        duration = end - start
        rows.append(("duration", _duration_str(duration)))
        rows.append(("start", "%s (%.2f)" % (time_to_str(start, tz), start)))
        rows.append(("end", "%s (%.2f)" % (time_to_str(end, tz), end)))
        rows.append(("size", human_readable_size(summary.size)))
        rows.append(("messages", str(summary.message_count())))
        rows.extend(_compression_rows(summary.chunks, duration))
        types = [(shown(t), shown(md5), d) for t, md5, d in summary.types()]
        topics = [dataclasses.replace(r, topic=shown(r.topic), datatype=shown(r.datatype))
                  for r in topic_rows(summary, freq)]
        type_w = max(len(t[0]) for t in types)
        topic_w = max(len(r.topic) for r in topics)
        count_w = max(len(str(r.count)) for r in topics)
        freqs = [human_readable_frequency(r.frequency) for r in topics if r.frequency is not None]
        freq_w = max((len(f) for f in freqs), default=0)
        for i, (datatype, md5, _def) in enumerate(types):
            rows.append(("types" if i == 0 else "", "%-*s [%s]" % (type_w, datatype, md5)))
        for i, r in enumerate(topics):
            s = "%-*s   %*d %s" % (topic_w, r.topic, count_w, r.count,
                                   "msgs" if r.count > 1 else "msg ")
            if r.frequency is not None:
                s += " @ %*s" % (freq_w, human_readable_frequency(r.frequency))
            else:
                s += "   %*s" % (freq_w, "")
            s += " : %-*s" % (type_w, r.datatype)
            if r.connections > 1:
                s += " (%d connections)" % r.connections
            rows.append(("topics" if i == 0 else "", s))
    width = max(len(k) for k, _ in rows) + 1
    return "".join("%-*s %s\n" % (width, k + ":" if k else "", v) for k, v in rows).rstrip()


def _yaml_text(summary: BagSummary, freq: bool) -> str:
    lines = []
    if summary.path:
        lines.append(f"path: {_yaml_str(summary.path)}")
    lines.append("version: 2.0")
    span = summary.span()
    if span is None:
        lines += [f"size: {summary.size}", "indexed: False"]
        return "".join(x + "\n" for x in lines)
    start, end = span
    lines += [f"duration: {end - start:.6f}", f"start: {start:.6f}", f"end: {end:.6f}",
              f"size: {summary.size}", f"messages: {summary.message_count()}", "indexed: True"]
    chunks = summary.chunks
    if not chunks:
        lines.append("compression: none")
    else:
        counts: dict[str, int] = {}
        for c in chunks:
            counts[c.compression] = counts.get(c.compression, 0) + 1
        lines.append(f"compression: {max((v, k) for k, v in counts.items())[1]}")
        if any(k != "none" for k in counts):
            lines.append(f"uncompressed: {sum(c.uncompressed_size for c in chunks)}")
            lines.append(f"compressed: {sum(c.compressed_size for c in chunks)}")
    lines.append("types:")
    for datatype, md5, _def in summary.types():
        lines += [f"    - type: {_yaml_str(datatype)}", f"      md5: {_yaml_str(md5)}"]
    lines.append("topics:")
    for r in topic_rows(summary, freq):
        lines += [f"    - topic: {_yaml_str(r.topic)}", f"      type: {_yaml_str(r.datatype)}",
                  f"      messages: {r.count}"]
        if r.connections > 1:
            lines.append(f"      connections: {r.connections}")
        if r.frequency is not None:
            lines.append(f"      frequency: {r.frequency:.4f}")
    return "".join(x + "\n" for x in lines)


def _lookup(data: object, key: str) -> object:
    """Follow ``a.b[0].c`` through parsed YAML (rosbag evaluates ``obj.<key>``)."""
    value = data
    for part in key.split("."):
        name, _, rest = part.partition("[")
        if not name.isidentifier() or not isinstance(value, dict) or name not in value:
            raise KeyError(key)
        value = value[name]
        while rest:
            index, sep, rest = rest.partition("]")
            if not sep or not index.strip().lstrip("-").isdigit() or not isinstance(value, list):
                raise KeyError(key)
            value = value[int(index)]
            if rest.startswith("["):
                rest = rest[1:]
            elif rest:
                raise KeyError(key)
    return value


def _print_yaml(value: object, indent: int = 0) -> str:
    pad = "  " * indent
    if isinstance(value, list):
        return "".join(f"{pad}- {_print_yaml(item, indent + 1)}\n" for item in value)
    if isinstance(value, dict):
        items = list(value.items())
        out = ""
        for i, (k, v) in enumerate(items):
            if i:
                out += pad
            out += f"{k}: {v}"
            if i < len(items) - 1:
                out += "\n"
        return out
    return pad + str(value)


def info_yaml(summary: BagSummary, *, freq: bool = False, key: str | None = None) -> str:
    """What ``rosbag info -y [-k KEY] BAG`` prints (before print's newline).

    An unknown ``key`` raises :class:`~ddes.errors.DdesKeyError` with the text
    ``Error getting key "KEY"`` that rosbag prints.  Keys are attribute paths
    with list indexes (``topics[0].type``); rosbag ``eval``s them, ddes
    does not evaluate code.
    """
    text = _yaml_text(summary, freq)
    if not key:
        return text
    try:
        data = yaml.safe_load(text)
    except yaml.YAMLError as exc:  # ddes quotes every odd name, so this is a ddes bug
        raise ROSBagFormatException(f"the YAML info of the bag does not parse, so key {key!r} "
                                    f"cannot be looked up: {exc}") from None
    try:
        value = _lookup(data, key)
    except (KeyError, IndexError):
        raise DdesKeyError(f'Error getting key "{key}"') from None
    return _print_yaml(value)
