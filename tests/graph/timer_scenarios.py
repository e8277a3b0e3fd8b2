"""Timer scenarios run both in ddes and in real rospy (tests/graph/test_timer_vs_rospy.py).

Each scenario drives a timer on simulated time with ``/clock`` messages: the
clock is reset to 0, ``pre`` ticks are published, the timer is created,
then the ``ticks`` are published one at a time.  The callback records
``(current_expected, current_real, last_expected, last_real)`` in integer
nanoseconds (None for a missing ``last_*``); on call ``i`` it sleeps
``sleeps[str(i)]`` ns of ROS time (a generator in ddes, ``rospy.sleep`` in
rospy) and calls ``timer.shutdown()`` when ``shutdown_at == i``.
"""

from __future__ import annotations

from collections.abc import Generator
from typing import Any

import ddes
from ddes.graph.timer import TimerEvent

MS = 1_000_000
S = 1_000_000_000


def steps(start_ms: int, stop_ms: int, step_ms: int) -> list[int]:
    """Clock ticks from ``start_ms`` to ``stop_ms`` inclusive, every ``step_ms`` (as ns)."""
    return [t * MS for t in range(start_ms, stop_ms + 1, step_ms)]


def _sc(name: str, period_ms: float, pre: list[int], ticks: list[int], **kw: Any) -> dict[str, Any]:
    return {"name": name, "period": round(period_ms * MS), "pre": pre, "ticks": ticks, **kw}


SCENARIOS: list[dict[str, Any]] = [
    # plain periods, created after the first /clock
    _sc("p100_fine_ticks", 100, [S], steps(1010, 1600, 10)),
    _sc("p100_coarse_ticks", 100, [S], steps(1030, 2000, 30)),
    _sc("p300_ticks_50ms", 300, [S], steps(1050, 3000, 50)),
    # 1.0 / 0.11 s -> Rate period int(1e9 / 9.0909...) = 109,999,999 ns
    _sc("p110_rate_a_nanosecond_short", 110, [S],
        sorted({S + k * 109_999_999 for k in range(1, 8)} | {S + k * 110 * MS for k in range(1, 8)})),
    _sc("p1000_slow_ticks", 1000, [S], steps(1100, 6000, 100)),
    _sc("p50_ticks_7ms", 50, [S], steps(1007, 1400, 7)),
    _sc("p10_aligned_ticks", 10, [S], steps(1010, 1100, 10)),
    _sc("p100_ticks_slower_than_period", 100, [S], steps(1250, 3000, 250)),
    _sc("p100_irregular_ticks", 100, [S],
        [t * MS for t in (1003, 1099, 1100, 1101, 1180, 1330, 1340, 1600, 1610, 1700, 1905, 2000)]),
    # callbacks that take simulated time
    _sc("slow_first_callback_250", 100, [S], steps(1010, 2000, 10), sleeps={"0": 250 * MS}),
    _sc("slow_second_callback_150", 100, [S], steps(1010, 2000, 10), sleeps={"1": 150 * MS}),
    _sc("every_callback_takes_the_period", 100, [S], steps(1010, 2000, 10),
        sleeps={str(i): 100 * MS for i in range(12)}),
    _sc("every_callback_half_the_period", 100, [S], steps(1010, 2000, 10),
        sleeps={str(i): 50 * MS for i in range(12)}),
    _sc("third_callback_350", 100, [S], steps(1010, 2200, 10), sleeps={"2": 350 * MS}),
    _sc("first_callback_one_second", 100, [S], steps(1020, 3000, 20), sleeps={"0": S}),
    _sc("callback_sleeps_zero", 100, [S], steps(1010, 1500, 10), sleeps={"0": 0, "1": 0}),
    # one-shot and shutdown
    _sc("oneshot_200", 200, [S], steps(1010, 1600, 10), oneshot=True),
    _sc("oneshot_110_rate_a_nanosecond_short", 110, [S], [S + 109_999_999, S + 110 * MS],
        oneshot=True),
    _sc("oneshot_slow_callback", 100, [S], steps(1010, 1600, 10), oneshot=True,
        sleeps={"0": 200 * MS}),
    _sc("shutdown_in_third_callback", 100, [S], steps(1010, 1800, 10), shutdown_at=2),
    _sc("shutdown_in_first_slow_callback", 100, [S], steps(1010, 1800, 10), shutdown_at=0,
        sleeps={"0": 150 * MS}),
    # created at time 0, before the first /clock
    _sc("created_at_zero_first_clock_1s", 100, [], steps(1000, 1600, 10)),
    _sc("created_at_zero_first_clock_50ms", 100, [], steps(50, 600, 10)),
    _sc("created_at_zero_first_clock_250ms", 100, [], steps(250, 800, 10)),
    _sc("created_at_zero_first_clock_100s", 1000, [], steps(100_000, 104_000, 100)),
    _sc("created_at_zero_slow_first_callback", 100, [], steps(1000, 1800, 10),
        sleeps={"0": 220 * MS}),
    _sc("created_at_zero_oneshot", 200, [], steps(5000, 5500, 10), oneshot=True),
    # /clock jumps
    _sc("forward_jump_far", 100, [S], steps(1010, 1300, 10) + steps(5000, 5400, 10)),
    _sc("forward_jump_150ms", 100, [S], steps(1010, 1200, 10) + steps(1350, 1700, 10)),
    _sc("backward_jump_reset", 100, [2 * S], steps(2010, 2450, 10) + steps(1000, 1400, 10),
        reset=True),
    _sc("backward_jump_above_sleep_start", 100, [S],
        steps(1010, 1150, 10) + [1130 * MS, 1120 * MS] + steps(1160, 1500, 10), reset=True),
    _sc("backward_jump_while_callback_runs", 100, [2 * S],
        steps(2010, 2120, 10) + steps(1000, 1500, 10), reset=True, sleeps={"0": 50 * MS}),
]

#: Scenarios whose ddes result deviates from rospy on purpose (docs/time.md): rospy's timer
#: thread dies on a backwards jump unless ``reset=True``; a ddes timer carries on as with reset.
DEVIATIONS: list[dict[str, Any]] = [
    _sc("backward_jump_no_reset", 100, [2 * S], steps(2010, 2450, 10) + steps(1000, 1400, 10)),
]


def run_in_ddes(sc: dict[str, Any]) -> dict[str, Any]:
    """Run one scenario in a fresh ddes world; ``{"calls": [...], "alive": bool}``."""
    world = ddes.World(seed=0, strict=False)  # a failing callback is logged, as rospy's is
    world.log_output = lambda line, level: None
    node = world.create_node("timer_driver", use_sim_time=True)
    clock_cls = ddes.get_message_class("rosgraph_msgs/Clock")
    pub = world.create_node("clock").advertise("/clock", clock_cls, queue_size=100)
    calls: list[list[int | None]] = []
    state: dict[str, ddes.Timer] = {}

    def ns_of(t: ddes.Time | None) -> int | None:
        return None if t is None else t.to_nsec()

    def cb(ev: TimerEvent) -> Generator[Any, Any, None]:
        i = len(calls)
        calls.append([ns_of(ev.current_expected), ns_of(ev.current_real),
                      ns_of(ev.last_expected), ns_of(ev.last_real)])
        d = sc.get("sleeps", {}).get(str(i))
        if d is not None:
            yield node.sleep(ddes.Duration(0, d))
        if sc.get("shutdown_at") == i:
            state["timer"].shutdown()

    def tick(ns: int) -> Generator[Any, Any, None]:
        pub.publish(clock_cls(ddes.Time(ns // S, ns % S)))
        yield world.timeout(0.01)

    def drive() -> Generator[Any, Any, None]:
        yield world.timeout(0.01)  # the /clock connection
        for t in [0, *sc["pre"]]:
            yield from tick(t)
        state["timer"] = ddes.Timer(node, ddes.Duration(0, sc["period"]), cb,
                                    oneshot=sc.get("oneshot", False), reset=sc.get("reset", False))
        for t in sc["ticks"]:
            yield from tick(t)
        alive = state["timer"].is_alive()
        state["timer"].shutdown()
        return alive

    proc = world.process(drive())
    world.run()
    return {"calls": calls, "alive": proc.value}
