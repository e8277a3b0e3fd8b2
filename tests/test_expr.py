"""ddes.expr: the safe expression subset holds against known escapes, bombs and random input."""

from __future__ import annotations

import ast
import math
import tracemalloc
from collections.abc import Callable
from typing import Any

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from ddes.errors import DdesError, ResourceLimitError, UnsafeExpressionError
from ddes.expr import MAX_SOURCE_CHARS, MAX_WORK, deep_size, evaluate, parse, to_text

#: Escapes that work against eval with restricted builtins; each must be refused.
ESCAPES = [
    "(x for x in ()).gi_frame.f_back.f_globals['os']",
    "(x for x in ()).gi_frame",
    "(lambda: 0).__globals__",
    "[c for c in ().__class__.__base__.__subclasses__()]",
    "().__class__.__mro__[1].__subclasses__()",
    "().__class__.__bases__[0].__subclasses__()",
    "''.__class__.mro()[1].__subclasses__()",
    "__builtins__",
    "__builtins__['__import__']('os')",
    "__import__('os').system('true')",
    "m.__class__.__init__.__globals__['__builtins__']",
    "m.__reduce_ex__(2)",
    "getattr(m, 'data')",
    "vars(m)", "globals()", "locals()", "dir()",
    "open('/etc/passwd').read()",
    "exec('1')", "eval('1')", "compile('1', 'x', 'eval')",
    "type(m)", "object", "breakpoint()", "input()", "help()",
    "'{0.__class__}'.format(m)",
    "'{0.data}'.format(m)",
    "'{x}'.format_map({'x': 1})",
    "str.format('{0.__class__}', 1)",
    "format(m, '')",
    "(y := 1)",
    "lambda: 1",
    "[x for x in [1]]", "{x for x in [1]}", "{x: x for x in [1]}",
    "(x for x in [1])",
    "[*[1]]", "{**{}}", "dict(**{'a': 1})",
    "m.tb_frame", "m.f_back", "m.cr_frame", "m.gi_code", "m.f_globals",
    "m.data.upper.__self__",
    "m.serialize(None)",
    "m.data.zfill(10)",
    "[].append(1)",
    "{}.update(a=1)",
    "math.__loader__",
    "math.prod([1, 2])",
    "(1).__class__",
    "sorted([1], key=getattr)",
    "list(map(pow, [9], [99999999]))",
    "max([1], key=m.data.upper)",
    "(len if True else abs)('x')",
    "f'{m.__class__}'",
    "f'{m:>{10}}'",
]

#: Expressions that would take minutes or gigabytes; each must be refused at once.
BOMBS = [
    "9**9**9", "9**999999", "pow(9, 10**9)", "pow(10**4000, 10**4000, 10**4000)",
    "'a' * 10**10", "[0] * 10**10", "b'x' * 10**9", "10**9 * 'a'",
    "1 << 10**9", "(10**3000) * (10**3000) * (10**3000) * (10**3000)",
    "list(range(10**12))", "range(10**30)", "sum(range(10**18))",
    "round(5, -10**9)", "math.factorial(10**7)", "math.comb(10**7, 10**6)",
    "'%1000000000d' % 1", "f'{1:1000000000}'", "f'{1.5:.1000000000f}'",
    "[[[[0] * 100] * 100] * 100] * 100",
    "('a' * 10**6).replace('a', 'bb')",
    "','.join(['a' * 10**5] * 11)",
    "('a' * 10**6).join('b' * 1500)",  # a str of 1500 items joined: 1.5 GB built (issue 38)
    "'%(a)s' * 166000 % {'a': 'x' * 10**5}",  # one value printed 166000 times: 16.6 GB
    "'%1000s' * 100000 % ((1,) * 100000)",  # 100000 widths of 1000: 100 MB
    "('a' * 10**6) + ('a' * 10**6)",
    "-" * 5000 + "1",
    "[" * 150 + "]" * 150,
    "not " * 300 + "1",
    "1" + "+1" * (MAX_SOURCE_CHARS // 2),
]

VALID: list[tuple[str, Any]] = [
    ("1 + 2 * 3 - 4 / 2", 5.0), ("7 // 2, 7 % 2, -7, +7, ~7", (3, 1, -7, 7, -8)),
    ("2 ** 10", 1024), ("2 ** -1", 0.5), ("(1, [2], {3: 4}, {5}, b'x', None)",
                                          (1, [2], {3: 4}, {5}, b"x", None)),
    ("1 < 2 <= 2 != 3", True), ("1 in [1] and 2 not in [1]", True), ("None is None", True),
    ("0 or 'x'", "x"), ("not 0", True), ("'a' if t.secs > 2 else 'b'", "a"),
    ("m.data[1:3]", "el"), ("m.data[::-1]", "olleh"), ("m.data.startswith('he')", True),
    ("t.to_sec()", 3.5), ("t.secs", 3), ("len(m.data)", 5), ("abs(-2)", 2),
    ("min(3, 1, 2)", 1), ("max([1, 5], default=0)", 5), ("round(2.567, 2)", 2.57),
    ("int('7') + float('1.5')", 8.5), ("str(1) + 'x'", "1x"), ("bool([])", False),
    ("sum([1, 2, 3])", 6), ("any([0, 1]) and all([1])", True), ("sorted([3, 1, 2])", [1, 2, 3]),
    ("sorted(['bb', 'a'], key=len)", ["a", "bb"]), ("math.sqrt(16) + math.pi", 4 + math.pi),
    ("math.floor(2.5)", 2), ("'a,b'.split(',')", ["a", "b"]), ("' x '.strip().upper()", "X"),
    ("{'a': 1}.get('b', 2)", 2), ("f'{t.secs}-{m.data!r}'", "3-'hello'"),
    ("f'{2.5:.2f}|{7:>4}'", "2.50|   7"), ("'%s=%03d' % ('x', 7)", "x=007"),
    ("list(range(3))", [0, 1, 2]), ("'a' * 3", "aaa"), ("[0] * 2", [0, 0]),
    ("isinstance(m.data, str)", True), ("divmod(7, 2)", (3, 1)), ("pow(2, 5, 7)", 4),
    ("'-'.join(['a', 'b'])", "a-b"), ("list(map(len, ['ab', 'c']))", [2, 1]),
    ("math.factorial(5)", 120), ("2 ** 9999 > 0", True),
]


class _Time:
    __slots__ = ("secs", "nsecs")

    def __init__(self) -> None:
        self.secs, self.nsecs = 3, 500_000_000

    def to_sec(self) -> float:
        return self.secs + self.nsecs / 1e9


class _Msg:
    __slots__ = ("data",)

    def __init__(self) -> None:
        self.data = "hello"

    def serialize(self, buff: object) -> None:  # pragma: no cover - must never be called
        raise AssertionError("called")


NAMES = {"m": _Msg(), "t": _Time(), "math": math, "topic": "/x"}
OPTIONS: dict[str, Any] = {"methods": {_Time: {"to_sec"}}}


def run(source: str) -> object:
    return evaluate(source, NAMES, **OPTIONS)


def peak_bytes(fn: Callable[[], None]) -> int:
    """Peak bytes allocated while ``fn()`` runs (tracemalloc): memory, not CPU time, shows a
    bomb refused before it is built and holds on a loaded machine; work that allocates
    nothing (``sum(range(10**18))``) is bounded by the evaluator's items-touched charge."""
    tracemalloc.start()
    try:
        fn()
        return tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()


@pytest.mark.parametrize("source", ESCAPES)
def test_every_known_escape_is_refused(source: str) -> None:
    with pytest.raises(UnsafeExpressionError) as info:
        run(source)
    assert "safe subset" in str(info.value)


@pytest.mark.parametrize("source", BOMBS)
def test_bombs_are_refused_before_they_are_built(source: str) -> None:
    def refused() -> None:
        with pytest.raises(ResourceLimitError) as info:
            run(source)
        # a named limit refused it (size, bits, items touched), not a MemoryError caught late
        assert "exceeds" in str(info.value)
        assert "the memory this expression needs" not in str(info.value)

    assert peak_bytes(refused) < 8 * 2**20  # built, the smallest bomb would take GiBs


@pytest.mark.parametrize(("source", "expected"), VALID)
def test_the_subset_evaluates_like_python(source: str, expected: object) -> None:
    assert run(source) == expected


def test_refusals_name_what_and_what_is_allowed() -> None:
    with pytest.raises(UnsafeExpressionError, match=r"'__class__'.*names starting with '_'"):
        run("m.__class__")
    with pytest.raises(UnsafeExpressionError, match=r"getattr.*the functions are abs"):
        run("getattr(m, 'x')")
    with pytest.raises(UnsafeExpressionError, match=r"\.zfill\(\).*the methods are"):
        run("m.data.zfill(3)")
    with pytest.raises(ResourceLimitError, match=r"9 \*\* 387420489.*10000 bits"):
        run("9**9**9")


@pytest.mark.parametrize(("source", "kind", "words"), [
    ("1 +", "DdesValueError", "SyntaxError"), ("nope", "DdesKeyError", "NameError: name 'nope'"),
    ("1 / 0", "DdesValueError", "ZeroDivisionError"), ("m.nope", "DdesAttributeError",
                                                       "AttributeError"),
    ("[1][3]", "DdesValueError", "IndexError"), ("'a' + 1", "DdesTypeError", "TypeError"),
    ("int('9' * 5000)", "DdesValueError", "ValueError"), ("'\0'", "DdesValueError", "null"),
    ("float(10 ** 400)", "DdesValueError", "OverflowError"), ("10.0 ** 400", "DdesValueError",
                                                              "OverflowError"),
])
def test_value_errors_are_ddes_errors_in_pythons_words(source: str, kind: str, words: str
                                                       ) -> None:
    with pytest.raises(DdesError) as info:
        run(source)
    assert type(info.value).__name__ == kind
    assert words in str(info.value)


#: Expressions cheap in memory whose calls cost far more CPU than the items they touch: before
#: issue 38 each ran for seconds (the pow list 38 s, the find list 0.7 s on 1 MB).
SLOW = [
    "[" + ",".join(["pow(2**4096-1, 2**4096-1, 2**4096-3)"] * 250) + "]",
    "[" + ",".join(["m.data.find('a' * 50 + 'b')"] * 200) + "]",
    "[" + ",".join(["m.data.count('ab')"] * 200) + "]",
    "[" + ",".join(["m.rows == m.copy"] * 200) + "]",  # 10**6 items compared each time
]


class _Big:
    __slots__ = ("copy", "data", "rows")

    def __init__(self) -> None:
        self.data = "a" * 10**6
        self.rows = [[0] * 999] * 999
        self.copy = [[0] * 999] * 999


@pytest.mark.parametrize("source", SLOW, ids=["pow-mod", "find", "count", "compare"])
def test_calls_are_charged_for_their_cost_before_they_run(source: str) -> None:
    with pytest.raises(ResourceLimitError, match="items touched"):
        evaluate(source, {"m": _Big()})


def test_a_modular_power_is_charged_before_it_is_computed() -> None:
    with pytest.raises(ResourceLimitError, match=f"limit of {MAX_WORK} items touched"):
        evaluate("pow(2**4096-1, 2**4096-1, 2**4096-3)")
    assert evaluate("pow(2**1024-1, 65537, 2**1024-3)") == pow(2**1024 - 1, 65537, 2**1024 - 3)


def test_a_budget_bounds_one_evaluation_below_max_work() -> None:
    expr = parse("len(x) + len(x)")
    assert expr.evaluate({"x": "a" * 1000}, budget=10_000) == 2000
    with pytest.raises(ResourceLimitError, match="limit of 1500 items touched"):
        expr.evaluate({"x": "a" * 1000}, budget=1500)
    with pytest.raises(ResourceLimitError, match=f"limit of {MAX_WORK} items"):
        expr.evaluate({"x": "a" * 4_000_000}, budget=10 * MAX_WORK)  # never past MAX_WORK


def test_too_long_and_non_str_sources() -> None:
    with pytest.raises(ResourceLimitError, match="characters"):
        parse("1" * (MAX_SOURCE_CHARS + 1))
    with pytest.raises(DdesError, match="must be a str"):
        parse(3)  # type: ignore[arg-type]


def test_caller_functions_only_are_callable() -> None:
    def double(x: int) -> int:
        return 2 * x

    def other(x: int) -> int:  # pragma: no cover - must never be called
        raise AssertionError

    assert evaluate("double(4)", {"double": double}, functions=[double]) == 8
    with pytest.raises(UnsafeExpressionError, match="calling 'other'"):
        evaluate("other(4)", {"other": other}, functions=[double])


def test_to_text_and_deep_size() -> None:
    assert to_text([1, "ab"]) == "[1, 'ab']"
    assert deep_size("abc") == 4
    big = ["x" * 1000] * 1000
    assert deep_size(big, 10) > 10
    with pytest.raises(ResourceLimitError):
        to_text(big, limit=10_000)


def test_the_module_never_calls_eval() -> None:
    import ddes.expr as module

    tree = ast.parse(open(module.__file__, encoding="utf-8").read())  # noqa: SIM115
    called = {n.func.id for n in ast.walk(tree)
              if isinstance(n, ast.Call) and isinstance(n.func, ast.Name)}
    assert not called & {"eval", "exec", "compile", "__import__"}


# -- fuzz ------------------------------------------------------------------------------------

_ATOMS = ["1", "0", "-3", "2.5", "10**4", "9", "'ab'", "b'x'", "None", "True", "m", "t", "m.data",
          "t.secs", "topic", "math", "math.pi", "[1, 2]", "(1,)", "{'a': 1}", "{1}", "range(5)",
          "len", "x", "__class__", "gi_frame", "''", "10**10"]
_BINARY = [" + ", " - ", " * ", " / ", " // ", " % ", " ** ", " << ", " >> ", " & ", " | ",
           " ^ ", " < ", " == ", " in ", " is ", " and ", " or ", " if 1 else "]
_WRAP = ["({})", "[{}]", "-{}", "not {}", "len({})", "str({})", "abs({})", "sorted({})",
         "{}.upper()", "{}[0]", "{}[1:]", "{}.__class__", "{}.gi_frame", "math.sqrt({})",
         "sum({})", "max({}, 1)", "f'{{{}}}'", "{}.split()", "list({})", "{} * 10**6",
         "round({}, 2)", "int({})", "(x for x in {})", "{}.format(1)", "getattr({}, 'a')",
         "pow({}, 99)", "range({})", "{}.to_sec()"]


@st.composite
def expressions(draw: st.DrawFn, depth: int = 0) -> str:
    if depth > 4 or draw(st.booleans()):
        return draw(st.sampled_from(_ATOMS))
    if draw(st.booleans()):
        return draw(st.sampled_from(_WRAP)).format(draw(expressions(depth + 1)))
    return draw(expressions(depth + 1)) + draw(st.sampled_from(_BINARY)) + draw(
        expressions(depth + 1))


def _bounded(source: str) -> None:
    def attempt() -> None:
        try:
            to_text(run(source))
        except DdesError:
            pass

    assert peak_bytes(attempt) < 16 * 2**20, source


@settings(max_examples=300, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(expressions())
def test_fuzz_structured_expressions(source: str) -> None:
    _bounded(source)


@settings(max_examples=300, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.text(alphabet="0123456789*+-/%<>=()[]{}.,:'\"_ abmtxfgi\\\n\0", max_size=60))
def test_fuzz_random_text(source: str) -> None:
    _bounded(source)


def test_an_invalid_escape_in_the_text_warns_nothing() -> None:
    import warnings

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        expr = parse('"a\\[" + "b"')  # Python 3.11 warns DeprecationWarning, 3.12+ SyntaxWarning
    assert caught == []
    assert expr.source == '"a\\[" + "b"'
