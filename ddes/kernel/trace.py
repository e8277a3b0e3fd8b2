"""The trace: structured events of one world, and their digest.

Every observable thing a world does (a timer fire, a delivery, a drop, a
service call, a goal transition, a log line) is appended as a
:class:`TraceEvent` ``(t, kind, source, details)``.  ``t`` is the kernel time
in integer nanoseconds; ``kind`` is a dotted name such as ``"timer.fire"``
(every kind ddes records is catalogued in :data:`ddes.kernel.kinds.TRACE_KINDS`);
``source`` names the entity (usually a node); ``details`` is a dict of
JSON-able values.

Writing: :meth:`Trace.append` (``details`` a dict) and :meth:`Trace.append_row`,
the hot-path form ``(t, kind, source, keys, *values)`` whose details dict is
built only when the event is read.  Reading: iterate, index,
:meth:`Trace.select` (a :class:`TraceSelection`), :attr:`Trace.counts`.

:meth:`Trace.digest` is a sha256 over a canonical JSON-lines form (sorted
keys, no whitespace, Time/Duration as integer nanoseconds, messages as
dicts) of the *stored* events, so two runs are identical iff their digests
are.  Events that are only counted (``enabled = False``, or filtered out by
:meth:`Trace.set_filter`) are not in the digest; :attr:`Trace.complete` says
whether that happened.  See ``docs/trace.md``.
"""

from __future__ import annotations

import hashlib
import json
import math
import re
from collections import Counter
from collections.abc import Callable, Iterable, Iterator, Mapping
from json.encoder import encode_basestring
from operator import attrgetter
from typing import IO, TYPE_CHECKING, Any, NamedTuple

from ddes.errors import DdesTypeError, DdesValueError, DigestError
from ddes.kernel.kinds import KIND_PREFIXES, TRACE_KINDS, TraceKind, close_matches, describe
from ddes.kernel.trace_lines import _WIRE, LineEncoder, holds_wire, wire_field
from ddes.time.units import HasNsec

__all__ = ["Trace", "TraceEvent", "TraceSelection", "canonical", "scrub_addresses"]

Row = tuple[Any, ...]
Listener = Callable[["TraceEvent"], None]

_MISSING = object()


class TraceEvent(NamedTuple):
    """One recorded event."""

    t: int
    kind: str
    source: str
    details: dict[str, Any]

    def to_json(self) -> str:
        """The canonical JSON line of this event (used by the digest).

        Memory addresses in reprs (``<X object at 0x7f…>``) are replaced by
        ``0x…`` (:func:`scrub_addresses`): they differ from run to run and machine to machine.
        """
        line = json.dumps(
            [self.t, self.kind, self.source, self.details],
            sort_keys=True,
            separators=(",", ":"),
            default=canonical,
            ensure_ascii=False,
        )
        return scrub_addresses(line)


#: A memory address as CPython's reprs print it: ``<X object at 0x7f…>``, ``<weakref at 0x…;
#: to 'X' at 0x…>``, ``<cell at 0x…: …>``, ``<code object f at 0x…, file …>``, a greenlet's
#: ``(otid=0x…)``: the digits after ``at 0x`` or ``otid=0x``.
_ADDRESS = re.compile(r"(?<=\bat 0x)[0-9a-fA-F]+|(?<=otid=0x)[0-9a-fA-F]+")


def scrub_addresses(text: str) -> str:
    """``text`` with every memory address of a repr shown as ``0x…`` (``<X object at 0x…>``):
    an address differs from one process to the next, so none may reach a digest.  The
    trace's digest scrubs its lines with it, and a node's log (:mod:`ddes.graph.rosout`) its
    text before the text enters the trace and ``/rosout`` (whose messages are digested as
    bytes)."""
    if "0x" not in text:
        return text
    return _ADDRESS.sub("…", text)


def canonical(value: object) -> object:
    """JSON fallback for values that json does not know.

    Time/Duration become integer nanoseconds, messages become dicts of their
    slots, bytes (message payloads) become ``"sha256:<hex>"`` of their
    content, sets become sorted lists.
    """
    to_nsec = getattr(value, "to_nsec", None)
    if to_nsec is not None:
        return to_nsec()
    slots = getattr(value, "__slots__", None)
    if slots is not None and hasattr(value, "_type"):
        return {"_type": value._type, **{s: getattr(value, s) for s in slots}}
    if isinstance(value, (bytes, bytearray, memoryview)):
        return "sha256:" + hashlib.sha256(value).hexdigest()
    if isinstance(value, (set, frozenset)):
        return sorted(value, key=lambda v: scrub_addresses(repr(v)))
    if isinstance(value, tuple):
        return list(value)
    tolist = getattr(value, "tolist", None)  # numpy arrays and scalars
    if tolist is not None:
        return tolist()
    return repr(value)


#: The canonical encoder of one value (the same options as :meth:`TraceEvent.to_json`).
_VALUE_JSON = json.JSONEncoder(sort_keys=True, separators=(",", ":"), default=canonical,
                               ensure_ascii=False)


def _value(v: Any) -> str:
    """The canonical JSON of one detail value, as it appears inside :meth:`TraceEvent.to_json`."""
    tp = type(v)
    if tp is str:
        return encode_basestring(v)
    if tp is int:
        return int.__repr__(v)
    if tp is bytes:
        return '"sha256:' + hashlib.sha256(v).hexdigest() + '"'
    if v is None:
        return "null"
    if tp is bool:
        return "true" if v else "false"
    if tp is float and math.isfinite(v):
        return float.__repr__(v)
    return _VALUE_JSON.encode(v)


_Enc = Callable[[int, str, str, tuple[Any, ...]], str]
_RowEnc = Callable[[Row], str]

#: Encoders of dict-form details by key tuple: None where the keys cannot be encoded this way
#: (not all str, or repeated), so the reference path does it.
_ENCODERS: dict[tuple[Any, ...], _Enc | None] = {}


def _slow(raw: Row) -> str:
    """The reference path: :meth:`TraceEvent.to_json`."""
    return _event(raw).to_json()


def _make_encoder(keys: tuple[Any, ...], row_form: bool) -> Callable[..., str] | None:
    """Generate a straight-line encoder of ``[t, kind, source, {sorted details}]`` for ``keys``.

    It writes what ``json.dumps(..., sort_keys=True, separators=(",", ":"),
    default=canonical, ensure_ascii=False)`` writes: keys in sorted order,
    strings through json's own C escaper, exact ints with ``repr``, anything
    else through :func:`_value`.  ``row_form``: it takes a whole
    ``(t, kind, source, keys, *values)`` row and hands any row that is not
    exactly that shape (int t, str kind and source, one value per key) to
    the reference path; otherwise it takes ``(t, kind, source, values)``.
    """
    if not all(type(k) is str for k in keys) or len(set(keys)) != len(keys):
        return None
    parts = []
    space: dict[str, Any] = {"S": encode_basestring, "T": type, "V": _value, "SLOW": _slow,
                             "I": int.__repr__}
    names = [f"v{i}" for i in range(len(keys))]
    for n, i in enumerate(sorted(range(len(keys)), key=lambda j: keys[j])):
        space[f"K{n}"] = encode_basestring(keys[i]) + ":"  # a constant, never source text
        x = names[i] if row_form else f"v[{i}]"
        parts.append(f"{{K{n}}}{{S({x}) if T({x}) is str else I({x}) if T({x}) is int else V({x})}}")
    body = ",".join(parts)
    consts = "".join(f", K{n}=K{n}" for n in range(len(keys)))
    line = f"f'[{{t}},{{S(kind)}},{{S(source)}},{{{{{body}}}}}]'"
    if row_form:
        unpack = ", ".join(["t", "kind", "source", "_keys", *names]) + ("," if not names else "")
        src = (f"def enc(r, S=S, I=I, T=T, V=V, SLOW=SLOW{consts}):\n"
               f"    try:\n"
               f"        {unpack} = r\n"
               f"    except ValueError:\n"
               f"        return SLOW(r)\n"
               f"    if T(t) is not int or T(kind) is not str or T(source) is not str:\n"
               f"        return SLOW(r)\n"
               f"    return {line}\n")
    else:
        src = (f"def enc(t, kind, source, v, S=S, I=I, T=T, V=V{consts}):\n"
               f"    return {line}\n")
    exec(compile(src, f"<trace encoder {keys!r}>", "exec"), space)  # noqa: S102 - keys are checked str
    enc: Callable[..., str] = space["enc"]
    return enc


#: Row-form encoders by ``id(keys)``, each with its key tuple (which keeps the id its own): call
#: sites pass the same module-level tuple every time, and an int lookup skips hashing it.
_BY_ID: dict[int, tuple[tuple[Any, ...], _RowEnc]] = {}


def _row_encoder(keys: tuple[Any, ...]) -> _RowEnc:
    entry = _BY_ID.get(id(keys))
    if entry is not None and entry[0] is keys:
        return entry[1]
    enc: _RowEnc | None = None
    try:
        hash(keys)
    except TypeError:  # unhashable keys (dict(zip()) would fail the same way in the reference)
        return _slow
    enc = _make_encoder(keys, row_form=True)
    if enc is None:
        enc = _slow
    if wire_field(keys) is not None:
        enc = _wire_encoder(enc)
    if len(_BY_ID) < 4096:
        _BY_ID[id(keys)] = (keys, enc)
    return enc


def _wire_encoder(enc: _RowEnc) -> _RowEnc:
    """The encoder of a :func:`~ddes.kernel.trace_lines.wire_keys` shape: ``enc`` of the row
    with its wire bytes decoded (the line of the row that held the message itself)."""

    def wire_enc(r: Row) -> str:
        return enc(_decoded(r))

    return wire_enc


def _decoded(raw: Row) -> Row:
    """``raw`` with the wire bytes of a :func:`~ddes.kernel.trace_lines.wire_keys` row decoded
    (the row as it would be had it held the message); any other row as it is."""
    keys = raw[3]
    if type(keys) is not tuple:
        return raw
    wire = wire_field(keys)
    if wire is None or len(raw) <= 4 + wire[0]:
        return raw
    at = 4 + wire[0]
    return (*raw[:3], wire[2], *raw[4:at], wire[1](raw[at]), *raw[at + 1:])


def _line(raw: Row) -> str:
    """The canonical JSON line of a stored row (without the address scrub: see :func:`_lines`)."""
    if len(raw) == 4 and type(raw[3]) is not tuple:
        details = raw[3]
        if type(details) is not dict:
            return _slow(raw)
        keys: tuple[Any, ...] = tuple(details)
        try:
            enc = _ENCODERS[keys]
        except KeyError:
            enc = _ENCODERS[keys] = _make_encoder(keys, row_form=False)
        except TypeError:
            return _slow(raw)
        if enc is None or type(raw[0]) is not int or type(raw[1]) is not str \
                or type(raw[2]) is not str:
            return _slow(raw)
        return enc(raw[0], raw[1], raw[2], tuple(details.values()))
    if type(raw[3]) is not tuple:
        return _slow(raw)
    return _row_encoder(raw[3])(raw)


def _row_line(raw: Row) -> str:
    """The canonical line of any stored row, by its shape's encoder (the reference path of
    :class:`~ddes.kernel.trace_lines.LineEncoder`; no address scrub)."""
    entry = _BY_ID.get(id(raw[3]))
    if entry is not None and entry[0] is raw[3]:
        return entry[1](raw)
    return _line(raw)


def _lines(rows: list[Row], encoder: LineEncoder | None = None) -> str:
    """The canonical lines of ``rows``, each ending in a newline: what the digest hashes.

    ``encoder`` (a trace's own, which learns its shapes) writes them faster; the text is the
    same either way.
    """
    if not rows:
        return ""
    if encoder is not None:
        text = encoder.lines(rows)
    else:
        text = "\n".join(map(_row_line, rows))
        text += "\n"
    return scrub_addresses(text)


#: Rows encoded per sha256 update when folding (bounds the text held at once).
_FOLD_CHUNK = 16_384


def _event(raw: Row) -> TraceEvent:
    # A stored row is either (t, kind, source, details_dict) from append(), or
    # (t, kind, source, keys, *values) from append_row(); keys is a tuple.
    if len(raw) == 4 and type(raw[3]) is not tuple:
        return TraceEvent(*raw)
    if id(raw[3]) in _WIRE:  # (wire_field's test, without a call per row)
        raw = _decoded(raw)
    return TraceEvent(raw[0], raw[1], raw[2], dict(zip(raw[3], raw[4:])))


def _same(have: object, want: object) -> bool:
    """Detail matching: equal values; a Time/Duration also equals its int nanoseconds."""
    if have is _MISSING:
        return False
    if have == want:
        return True
    for a, b in ((have, want), (want, have)):
        if type(b) is int:
            to_nsec = getattr(a, "to_nsec", None)
            if callable(to_nsec):
                return bool(to_nsec() == b)
    return False


def _nanoseconds(value: int | HasNsec | None, name: str) -> int | None:
    if value is None:
        return None
    if type(value) is int:
        return value
    to_nsec = getattr(value, "to_nsec", None)
    if callable(to_nsec):
        return int(to_nsec())
    raise DdesTypeError(
        f"{name} takes integer nanoseconds or a Time/Duration (to_nsec()), not "
        f"{type(value).__name__} {value!r}; e.g. {name}=int(2.5e9) or {name}=Time(2, 500000000)"
    )


def _value_indexes(keys: tuple[Any, ...], n: int,
                   want: tuple[tuple[str, object], ...]) -> tuple[int, ...] | None:
    """For each wanted key, the index among a row's ``n`` values of the value
    ``dict(zip(keys, values))`` gives it (its last occurrence in ``keys[:n]``), or -1; None
    where a key is unhashable (the reference path then fails as ``dict`` does)."""
    index: dict[Any, int] = {}
    for i, key in enumerate(keys[:n]):
        try:
            index[key] = i
        except TypeError:  # an unhashable key: dict(zip()) fails the same way in _event
            return None
    return tuple(index.get(k, -1) for k, _ in want)


def _match_details(details: Mapping[str, object], want: Mapping[str, object]) -> bool:
    return all(_same(details.get(k, _MISSING), v) for k, v in want.items())


class TraceSelection(list[TraceEvent]):
    """The events :meth:`Trace.select` found (a list), with helpers for asserting on them."""

    __slots__ = ()

    def kinds(self) -> Counter[str]:
        """How many events of each kind."""
        return Counter(ev.kind for ev in self)

    def sources(self) -> Counter[str]:
        """How many events from each source."""
        return Counter(ev.source for ev in self)

    def times(self) -> list[int]:
        """The time of every event (integer nanoseconds), in order."""
        return [ev.t for ev in self]

    def first(self) -> TraceEvent | None:
        """The earliest event, or None."""
        return self[0] if self else None

    def last(self) -> TraceEvent | None:
        """The latest event, or None."""
        return self[-1] if self else None

    def where(self, **details: object) -> TraceSelection:
        """The events whose details have all these values (compared with ``==``)."""
        return TraceSelection(ev for ev in self if _match_details(ev.details, details))

    def to_rows(self) -> list[dict[str, Any]]:
        """One flat dict per event: ``t``, ``kind``, ``source``, then the details' keys.

        A detail key that collides with ``t``/``kind``/``source`` is written
        as ``"details.<key>"``.  Handy for ``pandas.DataFrame(sel.to_rows())``.
        """
        rows = []
        for ev in self:
            row: dict[str, Any] = {"t": ev.t, "kind": ev.kind, "source": ev.source}
            for key, value in ev.details.items():
                row[f"details.{key}" if key in ("t", "kind", "source") else key] = value
            rows.append(row)
        return rows

    @staticmethod
    def _html(events: Iterable[TraceEvent], total: int, caption: str) -> str:
        """Rows t [s], kind, source, details of the first events (at most 50), escaped."""
        from ddes.display.tables import MAX_ROWS, html_table

        def details(ev: TraceEvent) -> str:
            text = " ".join(
                f"{k}={v if isinstance(v, (int, float, str)) else canonical(v)}"
                for k, v in sorted(ev.details.items()))
            return text if len(text) <= 200 else text[:199] + "…"

        rows = ((f"{ev.t / 1e9:.9f}", ev.kind, ev.source, details(ev))
                for _, ev in zip(range(MAX_ROWS), events))
        return html_table(("t [s]", "kind", "source", "details"), rows, caption=caption,
                          total=total, mono=(1, 2, 3))

    def _repr_html_(self) -> str:
        """The events as an HTML table for notebooks (the first 50, then how many more)."""
        kinds = ", ".join(f"{k} ×{n}" for k, n in self.kinds().most_common(5))
        more = len(self.kinds()) - 5
        caption = (f"{len(self)} event{'s' if len(self) != 1 else ''}"
                   + (f" ({kinds}{f', {more} more kinds' if more > 0 else ''})" if kinds else ""))
        return self._html(self, len(self), caption)


def _filter_active_marker(event: TraceEvent) -> None:
    """A no-op in ``Trace._listeners`` while a filter is set (see ``Trace._rebind``)."""


class Trace:
    """An append-only list of :class:`TraceEvent` with counters, filters, queries and a digest.

    ``append_row`` (and its old name ``record_fast``) is an attribute, not a
    method: while the trace is enabled with no listeners and no filter it *is*
    ``list.append`` of the stored rows, so the hot path costs one C call.
    Changing :attr:`enabled`, :meth:`subscribe`/:meth:`unsubscribe` or
    :meth:`set_filter` re-binds it to a checking method.
    """

    __slots__ = (
        "_raw", "_counts", "_enabled", "_subscribers", "_notify", "_listeners",
        "_include", "_exclude", "_decisions", "_fast", "append_row", "record_fast",
        "_hash", "_folded", "_bound", "_high", "_evicted", "_evicted_counts", "_spill",
        "_spill_path", "_encoder",
    )

    #: ``append_row(row)``: append ``(t, kind, source, keys, *values)``, keys a tuple of names.
    append_row: Callable[[Row], None]
    #: The old name of :attr:`append_row`.
    record_fast: Callable[[Row], None]

    def __init__(self) -> None:
        # Plain tuples on the hot path; wrapped in TraceEvent when read.  Never
        # re-assign _raw: append_row may be bound to its append.
        self._raw: list[Row] = []
        #: Events counted but not stored (disabled or filtered out), by kind.
        self._counts: dict[str, int] = {}
        self._enabled = True
        self._subscribers: list[Listener] = []
        self._notify: tuple[Listener, ...] = ()
        # Kept for callers written before append_row: truthy iff rows must go
        # through record_fast (listeners, or a filter) rather than _raw.append.
        self._listeners: tuple[Listener, ...] = ()
        self._include: tuple[frozenset[str], tuple[str, ...]] | None = None
        self._exclude: tuple[frozenset[str], tuple[str, ...]] | None = None
        self._decisions: dict[str, bool] = {}
        self._fast = True
        # The incremental digest: sha256 over the canonical lines of _raw[:_folded] and of
        # every evicted row before them.
        self._hash = hashlib.sha256()
        self._folded = 0
        self._encoder = LineEncoder(_row_line)
        # Bounded mode (see bound()): keep at most _bound rows; evict when _high is reached.
        self._bound: int | None = None
        self._high = 0
        self._evicted = 0
        self._evicted_counts: Counter[str] = Counter()
        self._spill: IO[str] | None = None
        self._spill_path: str | None = None
        self._rebind()

    # copy/deepcopy/pickle: append_row must be re-bound to the new object's own list
    # (copy.deepcopy treats a bound builtin method as atomic: it would keep appending
    # to the original list).
    # The running sha256 cannot be pickled: a copy re-folds its rows from the start, which
    # needs them all, so a bounded trace that has evicted rows cannot be copied.
    def __getstate__(self) -> dict[str, object]:
        if self._evicted:
            raise DdesValueError(
                f"cannot copy or pickle a bounded trace that has evicted {self._evicted} rows "
                "(its digest state lives in a running sha256); copy the world before "
                "trace.bound(...) evicts, or keep the trace unbounded")
        skip = {"append_row", "record_fast", "_notify", "_listeners", "_decisions", "_fast",
                "_hash", "_folded", "_spill", "_encoder"}
        state = {name: getattr(self, name) for name in self.__slots__ if name not in skip}
        # A wire_keys row is known by its key tuple's identity, which a copy does not keep:
        # the copy holds the decoded message instead (the same events, lines and digest).
        if holds_wire(self._raw):
            state["_raw"] = [_decoded(r) for r in self._raw]
        return state

    def __setstate__(self, state: dict[str, object]) -> None:
        for name, value in state.items():
            setattr(self, name, value)
        self._hash = hashlib.sha256()
        self._folded = 0
        self._encoder = LineEncoder(_row_line)
        self._spill = None
        self._rebind()

    # -- state that decides the hot path ---------------------------------------------

    def _rebind(self) -> None:
        filtered = self._include is not None or self._exclude is not None
        self._notify = tuple(self._subscribers)
        self._listeners = self._notify + ((_filter_active_marker,) if filtered else ())
        self._decisions = {}
        self._fast = self._enabled and not self._notify and not filtered and self._bound is None
        fn: Callable[[Row], None]
        if self._fast:
            fn = self._raw.append
        elif self._enabled and not self._notify and not filtered:
            fn = self._append_bounded
        else:
            fn = self._append_checked
        self.append_row = fn
        self.record_fast = fn

    def _set_enabled(self, value: bool) -> None:
        self._enabled = bool(value)
        self._rebind()

    if TYPE_CHECKING:

        @property
        def enabled(self) -> bool:
            """When False, events are counted but not stored (long benchmarks)."""
            return self._enabled

        @enabled.setter
        def enabled(self, value: bool) -> None: ...

    else:
        # A C getter (attrgetter): callers still test `trace.enabled` per event.
        enabled = property(
            attrgetter("_enabled"),
            _set_enabled,
            doc="When False, events are counted but not stored (long benchmarks).",
        )

    def _keep(self, kind: str) -> bool:
        keep = self._decisions.get(kind)
        if keep is None:
            keep = True
            if self._include is not None:
                exact, prefixes = self._include
                keep = kind in exact or kind.startswith(prefixes)
            if keep and self._exclude is not None:
                exact, prefixes = self._exclude
                keep = not (kind in exact or kind.startswith(prefixes))
            self._decisions[kind] = keep
        return keep

    def _append_checked(self, row: Row) -> None:
        """append_row when something is active: enabled flag, filter, listeners."""
        kind = row[1]
        if self._enabled and (self._include is None and self._exclude is None or self._keep(kind)):
            raw = self._raw
            raw.append(row)
            if self._notify:
                ev = _event(row)
                for listener in self._notify:
                    listener(ev)
            if self._bound is not None and len(raw) >= self._high:
                self._evict()
        else:
            self._counts[kind] = self._counts.get(kind, 0) + 1

    def _append_bounded(self, row: Row) -> None:
        """append_row of a bounded trace with nothing else active."""
        raw = self._raw
        raw.append(row)
        if len(raw) >= self._high:
            self._evict()

    # -- bounded mode ----------------------------------------------------------------

    def bound(self, max_rows: int | None, spill: str | None = None) -> None:
        """Keep at most ``max_rows`` recent rows in memory; ``bound(None)`` keeps all again.

        Older rows are folded into the digest and dropped (evicted) in chunks,
        so memory stays flat however long the run; :meth:`digest` still
        covers every event of the run, exactly as if nothing had been
        dropped.  With ``spill`` (a path), the evicted rows' canonical JSON
        lines are appended to that file as they leave memory (the file starts
        empty; :meth:`close_spill` flushes and closes it), so
        ``spill`` + :meth:`lines` of what remains is :meth:`dump`'s output.
        Reading (iterating, :meth:`select`, ``len``) sees the rows still in
        memory; :attr:`counts` and :attr:`total` count every row.
        """
        if max_rows is not None and (isinstance(max_rows, bool) or not isinstance(max_rows, int)
                                     or max_rows < 1):
            raise DdesValueError(f"bound(max_rows) takes None or an int >= 1, got {max_rows!r}; "
                                 "e.g. trace.bound(1_000_000)")
        if spill is not None and max_rows is None:
            raise DdesValueError("bound(None, spill=...) has nothing to spill: give max_rows too")
        self.close_spill()
        self._bound = max_rows
        # Evict in chunks of a quarter of the bound (at least 1): amortised O(1) per row.
        self._high = 0 if max_rows is None else max_rows + max(1, max_rows // 4)
        if spill is not None:
            self._spill = open(spill, "w", encoding="utf-8")  # noqa: SIM115 - closed by close_spill
            self._spill_path = spill
        self._rebind()
        if max_rows is not None and len(self._raw) >= self._high:
            self._evict()

    @property
    def bounded(self) -> int | None:
        """The ``max_rows`` of :meth:`bound`, or None when every row is kept."""
        return self._bound

    @property
    def evicted(self) -> int:
        """Rows a bounded trace has dropped from memory (all of them are in the digest)."""
        return self._evicted

    @property
    def total(self) -> int:
        """Every stored row of the run: those in memory plus those evicted."""
        return self._evicted + len(self._raw)

    def close_spill(self) -> None:
        """Flush and close the spill file of :meth:`bound` (no-op without one)."""
        if self._spill is not None:
            self._spill.close()
            self._spill = None

    def _fold(self, upto: int) -> None:
        """Fold ``_raw[_folded:upto]`` into the running digest."""
        raw, h, spill = self._raw, self._hash, self._spill
        i = self._folded
        while i < upto:
            j = min(upto, i + _FOLD_CHUNK)
            text = _lines(raw[i:j], self._encoder)
            h.update(text.encode("utf-8"))
            if spill is not None:
                spill.write(text)
            i = j
        self._folded = max(self._folded, upto)

    def _evict(self) -> None:
        """Drop the oldest rows down to the bound, folding them into the digest first."""
        assert self._bound is not None
        raw = self._raw
        k = len(raw) - self._bound
        if k <= 0:
            return
        if self._folded < k:
            self._fold(k)
        self._evicted_counts.update([r[1] for r in raw[:k]])
        del raw[:k]  # in place: append_row may be bound to raw.append
        self._folded -= k
        self._evicted += k

    # -- writing ---------------------------------------------------------------------

    def append(self, t: int, kind: str, source: str, details: dict[str, Any] | None = None) -> None:
        """Append one event (stored; or only counted while disabled or filtered out).

        ``details`` is stored as given (not copied): do not mutate it afterwards.
        """
        row = (t, kind, source, details if details is not None else {})
        if self._fast:
            self._raw.append(row)
        else:
            self._append_checked(row)

    #: The old name of :meth:`append`.
    record = append

    # -- filters ---------------------------------------------------------------------

    def set_filter(
        self,
        include: Iterable[str] | None = None,
        exclude: Iterable[str] | None = None,
        *,
        strict: bool = True,
    ) -> None:
        """Store only some kinds from now on; ``set_filter()`` stores everything again.

        ``include`` and ``exclude`` hold kinds (``"timer.fire"``) or kind
        prefixes ending in ``"."`` (``"topic."``).  An event is stored when it
        matches ``include`` (if given) and does not match ``exclude``.  The
        others are counted in :attr:`counts` but not stored, as with
        ``enabled = False``: they are not in :meth:`digest`, which covers stored
        events only, so a filter changes the digest, and :attr:`complete`
        becomes False.  With ``strict`` (the default) a name that is neither a
        catalogued kind nor a prefix of one raises ``DdesValueError``.
        """
        self._include = None if include is None else self._compile(include, "include", strict)
        self._exclude = None if exclude is None else self._compile(exclude, "exclude", strict)
        self._rebind()

    @staticmethod
    def _compile(names: Iterable[str], what: str, strict: bool) -> tuple[frozenset[str], tuple[str, ...]]:
        items = [names] if isinstance(names, str) else list(names)
        for name in items:
            if not isinstance(name, str):
                raise DdesTypeError(f"set_filter({what}=...) takes kind names, got {name!r}")
            if strict and name not in TRACE_KINDS and name not in KIND_PREFIXES:
                raise DdesValueError(_unknown(name, f"set_filter({what}=...)", strict_hint=True))
        exact = frozenset(n for n in items if not n.endswith("."))
        prefixes = tuple(sorted({n for n in items if n.endswith(".")}))
        return exact, prefixes

    @property
    def filtered(self) -> bool:
        """Whether a filter set with :meth:`set_filter` is active."""
        return self._include is not None or self._exclude is not None

    @property
    def complete(self) -> bool:
        """False once any event was counted but not stored (disabled or filtered out).

        The digest covers stored events only, so it describes an incomplete
        trace's run only partly.
        """
        return not self._counts

    def _incomplete_reason(self) -> str:
        """Why this trace cannot stand for its whole run ('' if it can)."""
        if self._counts:
            kinds = ", ".join(sorted(self._counts))
            return f"{sum(self._counts.values())} events were counted but not stored: {kinds}"
        if not self.enabled:
            return "recording is switched off: trace.enabled is False"
        if self.filtered:
            return "a recording filter is set"
        return ""

    @property
    def counts(self) -> Counter[str]:
        """How many events of each kind were recorded (stored or only counted)."""
        out: Counter[str] = Counter(raw[1] for raw in self._raw)
        out.update(self._evicted_counts)
        out.update(self._counts)
        return out

    @property
    def counted_only(self) -> Counter[str]:
        """How many events of each kind were only counted, not stored."""
        return Counter(self._counts)

    # -- listeners -------------------------------------------------------------------

    def subscribe(self, listener: Listener) -> None:
        """Call ``listener(event)`` for every event stored from now on."""
        self._subscribers.append(listener)
        self._rebind()

    def unsubscribe(self, listener: Listener) -> None:
        """Stop calling a listener added with :meth:`subscribe`."""
        self._subscribers.remove(listener)
        self._rebind()

    # -- reading ---------------------------------------------------------------------

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

    def select(
        self,
        kind: str | tuple[str, ...] | None = None,
        source: str | tuple[str, ...] | None = None,
        prefix: str | None = None,
        since_ns: int | HasNsec | None = None,
        until_ns: int | HasNsec | None = None,
        **details: object,
    ) -> TraceSelection:
        """The stored events that match every criterion given, in order.

        ``kind``: a kind, a prefix ending in ``"."`` (``"topic."``), or a tuple
        of those (any of them).  A single string that is neither a catalogued
        kind, nor a prefix of one, nor a kind this trace has recorded raises
        ``DdesValueError`` naming close matches.  ``source``: a source or a
        tuple of sources.  ``prefix``: a plain string prefix of the kind.
        ``since_ns``/``until_ns``: inclusive bounds on ``t``, as integer
        nanoseconds or a ``Time`` (anything with ``to_nsec()``); floats are
        refused.  ``**details``: detail values the event must have (``==``; a
        Time/Duration also equals its integer nanoseconds).
        """
        for name in ("since", "until", "t"):
            if name in details:
                raise DdesTypeError(
                    f"select() has no {name}=; bound times with since_ns=/until_ns= (integer "
                    f"nanoseconds or a Time), e.g. since_ns=Time(2) or since_ns=2_000_000_000")
        if isinstance(kind, str):
            if not (kind in TRACE_KINDS or kind in KIND_PREFIXES or self._has_kind(kind)):
                raise DdesValueError(_unknown(kind, "select(kind=...)"))
            kinds: tuple[str, ...] | None = (kind,)
        elif kind is None:
            kinds = None
        else:
            kinds = tuple(kind)
        return self._select(kinds, source, prefix, since_ns, until_ns, details)

    def _has_kind(self, kind: str) -> bool:
        if kind in self._counts:
            return True
        if kind.endswith("."):
            return any(raw[1].startswith(kind) for raw in self._raw) or any(
                k.startswith(kind) for k in self._counts)
        return any(raw[1] == kind for raw in self._raw)

    def _select(
        self,
        kinds: tuple[str, ...] | None,
        source: str | tuple[str, ...] | None,
        prefix: str | None,
        since_ns: int | HasNsec | None,
        until_ns: int | HasNsec | None,
        details: Mapping[str, object],
        *,
        kind_prefixes: bool = True,
    ) -> TraceSelection:
        lo = _nanoseconds(since_ns, "since_ns")
        hi = _nanoseconds(until_ns, "until_ns")
        exact: frozenset[str] | None = None
        kprefixes: tuple[str, ...] = ()
        if kinds is not None:
            if kind_prefixes:
                exact = frozenset(k for k in kinds if not k.endswith("."))
                kprefixes = tuple(k for k in kinds if k.endswith("."))
            else:
                exact = frozenset(kinds)
        sources = None if source is None else (
            frozenset((source,)) if isinstance(source, str) else frozenset(source))
        out = TraceSelection()
        want = tuple(details.items())
        # Row-form rows are matched where they lie, the event built only for a match: per key
        # tuple and value count, the index of each wanted key's value (the last occurrence
        # among the keys that have a value, as dict(zip(keys, values)) keeps), or -1.
        where: dict[tuple[int, int], tuple[tuple[Any, ...], tuple[int, ...] | None, bool]] = {}
        for raw in self._raw:
            t, k = raw[0], raw[1]
            if exact is not None and k not in exact and not (kprefixes and k.startswith(kprefixes)):
                continue
            if prefix is not None and not k.startswith(prefix):
                continue
            if sources is not None and raw[2] not in sources:
                continue
            if (lo is not None and t < lo) or (hi is not None and t > hi):
                continue
            if want:
                keys = raw[3]
                if type(keys) is tuple:
                    n = len(raw) - 4
                    hit = where.get((id(keys), n))
                    if hit is None or hit[0] is not keys:
                        hit = where[(id(keys), n)] = (keys, _value_indexes(keys, n, want),
                                                      wire_field(keys) is not None)
                    indexes = hit[1]
                    if indexes is None:
                        out.append(_event(raw))  # raises as dict(zip()) does
                        continue
                    if hit[2]:  # a message held as its wire bytes
                        ev = _event(raw)
                        if _match_details(ev.details, details):
                            out.append(ev)
                        continue
                    if not all(_same(raw[i + 4] if i >= 0 else _MISSING, w)
                               for i, (_, w) in zip(indexes, want)):
                        continue
                    out.append(_event(raw))
                    continue
                ev = _event(raw)
                if not _match_details(ev.details, details):
                    continue
                out.append(ev)
                continue
            out.append(_event(raw))
        return out

    def filter(
        self,
        kind: str | None = None,
        source: str | None = None,
        prefix: str | None = None,
    ) -> list[TraceEvent]:
        """Events of a kind (exact), a kind prefix (``"topic."``) and/or a source.

        The older, lenient form of :meth:`select`: an unknown kind gives ``[]``.
        """
        kinds = None if kind is None else (kind,)
        return self._select(kinds, source, prefix, None, None, {}, kind_prefixes=False)

    # -- the catalogue ---------------------------------------------------------------

    @staticmethod
    def kinds_catalogue() -> Mapping[str, TraceKind]:
        """Every kind ddes records (:data:`ddes.kernel.kinds.TRACE_KINDS`)."""
        return TRACE_KINDS

    @staticmethod
    def describe(kind: str) -> str:
        """A human-readable line on a kind, or on every kind under a prefix (``"topic."``)."""
        return describe(kind)

    # -- the canonical form ----------------------------------------------------------

    def lines(self) -> Iterator[str]:
        """The canonical JSON line of every stored event (still in memory)."""
        raw = self._raw
        for i in range(0, len(raw), _FOLD_CHUNK):
            # split on "\n" only: a line may hold U+2028 or U+0085 (not escaped by json)
            yield from _lines(raw[i:i + _FOLD_CHUNK], self._encoder)[:-1].split("\n")

    def digest(self) -> str:
        """sha256 (hex) over the canonical form of every stored event.

        A digest promises "identical runs", so it is refused for a trace that
        does not hold every event (recording switched off with ``enabled =
        False``, or a filter): :class:`~ddes.errors.DigestError` says which.
        """
        if self._incomplete_reason():
            raise DigestError(
                "cannot digest this trace: it does not hold every event of the run "
                f"({self._incomplete_reason()}); record everything (trace.enabled = True and "
                "trace.set_filter() before running) to digest a run")
        if self._spill is None:
            self._fold(len(self._raw))
            return self._hash.hexdigest()
        # A spilling trace writes a row to its file only when it is evicted: fold the rows
        # still in memory into a copy, leaving them to be spilled later.
        h = self._hash.copy()
        h.update(_lines(self._raw[self._folded:], self._encoder).encode("utf-8"))
        return h.hexdigest()

    def dump(self, path: str) -> None:
        """Write the canonical JSON lines to ``path``.

        A bounded trace that has evicted rows no longer holds them: it raises
        ``DdesValueError`` (bound it with ``spill=path`` to keep them on disk).
        """
        if self._evicted:
            raise DdesValueError(
                f"cannot dump this trace: it is bounded and has evicted {self._evicted} rows; "
                "pass spill=PATH to trace.bound(...) to stream every row to a file")
        with open(path, "w", encoding="utf-8") as f:
            for line in self.lines():
                f.write(line + "\n")

    def _repr_html_(self) -> str:
        """The stored events as an HTML table for notebooks (the first 50, then how many more)."""
        caption = f"trace: {len(self)} event{'s' if len(self) != 1 else ''} stored"
        counted = sum(self._counts.values())
        if counted:
            caption += f", {counted} counted only (recording off or filtered)"
        return TraceSelection._html((_event(raw) for raw in self._raw), len(self), caption)

    def format(self, limit: int | None = None) -> str:
        """A human-readable table: seconds, kind, source, details."""
        rows = []
        for ev in self.events[:limit]:
            det = " ".join(f"{k}={canonical(v) if not isinstance(v, (int, float, str)) else v}"
                           for k, v in sorted(ev.details.items()))
            rows.append(f"{ev.t / 1e9:14.9f}  {ev.kind:<20} {ev.source:<24} {det}")
        return "\n".join(rows)


def _unknown(kind: str, where: str, strict_hint: bool = False) -> str:
    near = close_matches(kind)
    msg = f"{where}: unknown trace kind {kind!r}"
    if near:
        msg += f"; did you mean {' or '.join(map(repr, near))}?"
    elif not kind.endswith(".") and any(k.startswith(kind + ".") for k in TRACE_KINDS):
        msg += f"; a prefix ends in '.': {kind + '.'!r}"
    msg += " (the kinds are listed in ddes.kernel.kinds.TRACE_KINDS and docs/trace.md"
    msg += "; pass strict=False for kinds of your own)" if strict_hint else ")"
    return msg
