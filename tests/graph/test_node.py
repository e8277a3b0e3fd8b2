"""Nodes: names and remapping, private parameters, lifecycle, spinners, /clock, logging."""

from __future__ import annotations

from collections.abc import Generator
from typing import Any

import pytest

import ddes
from ddes.errors import NodeShutdownError
from ddes.msg import get_message_class

Int32 = get_message_class("std_msgs/Int32")
Clock = get_message_class("rosgraph_msgs/Clock")
Log = get_message_class("rosgraph_msgs/Log")
MS = 1_000_000


def test_names_namespaces_and_remaps(world: ddes.World) -> None:
    node = world.create_node("talker", namespace="/robot", argv=["chatter:=/talk", "extra"])
    assert node.name == "/robot/talker" and node.namespace == "/robot/"
    assert node.resolve_name("chatter") == "/talk"
    assert node.resolve_name("~private") == "/robot/talker/private"
    assert node.resolve_name("other") == "/robot/other"
    assert node.argv == ["extra"]
    pub = node.advertise("chatter", Int32, queue_size=1)
    assert pub.resolved_name == "/talk"
    renamed = world.create_node("x", argv=["__name:=renamed", "__ns:=/ns"])
    assert renamed.name == "/ns/renamed"


def test_private_params_from_argv_and_param_api(world: ddes.World) -> None:
    node = world.create_node("ctrl", argv=["_gain:=2.5", "_topic:=/scan"])
    assert node.get_param("~gain") == 2.5 and node.get_param("~topic") == "/scan"
    node.set_param("shared", {"a": 1})
    assert world.params.get_param("/shared/a") == 1
    assert node.has_param("~gain") and not node.has_param("~nope")
    assert node.get_param("~nope", 7) == 7
    with pytest.raises(KeyError):
        node.get_param("~nope")
    world.params.set_param("/robot_description", "urdf")
    assert node.search_param("robot_description") == "/robot_description"
    node.delete_param("~gain")
    assert "/ctrl/gain" not in node.get_param_names()


def test_anonymous_names_are_deterministic() -> None:
    names = [ddes.World().create_node("listener", anonymous=True).name for _ in range(2)]
    assert names[0] == names[1] and names[0].startswith("/listener_")
    w = ddes.World()
    assert w.create_node("a", anonymous=True).name != w.create_node("a", anonymous=True).name


def test_illegal_node_names(world: ddes.World) -> None:
    for bad in ["a/b", "1abc", "my node"]:
        with pytest.raises(ddes.DdesError):
            world.create_node(bad)


def test_shutdown_removes_entities_and_refuses_use(world: ddes.World) -> None:
    node = world.create_node("n")
    node.advertise("t", Int32, queue_size=1)
    node.subscribe("u", Int32, lambda m: None)
    reasons: list[str] = []
    node.on_shutdown(reasons.append)
    node.shutdown("bye")
    assert reasons == ["bye"] and "/n" not in world.nodes
    state = world.master.get_system_state()
    assert all("/n" not in nodes for _, nodes in state[0] + state[1])
    with pytest.raises(NodeShutdownError, match="/n is shut down"):
        node.advertise("t", Int32, queue_size=1)
    with pytest.raises(NodeShutdownError):
        node.sleep(1)


def test_spin_event_fires_on_shutdown(world: ddes.World) -> None:
    node = world.create_node("n")
    done: list[int] = []

    def main() -> Generator[Any, Any, None]:
        yield node.spin()
        done.append(world.now)

    node.process(main())
    world.call_at(5 * MS, lambda: node.shutdown("done"))
    world.run()
    assert done == [5 * MS]


def _pub_every(world: ddes.World, period: float, n: int, topic: str = "t") -> None:
    world.connect_delay = 0
    node = world.create_node(f"pub_{topic}")
    pub = node.advertise(topic, Int32, queue_size=10)

    def main() -> Generator[Any, Any, None]:
        yield world.timeout(0.001)
        for i in range(n):
            pub.publish(Int32(i))
            yield world.timeout(period)

    node.process(main())


def test_single_spinner_serialises_callbacks_across_topics(world: ddes.World) -> None:
    _pub_every(world, 0.1, 3, "a")
    _pub_every(world, 0.1, 3, "b")
    node = world.create_node("sub")
    log: list[tuple[str, int, int]] = []

    def slow(tag: str) -> Any:
        def cb(m: Any) -> Generator[Any, Any, None]:
            log.append((tag, m.data, world.now // MS))
            yield node.sleep(0.03)
        return cb

    node.subscribe("a", Int32, slow("a"))
    node.subscribe("b", Int32, slow("b"))
    world.run()
    assert log == [("a", 0, 1), ("b", 0, 31), ("a", 1, 101), ("b", 1, 131), ("a", 2, 201), ("b", 2, 231)]


def test_async_spinner_runs_in_parallel(world: ddes.World) -> None:
    _pub_every(world, 0.1, 2, "a")
    _pub_every(world, 0.1, 2, "b")
    node = world.create_node("sub", spinner=2)
    log: list[tuple[str, int]] = []

    def cb(tag: str) -> Any:
        def f(m: Any) -> Generator[Any, Any, None]:
            log.append((tag, world.now // MS))
            yield node.sleep(0.03)
        return f

    node.subscribe("a", Int32, cb("a"))
    node.subscribe("b", Int32, cb("b"))
    world.run()
    assert log == [("a", 1), ("b", 1), ("a", 101), ("b", 101)]


def test_manual_spinner_with_spin_once(world: ddes.World) -> None:
    _pub_every(world, 0.05, 6)
    node = world.create_node("loop", spinner="manual")
    got: list[tuple[int, int]] = []
    node.subscribe("t", Int32, lambda m: got.append((world.now // MS, m.data)), queue_size=1)

    def main() -> Generator[Any, Any, None]:
        rate = node.create_rate(5)
        for _ in range(3):
            yield node.spin_once()
            yield rate.sleep()

    node.process(main())
    world.run()
    # every 200 ms the loop handles only the newest message (queue_size=1)
    assert got == [(200, 3), (400, 5)]


def test_sim_time_node_follows_clock_topic(world: ddes.World) -> None:
    world.use_sim_time = True
    world.connect_delay = 0
    sim = world.create_node("sim")
    clock_pub = world.create_node("player", use_sim_time=False).advertise("/clock", Clock, queue_size=1)
    seen: list[tuple[int, float]] = []

    def main() -> Generator[Any, Any, None]:
        seen.append((world.now // MS, sim.get_time()))
        yield sim.sleep(1.0)
        seen.append((world.now // MS, sim.get_time()))

    sim.process(main())

    def play() -> Generator[Any, Any, None]:
        for k in range(10):
            yield world.timeout(0.1)
            clock_pub.publish(Clock(clock=ddes.Time(50) + ddes.Duration.from_sec(0.5 * k)))

    world.process(play())
    world.run()
    # first /clock at 0.1 s reads 50.0; the sleep ends when /clock reaches 51.0 (at 0.3 s)
    assert seen == [(0, 0.0), (300, 51.0)]


def test_logging_trace_rosout_and_console(world: ddes.World) -> None:
    world.connect_delay = 0
    lines: list[str] = []
    world.log_output = lambda line, level: lines.append(line)
    rosout: list[Any] = []
    world.create_node("rosout_listener").subscribe("/rosout", Log, rosout.append)
    node = world.create_node("chatty")
    world.run(until=0.01)

    def main() -> Generator[Any, Any, None]:
        for i in range(5):
            node.loginfo("tick %d", i)
            node.logwarn_throttle(0.25, "throttled %d", i)
            node.logerr_once("once")
            node.logdebug("hidden")
            yield node.sleep(0.1)

    node.process(main())
    world.run()
    assert lines[:3] == ["[INFO] [0.010000]: tick 0", "[WARN] [0.010000]: throttled 0",
                         "[ERROR] [0.010000]: once"]
    assert sum("throttled" in x for x in lines) == 2  # at 0.01 and 0.31
    assert not any("hidden" in x for x in lines)
    logs = world.trace.filter(kind="log")
    assert [e.details["msg"] for e in logs][:3] == ["tick 0", "throttled 0", "once"]
    assert rosout[0].name == "/chatty" and rosout[0].level == 2 and rosout[0].msg == "tick 0"


def test_sim_time_log_line_shows_both_times(world: ddes.World) -> None:
    lines: list[str] = []
    world.log_output = lambda line, level: lines.append(line)
    node = world.create_node("sim", use_sim_time=True)
    node.clock.update(ddes.Time(12, 500_000_000))  # type: ignore[attr-defined]
    node.loginfo("hi")
    assert lines == ["[INFO] [0.000000, 12.500000]: hi"]


def test_callback_exceptions_follow_world_policy(world: ddes.World) -> None:
    world.raise_callback_errors = False
    _pub_every(world, 0.1, 3)

    def bad(m: Any) -> None:
        raise ValueError(f"bad {m.data}")

    world.create_node("sub").subscribe("t", Int32, bad)
    world.run()
    assert [e.details["error"] for e in world.trace.filter(kind="callback.exception")] == [
        "ValueError: bad 0", "ValueError: bad 1", "ValueError: bad 2"]


def test_name_remap_turns_anonymous_off(world: ddes.World) -> None:
    assert world.create_node("x", anonymous=True, argv=["__name:=fixed"]).name == "/fixed"
