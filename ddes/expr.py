"""A safe subset of Python expressions, evaluated without ``eval``.

``rosbag filter``, ``rostopic echo --filter``/``hz --filter`` and roslaunch's
``$(eval ...)`` take a Python expression from the user.  ROS hands it to
``eval``; a restricted ``__builtins__`` is no sandbox there (a generator's
``gi_frame.f_back.f_globals`` reaches any module).  ddes parses the text with
:mod:`ast` and walks the tree itself, so only what is listed here can run:

* literals (numbers, strings, bytes, ``True``/``False``/``None``, tuples,
  lists, dicts, sets), ``+ - * / // % ** << >> & | ^ ~``, comparisons (chained
  too), ``in``/``not in``/``is``/``is not``, ``and``/``or``/``not``,
  ``a if c else b``, subscripts and slices, f-strings (a format spec only on
  numbers and strings, widths up to 1000);
* names from the caller's namespace (``topic``, ``m``, ``t``; launch's args),
  then the functions of :data:`SAFE_FUNCTIONS` and the caller's own functions;
* attributes of values (message fields, ``t.secs``) and of ``math``;
* calls of :data:`SAFE_FUNCTIONS`, ``math`` functions, the caller's
  functions, and the methods of :data:`SAFE_METHODS` (``str.startswith``,
  ``str.split``, ``dict.get`` ...) plus those the caller allows
  (``Time.to_sec``).

Refused with :class:`~ddes.errors.UnsafeExpressionError`: every name or
attribute starting with ``_``, frame/generator/code attributes
(``gi_frame``, ``f_back``, ``tb_frame`` ...), ``format``/``format_map``,
lambda, comprehensions and generator expressions, ``:=``, ``*``/``**``
unpacking, ``await``/``yield``, and calls of anything else (``getattr``,
``open``, ``eval``, ``str.format``).  Refused with
:class:`~ddes.errors.ResourceLimitError` before the work is done: sources over
:data:`MAX_SOURCE_CHARS`, trees deeper than :data:`MAX_DEPTH`, integers over
:data:`MAX_INT_BITS` bits (``9**9**9``), strings, bytes, lists and ranges over
:data:`MAX_ITEMS` items (``'a' * 10**10``; a ``join`` or ``%``-format result is
sized before it is built), and evaluations that would touch more than
:data:`MAX_WORK` items in all (or the caller's lower ``budget``): a call is
charged for what it reads before it runs (a method its owner, each argument
its unfolded size, ``==`` both sides, ``pow(a, b, mod)`` its square-and-multiply
cost), so a cheap-looking expression cannot run for seconds.  An expression that fails on its
values (``1 / 0``, an unknown name) raises a ddes error whose message starts
with Python's (``ZeroDivisionError: division by zero``).
"""

from __future__ import annotations

import ast
import math
import re
import types
import warnings
from collections.abc import Callable, Collection, Iterable, Mapping
from typing import Any

from ddes.errors import (
    DdesAttributeError,
    DdesError,
    DdesKeyError,
    DdesTypeError,
    DdesValueError,
    ResourceLimitError,
    UnsafeExpressionError,
)

__all__ = ["MAX_DEPTH", "MAX_INT_BITS", "MAX_ITEMS", "MAX_SOURCE_CHARS", "MAX_WORK",
           "SAFE_FUNCTIONS", "SAFE_METHODS", "Expression", "deep_size", "evaluate", "parse",
           "to_text"]

#: Longest expression source, in characters.
MAX_SOURCE_CHARS = 10_000
#: Deepest syntax tree.
MAX_DEPTH = 100
#: Largest integer an operation may produce, in bits.
MAX_INT_BITS = 10_000
#: Largest string, bytes, list, tuple or range an operation may produce.
MAX_ITEMS = 1_000_000
#: Items one evaluation may touch in all (nodes, elements copied, compared, summed).
MAX_WORK = 5_000_000

#: The functions an expression may call by name (unless the caller shadows the name).
SAFE_FUNCTIONS: dict[str, Callable[..., Any]] = {
    f.__name__: f for f in (
        abs, all, any, bool, chr, dict, divmod, enumerate, filter, float, frozenset, int,
        isinstance, len, list, map, max, min, ord, pow, range, repr, reversed, round, set,
        sorted, str, sum, tuple, zip)
}

#: Functions that may be handed to ``map``, ``filter``, ``sorted(key=)``, ``min``/``max(key=)``:
#: only those whose cost is bounded by their argument's size.
_CHEAP_CALLBACKS: tuple[Callable[..., Any], ...] = (abs, bool, chr, float, int, len, ord)

#: Methods of builtin values an expression may call; none mutates, none formats.
SAFE_METHODS: dict[type, frozenset[str]] = {
    str: frozenset({"startswith", "endswith", "lower", "upper", "strip", "lstrip", "rstrip",
                    "split", "rsplit", "splitlines", "find", "rfind", "index", "rindex", "count",
                    "isdigit", "isalpha", "isalnum", "isspace", "isupper", "islower",
                    "isnumeric", "isdecimal", "casefold", "capitalize", "title", "swapcase",
                    "partition", "rpartition", "replace", "join"}),
    bytes: frozenset({"startswith", "endswith", "find", "count", "decode", "hex"}),
    dict: frozenset({"get", "keys", "values", "items"}),
    list: frozenset({"count", "index"}),
    tuple: frozenset({"count", "index"}),
}

#: Attribute names refused even without a leading ``_``: frames, code, generators, tracebacks.
_FORBIDDEN_ATTRS = frozenset({
    "gi_frame", "gi_code", "gi_yieldfrom", "gi_running", "cr_frame", "cr_code", "cr_await",
    "cr_origin", "ag_frame", "ag_code", "ag_await", "tb_frame", "tb_next", "tb_lasti",
    "f_back", "f_globals", "f_locals", "f_builtins", "f_code", "f_trace", "func_globals",
    "func_code", "im_func", "im_self", "mro", "format", "format_map"})

#: Builtins that must never be reachable, named in the refusal.
_FORBIDDEN_NAMES = frozenset({
    "getattr", "setattr", "delattr", "hasattr", "vars", "globals", "locals", "dir", "open",
    "exec", "eval", "compile", "input", "breakpoint", "help", "exit", "quit", "type", "object",
    "super", "classmethod", "staticmethod", "property", "memoryview", "bytearray", "id",
    "print", "iter", "next", "callable", "format"})

_MATH_NAMES = frozenset(k for k, v in vars(math).items()
                        if not k.startswith("_") and isinstance(v, (float, types.BuiltinFunctionType))
                        and k != "prod")

_ALLOWED_NODES = (
    "literals, + - * / // % ** << >> & | ^ ~, comparisons, in, is, and/or/not, "
    "'a if c else b', attributes, subscripts, slices, and calls of listed functions")

_BINOPS: dict[type, Callable[[Any, Any], Any]] = {
    ast.Add: lambda a, b: a + b, ast.Sub: lambda a, b: a - b, ast.Mult: lambda a, b: a * b,
    ast.Div: lambda a, b: a / b, ast.FloorDiv: lambda a, b: a // b, ast.Mod: lambda a, b: a % b,
    ast.Pow: lambda a, b: a ** b, ast.LShift: lambda a, b: a << b,
    ast.RShift: lambda a, b: a >> b, ast.BitOr: lambda a, b: a | b,
    ast.BitXor: lambda a, b: a ^ b, ast.BitAnd: lambda a, b: a & b,
    ast.MatMult: lambda a, b: a @ b,
}
_CMPOPS: dict[type, Callable[[Any, Any], Any]] = {
    ast.Eq: lambda a, b: a == b, ast.NotEq: lambda a, b: a != b, ast.Lt: lambda a, b: a < b,
    ast.LtE: lambda a, b: a <= b, ast.Gt: lambda a, b: a > b, ast.GtE: lambda a, b: a >= b,
    ast.Is: lambda a, b: a is b, ast.IsNot: lambda a, b: a is not b,
    ast.In: lambda a, b: a in b, ast.NotIn: lambda a, b: a not in b,
}
_UNARY: dict[type, Callable[[Any], Any]] = {
    ast.UAdd: lambda a: +a, ast.USub: lambda a: -a, ast.Invert: lambda a: ~a,
    ast.Not: lambda a: not a,
}
_NODE_WORDS = {
    "Lambda": "lambda", "ListComp": "a list comprehension", "SetComp": "a set comprehension",
    "DictComp": "a dict comprehension", "GeneratorExp": "a generator expression",
    "NamedExpr": "':=' (assignment expression)", "Starred": "'*' unpacking",
    "Await": "await", "Yield": "yield", "YieldFrom": "yield from",
}
#: printf-style conversions: ``%[(key)][flags][width][.precision][length]type``.
_PERCENT = re.compile(r"%(?:\(([^)]*)\))?[#0\- +]*(\*|\d+)?(?:\.(\*|\d+))?[hlL]?(.)", re.S)
#: format-spec mini language with plain numbers only.
_SPEC = re.compile(r"(?:.?[<>=^])?[+\- ]?z?#?0?(\d*)[,_]?(?:\.(\d+))?[bcdeEfFgGnosxX%]?\Z", re.S)
_MAX_WIDTH = 1000


def _refuse(what: str) -> UnsafeExpressionError:
    return UnsafeExpressionError(f"{what}; ddes evaluates a safe subset of Python: "
                                 f"{_ALLOWED_NODES} (see docs/reliability.md)")


def _too_big(what: str, limit: str) -> ResourceLimitError:
    return ResourceLimitError(f"{what} exceeds {limit}; simplify the expression (the limits "
                              "are ddes.expr.MAX_*)")


def _check_name(name: str, kind: str) -> None:
    if name.startswith("_"):
        raise _refuse(f"{kind} {name!r} is not allowed: names starting with '_' are refused "
                      "(as attributes too)")
    if kind == "attribute" and name in _FORBIDDEN_ATTRS:
        raise _refuse(f"the attribute {name!r} is not allowed (frame, code, generator, "
                      "format and mro attributes are refused)")


def _failure(exc: BaseException) -> DdesError:
    """A Python error of the expression's values, as a ddes error with Python's words."""
    text = f"{type(exc).__name__}: {exc}"
    if isinstance(exc, TypeError):
        return DdesTypeError(text)
    if isinstance(exc, AttributeError):
        return DdesAttributeError(text)
    if isinstance(exc, (KeyError, NameError)):
        return DdesKeyError(text)
    return DdesValueError(text)


class Expression:
    """A parsed, checked expression; :meth:`evaluate` runs it on a namespace.

    ``functions`` are extra callables the expression may call (launch's
    ``arg``, rosbag's ``Time``); ``methods`` maps a type to the method names an
    expression may call on its instances, ``class_methods`` a class to the
    names it may call on the class (``Time.from_sec``).
    """

    def __init__(self, source: str, tree: ast.expr, *, functions: Iterable[Callable[..., Any]],
                 methods: Mapping[type, Collection[str]],
                 class_methods: Mapping[type, Collection[str]],
                 builtins: Mapping[str, Callable[..., Any]]) -> None:
        self.source = source
        self._tree = tree
        self._functions = list(functions)
        self._methods = {**SAFE_METHODS, **{k: frozenset(v) for k, v in methods.items()}}
        self._class_methods = {k: frozenset(v) for k, v in class_methods.items()}
        self._builtins = dict(builtins)

    def evaluate(self, names: Mapping[str, object] | None = None, *,
                 budget: int | None = None) -> object:
        """The expression's value with ``names`` in scope; every failure a :class:`DdesError`.

        ``budget`` is the work this evaluation may do, in items touched (default and most
        :data:`MAX_WORK`); past it :class:`~ddes.errors.ResourceLimitError`.
        """
        return self.evaluate_counted(names, budget=budget)[0]

    def evaluate_counted(self, names: Mapping[str, object] | None = None, *,
                         budget: int | None = None) -> tuple[object, int]:
        """``(value, work)``: :meth:`evaluate` and the items it touched, for callers that
        bound many evaluations together (roslaunch's ``$(eval)``s of one load)."""
        limit = MAX_WORK if budget is None else min(int(budget), MAX_WORK)
        evaluator = _Evaluator(self, names if names is not None else {}, limit)
        return evaluator.run(), evaluator.work

    __call__ = evaluate

    def __repr__(self) -> str:
        return f"Expression({self.source!r})"


def parse(source: str, *, functions: Iterable[Callable[..., Any]] = (),
          methods: Mapping[type, Collection[str]] | None = None,
          class_methods: Mapping[type, Collection[str]] | None = None,
          builtins: Mapping[str, Callable[..., Any]] | None = None) -> Expression:
    """Parse and check ``source``; refusals are raised here, before any value is read.

    Raises :class:`DdesValueError` (``SyntaxError: ...``) for text that is not
    an expression, :class:`UnsafeExpressionError` for anything outside the
    subset and :class:`ResourceLimitError` for a source too long or too deep.
    """
    if not isinstance(source, str):
        raise DdesTypeError(f"an expression must be a str, got {type(source).__name__} "
                            f"{source!r}")
    if len(source) > MAX_SOURCE_CHARS:
        raise _too_big(f"an expression of {len(source)} characters",
                       f"the limit of {MAX_SOURCE_CHARS} characters")
    try:
        with warnings.catch_warnings():  # the user's text, not ddes's: no SyntaxWarning on stderr
            warnings.simplefilter("ignore", SyntaxWarning)
            warnings.simplefilter("ignore", DeprecationWarning)  # invalid escapes, Python 3.11
            tree = ast.parse(source.strip(), mode="eval")
    except SyntaxError as exc:
        raise DdesValueError(f"SyntaxError: {exc.msg} (column {exc.offset}): {source!r} is "
                             "not a valid Python expression") from None
    except (ValueError, TypeError) as exc:  # null bytes, huge literals
        raise DdesValueError(f"SyntaxError: {exc}: {source!r} is not a valid Python "
                             "expression") from None
    except (RecursionError, MemoryError):
        raise _too_big("the nesting of this expression", "what the parser can hold") from None
    _check_tree(tree.body)
    return Expression(source, tree.body, functions=functions, methods=methods or {},
                      class_methods=class_methods or {},
                      builtins=SAFE_FUNCTIONS if builtins is None else builtins)


def evaluate(source: str, names: Mapping[str, object] | None = None, **options: Any) -> object:
    """``parse(source, **options).evaluate(names)``."""
    return parse(source, **options).evaluate(names)


def _check_tree(root: ast.expr) -> None:
    """Refuse what the subset excludes, walking without recursion (a deep tree is refused)."""
    stack: list[tuple[ast.AST, int]] = [(root, 1)]
    while stack:
        node, depth = stack.pop()
        if depth > MAX_DEPTH:
            raise _too_big(f"an expression nested {depth} deep",
                           f"the limit of {MAX_DEPTH} levels")
        name = type(node).__name__
        if name in _NODE_WORDS:
            raise _refuse(f"{_NODE_WORDS[name]} is not allowed")
        if isinstance(node, ast.Name):
            _check_name(node.id, "the name")
            if node.id in _FORBIDDEN_NAMES:
                raise _refuse(f"NameError: name {node.id!r} is not defined: {node.id}() is not "
                              f"allowed; the functions are {', '.join(sorted(SAFE_FUNCTIONS))} "
                              "and math's")
        elif isinstance(node, ast.Attribute):
            _check_name(node.attr, "attribute")
        elif isinstance(node, ast.keyword):
            if node.arg is None:
                raise _refuse("'**' unpacking in a call is not allowed")
            _check_name(node.arg, "keyword argument")
        elif isinstance(node, ast.Dict) and any(k is None for k in node.keys):
            raise _refuse("'**' unpacking in a dict is not allowed")
        elif isinstance(node, ast.Constant) and isinstance(node.value, int) \
                and node.value.bit_length() > MAX_INT_BITS:
            raise _too_big("an integer literal", f"{MAX_INT_BITS} bits")
        elif not isinstance(node, (
                ast.expr, ast.expr_context, ast.operator, ast.unaryop, ast.cmpop, ast.boolop,
                ast.keyword)):
            raise _refuse(f"{name} is not allowed")
        stack.extend((child, depth + 1) for child in ast.iter_child_nodes(node))


_CONTAINERS = (list, tuple, set, frozenset, dict)
#: Nodes that make new values, whose size is checked.
_MAKERS = (ast.BinOp, ast.Call, ast.List, ast.Tuple, ast.Set, ast.Dict, ast.JoinedStr)


def deep_size(value: object, limit: int = MAX_ITEMS) -> int:
    """Items in ``value`` unfolded (shared parts counted each time), stopping past ``limit``.

    It bounds what ``str``, ``==`` and ``hash`` do with the value: a string or
    bytes counts its length, an int one per 64 bits, a container its items, an
    object with ``__slots__`` (a message, a Time) its fields, anything else 16.
    """
    total = 0
    stack = [value]
    while stack and total <= limit:
        v = stack.pop()
        total += 1
        if isinstance(v, (str, bytes, bytearray)):
            total += len(v)
        elif isinstance(v, bool) or v is None or isinstance(v, (float, complex)):
            pass
        elif isinstance(v, int):
            total += v.bit_length() // 64
        elif isinstance(v, (list, tuple, set, frozenset)):
            stack.extend(v)
        elif isinstance(v, dict):
            stack.extend(v.keys())
            stack.extend(v.values())
        elif isinstance(v, range):
            total += _size(v)
        else:
            slots = getattr(type(v), "__slots__", None)
            if isinstance(slots, (list, tuple)) and slots:
                stack.extend(getattr(v, s, None) for s in slots if isinstance(s, str))
            else:
                total += 16
    return total


def to_text(value: object, limit: int = 10 * MAX_ITEMS) -> str:
    """``str(value)``, refused with :class:`ResourceLimitError` when the text would be huge."""
    n = deep_size(value, limit)
    if n > limit:
        raise _too_big(f"printing a {type(value).__name__} of more than {limit} items",
                       f"the limit of {limit}")
    try:
        return str(value)
    except DdesError:
        raise
    except Exception as exc:  # noqa: BLE001 - e.g. an int over Python's 4300 digits
        raise _failure(exc) from None


def _size(value: object) -> int:
    if isinstance(value, (str, bytes, list, tuple, dict, set, frozenset, range)):
        try:
            return len(value)
        except OverflowError:
            return MAX_ITEMS + 1
    return 0


def _text_size(value: object) -> int:
    """About how many characters ``str(value)`` has, without building it."""
    if isinstance(value, (str, bytes)):
        return len(value)
    if isinstance(value, bool) or value is None:
        return 5
    if isinstance(value, int):
        return value.bit_length() * 31 // 100 + 2  # log10(2) digits per bit, and a sign
    if isinstance(value, float):
        return 24
    return deep_size(value, MAX_ITEMS)


def _is_int(value: object) -> bool:
    return isinstance(value, int)


def _check_pow(a: object, b: object, mod: object = None) -> int:
    """Refuse a power too large to build; returns the work a modular power costs."""
    if not (_is_int(a) and _is_int(b)):
        return 0
    assert isinstance(a, int) and isinstance(b, int)
    if mod is not None:
        if _is_int(mod) and max(abs(b).bit_length(), abs(mod).bit_length()) > 4096:  # type: ignore[arg-type]
            raise _too_big("pow(a, b, mod) with numbers over 4096 bits", "the modular pow limit")
        if not _is_int(mod):
            return 0
        # square-and-multiply: one product of mod-sized numbers per exponent bit, each
        # costing (64-bit digits)**2: pow(2**4096-1, 2**4096-1, 2**4096-3) takes 0.1 s
        digits = abs(mod).bit_length() // 64 + 1  # type: ignore[arg-type]
        return abs(b).bit_length() * digits * digits
    if b <= 0 or abs(a) <= 1:
        return 0
    bits = b * math.log2(abs(a))
    if bits > MAX_INT_BITS:
        raise _too_big(f"{a} ** {b} (about {bits:.3g} bits)", f"the limit of {MAX_INT_BITS} bits")
    return 0


def _check_binop(op: ast.operator, a: object, b: object) -> None:
    if isinstance(op, ast.Pow):
        _check_pow(a, b)
    elif isinstance(op, ast.Mult):
        if _is_int(a) and _is_int(b):
            assert isinstance(a, int) and isinstance(b, int)
            if a.bit_length() + b.bit_length() > MAX_INT_BITS:
                raise _too_big("a product of integers", f"the limit of {MAX_INT_BITS} bits")
        for seq, n in ((a, b), (b, a)):
            if _is_int(n) and isinstance(seq, (str, bytes, list, tuple)):
                assert isinstance(n, int)
                if len(seq) * n > MAX_ITEMS:
                    raise _too_big(f"repeating {type(seq).__name__} of {len(seq)} items {n} "
                                   "times", f"the limit of {MAX_ITEMS} items")
    elif isinstance(op, ast.LShift):
        if _is_int(a) and _is_int(b):
            assert isinstance(a, int) and isinstance(b, int)
            if b > 0 and a.bit_length() + b > MAX_INT_BITS:
                raise _too_big(f"{a} << {b}", f"the limit of {MAX_INT_BITS} bits")
    elif isinstance(op, ast.Add):
        if isinstance(a, (str, bytes, list, tuple)) and isinstance(b, (str, bytes, list, tuple)):
            if len(a) + len(b) > MAX_ITEMS:
                raise _too_big("a concatenation", f"the limit of {MAX_ITEMS} items")
    elif isinstance(op, ast.Mod) and isinstance(a, (str, bytes)):
        text = a.decode("latin-1") if isinstance(a, bytes) else a
        # the result's size, estimated before formatting: the text, every width and
        # precision, and each value it prints (a '%(k)s' repeated prints d['k'] each time)
        estimate = len(text)
        position = 0
        for m in _PERCENT.finditer(text):
            key, width, precision, kind = m.groups()
            if "*" in (width, precision):
                raise _refuse("'*' widths in %-formatting are not allowed")
            if any(x and int(x) > _MAX_WIDTH for x in (width, precision)):
                raise _too_big("a %-format width or precision", f"{_MAX_WIDTH}")
            estimate += int(width or 0) + int(precision or 0)
            if kind == "%":
                continue
            if key is not None:
                value = b.get(key) if isinstance(b, dict) else None
            elif isinstance(b, tuple):
                value = b[position] if position < len(b) else None
                position += 1
            else:
                value = b
            estimate += _text_size(value)
            if estimate > MAX_ITEMS:
                raise _too_big("the result of %-formatting (estimated before formatting)",
                               f"the limit of {MAX_ITEMS} items")


class _Evaluator:
    def __init__(self, expr: Expression, names: Mapping[str, object],
                 limit: int = MAX_WORK) -> None:
        self.expr = expr
        self.names = names
        self.work = 0
        self.limit = limit

    def charge(self, n: int) -> None:
        self.work += n
        if self.work > self.limit:
            raise _too_big(f"evaluating {self.expr.source[:80]!r}",
                           f"the limit of {self.limit} items touched")

    def left(self) -> int:
        """Work still allowed (a deep_size walk stops one item past it)."""
        return max(self.limit - self.work, 0)

    def run(self) -> object:
        try:
            return self.ev(self.expr._tree)
        except DdesError:
            raise
        except RecursionError:
            raise _too_big("the nesting of this expression's values", "the recursion limit"
                           ) from None
        except MemoryError:
            raise _too_big("the memory this expression needs", "what is available") from None
        except Exception as exc:  # noqa: BLE001 - the values' own errors, in Python's words
            raise _failure(exc) from None

    # -- nodes ---------------------------------------------------------------------------

    def ev(self, node: ast.expr) -> Any:
        self.charge(1)
        method = getattr(self, "ev_" + type(node).__name__, None)
        if method is None:
            raise _refuse(f"{type(node).__name__} is not allowed")
        result = method(node)
        if isinstance(node, _MAKERS):
            if isinstance(result, (str, bytes)):
                if len(result) > MAX_ITEMS:
                    raise _too_big(f"a {type(result).__name__} of {len(result)} items",
                                   f"the limit of {MAX_ITEMS} items")
            elif isinstance(result, _CONTAINERS):
                n = deep_size(result, MAX_ITEMS)
                self.charge(min(n, MAX_ITEMS))
                if n > MAX_ITEMS:
                    raise _too_big("a value that holds, unfolded, more items",
                                   f"the limit of {MAX_ITEMS} items")
        return result

    def ev_Constant(self, node: ast.Constant) -> Any:
        return node.value

    def ev_Name(self, node: ast.Name) -> Any:
        name = node.id
        try:
            return self.names[name]
        except KeyError:
            pass
        if name in self.expr._builtins:
            return self.expr._builtins[name]
        if name in ("True", "False", "None"):
            return {"True": True, "False": False, "None": None}[name]
        raise DdesKeyError(f"NameError: name {name!r} is not defined; the names are "
                           f"{', '.join(sorted(map(str, self.names)))} and the functions "
                           f"{', '.join(sorted(self.expr._builtins))}")

    def ev_Tuple(self, node: ast.Tuple) -> Any:
        return tuple(self.ev(e) for e in node.elts)

    def ev_List(self, node: ast.List) -> Any:
        return [self.ev(e) for e in node.elts]

    def ev_Set(self, node: ast.Set) -> Any:
        return {self.ev(e) for e in node.elts}

    def ev_Dict(self, node: ast.Dict) -> Any:
        return {self.ev(k): self.ev(v) for k, v in zip(node.keys, node.values)
                if k is not None}

    def ev_UnaryOp(self, node: ast.UnaryOp) -> Any:
        return _UNARY[type(node.op)](self.ev(node.operand))

    def ev_BinOp(self, node: ast.BinOp) -> Any:
        a, b = self.ev(node.left), self.ev(node.right)
        _check_binop(node.op, a, b)
        self.charge(_size(a) + _size(b))
        result = _BINOPS[type(node.op)](a, b)
        self.charge(_size(result))
        return result

    def ev_BoolOp(self, node: ast.BoolOp) -> Any:
        value: Any = None
        for e in node.values:
            value = self.ev(e)
            if isinstance(node.op, ast.And) and not value:
                return value
            if isinstance(node.op, ast.Or) and value:
                return value
        return value

    def ev_Compare(self, node: ast.Compare) -> Any:
        left = self.ev(node.left)
        for op, comp in zip(node.ops, node.comparators):
            right = self.ev(comp)
            if isinstance(op, (ast.Is, ast.IsNot)):
                self.charge(1)
            else:  # == on two nested values (messages too) walks both
                self.charge(deep_size(left, self.left()) + deep_size(right, self.left()))
            if not _CMPOPS[type(op)](left, right):
                return False
            left = right
        return True

    def ev_IfExp(self, node: ast.IfExp) -> Any:
        return self.ev(node.body) if self.ev(node.test) else self.ev(node.orelse)

    def ev_Attribute(self, node: ast.Attribute) -> Any:
        value = self.ev(node.value)
        return self.attribute(value, node.attr)

    def attribute(self, value: object, attr: str) -> Any:
        _check_name(attr, "attribute")
        if isinstance(value, types.ModuleType):
            if value is not math:
                raise _refuse(f"attributes of the module {value.__name__!r} are not allowed "
                              "(only math's)")
            if attr not in _MATH_NAMES:
                raise _refuse(f"math.{attr} is not allowed; math's functions and constants "
                              "are, except prod")
        result = getattr(value, attr)
        if isinstance(result, types.ModuleType):
            raise _refuse(f"the attribute {attr!r} is a module, which is not allowed")
        return result

    def ev_Subscript(self, node: ast.Subscript) -> Any:
        value = self.ev(node.value)
        index = self.ev(node.slice)
        result = value[index]
        self.charge(_size(result))
        return result

    def ev_Slice(self, node: ast.Slice) -> Any:
        return slice(*(None if p is None else self.ev(p)
                       for p in (node.lower, node.upper, node.step)))

    def ev_JoinedStr(self, node: ast.JoinedStr) -> Any:
        parts = []
        for v in node.values:
            parts.append(self.ev(v) if isinstance(v, ast.FormattedValue) else str(self.ev(v)))
            self.charge(len(parts[-1]))
        return "".join(parts)

    def ev_FormattedValue(self, node: ast.FormattedValue) -> Any:
        value = self.ev(node.value)
        if node.conversion == ord("r"):
            value = repr(value)
        elif node.conversion == ord("a"):
            value = ascii(value)
        elif node.conversion == ord("s"):
            value = str(value)
        if node.format_spec is None:
            return str(value)
        spec = self.ev(node.format_spec)
        if type(value) not in (int, float, str, bool):
            raise _refuse(f"a format spec on a {type(value).__name__} is not allowed (only on "
                          "int, float, str and bool)")
        m = _SPEC.match(spec)
        if m is None:
            raise _refuse(f"the format spec {spec!r} is not allowed (plain [fill]align, sign, "
                          "width, .precision and type only)")
        if any(x and int(x) > _MAX_WIDTH for x in m.groups()):
            raise _too_big(f"the format spec {spec!r}", f"widths of {_MAX_WIDTH}")
        return format(value, spec)

    # -- calls ---------------------------------------------------------------------------

    def ev_Call(self, node: ast.Call) -> Any:
        func = node.func
        if isinstance(func, ast.Attribute):
            owner = self.ev(func.value)
            fn = self.method(owner, func.attr)
            self.charge(_size(owner))  # a method reads its owner: s.count(x), s.find(x)
        elif isinstance(func, ast.Name):
            fn = self.ev(func)
            if not self.callable_by_name(fn):
                raise _refuse(f"calling {func.id!r} ({type(fn).__name__}) is not allowed; the "
                              f"functions are {', '.join(sorted(self.expr._builtins))}, math's "
                              "and the caller's")
        else:
            raise _refuse("only a function name or a method may be called")
        args = [self.ev(a) for a in node.args]
        kwargs = {k.arg: self.ev(k.value) for k in node.keywords if k.arg is not None}
        for a in [*args, *kwargs.values()]:
            if callable(a) and not any(a is c for c in _CHEAP_CALLBACKS) \
                    and not (fn is isinstance and isinstance(a, type)):
                raise _refuse(f"passing {getattr(a, '__name__', type(a).__name__)!r} as a "
                              "function is not allowed; only abs, bool, chr, float, int, len "
                              "and ord may be passed (and classes to isinstance)")
        self.check_call(fn, args, kwargs)
        for a in [*args, *kwargs.values()]:
            self.charge(deep_size(a, self.left()))
        result = fn(*args, **kwargs)
        self.charge(_size(result))
        if _size(result) > MAX_ITEMS:
            raise _too_big(f"a result of {_size(result)} items", f"the limit of {MAX_ITEMS}")
        return result

    def callable_by_name(self, fn: object) -> bool:
        if any(fn is f for f in self.expr._builtins.values()):
            return True
        if isinstance(fn, types.BuiltinFunctionType) and getattr(fn, "__module__", None) == "math":
            return getattr(fn, "__name__", "") in _MATH_NAMES
        return any(fn is f or (isinstance(fn, types.MethodType) and fn == f)
                   for f in self.expr._functions)

    def method(self, owner: object, name: str) -> Any:
        _check_name(name, "attribute")
        if owner is math:
            return self.attribute(owner, name)
        if isinstance(owner, type):
            allowed = self.expr._class_methods.get(owner, frozenset())
            if name in allowed:
                return getattr(owner, name)
            raise _refuse(f"calling {owner.__name__}.{name}() is not allowed; the class methods "
                          f"are {self.list_methods(self.expr._class_methods)}")
        for kind, names in self.expr._methods.items():
            if isinstance(owner, kind) and name in names:
                return getattr(owner, name)
        raise _refuse(f"calling the method .{name}() of a {type(owner).__name__} is not allowed;"
                      f" the methods are {self.list_methods(self.expr._methods)}")

    @staticmethod
    def list_methods(table: Mapping[type, Collection[str]]) -> str:
        return "; ".join(f"{k.__name__}: {', '.join(sorted(v))}" for k, v in table.items()) \
            or "none"

    def check_call(self, fn: object, args: list[Any], kwargs: dict[str, Any]) -> None:
        """Bound the cost of the builtins whose cost is not bounded by their arguments' sizes."""
        if fn is range:
            try:
                n = len(range(*args, **kwargs))
            except OverflowError:
                n = MAX_ITEMS + 1
            except (TypeError, ValueError):
                return  # the call itself reports it
            if n > MAX_ITEMS:
                raise _too_big(f"range{tuple(args)} of {n} items", f"the limit of {MAX_ITEMS}")
        elif fn is pow:
            self.charge(_check_pow(*args[:3], **kwargs))  # type: ignore[misc,unused-ignore]
        elif fn is round and len(args) > 1 and _is_int(args[1]) and abs(args[1]) > _MAX_WIDTH:
            raise _too_big(f"round(..., {args[1]})", f"ndigits of {_MAX_WIDTH}")
        elif fn is sum:
            start = args[1] if len(args) > 1 else kwargs.get("start", 0)
            if not isinstance(start, (int, float, complex)):
                raise _refuse("sum() with a non-number start is not allowed (it copies "
                              "sequences quadratically)")
        elif getattr(fn, "__module__", None) == "math" or (
                isinstance(fn, types.BuiltinFunctionType) and fn.__self__ is math):
            self.check_math(fn, args)
        elif isinstance(fn, types.BuiltinMethodType) and isinstance(fn.__self__, (str, bytes)):
            self.check_str_method(fn.__self__, fn.__name__, args)

    @staticmethod
    def check_math(fn: Any, args: list[Any]) -> None:
        name = getattr(fn, "__name__", "")
        if name == "factorial" and args and _is_int(args[0]) and args[0] > 1000:
            raise _too_big(f"math.factorial({args[0]})", "n of 1000")
        if name in ("comb", "perm") and args and _is_int(args[0]) and args[0] > 1000:
            raise _too_big(f"math.{name}({args[0]}, ...)", "n of 1000")

    @staticmethod
    def check_str_method(owner: str | bytes, name: str, args: list[Any]) -> None:
        if name == "replace" and len(args) >= 2 and isinstance(args[0], type(owner)) \
                and isinstance(args[1], type(owner)) and len(args[1]) > len(args[0]):
            count = owner.count(args[0]) if args[0] else len(owner) + 1  # type: ignore[arg-type]
            if len(owner) + count * (len(args[1]) - len(args[0])) > MAX_ITEMS:
                raise _too_big("the result of str.replace", f"the limit of {MAX_ITEMS} items")
        elif name == "join" and args:
            items = args[0]
            if isinstance(items, (list, tuple)):
                total = len(owner) * len(items) + sum(len(x) for x in items
                                                      if isinstance(x, (str, bytes)))
            elif isinstance(items, (str, bytes)):
                # the separator between every two characters: ('a' * 10**6).join('b' * 1500)
                total = len(owner) * max(len(items) - 1, 0) + len(items)
            else:
                raise _refuse("str.join takes a list, tuple or str here")
            if total > MAX_ITEMS:
                raise _too_big(f"the result of str.join ({total} items)",
                               f"the limit of {MAX_ITEMS} items")
