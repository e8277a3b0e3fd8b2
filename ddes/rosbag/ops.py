"""Operations on bags and bag files: filter, compress, decompress, reindex.

``filter_bag`` is ``rosbag filter``: a Python expression over ``topic``,
``m`` (the message) and ``t`` (its Time) chooses the messages to keep; the
output keeps each topic's original connection header.  rosbag ``eval``s the
expression with everything in scope; ddes parses it once with
:mod:`ddes.expr`, a safe subset of Python evaluated without ``eval``
(names ``topic``, ``m``, ``t``, ``math``, ``Time``, ``Duration``; the
methods ``to_sec``, ``to_nsec``, ``is_zero`` of times; see docs/bags.md).
A typo is a :class:`~ddes.errors.ROSBagException` before any message is
read; anything outside the subset is also an
:class:`~ddes.errors.UnsafeExpressionError` (:class:`UnsafeBagExpression`),
anything too costly a :class:`~ddes.errors.ResourceLimitError`
(:class:`CostlyBagExpression`); a failure on a message names the message.
Each evaluation on a message may touch at most :data:`FILTER_WORK_PER_MESSAGE`
items plus :data:`FILTER_WORK_PER_BYTE` per byte of the serialized message
(never more than :data:`ddes.expr.MAX_WORK`), so a filter's cost is bounded
by the bag's size: past it, :class:`CostlyBagExpression` naming the
expression and the message.

``change_compression`` and ``reindex_file`` are ``rosbag compress``,
``decompress`` and ``reindex`` on one file with rosbag's backup rule: the
original becomes ``NAME.orig.bag`` unless ``output_dir`` is given, and an
existing backup is kept unless ``force``.
"""

from __future__ import annotations

import math
import os
import shutil
from collections.abc import Callable
from typing import TYPE_CHECKING

from ddes import expr as safe_expr
from ddes.errors import DdesError, ResourceLimitError, ROSBagException, UnsafeExpressionError
from ddes.rosbag.bag import Bag
from ddes.time.rostime import Duration, Time

if TYPE_CHECKING:
    from ddes.msg.message import Message

__all__ = ["FILTER_WORK_PER_BYTE", "FILTER_WORK_PER_MESSAGE", "BagExpression",
           "CostlyBagExpression", "UnsafeBagExpression", "backup_name", "change_compression",
           "compile_expression", "filter_bag", "filter_budget", "reindex_file"]

#: Items one evaluation of a filter (or print) expression may touch on any message ...
FILTER_WORK_PER_MESSAGE = 10_000
#: ... plus this many per byte of the message's serialized data (``len(m.data)`` on a 1 MB
#: image touches a million items); never more than ``ddes.expr.MAX_WORK``.
FILTER_WORK_PER_BYTE = 16

#: A compiled ``rosbag filter`` expression: ``(topic, m, t) -> value`` (truth tested or printed);
#: a fourth argument, ``budget``, bounds the work of that evaluation (see :func:`filter_budget`).
BagExpression = Callable[..., object]

#: Methods an expression may call on a Time or Duration (``t.to_sec()``); class methods.
_TIME_METHODS = frozenset({"to_sec", "to_nsec", "is_zero"})
_METHODS: dict[type, frozenset[str]] = {Time: _TIME_METHODS, Duration: _TIME_METHODS}
_CLASS_METHODS: dict[type, frozenset[str]] = {Time: frozenset({"from_sec"}),
                                              Duration: frozenset({"from_sec"})}


class UnsafeBagExpression(ROSBagException, UnsafeExpressionError):
    """A filter or print expression outside ddes's safe subset (both error kinds at once)."""


class CostlyBagExpression(ROSBagException, ResourceLimitError):
    """A filter or print expression that would cost more than ddes allows."""


def _bag_error(exc: DdesError, message: str) -> ROSBagException:
    if isinstance(exc, UnsafeExpressionError):
        return UnsafeBagExpression(message)
    if isinstance(exc, ResourceLimitError):
        return CostlyBagExpression(message)
    return ROSBagException(message)


def compile_expression(expr: str, what: str = "filter expression") -> BagExpression:
    """``(topic, m, t) -> <expr>``, parsed once into ddes's safe subset (no ``eval``)."""
    if not isinstance(expr, str) or not expr.strip():
        raise ROSBagException(f"{what} must be a non-empty Python expression, got {expr!r}")
    try:
        parsed = safe_expr.parse(expr, functions=(Time, Duration), methods=_METHODS,
                                 class_methods=_CLASS_METHODS)
    except DdesError as exc:
        raise _bag_error(exc, f"{what} {expr!r}: {exc}") from None

    def fn(topic: str, m: Message, t: Time, budget: int | None = None) -> object:
        return parsed.evaluate({"topic": topic, "m": m, "t": t, "math": math, "Time": Time,
                                "Duration": Duration}, budget=budget)

    return fn


def filter_budget(size: int) -> int:
    """Items an expression may touch on a message of ``size`` serialized bytes."""
    return min(FILTER_WORK_PER_MESSAGE + FILTER_WORK_PER_BYTE * size, safe_expr.MAX_WORK)


def _call(fn: BagExpression, expr: str, what: str, index: int, topic: str, msg: Message,
          t: Time, size: int) -> object:
    budget = filter_budget(size)
    try:
        return fn(topic, msg, t, budget)
    except DdesError as exc:
        why = ""
        if isinstance(exc, ResourceLimitError) and "items touched" in str(exc):
            why = (f" (on a message of {size} bytes an expression may touch {budget} items: "
                   f"ddes.rosbag.ops.FILTER_WORK_PER_MESSAGE + FILTER_WORK_PER_BYTE per byte, "
                   f"at most ddes.expr.MAX_WORK; write a cheaper expression)")
        raise _bag_error(exc, f"{what} {expr!r} failed on message {index} ({topic} at "
                              f"{t.to_sec():.9f}): {exc}{why}") from None


def filter_bag(inbag: Bag, outbag: Bag, expr: str, *, print_expr: str | None = None,
               out: Callable[[str], None] | None = None) -> int:
    """Copy the messages of ``inbag`` for which ``expr`` is true into ``outbag``; returns how many.

    With ``print_expr`` each message prints ``MATCH <value>`` or ``NO MATCH
    <value>`` through ``out`` (``rosbag filter -p``).
    """
    keep = compile_expression(expr)
    show = compile_expression(print_expr, "print expression") if print_expr else None
    kept = 0
    conns = {c.id: c for c in inbag.get_connections()}
    for index, (t_ns, cid, data) in enumerate(inbag._entries(conns.values())):
        conn = conns[cid]
        msg = inbag._deserialize(conn, t_ns, data)
        t = Time._from_ns(t_ns)
        ok = _call(keep, expr, "filter expression", index, conn.topic, msg, t, len(data))
        if show is not None and out is not None:
            value = _call(show, print_expr or "", "print expression", index, conn.topic, msg, t,
                          len(data))
            try:
                text = safe_expr.to_text(value)
            except DdesError as exc:
                raise _bag_error(exc, f"print expression {print_expr!r} on message {index}: "
                                      f"{exc}") from None
            out(f"{'MATCH' if ok else 'NO MATCH'} {text}")
        if ok:
            outbag.write(conn.topic, (conn.datatype, data, conn.md5sum, None, type(msg)), t,
                         raw=True, connection_header=conn.header)
            kept += 1
    return kept


def backup_name(path: str) -> str:
    """rosbag's backup name: ``x.bag`` → ``x.orig.bag``."""
    root, ext = os.path.splitext(path)
    return f"{root}.orig{ext}"


def _rewrite(path: str, output_dir: str | None, force: bool, copy: bool,
             build: Callable[[str], tuple[Bag, str]]) -> str | None:
    """rosbag's ``bag_op``: back the input up (or write elsewhere), then write the result.

    Returns a message to print when the file is skipped, else None.
    """
    out_path = path if output_dir is None else os.path.join(output_dir, os.path.basename(path))
    source = path
    if out_path == path:
        backup = backup_name(path)
        if not force and os.path.exists(backup):
            return f"Skipping {path}. Backup path {backup} already exists."
        try:
            if copy:
                shutil.copy(path, backup)
            else:
                os.replace(path, backup)
        except OSError as exc:
            raise ROSBagException(f"ERROR {'copying' if copy else 'moving'} {path} to {backup}: "
                                  f"{exc.strerror}") from None
        source = backup
    bag, compression = build(source)
    bag.save(out_path, compression=compression)
    return None


def change_compression(path: str, compression: str, *, output_dir: str | None = None,
                       force: bool = False) -> str | None:
    """``rosbag compress``/``decompress`` of one file (see :func:`_rewrite` for the backup)."""
    Bag(path).get_message_count()  # the input must be readable before anything moves
    return _rewrite(path, output_dir, force, False, lambda src: (Bag(src), compression))


def reindex_file(path: str, *, output_dir: str | None = None, force: bool = False) -> str | None:
    """``rosbag reindex`` of one file: keep every complete chunk, rebuild the index."""
    Bag(path, allow_unindexed=True)

    def build(src: str) -> tuple[Bag, str]:
        bag = Bag(src, allow_unindexed=True)
        return bag, bag.get_compression_info().compression

    return _rewrite(path, output_dir, force, True, build)

