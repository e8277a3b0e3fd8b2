"""Runaway student code ends with a verdict, not a hang (issue 13, item 6)."""

from __future__ import annotations

import time
import warnings
from collections.abc import Generator
from typing import Any

import pytest

import ddes
from ddes.errors import DdesValueError, RunawayError
from ddes.kernel.events import NeverYieldedWarning

String = ddes.get_message_class("std_msgs/String")


def test_a_callback_looping_forever_is_stopped_and_named() -> None:
    world = ddes.World(wall_budget=0.3)
    node = world.create_node("spinner")

    def stuck(_ev: Any) -> None:
        x = 0
        while True:  # a student's loop without yield
            try:
                x += 1
            except Exception:  # noqa: BLE001 - cannot swallow the watchdog
                pass

    ddes.Timer(node, 0.5, stuck, oneshot=True)
    start = time.monotonic()
    with pytest.raises(RunawayError) as err:
        world.run(until=2)
    # The wall budget is a real-time feature (the watchdog's one use of the wall clock), so
    # this bound is wall time, but 100x the 0.3 s budget: it fails only for a watchdog that
    # never fires in time, never for a loaded machine. That the configured budget (not the
    # 10 s default) stopped the loop is checked exactly by the message below.
    assert time.monotonic() - start < 30
    text = str(err.value)
    assert "ran for more than 0.3 s of wall-clock time" in text
    assert "node /spinner" in text and "stuck" in text and "t=0.500000000 s" in text
    assert "yield" in text and "wall_budget" in text


def test_a_generator_callback_stuck_between_yields_is_stopped() -> None:
    world = ddes.World(wall_budget=0.3)
    node = world.create_node("gen")
    other = world.create_node("talker")
    pub = ddes.Publisher(other, "t", String, queue_size=1)

    def cb(_msg: Any) -> Generator[Any, Any, None]:
        yield node.sleep(0.1)
        while True:
            pass

    ddes.Subscriber(node, "t", String, cb)
    world.call_at(10_000_000, lambda: pub.publish(data="x"))
    with pytest.raises(RunawayError, match=r"node /gen: callback .*cb.* more than 0.3 s"):
        world.run(until=1)


def test_a_zero_time_livelock_is_stopped_and_named() -> None:
    world = ddes.World(instant_budget=10_000)
    node = world.create_node("looper")

    def loop() -> Generator[Any, Any, None]:
        yield node.sleep(0.25)
        while True:
            yield world.env.timeout(0)

    node.process(loop())
    with pytest.raises(RunawayError) as err:
        world.run(until=1)
    text = str(err.value)
    assert "zero-time livelock at simulated t=0.250000000 s" in text
    assert "loop" in text and "instant_budget" in text


def test_budgets_are_checked_and_can_be_switched_off() -> None:
    for bad in (0, -1, "1", True):
        with pytest.raises(DdesValueError):
            ddes.World(wall_budget=bad)  # type: ignore[arg-type]
        with pytest.raises(DdesValueError):
            ddes.World(instant_budget=bad)  # type: ignore[arg-type]
    world = ddes.World(wall_budget=None, instant_budget=None)
    assert world.wall_budget is None and world.instant_budget is None
    world.instant_budget = 5
    assert world.instant_budget == 5


def test_the_budgets_do_not_change_a_normal_run() -> None:
    digests = set()
    for budget in (None, 0.5, 60.0):
        world = ddes.World(seed=3, wall_budget=budget)
        node = world.create_node("n")
        ddes.Timer(node, 0.1, lambda _e: None)
        world.run(until=2)
        digests.add(world.digest())
    assert len(digests) == 1


def test_a_forgotten_yield_is_reported_like_a_never_awaited_coroutine() -> None:
    world = ddes.World()
    node = world.create_node("forgetful")
    rate = ddes.Rate(node, 10)
    ticks: list[int] = []

    def main() -> Generator[Any, Any, None]:
        for _ in range(3):
            ticks.append(world.now)
            rate.sleep()  # forgot the yield
        yield node.sleep(0.05)

    node.process(main())
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        world.run(until=1)
    texts = [str(w.message) for w in caught if issubclass(w.category, NeverYieldedWarning)]
    assert texts and all("rate.sleep() was never yielded" in t for t in texts)
    assert "write 'yield rate.sleep()'" in texts[0]
    assert ticks == [0, 0, 0]  # the loop did not wait: that is the bug the warning names


@pytest.mark.parametrize("call", ["node.sleep", "proxy", "wait_for_service"])
def test_other_blocking_calls_warn_too(call: str) -> None:
    world = ddes.World()
    node = world.create_node("n")
    srv_cls = ddes.get_service_class("std_srvs/Empty")
    ddes.Service(world.create_node("s"), "e", srv_cls, lambda req: srv_cls._response_class())

    def main() -> Generator[Any, Any, None]:
        if call == "node.sleep":
            node.sleep(0.1)
        elif call == "proxy":
            ddes.ServiceProxy(node, "e", srv_cls)(srv_cls._request_class())
        else:
            ddes.wait_for_service(node, "e")
        yield node.sleep(0.5)

    node.process(main())
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        world.run(until=1)
    assert any(issubclass(w.category, NeverYieldedWarning) for w in caught)


def test_yielded_calls_do_not_warn() -> None:
    world = ddes.World()
    node = world.create_node("n")
    rate = ddes.Rate(node, 10)

    def main() -> Generator[Any, Any, None]:
        for _ in range(5):
            yield rate.sleep()
        yield node.sleep(0.1)

    node.process(main())
    with warnings.catch_warnings():
        warnings.simplefilter("error", NeverYieldedWarning)
        world.run(until=1)


def test_the_console_reports_runaway_code() -> None:
    world = ddes.World(wall_budget=0.3)
    node = world.create_node("bad")

    def stuck(_ev: Any) -> None:
        while True:
            pass

    ddes.Timer(node, 0.1, stuck, oneshot=True)
    console = ddes.Console(world)
    out = console.run("sleep 1", check=False)
    assert "node /bad: callback" in out and "stuck" in out
