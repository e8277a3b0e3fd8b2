"""Yield-style slips stopped with the fix named (issue 42 item 4): a loop whose ``yield`` is
missing, a process given the function instead of its generator, a main without ``yield``."""

from __future__ import annotations

import pytest

import ddes
from ddes.errors import DdesTypeError, ForgottenYieldError
from ddes.time.sleep import FORGOTTEN_YIELD_CALLS


def test_the_readme_loop_without_yield_is_stopped_with_the_hint() -> None:
    world = ddes.World(seed=1)
    node = world.create_node("looper")
    rate = ddes.Rate(node, 10)
    printed: list[float] = []

    def main() -> None:  # the README's loop with its `yield` forgotten: no generator at all
        while not node.is_shutdown():
            printed.append(node.get_time())
            rate.sleep()

    with pytest.raises(ForgottenYieldError, match=r"Write `yield rate\.sleep\(\)`"):
        main()
    assert len(printed) == FORGOTTEN_YIELD_CALLS


@pytest.mark.filterwarnings("ignore::ddes.kernel.events.NeverYieldedWarning")
def test_a_loop_inside_a_process_without_its_yield_ends_that_process() -> None:
    world = ddes.World(seed=1, strict=False)
    node = world.create_node("looper")
    lines: list[str] = []
    world.log_output = lambda line, _level: lines.append(line)

    def main():  # type: ignore[no-untyped-def]
        yield node.sleep(0.1)
        while True:
            node.sleep(0.5)  # forgotten yield

    node.process(main())
    world.run(until=1.0)
    assert node.is_shutdown()
    assert any("ForgottenYieldError" in line and "yield node.sleep(...)" in line
               for line in lines), lines


def test_a_loop_that_yields_is_never_stopped() -> None:
    world = ddes.World()
    node = world.create_node("looper")
    count = 0

    def main():  # type: ignore[no-untyped-def]
        nonlocal count
        while True:
            count += 1
            yield node.sleep(0)  # zero-length sleeps: the kernel steps between them

    node.process(main())
    world.env.instant_budget = 10 * FORGOTTEN_YIELD_CALLS
    with pytest.raises(ddes.errors.RunawayError, match="zero-time livelock"):
        world.run(until=1.0)
    assert count > FORGOTTEN_YIELD_CALLS


@pytest.mark.parametrize("kind, expected", [
    ("function", r"got the function itself: call it, node\.process\(main\(\)\)"),
    ("no_yield", r"got a function without `yield`"),
    ("none", r"returned None, so it has no `yield`"),
])
def test_process_names_the_fix(kind: str, expected: str) -> None:
    world = ddes.World()
    node = world.create_node("n")

    def main():  # type: ignore[no-untyped-def]
        yield node.sleep(1)

    def plain() -> None:
        pass

    arg = {"function": main, "no_yield": plain, "none": None}[kind]
    with pytest.raises(DdesTypeError, match=expected):
        node.process(arg)  # type: ignore[arg-type]
