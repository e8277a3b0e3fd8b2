"""The framed protocol between the trusted grader and the sandboxed child.

Only this crosses the pipe: fixed binary frames built with :mod:`struct` and
UTF-8 strings, each size bounded; no pickle, no JSON, no ``eval``.  The trusted
side decodes a frame with :func:`decode_frame`, which checks every length, and
then validates the content (names, types, md5 sums, stamps) itself.

A frame is ``b"DG"``, one byte of kind, a big-endian ``u32`` payload length,
then the payload.  Payload fields: ``str`` is a ``u16`` length and UTF-8 bytes
(at most :data:`MAX_STR` bytes), ``blob`` a ``u32`` length and raw bytes,
``i64``/``i32``/``u8`` fixed-width big-endian integers.

Kinds, grader → child:

* ``STEP t_ns [topic type md5 blob]*``: the messages the student's
  subscriptions receive at ``t_ns``; the child publishes them at ``t_ns`` and
  runs every event due at or before ``t_ns``.
* ``END``: the grade is over; the child exits.
* ``CALL id service blob``: a grader-side client called the student's service ``service`` with
  these request bytes; sent just before the ``STEP`` of the instant it happened at, and answered
  by a ``RESP`` with the same ``id`` in that step's reply or a later one (a handler may take
  simulated time).
* ``OFFER service type md5``: a service served outside this child (by another student node's
  child, or by the grader's world) exists; the child serves a stand-in that forwards each call
  as ``ASK``.  Sent before a ``STEP``.
* ``ANSWER id ok blob``: the answer to the child's ``ASK id``: ``ok`` 1 and the response's wire
  bytes, or ``ok`` 0 and the error text.  Sent before the ``STEP`` of the instant it arrived at.

Kinds, child → grader (the reply to one STEP ends with ``DONE``):

* ``ADV node topic type md5 latch``: a student node advertised a topic.
* ``SUB node topic type md5 queue_size``: a student node subscribed (-1: no limit).
* ``MSG node topic t_ns blob``: a student node published these wire bytes at ``t_ns``.
* ``GONE node``: a student node has shut down.
* ``SRV node service type md5``: a student node advertised a service.
* ``RESP id ok blob``: the answer to ``CALL id``: ``ok`` 1 and the response's wire bytes, or
  ``ok`` 0 and the error text (UTF-8, at most :data:`MAX_ERROR` bytes) the caller receives.
* ``DIED node t_ns fatal text``: a student node's main ended with an exception at ``t_ns``
  (``fatal`` 1; ``node`` is the node's name, or the script's base name when it died before
  ``init_node``), or one of its callbacks raised and the node went on, as rospy's do
  (``fatal`` 0; sent for the first failure of each callback only); ``text`` is the traceback
  with the student's own frames by base name (UTF-8, at most :data:`MAX_ERROR` bytes).  Shown
  to the student as written, never used for a score.
* ``READ node key found``: a student node read the parameter ``key`` (resolved, global) with
  ``get_param`` or ``has_param``; ``found`` 1 when it was set.  Sent once per ``(node, key,
  found)``.
* ``ASK id node service blob``: the student node ``node`` called ``service``, which this child
  serves only as an ``OFFER``'s stand-in, with these request bytes; answered by ``ANSWER id``.
* ``DONE next_ns``: the step is over; the child's next event is at ``next_ns`` (-1: none).
* ``READY``: sent once, before the first step, when the child has imported ddes and confined
  itself (the grader gives that phase its own wall budget).
"""

from __future__ import annotations

import struct
from dataclasses import dataclass

from ddes.errors import ProtocolError

__all__ = [
    "ADV",
    "ANSWER",
    "ASK",
    "CALL",
    "DIED",
    "DONE",
    "END",
    "GONE",
    "HEADER",
    "MAX_FRAME",
    "MAX_ERROR",
    "MAX_STR",
    "MSG",
    "OFFER",
    "READ",
    "READY",
    "RESP",
    "SRV",
    "STEP",
    "SUB",
    "Adv",
    "Answer",
    "Ask",
    "Call",
    "Died",
    "Done",
    "Gone",
    "Msg",
    "Offer",
    "Read",
    "Resp",
    "Srv",
    "Step",
    "Sub",
    "decode_frame",
    "decode_header",
    "encode_adv",
    "encode_answer",
    "encode_ask",
    "encode_call",
    "encode_died",
    "encode_done",
    "encode_end",
    "encode_gone",
    "encode_msg",
    "encode_offer",
    "encode_read",
    "encode_ready",
    "encode_resp",
    "encode_srv",
    "encode_step",
    "encode_sub",
]

MAGIC = b"DG"
HEADER = struct.Struct(">2sBI")
#: Largest payload of one frame (bytes); a longer announced length is a protocol error.
MAX_FRAME = 8 * 1024 * 1024
#: Longest string field (bytes of UTF-8): names, types and md5 sums are far shorter.
MAX_STR = 1024
#: Longest error text of a ``RESP`` (bytes of UTF-8).
MAX_ERROR = 4096

STEP, END, CALL, OFFER, ANSWER = 1, 2, 3, 4, 5
ADV, SUB, MSG, GONE, DONE, READY, SRV, RESP, DIED, READ, ASK = (10, 11, 12, 13, 14, 15, 16, 17,
                                                               18, 19, 20)
_KINDS = {STEP, END, CALL, OFFER, ANSWER, ADV, SUB, MSG, GONE, DONE, READY, SRV, RESP, DIED,
          READ, ASK}

_I64 = struct.Struct(">q")
_I32 = struct.Struct(">i")
_U32 = struct.Struct(">I")
_U16 = struct.Struct(">H")


@dataclass(frozen=True)
class Step:
    t_ns: int
    messages: tuple[tuple[str, str, str, bytes], ...]


@dataclass(frozen=True)
class Adv:
    node: str
    topic: str
    type: str
    md5: str
    latch: bool


@dataclass(frozen=True)
class Sub:
    node: str
    topic: str
    type: str
    md5: str
    queue_size: int


@dataclass(frozen=True)
class Msg:
    node: str
    topic: str
    t_ns: int
    data: bytes


@dataclass(frozen=True)
class Gone:
    node: str


@dataclass(frozen=True)
class Done:
    next_ns: int


@dataclass(frozen=True)
class Call:
    id: int
    service: str
    data: bytes


@dataclass(frozen=True)
class Srv:
    node: str
    service: str
    type: str
    md5: str


@dataclass(frozen=True)
class Resp:
    id: int
    ok: bool
    #: The response's wire bytes (``ok``) or the error text's UTF-8 bytes.
    data: bytes


@dataclass(frozen=True)
class Died:
    node: str
    t_ns: int
    fatal: bool
    text: str


@dataclass(frozen=True)
class Read:
    node: str
    key: str
    found: bool


@dataclass(frozen=True)
class Offer:
    service: str
    type: str
    md5: str


@dataclass(frozen=True)
class Answer:
    id: int
    ok: bool
    data: bytes


@dataclass(frozen=True)
class Ask:
    id: int
    node: str
    service: str
    data: bytes


Frame = (Step | Adv | Sub | Msg | Gone | Done | Call | Srv | Resp | Died | Read | Offer | Answer
         | Ask | None)


def _s(text: str) -> bytes:
    raw = text.encode("utf-8")
    if len(raw) > MAX_STR:
        raise ProtocolError(f"string field of {len(raw)} bytes (at most {MAX_STR}): {text[:40]!r}…")
    return _U16.pack(len(raw)) + raw


def _b(data: bytes) -> bytes:
    return _U32.pack(len(data)) + data


def _frame(kind: int, payload: bytes) -> bytes:
    if len(payload) > MAX_FRAME:
        raise ProtocolError(f"frame of {len(payload)} bytes (at most {MAX_FRAME})")
    return HEADER.pack(MAGIC, kind, len(payload)) + payload


def encode_step(t_ns: int, messages: list[tuple[str, str, str, bytes]]) -> bytes:
    parts = [_I64.pack(t_ns), _U32.pack(len(messages))]
    for topic, type_, md5, data in messages:
        parts += [_s(topic), _s(type_), _s(md5), _b(data)]
    return _frame(STEP, b"".join(parts))


def encode_end() -> bytes:
    return _frame(END, b"")


def encode_adv(node: str, topic: str, type_: str, md5: str, latch: bool) -> bytes:
    return _frame(ADV, _s(node) + _s(topic) + _s(type_) + _s(md5) + bytes([1 if latch else 0]))


def encode_sub(node: str, topic: str, type_: str, md5: str, queue_size: int) -> bytes:
    return _frame(SUB, _s(node) + _s(topic) + _s(type_) + _s(md5) + _I32.pack(queue_size))


def encode_msg(node: str, topic: str, t_ns: int, data: bytes) -> bytes:
    return _frame(MSG, _s(node) + _s(topic) + _I64.pack(t_ns) + _b(data))


def encode_gone(node: str) -> bytes:
    return _frame(GONE, _s(node))


def encode_call(call_id: int, service: str, data: bytes) -> bytes:
    return _frame(CALL, _I64.pack(call_id) + _s(service) + _b(data))


def encode_srv(node: str, service: str, type_: str, md5: str) -> bytes:
    return _frame(SRV, _s(node) + _s(service) + _s(type_) + _s(md5))


def encode_resp(call_id: int, ok: bool, data: bytes | str) -> bytes:
    """``data``: the response's bytes (ok) or the error text, cut to :data:`MAX_ERROR` bytes."""
    if isinstance(data, str):
        data = _cut(data, MAX_ERROR)
    return _frame(RESP, _I64.pack(call_id) + bytes([1 if ok else 0]) + _b(data))


def _cut(text: str, limit: int) -> bytes:
    """``text`` as UTF-8 of at most ``limit`` bytes, cut at a character's boundary."""
    return text.encode("utf-8", "replace")[:limit].decode("utf-8", "ignore").encode("utf-8")


def encode_died(node: str, t_ns: int, fatal: bool, text: str) -> bytes:
    """``text`` is cut to :data:`MAX_ERROR` bytes, ``node`` to :data:`MAX_STR`."""
    return _frame(DIED, _s(_cut(node, MAX_STR).decode("utf-8")) + _I64.pack(t_ns)
                  + bytes([1 if fatal else 0]) + _b(_cut(text, MAX_ERROR)))


def encode_read(node: str, key: str, found: bool) -> bytes:
    return _frame(READ, _s(_cut(node, MAX_STR).decode("utf-8"))
                  + _s(_cut(key, MAX_STR).decode("utf-8")) + bytes([1 if found else 0]))


def encode_offer(service: str, type_: str, md5: str) -> bytes:
    return _frame(OFFER, _s(service) + _s(type_) + _s(md5))


def encode_answer(ask_id: int, ok: bool, data: bytes | str) -> bytes:
    """``data``: the response's bytes (ok) or the error text, cut to :data:`MAX_ERROR` bytes."""
    if isinstance(data, str):
        data = _cut(data, MAX_ERROR)
    return _frame(ANSWER, _I64.pack(ask_id) + bytes([1 if ok else 0]) + _b(data))


def encode_ask(ask_id: int, node: str, service: str, data: bytes) -> bytes:
    return _frame(ASK, _I64.pack(ask_id) + _s(node) + _s(service) + _b(data))


def encode_ready() -> bytes:
    return _frame(READY, b"")


def encode_done(next_ns: int) -> bytes:
    return _frame(DONE, _I64.pack(next_ns))


def decode_header(header: bytes) -> tuple[int, int]:
    """``(kind, payload length)`` of a 7-byte header; ProtocolError if it is not one."""
    if len(header) != HEADER.size:
        raise ProtocolError(f"cut frame header ({len(header)} of {HEADER.size} bytes)")
    magic, kind, length = HEADER.unpack(header)
    if magic != MAGIC:
        raise ProtocolError(f"bad frame magic {magic!r} (expected {MAGIC!r})")
    if kind not in _KINDS:
        raise ProtocolError(f"unknown frame kind {kind}")
    if length > MAX_FRAME:
        raise ProtocolError(f"frame announces {length} bytes (at most {MAX_FRAME})")
    return kind, length


class _Reader:
    def __init__(self, data: bytes) -> None:
        self.data = data
        self.pos = 0

    def take(self, n: int) -> bytes:
        end = self.pos + n
        if end > len(self.data):
            raise ProtocolError(f"frame field runs past the payload ({end} > {len(self.data)})")
        out = self.data[self.pos:end]
        self.pos = end
        return out

    def s(self) -> str:
        (n,) = _U16.unpack(self.take(2))
        if n > MAX_STR:
            raise ProtocolError(f"string field of {n} bytes (at most {MAX_STR})")
        try:
            return self.take(n).decode("utf-8")
        except UnicodeDecodeError:
            raise ProtocolError("string field is not UTF-8") from None

    def b(self) -> bytes:
        (n,) = _U32.unpack(self.take(4))
        return self.take(n)

    def i64(self) -> int:
        return int(_I64.unpack(self.take(8))[0])

    def i32(self) -> int:
        return int(_I32.unpack(self.take(4))[0])

    def u8(self) -> int:
        return self.take(1)[0]

    def end(self) -> None:
        if self.pos != len(self.data):
            raise ProtocolError(f"{len(self.data) - self.pos} stray bytes after the frame's fields")


def decode_frame(kind: int, payload: bytes) -> Frame:
    """The frame of ``kind`` from its payload (None for END and READY); ProtocolError on any
    bad field."""
    r = _Reader(payload)
    out: Frame
    if kind == STEP:
        t = r.i64()
        (n,) = _U32.unpack(r.take(4))
        msgs = []
        for _ in range(n):
            msgs.append((r.s(), r.s(), r.s(), r.b()))
        out = Step(t, tuple(msgs))
    elif kind in (END, READY):
        out = None
    elif kind == ADV:
        node, topic, type_, md5 = r.s(), r.s(), r.s(), r.s()
        latch = r.u8()
        if latch not in (0, 1):
            raise ProtocolError(f"latch flag {latch} (0 or 1)")
        out = Adv(node, topic, type_, md5, bool(latch))
    elif kind == SUB:
        out = Sub(r.s(), r.s(), r.s(), r.s(), r.i32())
    elif kind == MSG:
        out = Msg(r.s(), r.s(), r.i64(), r.b())
    elif kind == GONE:
        out = Gone(r.s())
    elif kind == DONE:
        out = Done(r.i64())
    elif kind == CALL:
        out = Call(r.i64(), r.s(), r.b())
    elif kind == SRV:
        out = Srv(r.s(), r.s(), r.s(), r.s())
    elif kind == OFFER:
        out = Offer(r.s(), r.s(), r.s())
    elif kind == ANSWER:
        ask_id, ok = r.i64(), r.u8()
        if ok not in (0, 1):
            raise ProtocolError(f"ok flag {ok} (0 or 1)")
        out = Answer(ask_id, bool(ok), r.b())
    elif kind == ASK:
        out = Ask(r.i64(), r.s(), r.s(), r.b())
    elif kind == DIED:
        node, t, fatal = r.s(), r.i64(), r.u8()
        if fatal not in (0, 1):
            raise ProtocolError(f"fatal flag {fatal} (0 or 1)")
        raw = r.b()
        if len(raw) > MAX_ERROR:
            raise ProtocolError(f"death text of {len(raw)} bytes (at most {MAX_ERROR})")
        try:
            out = Died(node, t, bool(fatal), raw.decode("utf-8"))
        except UnicodeDecodeError:
            raise ProtocolError("death text is not UTF-8") from None
    elif kind == READ:
        node, key = r.s(), r.s()
        found = r.u8()
        if found not in (0, 1):
            raise ProtocolError(f"found flag {found} (0 or 1)")
        out = Read(node, key, bool(found))
    elif kind == RESP:
        call_id, ok = r.i64(), r.u8()
        if ok not in (0, 1):
            raise ProtocolError(f"ok flag {ok} (0 or 1)")
        data = r.b()
        if not ok and len(data) > MAX_ERROR:
            raise ProtocolError(f"error text of {len(data)} bytes (at most {MAX_ERROR})")
        out = Resp(call_id, bool(ok), data)
    else:  # decode_header refused it already
        raise ProtocolError(f"unknown frame kind {kind}")
    r.end()
    return out
