"""The trace at scale: the incremental digest, its fast encoder, and the bounded mode.

The digest must equal the reference form (sha256 over ``TraceEvent.to_json``
lines, the form every golden digest was made with); a bounded trace must give
the same digest as an unbounded one in flat memory (tracemalloc peak, not time).
"""

from __future__ import annotations

import copy
import enum
import hashlib
import tracemalloc
from pathlib import Path
from typing import Any

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import ddes
from ddes.errors import DdesValueError
from ddes.kernel.trace import Trace

from .test_trace_api import FIXED_DIGEST, fill_fixed

String = ddes.get_message_class("std_msgs/String")


def reference_digest(trace: Trace) -> str:
    """The digest as it was computed before it became incremental."""
    h = hashlib.sha256()
    for ev in trace:
        h.update(ev.to_json().encode("utf-8"))
        h.update(b"\n")
    return h.hexdigest()


class Colour(enum.IntEnum):
    RED = 1


class Thing:
    def __repr__(self) -> str:
        return "<Thing object at 0x7f00deadbeef>"


scalars = st.one_of(
    st.none(), st.booleans(), st.integers(), st.text(),
    st.floats(allow_nan=True, allow_infinity=True), st.binary(max_size=40),
    st.sampled_from([Colour.RED, ddes.Time(3, 4), ddes.Duration(-1, 5), Thing(),
                     "line\u2028sep\x85 <X at 0x12ab>", frozenset({"b", "a"}), (1, "x")]),
)
values = st.recursive(scalars, lambda inner: st.one_of(
    st.lists(inner, max_size=3), st.dictionaries(st.text(max_size=5), inner, max_size=3)),
    max_leaves=8)
keys = st.lists(st.text(max_size=6), min_size=0, max_size=5)


@settings(max_examples=300, deadline=None)
@given(st.lists(st.tuples(st.integers(0, 10**12), st.text(max_size=8), st.text(max_size=8),
                          keys, st.lists(values, max_size=5), st.booleans()),
                max_size=6))
def test_fast_lines_equal_the_reference_form(rows: list[Any]) -> None:
    trace = Trace()
    for t, kind, source, names, vals, as_row in rows:
        if as_row:
            n = min(len(names), len(vals))
            trace.append_row((t, kind, source, tuple(names[:n]), *vals[:n]))
        else:
            trace.append(t, kind, source, dict(zip(names, vals)))
    assert list(trace.lines()) == [ev.to_json() for ev in trace]
    assert trace.digest() == reference_digest(trace)


def test_incremental_digest_asked_mid_run_equals_the_whole() -> None:
    world = ddes.World(seed=3)
    pub = world.create_node("talker").advertise("chatter", String, queue_size=10)
    world.create_node("listener").subscribe("chatter", String, lambda m: None)
    world.run(until=0.01)
    seen = []
    for i in range(5):
        pub.publish(String(data=f"m{i}"))
        world.run_for(0.01)
        seen.append(world.digest())
    assert world.digest() == reference_digest(world.trace)
    assert len(set(seen)) == len(seen)  # each digest covers the events so far
    trace = Trace()
    fill_fixed(trace, "append_row", "append")
    assert trace.digest() == trace.digest() == FIXED_DIGEST


def _world(bound: int | None, spill: Path | None = None) -> ddes.World:
    world = ddes.World(seed=1)
    talker = world.create_node("talker", disable_rosout=True)
    pub = talker.advertise("chatter", String, queue_size=10)
    for i in range(2):
        world.create_node(f"listener{i}", disable_rosout=True).subscribe(
            "chatter", String, lambda m: None)
    world.create_node("ticker", disable_rosout=True).create_timer(
        ddes.Duration(0, 1_000_000), lambda ev: None)
    if bound is not None:
        world.trace.bound(bound, spill=None if spill is None else str(spill))

    def loop() -> Any:
        i = 0
        while True:
            pub.publish(String(data=f"hello {i % 7}"))
            i += 1
            yield world.env.timeout(100_000)

    talker.process(loop())
    return world


def test_bounded_trace_keeps_the_digest_counts_and_spills_every_line(tmp_path: Path) -> None:
    full = _world(None)
    full.run(until=0.2)
    spill = tmp_path / "spill.jsonl"
    bounded = _world(500, spill)
    bounded.run(until=0.2)
    tr = bounded.trace
    assert tr.evicted > 0 and len(tr) <= 500 + 125 and tr.total == len(full.trace)
    assert tr.digest() == full.digest() == reference_digest(full.trace)
    assert tr.digest() == full.digest()  # asking twice changes nothing
    assert tr.counts == full.trace.counts
    assert tr.complete
    tr.close_spill()
    assert spill.read_text(encoding="utf-8").splitlines() + list(tr.lines()) == \
        list(full.trace.lines())
    assert [ev.to_json() for ev in tr] == list(full.trace.lines())[-len(tr):]
    # running on after a digest still folds exactly
    bounded.run(until=0.3)
    full.run(until=0.3)
    assert bounded.digest() == full.digest()


def test_a_bounded_run_of_100k_events_stays_in_flat_memory() -> None:
    """10^5 events with a 5,000-row bound: the peak is a fraction of the unbounded trace's."""
    until = 100_000 / 31 * 1e-3  # about 31 rows per simulated ms
    tracemalloc.start()
    try:
        world = _world(5_000)
        world.run(until=until)
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    assert world.trace.total >= 95_000
    # the rows alone of an unbounded trace take ~15 MiB here; 5,000 rows take well under 2 MiB
    assert peak < 6 * 2**20, f"peak {peak / 2**20:.1f} MiB"
    ref = _world(None)
    ref.run(until=until)
    assert world.digest() == ref.digest()


def test_bound_refuses_bad_values_and_dumping_or_copying_what_it_dropped(tmp_path: Path) -> None:
    trace = Trace()
    for bad in (0, -1, True, 2.5, "10"):
        with pytest.raises(DdesValueError, match="bound"):
            trace.bound(bad)  # type: ignore[arg-type]
    with pytest.raises(DdesValueError, match="spill"):
        trace.bound(None, spill=str(tmp_path / "x"))
    trace.bound(2)
    for i in range(10):
        trace.append(i, "log", "/n", {"msg": str(i)})
    assert trace.evicted > 0 and trace.bounded == 2
    with pytest.raises(DdesValueError, match="spill=PATH"):
        trace.dump(str(tmp_path / "t.jsonl"))
    with pytest.raises(DdesValueError, match="evicted"):
        copy.deepcopy(trace)
    trace.bound(None)
    assert trace.bounded is None
    fresh = Trace()
    fresh.bound(100)
    fresh.append(0, "log", "/n", {"msg": "x"})
    twin = copy.deepcopy(fresh)  # nothing evicted yet: copies fine, digest re-folded
    assert twin.digest() == fresh.digest()
