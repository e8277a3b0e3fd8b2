"""Timer and Rate ticks per second against raw SimPy ``timeout`` resumptions.

Fair baselines (raw SimPy plus what the ROS semantics require): for a timer,
a :class:`ddes.TimerEvent` built per tick and one ``timer.fire`` trace row;
for a rate, rospy's ``Rate.sleep`` arithmetic (remaining time, advancing
``last_time``, the catch-up rule) per tick.  A rate records no trace row.
"""

from __future__ import annotations

import sys
from pathlib import Path
from typing import Any

import simpy

sys.path.insert(0, str(Path(__file__).resolve().parent))

from common import compare, result, size  # noqa: E402

import ddes  # noqa: E402
from ddes.kernel.trace import Trace  # noqa: E402

N = size(50_000)
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


def fair_timer() -> int:
    env = simpy.Environment()
    trace = Trace()
    append = trace.append_row
    keys = ("expected", "real")
    count = [0]

    def cb(event: ddes.TimerEvent) -> None:
        count[0] += 1

    def proc() -> Any:
        le = lr = 0
        ce = PERIOD_NS
        while True:
            yield env.timeout(PERIOD_NS)
            now = env.now
            event = ddes.TimerEvent.__new__(ddes.TimerEvent)
            event._le, event._lr, event._ce, event._cr = le, lr, ce, now
            event.last_duration = 0.0
            append((now, "timer.fire", "/bench", keys, ce, now))
            cb(event)
            le, lr, ce = ce, now, ce + PERIOD_NS

    env.process(proc())
    env.run(until=N * PERIOD_NS + 1)
    return count[0]


def fair_rate() -> int:
    env = simpy.Environment()
    count = [0]
    period = PERIOD_NS

    def proc() -> Any:
        last = 0
        while True:
            curr = env.now
            if last > curr:
                last = curr
            remaining = period - (curr - last)
            yield env.timeout(remaining if remaining > 0 else 0)
            last += period
            if curr - last > 2 * period:
                last = curr
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
    timer = compare(ddes_timer, raw_simpy, fair_fn=fair_timer)
    rate = compare(ddes_rate, raw_simpy, fair_fn=fair_rate)
    return [
        result("timer_ticks", timer, "ticks/s", "simpy timeout resumptions",
               "+ TimerEvent and a timer.fire trace row per tick", n=N),
        result("rate_sleeps", rate, "ticks/s", "simpy timeout resumptions",
               "+ rospy Rate.sleep arithmetic per tick", n=N),
    ]
