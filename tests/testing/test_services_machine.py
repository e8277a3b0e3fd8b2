"""The service protocol machine (ddes.testing.services): correct handlers pass under concurrent
calls, faults, timeouts and a vanishing server; a handler with shared state is found and shrunk."""

from __future__ import annotations

import functools
from collections.abc import Generator
from typing import Any

import matplotlib

matplotlib.use("Agg")

import pytest  # noqa: E402
from hypothesis import strategies as st  # noqa: E402

from ddes.errors import DdesTypeError, DdesValueError, ServiceException  # noqa: E402
from ddes.msg import get_service_class  # noqa: E402
from ddes.services import Service  # noqa: E402
from ddes.testing._replay import VIOLATION_GID  # noqa: E402
from ddes.testing.services import (  # noqa: E402
    ServiceProtocolMachine,
    ServiceViolation,
    replay_service_schedule,
    run_service_machine,
)

AddTwoInts = get_service_class("rospy_tutorials/AddTwoInts")
SMALL = st.fixed_dictionaries({"a": st.integers(-5, 5), "b": st.integers(-5, 5)})


def add(req: Any) -> int:
    return req.a + req.b


def contract(req: Any) -> int:
    return req.a + req.b


def make_slow_adder(world: Any, node: Any) -> None:
    """A correct handler that takes time: every call keeps its own request."""

    def handler(req: Any) -> Generator[Any, Any, int]:
        yield node.sleep(0.001)
        return req.a + req.b

    Service(node, "/service", AddTwoInts, handler)


def make_shared_state_adder(world: Any, node: Any) -> None:
    """A planted bug: the handler keeps the request in state shared by every call, then takes
    time; rospy serves each connection in its own thread, so a second call overwrites it."""
    current: dict[str, int] = {}

    def handler(req: Any) -> Generator[Any, Any, int]:
        current["a"], current["b"] = req.a, req.b
        yield node.sleep(0.001)
        return current["a"] + current["b"]

    Service(node, "/service", AddTwoInts, handler)


TestAddHandler = ServiceProtocolMachine.for_service(
    AddTwoInts, add, contract=contract, requests=SMALL, max_examples=30, derandomize=True)
TestSlowAdderOnOneThread = ServiceProtocolMachine.for_service(
    AddTwoInts, make_server=make_slow_adder, contract=contract, requests=SMALL, spinner="single",
    max_examples=30, derandomize=True)


def test_a_slow_correct_handler_passes_with_a_thread_per_connection() -> None:
    run_service_machine(AddTwoInts, make_server=make_slow_adder, contract=contract,
                        requests=SMALL, max_examples=30, derandomize=True, database=None)


def test_handler_errors_reach_the_caller_as_rospy_says() -> None:
    def picky(req: Any) -> object:
        if req.a < 0:
            raise ValueError("a must be >= 0")
        if req.b < 0:
            raise ServiceException("b must be >= 0")
        return None if req.a == req.b == 0 else req.a + req.b

    def picky_contract(req: Any) -> object:
        if req.a < 0 or req.b < 0 or req.a == req.b == 0:
            return ServiceException
        return req.a + req.b

    run_service_machine(AddTwoInts, picky, contract=picky_contract, requests=SMALL,
                        max_examples=30, derandomize=True, database=None)


@functools.lru_cache(maxsize=1)
def shared_state_violation() -> ServiceViolation:
    with pytest.raises(ServiceViolation) as info:
        run_service_machine(AddTwoInts, make_server=make_shared_state_adder, contract=contract,
                            requests=SMALL, max_examples=400, stateful_step_count=10,
                            derandomize=True, database=None)
    return info.value


def test_a_handler_with_shared_state_is_found_and_shrunk() -> None:
    v = shared_state_violation()
    print(v)  # the shrunk schedule, as a user sees it
    assert "the contract expects" in v.problem
    calls = [s for s in v.steps if s[0] == "call"]
    assert len(calls) == 2 and len(v.steps) <= 4, v
    assert f"replay_service_schedule('rospy_tutorials/AddTwoInts', {v.steps!r}, seed={v.seed}, " \
           "make_server=make_shared_state_adder, contract=contract)" in str(v)
    # the printed call replays it; its plot marks the violating step
    replay = eval(v.replay, {"replay_service_schedule": replay_service_schedule,  # noqa: S307
                             "make_shared_state_adder": make_shared_state_adder,
                             "contract": contract})
    assert replay.violation is not None and replay.violation.problem == v.problem
    assert replay.step == v.step
    fig = replay.plot()
    marks = [a for a in fig.axes[0].get_children() if a.get_gid() == VIOLATION_GID]
    assert any(getattr(a, "get_text", lambda: "")().startswith(f"step {v.step}") for a in marks)
    # on one thread (roscpp's single spinner) the same schedule is fine
    one = replay_service_schedule(AddTwoInts, v.steps, seed=v.seed,
                                  make_server=make_shared_state_adder, contract=contract,
                                  spinner="single")
    assert one.violation is None


def test_persistent_proxy_fails_every_call_once_its_server_went_away() -> None:
    steps = [("call", 0, {"a": 1, "b": 2}, "persistent", None), ("advance", 0.01),
             ("stop_server", "node"), ("start_server",),
             ("call", 0, {"a": 1, "b": 2}, "persistent", None), ("advance", 0.01),
             ("new_persistent_proxy", 0),
             ("call", 0, {"a": 3, "b": 4}, "persistent", None), ("advance", 0.01)]
    replay = replay_service_schedule(AddTwoInts, steps, handler=add, contract=contract)
    assert replay.violation is None, replay.violation
    first, second, third = replay.calls
    assert first.response.sum == 3 and third.response.sum == 7
    assert str(second.error) == ("persistent connection to service [/service] was closed: the "
                                 "server went away; create a new ServiceProxy")


def test_timeouts_wait_for_service_and_a_vanishing_server() -> None:
    steps = [("stop_server", "service"), ("wait_for_service", 0, 0.1),
             ("call", 1, {"a": 1, "b": 1}, "one-shot", None), ("advance", 0.05),
             ("start_server",), ("wait_for_service", 2, 0.001),
             ("call", 1, {"a": 1, "b": 1}, "one-shot", 0.0005), ("advance", 0.01)]
    replay = replay_service_schedule(AddTwoInts, steps, make_server=make_slow_adder,
                                     contract=contract)
    assert replay.violation is None, replay.violation
    unavailable, timed_out = replay.calls
    assert str(unavailable.error) == "service [/service] unavailable"
    assert type(timed_out.error).__name__ == "ServiceTimeout"
    assert timed_out.end - timed_out.start == 500_000


def test_machine_arguments_are_checked() -> None:
    with pytest.raises(DdesValueError, match="one of the two"):
        ServiceProtocolMachine.machine_for(AddTwoInts)
    with pytest.raises(DdesTypeError):
        ServiceProtocolMachine.machine_for(AddTwoInts, "not callable")  # type: ignore[arg-type]
    with pytest.raises(DdesValueError, match="resolved name"):
        ServiceProtocolMachine.machine_for(AddTwoInts, add, name="add")
    with pytest.raises(DdesValueError, match="unknown step"):
        replay_service_schedule(AddTwoInts, [("jump",)], handler=add)
