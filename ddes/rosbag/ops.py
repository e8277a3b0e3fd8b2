"""Operations on bags and bag files: filter, compress, decompress, reindex.

``filter_bag`` is ``rosbag filter``: a Python expression over ``topic``,
``m`` (the message) and ``t`` (its Time) chooses the messages to keep; the
output keeps each topic's original connection header.  rosbag ``eval``s the
expression with everything in scope; ddes compiles it once with a
restricted namespace (a few harmless builtins, ``math``, ``Time``,
``Duration``; no names or attributes starting with ``_``, no ``format``),
so a typo or a forbidden name is a :class:`~ddes.errors.ROSBagException`
before any message is read, and a failure on a message names the message.
This keeps mistakes out; it is not a sandbox for hostile input.

``change_compression`` and ``reindex_file`` are ``rosbag compress``,
``decompress`` and ``reindex`` on one file with rosbag's backup rule: the
original becomes ``NAME.orig.bag`` unless ``output_dir`` is given, and an
existing backup is kept unless ``force``.
"""

from __future__ import annotations

import ast
import builtins
import math
import os
import shutil
from collections.abc import Callable
from typing import TYPE_CHECKING

from ddes.errors import ROSBagException
from ddes.rosbag.bag import Bag
from ddes.time.rostime import Duration, Time

if TYPE_CHECKING:
    from ddes.msg.message import Message

__all__ = ["BagExpression", "backup_name", "change_compression", "compile_expression",
           "filter_bag", "reindex_file"]

#: A compiled ``rosbag filter`` expression: ``(topic, m, t) -> value`` (truth tested or printed).
BagExpression = Callable[[str, "Message", Time], object]

_SAFE_BUILTINS: dict[str, Callable[..., object]] = {
    name: getattr(builtins, name)
    for name in ("abs", "all", "any", "bool", "dict", "divmod", "enumerate", "float", "frozenset",
                 "int", "isinstance", "len", "list", "max", "min", "range", "repr", "reversed",
                 "round", "set", "sorted", "str", "sum", "tuple", "zip")
}
_FORBIDDEN_ATTRS = {"format", "format_map", "mro"}


def _check_names(tree: ast.AST, expr: str, what: str) -> None:
    for node in ast.walk(tree):
        name = None
        if isinstance(node, ast.Name):
            name = node.id
        elif isinstance(node, ast.Attribute):
            name = node.attr
            if name in _FORBIDDEN_ATTRS:
                raise ROSBagException(f"{what} {expr!r}: the attribute '.{name}' is not allowed")
        if name is not None and name.startswith("_"):
            raise ROSBagException(f"{what} {expr!r}: names starting with '_' ({name}) are not "
                                  "allowed")
        if isinstance(node, (ast.NamedExpr, ast.Await, ast.Yield, ast.YieldFrom)):
            raise ROSBagException(f"{what} {expr!r}: {type(node).__name__} is not allowed")


def compile_expression(expr: str, what: str = "filter expression") -> BagExpression:
    """``lambda topic, m, t: <expr>`` compiled in a restricted namespace."""
    if not isinstance(expr, str) or not expr.strip():
        raise ROSBagException(f"{what} must be a non-empty Python expression, got {expr!r}")
    try:
        tree = ast.parse(expr.strip(), mode="eval")
    except SyntaxError as exc:
        raise ROSBagException(f"{what} {expr!r} is not a valid Python expression: {exc.msg} "
                              f"(column {exc.offset})") from None
    _check_names(tree, expr, what)
    args = ast.arguments(posonlyargs=[], args=[ast.arg("topic"), ast.arg("m"), ast.arg("t")],
                         kwonlyargs=[], kw_defaults=[], defaults=[])
    lam = ast.Expression(ast.Lambda(args, tree.body))
    ast.fix_missing_locations(lam)
    scope = {"__builtins__": _SAFE_BUILTINS, "math": math, "Time": Time, "Duration": Duration}
    fn = eval(compile(lam, f"<{what}>", "eval"), scope)  # noqa: S307 - names checked above
    return fn  # type: ignore[no-any-return]


def _call(fn: BagExpression, expr: str, what: str, index: int, topic: str, msg: Message,
          t: Time) -> object:
    try:
        return fn(topic, msg, t)
    except Exception as exc:  # noqa: BLE001 - the user's expression may raise anything
        raise ROSBagException(
            f"{what} {expr!r} failed on message {index} ({topic} at {t.to_sec():.9f}): "
            f"{type(exc).__name__}: {exc}") from None


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
        ok = _call(keep, expr, "filter expression", index, conn.topic, msg, t)
        if show is not None and out is not None:
            value = _call(show, print_expr or "", "print expression", index, conn.topic, msg, t)
            out(f"{'MATCH' if ok else 'NO MATCH'} {value}")
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

