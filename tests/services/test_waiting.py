"""wait_for_service: an event that lands on exact simulated instants."""

from __future__ import annotations

from collections.abc import Generator
from typing import Any

import pytest

import ddes
from ddes.errors import ROSException, ROSInterruptException, ROSNameException
from ddes.services import Service, ServiceProxy, wait_for_service
from ddes.time.clock import SimClock

MS = 1_000_000


def advertise_at(world: ddes.World, cls: Any, t_ms: int, name: str = "s") -> None:
    world.call_at(t_ms * MS, lambda: Service(world.create_node(f"server{t_ms}"), name, cls,
                                             lambda req: 0))


def test_wakes_exactly_when_the_service_registers(world: ddes.World, run_client: Any,
                                                  add_two_ints: Any) -> None:
    advertise_at(world, add_two_ints, 1234)
    client = world.create_node("client")
    out = run_client(world, client, lambda: (yield wait_for_service(client, "s")))
    assert (out.value, out.error, out.t) == (None, None, 1234 * MS)


def test_already_available_returns_at_once(world: ddes.World, run_client: Any,
                                           add_two_ints: Any) -> None:
    Service(world.create_node("server"), "s", add_two_ints, lambda req: 0)
    client = world.create_node("client")
    out = run_client(world, client, lambda: (yield wait_for_service(client, "/s", timeout=1)))
    assert (out.error, out.t) == (None, 0)


def test_names_resolve_in_the_callers_namespace(world: ddes.World, run_client: Any,
                                                add_two_ints: Any) -> None:
    world.call_at(5 * MS, lambda: Service(world.create_node("server", namespace="/robot"), "s",
                                          add_two_ints, lambda req: 0))
    client = world.create_node("client", namespace="/robot")
    out = run_client(world, client, lambda: (yield wait_for_service(client, "s", 1.0)))
    assert out.t == 5 * MS


def test_timeout_expires_at_the_exact_instant(world: ddes.World, run_client: Any,
                                              add_two_ints: Any) -> None:
    advertise_at(world, add_two_ints, 2000)
    client = world.create_node("client")

    def main() -> Generator[Any, Any, None]:
        yield world.timeout(0.25)
        yield wait_for_service(client, "s", timeout=ddes.Duration(1, 500_000_000))

    out = run_client(world, client, main)
    assert isinstance(out.error, ROSException)
    assert str(out.error) == "timeout exceeded while waiting for service /s"
    assert out.t == 1750 * MS


def test_a_registration_at_the_deadline_wins_only_if_it_comes_first(
        world: ddes.World, run_client: Any, add_two_ints: Any) -> None:
    advertise_at(world, add_two_ints, 1000)  # scheduled before the wait's deadline
    client = world.create_node("client")
    out = run_client(world, client, lambda: (yield wait_for_service(client, "s", timeout=1.0)))
    assert (out.error, out.t) == (None, 1000 * MS)


def test_zero_timeout_is_a_value_error(world: ddes.World, add_two_ints: Any) -> None:
    client = world.create_node("client")
    with pytest.raises(ValueError, match="^timeout must be non-zero$"):
        wait_for_service(client, "s", timeout=0)
    with pytest.raises(ValueError, match="^timeout must be non-zero$"):
        ServiceProxy(client, "s", add_two_ints).wait_for_service(ddes.Duration(0))


def test_negative_timeout_fails_at_once_even_if_available(world: ddes.World, run_client: Any,
                                                          add_two_ints: Any) -> None:
    Service(world.create_node("server"), "s", add_two_ints, lambda req: 0)
    client = world.create_node("client")
    out = run_client(world, client, lambda: (yield wait_for_service(client, "s", timeout=-1.0)))
    assert str(out.error) == "timeout exceeded while waiting for service /s"
    assert out.t == 0


def test_shutdown_interrupts_the_wait(world: ddes.World, run_client: Any) -> None:
    client = world.create_node("client")
    world.call_at(300 * MS, lambda: client.shutdown("bye"))
    out = run_client(world, client, lambda: (yield wait_for_service(client, "s")))
    assert isinstance(out.error, ROSInterruptException)
    assert str(out.error) == "rospy shutdown"
    assert out.t == 300 * MS


def test_many_waiters_wake_in_the_order_they_started(world: ddes.World,
                                                     add_two_ints: Any) -> None:
    advertise_at(world, add_two_ints, 10)
    order: list[str] = []
    for who in ("c", "a", "b"):
        node = world.create_node(who)

        def main(node: ddes.Node = node) -> Generator[Any, Any, None]:
            yield wait_for_service(node, "s")
            order.append(node.name)

        node.process(main())
    world.run()
    assert order == ["/c", "/a", "/b"]


def test_a_finished_wait_leaves_nothing_behind(world: ddes.World, run_client: Any,
                                               add_two_ints: Any) -> None:
    client = world.create_node("client")
    advertise_at(world, add_two_ints, 10)
    run_client(world, client, lambda: (yield wait_for_service(client, "s", timeout=5.0)))
    run_client(world, client, lambda: (yield wait_for_service(client, "t", timeout=0.1)))
    assert world.service_network._waiters == {}
    assert [type(e).__name__ for e in client._entities] == ["Publisher"]  # /rosout only


def test_illegal_name(world: ddes.World) -> None:
    with pytest.raises(ROSNameException):
        wait_for_service(world.create_node("client"), "9lives")


def test_on_simulated_time(world: ddes.World, run_client: Any, add_two_ints: Any) -> None:
    client = world.create_node("client", use_sim_time=True)
    clock = client.clock
    assert isinstance(clock, SimClock)

    def drive() -> Generator[Any, Any, None]:
        yield world.timeout(1.0)
        for k in range(50):
            clock.update(100_000_000_000 + k * 500 * MS)  # /clock from 100 s at 5x
            yield world.timeout(0.1)

    world.process(drive())

    def main() -> Generator[Any, Any, None]:
        yield client.sleep(0.001)  # wait for the first /clock
        yield wait_for_service(client, "s", timeout=2.0)

    out = run_client(world, client, main, until=10)
    assert str(out.error) == "timeout exceeded while waiting for service /s"
    # the sleep ends at kernel 1.1 s (ROS 100.5 s); the deadline ROS 102.5 s comes at kernel 1.5 s
    assert out.t == 1500 * MS
