"""A long run with a bounded trace: 10⁷ events in flat memory, with an exact digest.

    python benchmarks/trace_scale.py                      # 10^7 events, bound 100_000 rows
    python benchmarks/trace_scale.py --events 1e6 --unbounded
    python benchmarks/trace_scale.py --events 1e6 --check  # also the unbounded digest, compared

The world: a talker publishing std_msgs/String at 10 kHz to two listeners
and a 1 kHz timer (≈ 3 trace rows per publish, one per tick).  It runs until
the trace holds ``--events`` rows.  Prints one JSON line: events, the digest,
CPU seconds, µs of CPU per event (run + digest), the digest's own µs per event,
and the peak resident set size (``ru_maxrss``) of this process — the figure
that shows the memory bound.  ``--spill PATH`` also streams every evicted
row's canonical line to PATH.  ``--gc-freeze`` calls ``gc.freeze()`` after
the world is set up (and reports it).
"""

from __future__ import annotations

import argparse
import gc
import json
import resource
import sys
import time
from pathlib import Path
from typing import Any

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

import ddes  # noqa: E402
from ddes.msg import get_message_class  # noqa: E402

String = get_message_class("std_msgs/String")
PERIOD_NS = 100_000  # 10 kHz publishing


def build(events: int) -> tuple[ddes.World, int]:
    """The world, and the simulated ns to run so that it records about ``events`` rows."""
    world = ddes.World()
    talker = world.create_node("talker", disable_rosout=True)
    pub = talker.advertise("chatter", String, queue_size=10)
    got = [0]

    def cb(_msg: Any) -> None:
        got[0] += 1

    for i in range(2):
        world.create_node(f"listener{i}", disable_rosout=True).subscribe("chatter", String, cb)
    world.create_node("ticker", disable_rosout=True).create_timer(
        ddes.Duration(0, 1_000_000), lambda _ev: None)
    msg = String(data="hello")

    def loop() -> Any:
        while True:
            pub.publish(msg)
            yield world.env.timeout(PERIOD_NS)

    talker.process(loop())
    # per 1 ms: 10 publishes x 3 rows + 1 timer row
    until_ns = int(events / 31 * 1_000_000)
    return world, until_ns


def run(events: int, bound: int | None, spill: str | None = None,
        freeze: bool = False) -> dict[str, Any]:
    world, until_ns = build(events)
    if bound is not None:
        world.trace.bound(bound, spill=spill)
    if freeze:
        gc.freeze()
    t0 = time.process_time()
    world.run(until=ddes.Duration.from_nsec(until_ns))
    t1 = time.process_time()
    digest = world.digest()
    t2 = time.process_time()
    world.trace.close_spill()
    total = world.trace.total
    return {
        "events": total,
        "bound": bound,
        "in_memory": len(world.trace),
        "digest": digest,
        "cpu_s": round(t2 - t0, 2),
        "us_per_event": round((t2 - t0) / total * 1e6, 3),
        "digest_us_per_event_at_end": round((t2 - t1) / total * 1e6, 3),
        "peak_rss_mib": round(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024, 1),
        "gc_freeze": freeze,
    }


def main(argv: list[str]) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--events", type=float, default=1e7)
    ap.add_argument("--bound", type=int, default=100_000)
    ap.add_argument("--unbounded", action="store_true")
    ap.add_argument("--spill", default=None)
    ap.add_argument("--gc-freeze", action="store_true")
    ap.add_argument("--check", action="store_true",
                    help="also run unbounded and compare the digests (needs the memory)")
    args = ap.parse_args(argv)
    out = run(int(args.events), None if args.unbounded else args.bound, args.spill,
              args.gc_freeze)
    if args.check:
        ref = run(int(args.events), None)
        out["unbounded_digest_equal"] = ref["digest"] == out["digest"]
    print(json.dumps(out))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
