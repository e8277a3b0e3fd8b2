"""$(eval ...) runs in ddes.expr's safe subset: escapes and bombs are refused, uses still work."""

from __future__ import annotations

import random
import tracemalloc

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from ddes.errors import DdesError, ResourceLimitError, ROSLaunchException, UnsafeExpressionError
from ddes.launch import SubstitutionContext, resolve_args
from ddes.rospack import RosPack


def ctx(**args: str) -> SubstitutionContext:
    return SubstitutionContext(RosPack([], use_env=False, bundled=False), {"A": "from env"},
                               random.Random(1), "/w/launch/x.launch", dict(args))


@pytest.mark.parametrize("expr", [
    "(x for x in ()).gi_frame.f_back.f_globals['os']",
    "().__class__", "open('/etc/passwd').read()", "getattr(1, 'real')", "globals()",
    "'{0.real}'.format(1)", "[x for x in range(3)]", "(lambda: 1)()", "arg.gi_code",
    "exec('1')", "eval('1')", "compile('1', 'x', 'eval')", "vars()", "dirname.f_globals",
])
def test_escapes_are_unsafe_launch_expressions(expr: str) -> None:
    with pytest.raises(UnsafeExpressionError) as info:
        resolve_args(f"$(eval {expr})", ctx())
    assert isinstance(info.value, ROSLaunchException)
    assert "$(eval" in str(info.value)


@pytest.mark.parametrize("expr", ["9**9**9", "'a' * 10**10", "range(10**12)",
                                  "str([[[[0] * 100] * 100] * 100] * 100)"])
def test_bombs_are_refused_quickly(expr: str) -> None:
    # refused before the bomb is built: the evaluation allocates almost nothing (built, each
    # would take hundreds of MiB); memory, not time, so the check holds on a loaded machine
    tracemalloc.start()
    try:
        with pytest.raises(ResourceLimitError) as info:
            resolve_args(f"$(eval {expr})", ctx())
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    assert isinstance(info.value, ROSLaunchException)
    assert peak < 8 * 2**20, peak


@pytest.mark.parametrize(("expr", "expected"), [
    ("arg('x') == 'y'", "True"), ("2 * arg('n')", "6"), ("optenv('A', 'b')", "from env"),
    ("optenv('NOPE', 'b')", "b"), ("env('A').upper()", "FROM ENV"), ("n * 2 + floor(pi)", "9"),
    ("'on' if x == 'y' and true else 'off'", "on"), ("dict(k=n)", "{'k': 3}"),
    ("list(range(n))", "[0, 1, 2]"), ("round(sqrt(2), 3)", "1.414"), ("anon('w')", "w_"),
])
def test_roslaunch_uses_still_work(expr: str, expected: str) -> None:
    assert resolve_args(f"$(eval {expr})", ctx(x="y", n="3")).startswith(expected)


@settings(max_examples=100, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.lists(st.sampled_from(["arg('n')", "n", " * ", " ** ", "10**9", "'a'", "(", ")",
                                 "sqrt(", "pi", " + ", "optenv('A')", ".upper()", "_", "__",
                                 "len(", " if true else ", "9", "[0]", ",", "e"]),
                max_size=12).map("".join))
def test_fuzz_eval(expr: str) -> None:
    # any expression either resolves or raises a typed error, within a small memory bound
    # (the evaluator's size charges stop bombs before they are built)
    tracemalloc.start()
    try:
        try:
            resolve_args(f"$(eval {expr})", ctx(n="3"))
        except DdesError:
            pass
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    assert peak < 16 * 2**20, (expr, peak)
