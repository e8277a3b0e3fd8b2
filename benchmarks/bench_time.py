"""Timer and Rate ticks per second against raw SimPy ``timeout`` resumptions."""

from __future__ import annotations

import sys
from pathlib import Path
from typing import Any

import simpy

sys.path.insert(0, str(Path(__file__).resolve().parent))

from common import compare, row  # noqa: E402

import ddes  # noqa: E402

N = 50_000
PERIOD_NS = 1_000_000


def raw_simpy() -> int:
    env = simpy.Environment()
    count = [0]

    def proc() -> Any:
        while True:
            yield env.timeout(PERIOD_NS)
            count[0] += 1

    env.process(proc())
    env.run(until=N * PERIOD_NS + 1)
    return count[0]


def ddes_timer() -> int:
    world = ddes.World()
    node = world.create_node("bench")
    count = [0]

    def cb(_ev: ddes.TimerEvent) -> None:
        count[0] += 1

    node.create_timer(ddes.Duration(0, PERIOD_NS), cb)
    world.run(until=ddes.Time(0, 0) + ddes.Duration.from_nsec(N * PERIOD_NS + 1))
    return count[0]


def ddes_rate() -> int:
    world = ddes.World()
    node = world.create_node("bench")
    rate = node.create_rate(1e9 / PERIOD_NS)
    count = [0]

    def loop() -> Any:
        while True:
            yield rate.sleep()
            count[0] += 1

    node.process(loop())
    world.run(until=ddes.Duration.from_nsec(N * PERIOD_NS + 1))
    return count[0]


def benchmarks() -> list[dict[str, Any]]:
    timer, base = compare(ddes_timer, raw_simpy)
    rate, base2 = compare(ddes_rate, raw_simpy)
    return [
        row("timer_ticks", timer, "ticks/s", base, "simpy timeout resumptions", n=N),
        row("rate_sleeps", rate, "ticks/s", base2, "simpy timeout resumptions", n=N),
    ]
