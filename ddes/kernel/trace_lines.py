"""The trace's canonical lines, fast: one generated loop with a branch per frequent row shape.

:meth:`ddes.kernel.trace.Trace.digest` hashes the canonical JSON line of every row (see
:mod:`ddes.kernel.trace`).  Written row by row, each line costs a Python call, a type test per
value and json's escaper per string.  A trace holds few *shapes* (the key tuple of
``append_row``, the same object at every call site), so :class:`LineEncoder` generates, for
the shapes it has seen often, one loop over a chunk of rows with a branch per shape that
writes the line with a single f-string:

* the branch tests each value's exact type against the shape's *signature* (``t`` an int, the
  kind and source str, each value the type the shape showed: str, int, finite float or bytes);
  a row that does not fit goes to the reference path (``fallback``, the per-row encoder);
* a str is written between quotes as it is, *without* json's escaper.  That is the canonical
  form exactly when the string holds no ``"``, ``\\`` or control character.  Instead of
  testing every string, the chunk is checked as a whole.  The loop counts the quotes and
  backslashes ("marks") its lines hold besides those raw strings: the branches' constants,
  and each reference line's and escaped string's own.  The joined text must then hold exactly
  that many marks plus one newline per line, and no other control character.  Each line holds
  at least its counted marks and its newline (json never writes a raw control character), and
  a raw string that needed escaping adds a mark or a control character, so one length
  compares them all: that of the text's bytes with every other byte deleted.  When the check
  fails the chunk is written again by the reference path, and the strings of the shapes whose
  lines differed are escaped from then on (their branch counts their marks per row).

The text is the same as the reference path's in every case (``tests/kernel/test_trace_lines.py``
checks it with hypothesis, also against rows built to fool the check).
"""

from __future__ import annotations

import hashlib
from collections.abc import Callable
from hashlib import sha256
from json.encoder import encode_basestring
from operator import itemgetter
from typing import Any

from ddes.errors import DdesValueError


def _builtin_sha256() -> Any:
    """CPython's own sha256 constructor (``_sha256`` in 3.11, ``_sha2`` after), as hashlib
    finds it without OpenSSL: less set-up per call, more time per byte; OpenSSL's if absent."""
    try:
        return getattr(hashlib, "__get_builtin_constructor")("sha256")
    except (AttributeError, ValueError):  # pragma: no cover - another Python, or no builtin
        return sha256


_sha256_small = _builtin_sha256()

__all__ = ["LineEncoder", "holds_wire", "wire_field", "wire_keys"]

Row = tuple[Any, ...]

#: Most shapes with a branch of their own (each miss walks the chain of ``is`` tests).
MAX_BRANCHES = 12
#: Rows of one shape that took the reference path and give it a branch.
LEARN_AT = 16
#: Rows of the first chunk looked at to find its shapes before the first loop is generated.
PRESCAN = 1024
#: Bytes values shorter than this are hashed by CPython's own sha256, longer ones by OpenSSL's
#: (the same digest): a small message's bytes cost less to hash there, a large one's more.
SMALL_BYTES = 64

#: Every byte but the quote, the backslash and the control characters (the newline among them).
_OTHER_BYTES = bytes(i for i in range(0x20, 0x100) if i not in (0x22, 0x5C))

# Slot codes of a signature: s a str written as is, S a str through json's escaper, i an int,
# f a finite float, b bytes (as their "sha256:<hex>").
_STR, _ESCAPED, _INT, _FLOAT, _BYTES = "s", "S", "i", "f", "b"

#: Generated sources already compiled (the same shapes recur in every world of a process).
_COMPILED: dict[str, Any] = {}
_MAX_COMPILED = 256
#: Shapes whose misses are counted at once (more are forgotten, and counted again).
_MAX_MISSES = 4096


#: Key tuples, by identity, whose rows hold a message's wire bytes in one field (see
#: :func:`wire_keys`): ``id(keys) -> (keys, index, decode, plain)``, ``plain`` the tuple it was
#: made from.  Each entry keeps its tuple alive, so its id stays its own; a cache of what the
#: program's classes are, not state of a run.
_WIRE: dict[int, tuple[tuple[str, ...], int, Callable[[bytes], object], tuple[str, ...]]] = {}


def wire_keys(keys: tuple[str, ...], field: str, decode: Callable[[bytes], object]) -> tuple[str, ...]:
    """A key tuple equal to ``keys`` whose rows hold, as ``field``, a message's wire bytes.

    ``Trace.append_row((t, kind, source, wkeys, ..., data, ...))`` with the returned tuple
    stores ``data`` (bytes) where a message would be; every reader of the trace (events,
    queries, lines and the digest, copies and pickles) sees ``decode(data)`` instead, read
    when looked at.  A row of only bytes, strs and ints is one the garbage collector stops
    tracking, where a row holding a message object would be traversed by every collection of
    its generation.  The tuple is a new object, recognised by identity: a row built with an
    equal tuple of the caller's own holds what it holds.
    """
    if field not in keys:
        raise DdesValueError(f"wire_keys: {field!r} is not one of the keys {keys!r}; name the "
                             "key whose value holds the wire bytes")
    out = tuple(list(keys))
    _WIRE[id(out)] = (out, keys.index(field), decode, keys)
    return out


def holds_wire(rows: list[Row]) -> bool:
    """Whether any of ``rows`` was appended with a :func:`wire_keys` tuple (a scan in C)."""
    return bool(_WIRE) and not _WIRE.keys().isdisjoint(map(id, map(_KEYS_OF, rows)))


_KEYS_OF = itemgetter(3)


def wire_field(keys: object) -> tuple[int, Callable[[bytes], object], tuple[str, ...]] | None:
    """``(index, decode, plain)`` when ``keys`` is a tuple made by :func:`wire_keys` (``plain``
    the tuple it was made from), else None."""
    entry = _WIRE.get(id(keys))
    if entry is None or entry[0] is not keys:
        return None
    return entry[1], entry[2], entry[3]


def _code(t: object) -> str | None:
    tp = type(t)
    if tp is str:
        return _STR if _plain(t) else _ESCAPED  # type: ignore[arg-type]
    if tp is int:
        return _INT
    if tp is float:
        return _FLOAT if t - t == 0.0 else None  # type: ignore[operator]  # finite
    if tp is bytes:
        return _BYTES
    return None


def _plain(text: str) -> bool:
    """Whether json writes ``text`` as it is, between quotes."""
    return encode_basestring(text) == f'"{text}"'


def signature(row: Row) -> tuple[str, ...] | None:
    """The slot codes of a row-form ``(t, kind, source, keys, *values)``, or None when its shape
    cannot have a branch (keys not distinct plain strs, or a value of another type)."""
    keys = row[3]
    if type(keys) is not tuple or len(row) != 4 + len(keys) or type(row[0]) is not int:
        return None
    if id(keys) in _WIRE:  # its bytes stand for a message: the reference path decodes them
        return None
    if not all(type(k) is str and _plain(k) for k in keys) or len(set(keys)) != len(keys):
        return None
    codes = [_code(v) for v in row[:3] + row[4:]]
    if codes[1] not in (_STR, _ESCAPED) or codes[2] not in (_STR, _ESCAPED) or None in codes:
        return None
    return tuple(codes)  # type: ignore[arg-type]


def _branch(n: int, keys: tuple[str, ...], sig: tuple[str, ...]) -> list[str]:
    """The source lines of shape ``n``'s branch (inside the loop)."""
    names = ["t", "kind", "source"] + [f"v{j}" for j in range(len(keys))]
    tests = []
    pre: list[str] = []
    quotes = 2 * len(keys)  # the marks of a line besides its escaped strings
    for name, code in zip(names, sig):
        if code == _INT:
            tests.append(f"T({name}) is TI")
        elif code == _FLOAT:
            tests.append(f"T({name}) is TF and {name} - {name} == 0.0")
        elif code == _BYTES:
            tests.append(f"T({name}) is TB")
            quotes += 2
        else:
            tests.append(f"T({name}) is TS")
            if code == _STR:
                quotes += 2
            else:  # escaped: its quotes and backslashes are counted per row
                pre += [f"e_{name} = S({name})",
                        f"q += e_{name}.count('\"') + e_{name}.count('\\\\')"]

    def value(name: str, code: str) -> str:
        if code == _STR:
            return repr('"') + f" f'{{{name}}}' " + repr('"')
        if code == _ESCAPED:
            return f"f'{{e_{name}}}'"
        if code == _BYTES:
            return (repr('"sha256:') + f" f'{{(HS if L({name}) < {SMALL_BYTES} else H)({name})"
                    ".hexdigest()}' " + repr('"'))
        return f"f'{{{name}}}'"

    codes = dict(zip(names, sig))
    parts = [repr("["), value("t", codes["t"]), repr(","), value("kind", codes["kind"]),
             repr(","), value("source", codes["source"]), repr(",{")]
    order = sorted(range(len(keys)), key=keys.__getitem__)
    for m, j in enumerate(order):
        parts.append(repr(("," if m else "") + f'"{keys[j]}":'))
        parts.append(value(f"v{j}", sig[3 + j]))
    parts.append(repr("}]"))
    unpack = ", ".join(["t", "kind", "source", "_k", *names[3:]])
    lines = [f"{'if' if n == 0 else 'elif'} k is K{n}:",
             "    try:",
             f"        {unpack} = r",
             "    except ValueError:",
             "        pass",
             "    else:",
             f"        if {' and '.join(tests)}:",
             *(f"            {p}" for p in pre),
             f"            a({' '.join(parts)})",
             f"            q += {quotes}",
             "            continue"]
    return lines


def _generate(shapes: list[tuple[tuple[str, ...], tuple[str, ...]]]) -> str:
    """The source of the chunk loop for ``shapes`` ((keys, signature), in branch order)."""
    body: list[str] = []
    for n, (keys, sig) in enumerate(shapes):
        body += _branch(n, keys, sig)
    if shapes:
        body += ["else:", "    if T(k) is tuple:", "        miss(k, r)"]
    else:
        body += ["if T(k) is tuple:", "    miss(k, r)"]
    args = "".join(f", K{n}=None" for n in range(len(shapes)))
    return "\n".join([
        f"def loop(rows, miss, LINE, T=type, S=None, H=None, HS=None, L=len, TI=int, TS=str, "
        f"TF=float, TB=bytes{args}):",
        "    out = []",
        "    a = out.append",
        "    q = 0",
        "    for r in rows:",
        "        k = r[3]",
        *(f"        {line}" for line in body),
        "        line = LINE(r)",
        "        a(line)",
        "        q += line.count('\"') + line.count('\\\\')",
        "    return out, q",
    ])


class LineEncoder:
    """The canonical lines of chunks of one trace's rows (see the module docstring).

    ``fallback(row)`` is the reference path: the canonical line of any row (without the
    address scrub, which the caller applies to the whole text).
    """

    __slots__ = ("_fallback", "_shapes", "_loop", "_misses", "fallbacks")

    def __init__(self, fallback: Callable[[Row], str]) -> None:
        self._fallback = fallback
        #: (keys, signature) per branch, in branch order.
        self._shapes: list[tuple[tuple[str, ...], tuple[str, ...]]] = []
        self._loop: Callable[..., tuple[list[str], int]] | None = None
        self._misses: dict[int, list[Any]] = {}
        #: Chunks the whole-text check sent back to the reference path (for tests).
        self.fallbacks = 0

    def _miss(self, keys: tuple[Any, ...], row: Row) -> None:
        seen = self._misses.get(id(keys))
        if seen is None:
            self._misses[id(keys)] = [1, row]
        else:
            seen[0] += 1

    def _learn(self) -> bool:
        """Give a branch to each shape that has missed ``LEARN_AT`` times or more, most first.

        Misses add up across calls (a digest asked after every few events still learns), for at
        most ``_MAX_MISSES`` shapes at a time."""
        misses = self._misses
        known = {id(keys) for keys, _ in self._shapes}
        added = False
        ready = [(m[0], i) for i, m in misses.items() if m[0] >= LEARN_AT]  # in order of first miss
        for _count, i in sorted(ready, key=lambda c: -c[0]):
            row = misses.pop(i)[1]
            if len(self._shapes) >= MAX_BRANCHES:
                break
            if id(row[3]) in known:
                continue
            sig = signature(row)
            if sig is not None:
                self._shapes.append((row[3], sig))
                added = True
        if len(misses) > _MAX_MISSES or len(self._shapes) >= MAX_BRANCHES:
            misses.clear()
        return added

    def _build(self) -> None:
        source = _generate(self._shapes)
        code = _COMPILED.get(source)
        if code is None:
            code = compile(source, "<trace line loop>", "exec")
            if len(_COMPILED) < _MAX_COMPILED:
                _COMPILED[source] = code
        space: dict[str, Any] = {}
        exec(code, space)  # noqa: S102 - generated here; keys enter only through repr()
        loop = space["loop"]
        defaults = list(loop.__defaults__)
        defaults[1:4] = [encode_basestring, sha256, _sha256_small]
        defaults[9:] = [keys for keys, _ in self._shapes]  # after T, S, H, HS, L, the four types
        loop.__defaults__ = tuple(defaults)
        self._loop = loop

    def lines(self, rows: list[Row]) -> str:
        """The canonical lines of ``rows``, each ending in a newline (no address scrub)."""
        if not rows:
            return ""
        if self._loop is None:
            for row in rows[:PRESCAN]:
                keys = row[3]
                if type(keys) is tuple:
                    self._miss(keys, row)
            self._learn()
            self._build()
        assert self._loop is not None
        out, marks = self._loop(rows, self._miss, self._fallback)
        text = "\n".join(out)
        text += "\n"
        # Only the quotes, backslashes, newlines and control characters of the text (UTF-8
        # writes no byte below 0x80 but the ASCII character itself).
        rest = text.encode("utf-8", "surrogatepass").translate(None, _OTHER_BYTES)
        if len(rest) != marks + len(out):
            text = self._redo(rows, out)
        if self._misses and self._learn():
            self._build()
        return text

    def _redo(self, rows: list[Row], fast: list[str]) -> str:
        """The chunk by the reference path; the shapes whose lines differed escape their str
        values from now on."""
        self.fallbacks += 1
        exact = list(map(self._fallback, rows))
        branch = {id(keys): n for n, (keys, _) in enumerate(self._shapes)}
        changed = False
        for i in range(len(rows)):
            if fast[i] == exact[i]:
                continue
            n = branch.get(id(rows[i][3]))
            if n is None:
                continue
            keys, sig = self._shapes[n]
            row = rows[i]
            blamed = [j for j, v in enumerate(row[1:3] + row[4:], start=1)
                      if type(v) is str and not _plain(v)]
            codes = tuple(_ESCAPED if j in blamed and c == _STR else c for j, c in enumerate(sig))
            if codes != sig:
                self._shapes[n] = (keys, codes)
                changed = True
        if changed:
            self._build()
        text = "\n".join(exact)
        return text + "\n"
