"""Bounded YAML for parameters: every YAML that ddes reads from a user goes through here.

PyYAML's ``safe_load`` runs no code, but it is not safe against size: an
alias bomb ("billion laughs": nine anchors of nine aliases each) is a few
hundred bytes that stand for 387 million values, which the parameter
server would copy, dump or walk; ``[[[[...]]]]`` nested a few hundred deep
ends in a ``RecursionError``; a recursive alias (``&a [*a]``) makes a
list that contains itself; and rosparam's ``!radians`` runs Python's
``eval`` (``!radians 9**9**9`` never returns).  The loaders here refuse all
of these with :class:`~ddes.errors.ResourceLimitError` before anything is
expanded:

* the text may hold at most ``max_bytes`` characters (16 MiB);
* at most ``max_documents`` documents (1000) in one stream;
* at most ``max_nodes`` values (100,000) *after* alias expansion, counted
  without expanding (each anchored node is sized once);
* nesting at most ``max_depth`` deep (64), after alias expansion too;
* no recursive alias.

``!degrees``/``!radians`` and ``deg(..)``/``rad(..)`` (the tags that
importing ``rosparam`` installs) are evaluated by a tiny arithmetic
evaluator on :mod:`ast`: numbers, ``pi``, ``+ - * / // % **`` and
parentheses, in floating point (so ``9**9**9`` overflows at once), at most
256 characters and 64 operations.  rosparam evaluates ``!radians`` with
``eval`` and ``!degrees`` with ``float()``; ddes keeps ``float()`` for degrees.

:func:`read_bounded` reads a file for any loader (launch XML, rosparam
YAML, ``textfile=``/``binfile=``): it refuses anything that is not a
regular file (``/dev/zero``, a FIFO, a directory, a device) *before*
opening it, and files larger than the limit, without reading past it.
"""

from __future__ import annotations

import ast
import math
import os
import re
import stat
from dataclasses import dataclass
from typing import Any

import yaml

from ddes.errors import DdesError, ResourceLimitError

__all__ = [
    "DEFAULT_LIMITS",
    "MAX_FILE_BYTES",
    "YamlLimits",
    "evaluate_angle",
    "load_yaml",
    "load_yaml_all",
    "read_bounded",
]

#: The largest file any ddes loader reads (launch XML, YAML, textfile/binfile).
MAX_FILE_BYTES = 16 * 1024 * 1024

_MAX_EXPR_CHARS = 256
_MAX_EXPR_NODES = 64


@dataclass(frozen=True)
class YamlLimits:
    """How much YAML one load may hold (see the module docstring)."""

    max_bytes: int = MAX_FILE_BYTES
    max_nodes: int = 100_000
    max_depth: int = 64
    max_documents: int = 1000


DEFAULT_LIMITS = YamlLimits()

_RAISE = ("split the YAML into several smaller files, or pass "
          "limits=ddes.graph.yamlsafe.YamlLimits(...) where the input is genuine")


# -- angles ------------------------------------------------------------------------------------


def _arith(node: ast.AST) -> float:
    if isinstance(node, ast.Expression):
        return _arith(node.body)
    if isinstance(node, ast.Constant) and type(node.value) in (int, float):
        return float(node.value)  # type: ignore[arg-type]
    if isinstance(node, ast.Name) and node.id == "pi":
        return math.pi
    if isinstance(node, ast.UnaryOp) and isinstance(node.op, (ast.UAdd, ast.USub)):
        v = _arith(node.operand)
        return v if isinstance(node.op, ast.UAdd) else -v
    if isinstance(node, ast.BinOp):
        a, b = _arith(node.left), _arith(node.right)
        op = node.op
        if isinstance(op, ast.Add):
            return a + b
        if isinstance(op, ast.Sub):
            return a - b
        if isinstance(op, ast.Mult):
            return a * b
        if isinstance(op, ast.Div):
            return a / b
        if isinstance(op, ast.FloorDiv):
            return a // b
        if isinstance(op, ast.Mod):
            return a % b
        if isinstance(op, ast.Pow):
            r = a**b  # floats: overflows at once instead of building a huge int
            if not isinstance(r, float):
                raise ValueError("the power has no real value")
            return r
    raise ValueError("only numbers, pi, + - * / // % ** and parentheses are allowed")


def evaluate_angle(expr: str) -> float:
    """Evaluate a ``!radians`` expression: arithmetic on numbers and ``pi`` only (no eval).

    Raises :class:`ValueError` (a plain one, for the YAML constructor to
    wrap) on anything else, on overflow and on division by zero.
    """
    text = expr.strip()
    if len(text) > _MAX_EXPR_CHARS:
        raise ValueError(f"expression longer than {_MAX_EXPR_CHARS} characters")
    try:
        tree = ast.parse(text, mode="eval")
    except (SyntaxError, ValueError, MemoryError, RecursionError) as exc:
        raise ValueError(f"not an arithmetic expression ({type(exc).__name__})") from None
    if sum(1 for _ in ast.walk(tree)) > _MAX_EXPR_NODES:
        raise ValueError(f"more than {_MAX_EXPR_NODES} operations")
    try:
        return _arith(tree)
    except OverflowError:
        raise ValueError("the result is too large for a float") from None
    except (ArithmeticError, TypeError) as exc:
        raise ValueError(str(exc) or type(exc).__name__) from None


def _construct_radians(loader: yaml.SafeLoader, node: yaml.Node) -> float:
    value = str(loader.construct_scalar(node)).strip()  # type: ignore[arg-type]
    expr = value[4:-1] if value.startswith("rad(") else value
    try:
        return evaluate_angle(expr)
    except ValueError as exc:
        raise yaml.constructor.ConstructorError(
            None, None,
            f"invalid radian expression: {value[:80]!r} ({exc}); write numbers, pi, "
            "+ - * / // % ** and parentheses, e.g. !radians pi/2",
            node.start_mark,
        ) from None


def _construct_degrees(loader: yaml.SafeLoader, node: yaml.Node) -> float:
    value = str(loader.construct_scalar(node))  # type: ignore[arg-type]
    expr = value.strip()[4:-1] if value.startswith("deg(") else value
    try:
        return float(expr) * math.pi / 180.0
    except ValueError:
        raise yaml.constructor.ConstructorError(
            None, None,
            f"invalid degree value: {value[:80]} (rosparam takes one number, e.g. !degrees 90)",
            node.start_mark,
        ) from None


# -- the bounded loader -------------------------------------------------------------------------


class _BoundedLoader(yaml.SafeLoader):
    """SafeLoader that counts and bounds what it composes, then sizes the expansion."""

    limits: YamlLimits = DEFAULT_LIMITS

    def __init__(self, stream: str) -> None:
        super().__init__(stream)
        self._depth = 0
        self._composed = 0
        self._expanded = 0
        self._documents = 0

    def compose_node(self, parent: yaml.Node | None, index: int) -> yaml.Node | None:
        lim = self.limits
        self._depth += 1
        self._composed += 1
        try:
            if self._depth > lim.max_depth:
                event = self.peek_event()  # type: ignore[no-untyped-call]
                raise ResourceLimitError(
                    f"YAML nested more than {lim.max_depth} deep (at line "
                    f"{event.start_mark.line + 1}); flatten the structure or {_RAISE}")
            if self._composed > lim.max_nodes:
                raise ResourceLimitError(
                    f"YAML holds more than {lim.max_nodes} values; {_RAISE}")
            return super().compose_node(parent, index)
        finally:
            self._depth -= 1

    def compose_document(self) -> yaml.Node | None:
        self._documents += 1
        if self._documents > self.limits.max_documents:
            raise ResourceLimitError(
                f"YAML stream holds more than {self.limits.max_documents} documents; {_RAISE}")
        return super().compose_document()

    def construct_document(self, node: yaml.Node) -> Any:
        self._size(node, 1, {}, set())
        return super().construct_document(node)

    def _size(self, node: yaml.Node, depth: int, memo: dict[int, tuple[int, int]],
              path: set[int]) -> tuple[int, int]:
        """(values, height) of ``node`` with aliases expanded; refuse past the limits."""
        lim = self.limits
        key = id(node)
        if key in memo:
            count, height = memo[key]
        else:
            if key in path:
                raise ResourceLimitError(
                    f"recursive YAML alias at line {node.start_mark.line + 1}: an anchor "
                    "refers to itself, so its value would be infinite; remove the alias")
            children: list[yaml.Node] = []
            if isinstance(node, yaml.SequenceNode):
                children = list(node.value)
            elif isinstance(node, yaml.MappingNode):
                children = [n for pair in node.value for n in pair]
            count, height = 1, 1
            path.add(key)
            for child in children:
                c, h = self._size(child, depth + 1, memo, path)
                count += c
                height = max(height, h + 1)
                if count > lim.max_nodes:
                    break
            path.discard(key)
            memo[key] = (count, height)
        if depth - 1 + height > lim.max_depth:
            raise ResourceLimitError(
                f"YAML nested more than {lim.max_depth} deep once its aliases are expanded "
                f"(line {node.start_mark.line + 1}); flatten the structure or {_RAISE}")
        if depth == 1:
            self._expanded += count
            if self._expanded > lim.max_nodes:
                raise ResourceLimitError(
                    f"YAML expands to more than {lim.max_nodes} values once its aliases are "
                    f"expanded (an alias bomb? {self._composed} values written); {_RAISE}")
        elif count > lim.max_nodes:
            raise ResourceLimitError(
                f"YAML expands to more than {lim.max_nodes} values (an alias bomb? "
                f"{self._composed} values written, line {node.start_mark.line + 1}); {_RAISE}")
        return count, height


class _AngleLoader(_BoundedLoader):
    """The bounded loader plus rosparam's angle tags (configured once, at import)."""


_AngleLoader.add_constructor("!radians", _construct_radians)
_AngleLoader.add_constructor("!degrees", _construct_degrees)
_AngleLoader.add_implicit_resolver("!degrees", re.compile(r"^deg\([^\)]*\)$"), ["d"])
_AngleLoader.add_implicit_resolver("!radians", re.compile(r"^rad\([^\)]*\)$"), ["r"])


def _loader(text: str, angles: bool, limits: YamlLimits) -> _BoundedLoader:
    if not isinstance(text, str):
        raise yaml.YAMLError(f"YAML must be text, got {type(text).__name__}")
    if len(text) > limits.max_bytes:
        raise ResourceLimitError(
            f"YAML text of {len(text)} characters is larger than the {limits.max_bytes} "
            f"ddes reads; {_RAISE}")
    loader = (_AngleLoader if angles else _BoundedLoader)(text)
    loader.limits = limits
    return loader


def _guard(exc: Exception) -> yaml.YAMLError:
    """PyYAML lets a few builtin errors out of its constructors; make them YAML errors."""
    return yaml.constructor.ConstructorError(
        None, None, f"cannot construct a value: {str(exc)[:200]}", None)


def load_yaml(text: str, *, angles: bool = False, limits: YamlLimits = DEFAULT_LIMITS) -> Any:
    """``yaml.safe_load`` within ``limits`` (``angles``: rosparam's ``!degrees``/``!radians``).

    Raises :class:`~ddes.errors.ResourceLimitError` past a limit and
    :class:`yaml.YAMLError` on malformed YAML (callers turn it into their
    own ROS error); nothing else.
    """
    loader = _loader(text, angles, limits)
    try:
        return loader.get_single_data()
    except (DdesError, yaml.YAMLError):
        raise
    except (ValueError, TypeError, ArithmeticError, LookupError, AttributeError,
            RecursionError, MemoryError) as exc:
        raise _guard(exc) from None
    finally:
        loader.dispose()


def load_yaml_all(text: str, *, angles: bool = False,
                  limits: YamlLimits = DEFAULT_LIMITS) -> list[Any]:
    """``yaml.safe_load_all`` within ``limits``: every document, as a list."""
    loader = _loader(text, angles, limits)
    docs: list[Any] = []
    try:
        while loader.check_data():  # type: ignore[no-untyped-call]
            docs.append(loader.get_data())
        return docs
    except (DdesError, yaml.YAMLError):
        raise
    except (ValueError, TypeError, ArithmeticError, LookupError, AttributeError,
            RecursionError, MemoryError) as exc:
        raise _guard(exc) from None
    finally:
        loader.dispose()


# -- files ---------------------------------------------------------------------------------------


def read_bounded(path: str | os.PathLike[str], *, what: str, error: type[DdesError],
                 limit: int = MAX_FILE_BYTES) -> bytes:
    """The bytes of the regular file ``path``, refusing anything else before opening it.

    A missing file, a directory, a FIFO, a device (``/dev/zero``) or a
    socket raises ``error`` naming ``what`` and the path; a file larger than
    ``limit`` raises :class:`~ddes.errors.ResourceLimitError` (checked on
    ``stat`` first and again while reading, so a file that grows, or a
    ``/proc`` file that reports size 0, cannot exceed it).
    """
    name = os.fspath(path)
    try:
        st = os.stat(name)
    except FileNotFoundError:
        raise error(f"{what} not found: {name}; check the path") from None
    except (OSError, ValueError) as exc:
        raise error(f"cannot read {what} {name}: {getattr(exc, 'strerror', None) or exc}"
                    ) from None
    if not stat.S_ISREG(st.st_mode):
        kind = ("a directory" if stat.S_ISDIR(st.st_mode) else
                "a FIFO (named pipe)" if stat.S_ISFIFO(st.st_mode) else
                "a device" if stat.S_ISCHR(st.st_mode) or stat.S_ISBLK(st.st_mode) else
                "a socket" if stat.S_ISSOCK(st.st_mode) else "not a regular file")
        raise error(f"{what} {name} is {kind}, not a regular file; give the path of a file")
    too_big = (f"{what} {name} is larger than {limit} bytes, the most ddes reads; "
               "split it into smaller files")
    if st.st_size > limit:
        raise ResourceLimitError(f"{too_big} (it is {st.st_size} bytes)")
    try:
        with open(name, "rb") as f:
            data = f.read(limit + 1)
    except OSError as exc:
        raise error(f"cannot read {what} {name}: {exc.strerror}") from None
    if len(data) > limit:
        raise ResourceLimitError(too_big)
    return data
