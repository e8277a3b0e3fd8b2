"""Trace.select(**details) matches row-form rows where they lie; the events it returns are the
ones the reference rule picks: build each event, then compare its details dict."""

from __future__ import annotations

from typing import Any

from hypothesis import given
from hypothesis import strategies as st

from ddes.kernel.trace import Trace, _match_details
from ddes.time import Duration

KEYS = ("a", "b", "c")
values = st.one_of(st.integers(0, 3), st.sampled_from(["x", "y"]), st.none(),
                   st.builds(Duration.from_nsec, st.integers(0, 3)))
rows = st.tuples(st.integers(0, 5), st.sampled_from(["k.one", "k.two"]),
                 st.lists(st.sampled_from(KEYS), max_size=4).map(tuple),
                 st.lists(values, max_size=5))
wants = st.dictionaries(st.sampled_from([*KEYS, "d"]), values, max_size=2)


@given(st.lists(rows, max_size=12), wants, st.booleans())
def test_select_details_on_rows_is_the_reference_rule(raw: list[Any], want: dict[str, Any],
                                                      dict_form: bool) -> None:
    trace = Trace()
    for t, kind, keys, vals in raw:
        if dict_form:
            trace.append(t, kind, "/n", dict(zip(keys, vals)))
        else:
            trace.append_row((t, kind, "/n", keys, *vals))
    got = trace.select(**want)
    expected = [ev for ev in trace.events if _match_details(ev.details, want)]
    assert list(got) == expected


def test_a_repeated_key_matches_its_last_value_and_a_missing_value_matches_nothing() -> None:
    trace = Trace()
    trace.append_row((1, "k.one", "/n", ("a", "a"), 1, 2))
    trace.append_row((2, "k.one", "/n", ("a", "b"), 5))
    assert [ev.t for ev in trace.select(a=2)] == [1]
    assert [ev.t for ev in trace.select(a=1)] == []
    assert [ev.t for ev in trace.select(b=None)] == []
    assert [ev.t for ev in trace.select(a=5)] == [2]
