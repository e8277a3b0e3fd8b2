"""Blocking calls on greenlets (ddes.graph.blocking): same order as the kernel's, both styles."""

from __future__ import annotations

import threading
from collections.abc import Generator
from typing import Any

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import ddes
from ddes.compat import rospy
from ddes.errors import (
    BlockingInYieldCodeError,
    BlockingOutsideNodeError,
    ROSInterruptException,
)
from ddes.graph.blocking import (
    INIT_TEXT,
    current_node,
    current_task,
    is_blocking_node,
    spawn,
    wait,
    wait_ns,
)
from ddes.graph.callbacks import GreenCallbackQueue
from ddes.msg import get_message_class

String = get_message_class("std_msgs/String")
MS = 1_000_000


def _loops(green: bool | str, periods: list[int], until: float
           ) -> tuple[list[tuple[str, int]], str]:
    """Loops at several rates, one node each, written blocking (``"rospy"``: with
    ``rospy.Rate``) or yield-style."""
    world = ddes.World(seed=3)
    log: list[tuple[str, int]] = []
    for i, hz in enumerate(periods):
        node = world.create_node(f"n{i}")
        rate = ddes.Rate(node, hz)
        if green == "rospy":
            def rospy_main(node: Any = node, hz: int = hz) -> None:
                rospy_rate = rospy.Rate(hz)
                while not rospy.is_shutdown():
                    log.append((node.name, world.now))
                    rospy_rate.sleep()
            spawn(world, rospy_main, node=node)
        elif green:
            def main(node: Any = node, rate: Any = rate) -> None:
                while not node.is_shutdown():
                    log.append((node.name, world.now))
                    wait(rate.sleep())
            spawn(world, main, node=node)
        else:
            def gen(node: Any = node, rate: Any = rate) -> Generator[Any, Any, None]:
                while not node.is_shutdown():
                    log.append((node.name, world.now))
                    yield rate.sleep()
            node.process(gen())
    world.run(until=until)
    return log, world.digest()


@settings(max_examples=25, deadline=None)
@given(st.lists(st.integers(1, 50), min_size=1, max_size=4), st.floats(0.1, 2.0))
def test_blocking_loops_run_in_the_order_and_trace_of_yield_style(periods: list[int],
                                                                  until: float) -> None:
    assert _loops(True, periods, until) == _loops(False, periods, until) \
        == _loops("rospy", periods, until)


def test_a_rospy_rate_sleep_is_interrupted_by_shutdown_on_sim_time_only() -> None:
    """rospy/timer.py: on /clock time a shutdown raises ROSInterruptException in the sleep; on
    the wall clock the sleep is time.sleep and ends on time."""
    world = ddes.World()
    node = world.create_node("n", use_sim_time=True)
    clock = world.create_node("clock").advertise("/clock", ddes.get_message_class(
        "rosgraph_msgs/Clock"), queue_size=1)
    log: list[str] = []

    def main() -> None:
        rate = rospy.Rate(1)
        try:
            rate.sleep()
        except ROSInterruptException as exc:
            log.append(f"{exc} at {world.now / 1e9}")
            raise

    world.call_at(MS, lambda: clock.publish(clock=ddes.Time(1)))
    done = spawn(world, main, node=node)
    world.call_at(300 * MS, lambda: node.shutdown("bye"))
    world.run(until=5.0)
    assert log == ["ROS shutdown request at 0.3"] and done.ok and done.value is None

    wall = ddes.World()
    walled = wall.create_node("n")
    ends: list[float] = []

    def sleeper() -> None:
        rospy.Rate(1).sleep()
        ends.append(wall.now / 1e9)

    spawn(wall, sleeper, node=walled)
    wall.call_at(300 * MS, lambda: walled.shutdown("bye"))
    wall.run(until=5.0)
    assert ends == [1.0]
    with pytest.raises(BlockingOutsideNodeError, match="rate.sleep"):
        wait_ns(world.env, MS, "rate.sleep()")


def test_a_main_runs_at_once_until_it_blocks_and_sees_the_events_value() -> None:
    world = ddes.World()
    node = world.create_node("n")
    seen: list[object] = []

    def main() -> int:
        seen.append(("start", world.now, current_node() is node))
        value = wait(world.env.timeout(5 * MS, "v"))
        seen.append(("woke", world.now, value))
        return 7

    done = spawn(world, main, node=node)
    assert seen == [("start", 0, True)]  # ran at once, in the caller's instant
    assert is_blocking_node(node) and isinstance(node.callbacks, GreenCallbackQueue)
    world.run()
    assert seen[1] == ("woke", 5 * MS, "v")
    assert done.value == 7


def test_a_failed_event_raises_in_the_waiting_code() -> None:
    world = ddes.World()
    node = world.create_node("n")
    got: list[str] = []

    def main() -> None:
        ev = world.env.event()
        world.call_at(MS, lambda: ev.fail(ValueError("bad")))
        try:
            wait(ev)
        except ValueError as exc:
            got.append(str(exc))

    spawn(world, main, node=node)
    world.run()
    assert got == ["bad"]


def test_both_styles_talk_in_one_world() -> None:
    world = ddes.World()
    green = world.create_node("green")
    plain = world.create_node("plain")
    pub = ddes.Publisher(green, "chatter", String, queue_size=10)
    heard: list[tuple[int, str]] = []
    ddes.Subscriber(plain, "chatter", String, lambda m: heard.append((world.now, m.data)))
    echo = ddes.Publisher(plain, "echo", String, queue_size=10)

    def echo_later(m: Any) -> Generator[Any, Any, None]:  # a yield-style generator callback
        yield plain.sleep(0.05)
        echo.publish(String(data=m.data + "!"))

    ddes.Subscriber(plain, "chatter", String, echo_later)

    def main() -> None:
        rate = ddes.Rate(green, 10)
        wait(green.sleep(0.01))
        for i in range(3):
            pub.publish(String(data=f"hi {i}"))
            msg = wait(green.wait_for_message("echo", String, timeout=1.0))
            heard.append((world.now, "green got " + msg.data))
            wait(rate.sleep())

    spawn(world, main, node=green)
    world.run(until=1.0)
    assert [d for _, d in heard] == ["hi 0", "green got hi 0!", "hi 1", "green got hi 1!",
                                     "hi 2", "green got hi 2!"]


def test_a_blocking_callback_holds_the_single_spinner_as_a_generator_does() -> None:
    world = ddes.World()
    node = world.create_node("probe")
    other = world.create_node("other")
    pub = ddes.Publisher(other, "t", String, queue_size=10)
    log: list[str] = []

    def timer_cb(_ev: Any) -> None:
        log.append(f"timer start {world.now / 1e9:.1f}")
        wait(node.sleep(0.5))
        log.append(f"timer end {world.now / 1e9:.1f}")

    ddes.Subscriber(node, "t", String, lambda _m: log.append(f"sub cb {world.now / 1e9:.1f}"),
                    queue_size=10)
    ddes.Timer(node, 1.0, timer_cb)
    spawn(world, lambda: None, node=node)  # the node's code blocks from now on
    world.call_at(1_200 * MS, lambda: pub.publish(String(data="x")))
    world.run(until=1.9)
    assert log == ["timer start 1.0", "timer end 1.5", "sub cb 1.5"]


def test_with_the_rospy_spinner_a_blocked_callback_blocks_only_its_own_subscription() -> None:
    world = ddes.World()
    node = world.create_node("probe", spinner="rospy")
    other = world.create_node("other")
    a = ddes.Publisher(other, "a", String, queue_size=10)
    b = ddes.Publisher(other, "b", String, queue_size=10)
    log: list[str] = []

    def slow(m: Any) -> None:
        log.append(f"a start {m.data} {world.now / 1e9:.1f}")
        wait(node.sleep(0.5))
        log.append(f"a end {m.data} {world.now / 1e9:.1f}")

    ddes.Subscriber(node, "a", String, slow, queue_size=10)
    ddes.Subscriber(node, "b", String, lambda m: log.append(f"b {world.now / 1e9:.1f}"))
    spawn(world, lambda: None, node=node)
    world.call_at(100 * MS, lambda: (a.publish(String(data="1")), a.publish(String(data="2"))))
    world.call_at(200 * MS, lambda: b.publish(String(data="x")))
    world.run(until=2.0)
    assert log == ["a start 1 0.1", "b 0.2", "a end 1 0.6", "a start 2 0.6", "a end 2 1.1"]


def test_shutdown_interrupts_a_blocked_main_and_its_callbacks() -> None:
    world = ddes.World()
    node = world.create_node("n")
    log: list[str] = []

    def timer_cb(_ev: Any) -> None:
        log.append("cb sleeps")
        wait(node.sleep(10.0))
        log.append("never")

    def main() -> str:
        ddes.Timer(node, 0.5, timer_cb, oneshot=True)
        try:
            wait(node.sleep(10.0))
        except ROSInterruptException as exc:
            log.append(f"main: {exc} at {world.now / 1e9}")
            raise
        return "never"

    done = spawn(world, main, node=node)
    world.call_at(1_000 * MS, lambda: node.shutdown("bye"))
    world.run(until=20.0)
    assert log == ["cb sleeps", "main: ROS shutdown request at 1.0"]
    assert done.ok and done.value is None  # a rospy script ends quietly this way
    assert not world.callback_errors


def test_an_uninterruptible_wait_returns_at_shutdown() -> None:
    world = ddes.World()
    node = world.create_node("n")
    done = spawn(world, lambda: wait(node.spin(), "rospy.spin()", interruptible=False),
                 node=node)
    world.call_at(MS, lambda: node.shutdown("bye"))
    world.run()
    assert done.ok and done.value == "bye"


def test_a_raising_main_crashes_its_node_and_exit_codes_pass_through() -> None:
    world = ddes.World(strict=False)
    world.log_output = False
    node = world.create_node("n")

    def main() -> None:
        wait(node.sleep(1.0))
        raise RuntimeError("boom")

    spawn(world, main, node=node)
    other = world.create_node("m")
    code = spawn(world, lambda: (wait(other.sleep(0.5)), exit(3)), node=other)
    world.run(until=2.0)
    assert node.is_shutdown() and code.value == 3
    crash = world.trace.select(kind="node.exit", source="/n")
    assert [e.details["code"] for e in crash] == [1]


def test_a_callback_that_raises_after_blocking_is_a_bad_callback() -> None:
    world = ddes.World(strict=False)
    world.log_output = False
    node = world.create_node("n")

    def cb(_ev: Any) -> None:
        wait(node.sleep(0.1))
        raise KeyError("late")

    ddes.Timer(node, 1.0, cb)
    spawn(world, lambda: None, node=node)
    world.run(until=2.5)  # a raising callback ends rospy's timer: one error, not two
    assert [(n, e.args) for n, _, e, _ in world.callback_errors] == [("/n", ("late",))]


def test_strict_worlds_raise_a_blocked_callbacks_error_out_of_run() -> None:
    world = ddes.World(strict=True)
    node = world.create_node("n")

    def cb(_ev: Any) -> None:
        wait(node.sleep(0.1))
        raise KeyError("late")

    ddes.Timer(node, 1.0, cb)
    spawn(world, lambda: None, node=node)
    with pytest.raises(KeyError, match="late"):
        world.run(until=1.5)


def test_blocking_outside_any_node_raises_rospys_text_and_the_fix() -> None:
    world = ddes.World()
    with pytest.raises(BlockingOutsideNodeError) as info:
        wait(world.env.timeout(1), "rospy.sleep()")
    assert INIT_TEXT in str(info.value) and "from ddes.compat import rospy" in str(info.value)
    assert current_task() is None and current_node() is None


def test_blocking_in_yield_style_code_says_to_yield() -> None:
    world = ddes.World()
    node = world.create_node("n")
    errors: list[BaseException] = []

    def gen() -> Generator[Any, Any, None]:
        try:
            wait(world.env.timeout(1), "rate.sleep()")
        except BlockingInYieldCodeError as exc:
            errors.append(exc)
        yield node.sleep(0.1)

    node.process(gen())
    world.run()
    assert len(errors) == 1 and "yield rate.sleep()" in str(errors[0])


def test_blocking_from_a_thread_of_ones_own_names_the_thread() -> None:
    world = ddes.World()
    errors: list[BaseException] = []

    def body() -> None:
        try:
            wait(world.env.timeout(1), "rospy.sleep()")
        except BlockingOutsideNodeError as exc:
            errors.append(exc)

    t = threading.Thread(target=body, name="worker")
    t.start()
    t.join()
    assert len(errors) == 1 and "thread ddes did not start (worker)" in str(errors[0])


def test_an_event_already_processed_returns_without_blocking() -> None:
    world = ddes.World()
    node = world.create_node("n")
    ev = world.env.timeout(0, "early")
    world.run()
    got: list[object] = []
    spawn(world, lambda: got.append((wait(ev), world.now)), node=node)
    assert got == [("early", 0)]


def test_callback_tasks_are_reused_but_never_while_one_is_blocked() -> None:
    from ddes.graph.blocking import _POOL_KEY

    world = ddes.World()
    node = world.create_node("n", spinner="rospy")
    other = world.create_node("o")
    fast = ddes.Publisher(other, "fast", String, queue_size=100)
    slow = ddes.Publisher(other, "slow", String, queue_size=100)
    seen: list[tuple[str, int, int]] = []

    def on_slow(m: Any) -> None:
        me = id(current_task())
        wait(node.sleep(0.05))
        seen.append(("slow", world.now // MS, int(id(current_task()) == me)))

    ddes.Subscriber(node, "fast", String, lambda m: seen.append(("fast", world.now // MS, 0)),
                    queue_size=100)
    ddes.Subscriber(node, "slow", String, on_slow, queue_size=100)
    spawn(world, lambda: None, node=node)

    def talk() -> Generator[Any, Any, None]:
        yield other.sleep(0.01)
        slow.publish(String(data="s"))
        for _ in range(5):
            fast.publish(String(data="f"))
            yield other.sleep(0.01)

    other.process(talk())
    world.run(until=1.0)
    assert seen == [("fast", 10, 0), ("fast", 20, 0), ("fast", 30, 0), ("fast", 40, 0),
                    ("fast", 50, 0), ("slow", 60, 1)]
    assert len(world.extensions[_POOL_KEY]) == 2  # one ran the fast callbacks, one was blocked
