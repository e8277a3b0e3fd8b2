"""ddes.tf2.TimeCache.insert: the in-order fast path (append, then prune by bisection) keeps
exactly what tf2's ``TimeCache::insertData`` + ``pruneList`` keep, written here as the plain
sorted-insert-and-prune-from-the-front it is."""

from __future__ import annotations

from bisect import bisect_right

from hypothesis import given
from hypothesis import strategies as st

from ddes.tf2.cache import OLD_DATA, REPEATED_DATA, TimeCache


def reference_insert(stamps: list[int], max_ns: int, stamp: int) -> str | None:
    """tf2: refuse data older than the window or with a stamp already there; insert sorted;
    drop from the front what fell more than ``max_ns`` behind the newest stamp."""
    if stamps and stamps[-1] > stamp + max_ns:
        return OLD_DATA
    i = bisect_right(stamps, stamp)
    if i and stamps[i - 1] == stamp:
        return REPEATED_DATA
    stamps.insert(i, stamp)
    while stamps and stamps[0] + max_ns < stamps[-1]:
        del stamps[0]
    return None


@given(max_ns=st.integers(0, 50),
       stamps=st.lists(st.one_of(st.integers(0, 200),                  # anywhere: old, repeated
                                 st.integers(1, 20).map(lambda d: -d)),  # ahead of the newest
                       max_size=80))
def test_insert_keeps_what_tf2_keeps(max_ns: int, stamps: list[int]) -> None:
    cache = TimeCache(max_ns)
    ref: list[int] = []
    for s in stamps:
        if s < 0:  # "ahead": the newest stamp plus -s (the fast path)
            s = (ref[-1] if ref else 0) - s
        entry = (s, 1, 2, float(s), 0.0, 0.0, 0.0, 0.0, 0.0, 1.0)
        assert cache.insert(entry) == reference_insert(ref, max_ns, s)
        assert cache.stamps == ref
        assert [e[0] for e in cache.entries] == ref
        assert all(e[3] == float(e[0]) for e in cache.entries)  # each stamp with its own values
