"""Fixtures of the service tests: service classes and a way to run a client coroutine."""

from __future__ import annotations

from collections.abc import Callable, Generator
from typing import Any

import pytest

import ddes
from ddes.msg import get_service_class

#: The default one-way latency of service messages, in ns.
L = 100_000


@pytest.fixture
def add_two_ints() -> Any:
    return get_service_class("rospy_tutorials/AddTwoInts")


@pytest.fixture
def two_ints() -> Any:
    return get_service_class("roscpp_tutorials/TwoInts")


@pytest.fixture
def set_bool() -> Any:
    return get_service_class("std_srvs/SetBool")


@pytest.fixture
def trigger() -> Any:
    return get_service_class("std_srvs/Trigger")


class Outcome:
    """What a client coroutine ended with: its value or its exception, and when."""

    def __init__(self) -> None:
        self.value: Any = None
        self.error: BaseException | None = None
        self.t: int | None = None

    def __repr__(self) -> str:
        return f"Outcome(value={self.value!r}, error={self.error!r}, t={self.t})"


@pytest.fixture
def run_client() -> Callable[..., Outcome]:
    """``run_client(world, node, gen_fn, until=None)``: run ``gen_fn()`` as a process of ``node``,
    run the world, and return its :class:`Outcome` (value or exception, and the instant)."""

    def run(world: ddes.World, node: ddes.Node, gen_fn: Callable[[], Generator[Any, Any, Any]],
            until: float | None = None) -> Outcome:
        out = Outcome()

        def wrapper() -> Generator[Any, Any, None]:
            try:
                out.value = yield from gen_fn()
            except Exception as exc:  # noqa: BLE001 - the test inspects it
                out.error = exc
            out.t = world.now

        node.process(wrapper())
        world.run(until)
        return out

    return run
