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


class Trace:
    """An append-only list of :class:`TraceEvent` with counters and a digest."""

    __slots__ = ("_events", "counts", "enabled", "_listeners")

    def __init__(self) -> None:
        self._events: list[TraceEvent] = []
        self.counts: Counter[str] = Counter()
        #: When False, events are counted but not stored (long benchmarks).
        self.enabled = True
        self._listeners: list[Callable[[TraceEvent], None]] = []

    def record(self, t: int, kind: str, source: str, details: dict[str, Any] | None = None) -> None:
        """Append one event (and count it under ``kind``)."""
        self.counts[kind] += 1
        if self.enabled:
            ev = TraceEvent(t, kind, source, details if details is not None else {})
            self._events.append(ev)
            for listener in self._listeners:
                listener(ev)

    def subscribe(self, listener: Callable[[TraceEvent], None]) -> None:
        """Call ``listener(event)`` for every event recorded from now on."""
        self._listeners.append(listener)

    def unsubscribe(self, listener: Callable[[TraceEvent], None]) -> None:
        """Stop calling a listener added with :meth:`subscribe`."""
        self._listeners.remove(listener)

    def __len__(self) -> int:
        return len(self._events)

    def __iter__(self) -> Iterator[TraceEvent]:
        return iter(self._events)

    def __getitem__(self, index: int) -> TraceEvent:
        return self._events[index]

    @property
    def events(self) -> list[TraceEvent]:
        """All stored events, in the order they happened."""
        return self._events

    def filter(
        self,
        kind: str | None = None,
        source: str | None = None,
        prefix: str | None = None,
    ) -> list[TraceEvent]:
        """Events of a kind (exact), a kind prefix (``"topic."``) and/or a source."""
        out: Iterable[TraceEvent] = self._events
        if kind is not None:
            out = (e for e in out if e.kind == kind)
        if prefix is not None:
            out = (e for e in out if e.kind.startswith(prefix))
        if source is not None:
            out = (e for e in out if e.source == source)
        return list(out)

    def lines(self) -> Iterator[str]:
        """The canonical JSON line of every event."""
        for ev in self._events:
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
        for ev in self._events[:limit]:
            det = " ".join(f"{k}={canonical(v) if not isinstance(v, (int, float, str)) else v}"
                           for k, v in sorted(ev.details.items()))
            rows.append(f"{ev.t / 1e9:14.9f}  {ev.kind:<20} {ev.source:<24} {det}")
        return "\n".join(rows)
