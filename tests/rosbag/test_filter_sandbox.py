"""rosbag filter expressions run in ddes.expr's safe subset: escapes and bombs are refused."""

from __future__ import annotations

import tracemalloc
from collections.abc import Callable

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from ddes import Time
from ddes.errors import DdesError, ResourceLimitError, ROSBagException, UnsafeExpressionError
from ddes.expr import MAX_WORK
from ddes.rosbag import Bag, filter_bag
from ddes.rosbag.ops import (
    FILTER_WORK_PER_BYTE,
    FILTER_WORK_PER_MESSAGE,
    CostlyBagExpression,
    filter_budget,
)

from .conftest import Int32, String


def _peak(fn: Callable[[], object]) -> int:
    """Peak bytes allocated while ``fn()`` runs (tracemalloc): memory, not CPU time, shows a
    bomb refused before it is built, and holds on a loaded machine."""
    tracemalloc.start()
    try:
        fn()
        return tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()


def _bag() -> Bag:
    bag = Bag()
    for i in range(4):
        bag.write("/a", String(data=f"message {i}"), Time(i, 5))
        bag.write("/b", Int32(data=i), Time(i, 7))
    return Bag.from_bytes(bag.to_bytes())


@pytest.mark.parametrize("expr", [
    "(x for x in ()).gi_frame.f_back.f_globals['os']",
    "().__class__.__mro__[1].__subclasses__()",
    "m.__class__", "t.__reduce__()", "__builtins__", "getattr(m, 'data')", "open('/x')",
    "'{0.__class__}'.format(m)", "[x for x in [m]]", "m.serialize(None)", "lambda: 1",
    "Time.__init__", "math.__spec__",
])
def test_escapes_are_unsafe_bag_expressions(expr: str) -> None:
    with pytest.raises(UnsafeExpressionError) as info:
        filter_bag(_bag(), Bag(), expr)
    assert isinstance(info.value, ROSBagException)
    assert repr(expr) in str(info.value)


@pytest.mark.parametrize("expr", ["9**9**9", "'a' * 10**10", "len(list(range(10**12))) > 0",
                                  "m.data * 10**9 == ''"])
def test_bombs_are_refused_before_they_are_built(expr: str) -> None:
    bag = _bag()

    def run() -> None:
        with pytest.raises(ResourceLimitError) as info:
            filter_bag(bag, Bag(), expr)
        assert isinstance(info.value, ROSBagException)
        assert "exceeds" in str(info.value)

    assert _peak(run) < 8 * 2**20  # built, each bomb would take GiBs


@pytest.mark.parametrize(("expr", "kept"), [
    ("topic == '/a' and m.data.endswith('1')", 1),
    ("t.to_sec() < 2", 4),
    ("t > Time.from_sec(2.5)", 2),
    ("t.secs == 1 and t.nsecs == 7", 1),
    ("topic == '/b' and m.data % 2 == 0", 2),
    ("math.sqrt(t.secs) >= 1", 6),
    ("t - Time(1) > Duration(1)", 4),
])
def test_documented_filters_still_work(expr: str, kept: int) -> None:
    out = Bag()
    assert filter_bag(_bag(), out, expr) == kept


def test_print_expression_uses_the_subset() -> None:
    lines: list[str] = []
    filter_bag(_bag(), Bag(), "topic == '/b'", print_expr="f'{t.secs}:{m.data}'",
               out=lines.append)
    assert lines[:2] == ["NO MATCH 0:message 0", "MATCH 0:0"]
    with pytest.raises(UnsafeExpressionError):
        filter_bag(_bag(), Bag(), "True", print_expr="m.__class__", out=lines.append)


@settings(max_examples=100, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.lists(st.sampled_from(["m", ".data", "t", ".secs", " + ", " * ", "10**9", "'a'",
                                 " == ", "(", ")", "topic", "[0]", ".__class__", "len(",
                                 "x", " ** ", "9", ".to_sec()", " and ", "math.", "pi"]),
                max_size=12).map("".join))
def test_fuzz_filter(expr: str) -> None:
    bag = _bag()

    def run() -> None:
        try:
            filter_bag(bag, Bag(), expr)
        except DdesError:
            pass

    assert _peak(run) < 16 * 2**20, expr


#: Filters cheap in memory that took seconds of CPU on every message before issue 38
#: (0.6 s a message for the sort, 2.8 s for the twenty modular powers).
SLOW_FILTERS = [
    "len(sorted(range(999990), key=abs)) > 0",
    "len([" + ",".join(["pow(2**4096-1, 2**4096-1, 2**4096-3)"] * 20) + "]) > 0",
    "len(str(2**9999) * 300) > 0",
]


@pytest.mark.parametrize("expr", SLOW_FILTERS, ids=["sort", "pow-mod", "text"])
def test_a_slow_filter_is_refused_on_its_first_message(expr: str) -> None:
    with pytest.raises(CostlyBagExpression) as info:
        filter_bag(_bag(), Bag(), expr)
    text = str(info.value)
    budget = FILTER_WORK_PER_MESSAGE + FILTER_WORK_PER_BYTE * 13  # message 0: 'message 0'
    assert f"filter expression {expr!r} failed on message 0 (/a at 0.000000005)" in text
    assert f"on a message of 13 bytes an expression may touch {budget} items" in text
    assert "FILTER_WORK_PER_MESSAGE" in text and isinstance(info.value, ResourceLimitError)


def test_the_filter_budget_grows_with_the_message() -> None:
    # touching each of a large message's bytes is allowed: the budget is per byte too
    bag = Bag()
    bag.write("/big", String(data="x" * 200_000), Time(1))
    assert filter_bag(Bag.from_bytes(bag.to_bytes()), Bag(),
                      "m.data.count('x') + len(m.data) == 400000") == 1
    assert filter_budget(0) == FILTER_WORK_PER_MESSAGE
    assert filter_budget(10**9) == MAX_WORK
    with pytest.raises(CostlyBagExpression, match="print expression"):
        filter_bag(_bag(), Bag(), "True", print_expr="sorted(range(99999))", out=print)
