"""The trace: structured events of one world, and their digest.

Every observable thing a world does (a timer fire, a delivery, a drop, a
service call, a goal transition, a log line) is appended as a
:class:`TraceEvent` ``(t, kind, source, details)``.  ``t`` is the kernel time
in integer nanoseconds; ``kind`` is a dotted name such as ``"timer.fire"``;
``source`` names the entity (usually a node or topic); ``details`` is a dict
of JSON-able values.

:meth:`Trace.digest` is a sha256 over a canonical JSON-lines form (sorted
keys, no whitespace, Time/Duration as integer nanoseconds, messages as
dicts), so two runs are identical iff their digests are.
"""

from __future__ import annotations

import hashlib
import json
from collections import Counter
from collections.abc import Callable, Iterable, Iterator
from typing import Any, NamedTuple

__all__ = ["Trace", "TraceEvent", "canonical"]


class TraceEvent(NamedTuple):
    """One recorded event."""

    t: int
    kind: str
    source: str
    details: dict[str, Any]

    def to_json(self) -> str:
        """The canonical JSON line of this event (used by the digest)."""
        return json.dumps(
            [self.t, self.kind, self.source, self.details],
            sort_keys=True,
            separators=(",", ":"),
            default=canonical,
            ensure_ascii=False,
        )


def canonical(value: Any) -> Any:
    """JSON fallback for values that json does not know.

    Time/Duration become integer nanoseconds, messages become dicts of their
    slots, bytes become lists of ints, sets become sorted lists.
    """
    to_nsec = getattr(value, "to_nsec", None)
    if to_nsec is not None:
        return to_nsec()
    slots = getattr(value, "__slots__", None)
    if slots is not None and hasattr(value, "_type"):
        return {"_type": value._type, **{s: getattr(value, s) for s in slots}}
    if isinstance(value, (bytes, bytearray)):
        return list(value)
    if isinstance(value, (set, frozenset)):
        return sorted(value, key=repr)
    if isinstance(value, tuple):
        return list(value)
    tolist = getattr(value, "tolist", None)  # numpy arrays and scalars
    if tolist is not None:
        return tolist()
    return repr(value)


def _event(raw: tuple[Any, ...]) -> TraceEvent:
    if len(raw) == 4:
        return TraceEvent(*raw)
    return TraceEvent(raw[0], raw[1], raw[2], dict(zip(raw[3], raw[4:])))


class Trace:
    """An append-only list of :class:`TraceEvent` with counters and a digest."""

    __slots__ = ("_raw", "_counts", "enabled", "_listeners")

    def __init__(self) -> None:
        # Plain tuples on the hot path; wrapped in TraceEvent when read.
        self._raw: list[tuple[Any, ...]] = []
        self._counts: dict[str, int] = {}
        #: When False, events are counted but not stored (long benchmarks).
        self.enabled = True
        self._listeners: list[Callable[[TraceEvent], None]] = []

    def record(self, t: int, kind: str, source: str, details: dict[str, Any] | None = None) -> None:
        """Append one event (stored, or only counted while :attr:`enabled` is False)."""
        if self.enabled:
            raw = (t, kind, source, details if details is not None else {})
            self._raw.append(raw)
            if self._listeners:
                ev = TraceEvent(*raw)
                for listener in self._listeners:
                    listener(ev)
        else:
            self._counts[kind] = self._counts.get(kind, 0) + 1

    def record_fast(self, row: tuple[Any, ...]) -> None:
        """Hot-path form: ``(t, kind, source, keys, *values)``, keys a tuple of names.

        Stored as given; the details dict is built only when the event is read.
        """
        if self.enabled:
            self._raw.append(row)
            if self._listeners:
                ev = _event(row)
                for listener in self._listeners:
                    listener(ev)
        else:
            kind = row[1]
            self._counts[kind] = self._counts.get(kind, 0) + 1

    @property
    def counts(self) -> Counter[str]:
        """How many events of each kind were recorded (stored or only counted)."""
        out: Counter[str] = Counter(raw[1] for raw in self._raw)
        out.update(self._counts)
        return out

    def subscribe(self, listener: Callable[[TraceEvent], None]) -> None:
        """Call ``listener(event)`` for every event recorded from now on."""
        self._listeners.append(listener)

    def unsubscribe(self, listener: Callable[[TraceEvent], None]) -> None:
        """Stop calling a listener added with :meth:`subscribe`."""
        self._listeners.remove(listener)

    def __len__(self) -> int:
        return len(self._raw)

    def __iter__(self) -> Iterator[TraceEvent]:
        return (_event(raw) for raw in self._raw)

    def __getitem__(self, index: int) -> TraceEvent:
        return _event(self._raw[index])

    @property
    def events(self) -> list[TraceEvent]:
        """All stored events, in the order they happened."""
        return [_event(raw) for raw in self._raw]

    def filter(
        self,
        kind: str | None = None,
        source: str | None = None,
        prefix: str | None = None,
    ) -> list[TraceEvent]:
        """Events of a kind (exact), a kind prefix (``"topic."``) and/or a source."""
        out: Iterable[TraceEvent] = iter(self)
        if kind is not None:
            out = (e for e in out if e.kind == kind)
        if prefix is not None:
            out = (e for e in out if e.kind.startswith(prefix))
        if source is not None:
            out = (e for e in out if e.source == source)
        return list(out)

    def lines(self) -> Iterator[str]:
        """The canonical JSON line of every event."""
        for ev in self:
            yield ev.to_json()

    def digest(self) -> str:
        """sha256 (hex) over the canonical form of every stored event."""
        h = hashlib.sha256()
        for line in self.lines():
            h.update(line.encode("utf-8"))
            h.update(b"\n")
        return h.hexdigest()

    def dump(self, path: str) -> None:
        """Write the canonical JSON lines to ``path``."""
        with open(path, "w", encoding="utf-8") as f:
            for line in self.lines():
                f.write(line + "\n")

    def format(self, limit: int | None = None) -> str:
        """A human-readable table: seconds, kind, source, details."""
        rows = []
        for ev in self.events[:limit]:
            det = " ".join(f"{k}={canonical(v) if not isinstance(v, (int, float, str)) else v}"
                           for k, v in sorted(ev.details.items()))
            rows.append(f"{ev.t / 1e9:14.9f}  {ev.kind:<20} {ev.source:<24} {det}")
        return "\n".join(rows)
