"""The trace at scale: digest cost per event and memory per event.

* ``trace_digest_per_event``: events digested per CPU second by
  ``Trace.digest()`` (per-shape encoders, folded incrementally) against the
  reference form it must equal (``TraceEvent.to_json`` per event, then
  sha256, as the digest was computed before), on the same recorded run
  (talker at 10 kHz to two listeners, a 1 kHz timer), interleaved;
  ``us_per_event`` is the median CPU µs per event;
* ``trace_memory_per_event``: bytes the world holds per recorded event with
  an unbounded trace (tracemalloc), against the same run with the trace
  bounded to 5,000 rows (``Trace.bound``): the bound makes memory flat, so
  its bytes per event shrink as the run grows.
"""

from __future__ import annotations

import copy
import hashlib
import sys
import tracemalloc
from collections.abc import Callable
from pathlib import Path
from typing import Any

sys.path.insert(0, str(Path(__file__).resolve().parent))

from common import compare, result, row, size  # noqa: E402
from trace_scale import build  # noqa: E402

import ddes  # noqa: E402
from ddes.kernel.trace import Trace  # noqa: E402

EVENTS = size(100_000)


def _recorded() -> Trace:
    world, until_ns = build(EVENTS)
    world.run(until=ddes.Duration.from_nsec(until_ns))
    return world.trace


def _reference(trace: Trace) -> str:
    h = hashlib.sha256()
    for ev in trace:
        h.update(ev.to_json().encode("utf-8"))
        h.update(b"\n")
    return h.hexdigest()


def _memory(bound: int | None) -> tuple[float, int]:
    tracemalloc.start()
    try:
        before = tracemalloc.get_traced_memory()[0]
        world, until_ns = build(EVENTS)
        if bound is not None:
            world.trace.bound(bound)
        world.run(until=ddes.Duration.from_nsec(until_ns))
        held = tracemalloc.get_traced_memory()[0] - before
    finally:
        tracemalloc.stop()
    return held / world.trace.total, world.trace.total


def digests(trace: Trace) -> tuple[Callable[[], int], Callable[[], int]]:
    """``trace``'s digest the ddes way and the reference way, each returning the event count."""
    n = len(trace)

    def new() -> int:
        copy.copy(trace).digest()  # a copy starts with nothing folded
        return n

    def old() -> int:
        _reference(trace)
        return n

    return new, old


def benchmarks() -> list[dict[str, Any]]:
    trace = _recorded()
    n = len(trace)
    if copy.copy(trace).digest() != _reference(trace):
        raise AssertionError("the incremental digest differs from the reference form")
    new, old = digests(trace)
    c = compare(new, old, repeat=5)
    out = [result("trace_digest_per_event", c, "events/s", "TraceEvent.to_json + sha256 per event",
                  n=n, us_per_event=round(1e6 / c[0], 3),
                  reference_us_per_event=round(1e6 / c[1], 3))]
    per, total = _memory(None)
    per_bounded, _ = _memory(5_000)
    out.append(row("trace_memory_per_event", per, "bytes/event", per_bounded,
                   "the same run, trace.bound(5000)", n=total))
    return out


if __name__ == "__main__":
    import json

    for r in benchmarks():
        print(json.dumps(r))
