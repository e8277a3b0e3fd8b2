"""The add_two_ints node types of roscpp_tutorials and rospy_tutorials, and the example script."""

from __future__ import annotations

import runpy
from pathlib import Path
from typing import Any

import pytest

import ddes
from ddes.nodes import start_node
from ddes.services import Service

ROOT = Path(__file__).resolve().parents[2]


def logs(world: ddes.World) -> list[tuple[str, str, str]]:
    return [(e.source, e.details["level"], e.details["msg"]) for e in world.trace.filter(kind="log")]


def exits(world: ddes.World) -> list[tuple[str, int]]:
    return [(e.source, e.details["code"]) for e in world.trace.filter(kind="node.exit")]


class TestRoscpp:
    def test_server_and_client(self, world: ddes.World) -> None:
        lines: list[str] = []
        world.log_output = lambda line, level: lines.append(line)
        start_node(world, "roscpp_tutorials", "add_two_ints_server")
        start_node(world, "roscpp_tutorials", "add_two_ints_client", argv=["10", "5"])
        world.run(1)
        assert lines == ["[ INFO] [0.000300000]: request: x=10, y=5",
                         "[ INFO] [0.000300000]:   sending back response: [15]",
                         "[ INFO] [0.000400000]: Sum: 15"]
        assert exits(world) == [("/add_two_ints_client", 0)]

    @pytest.mark.parametrize(("argv", "expected"), [
        (["12abc", "-3"], 9), (["x", "7"], 7), (["99999999999999999999", "0"], 2**63 - 1),
    ])
    def test_client_parses_like_atoll(self, world: ddes.World, argv: list[str],
                                      expected: int) -> None:
        start_node(world, "roscpp_tutorials", "add_two_ints_server")
        start_node(world, "roscpp_tutorials", "add_two_ints_client", argv=argv)
        world.run(1)
        assert logs(world)[-1] == ("/add_two_ints_client", "INFO", f"Sum: {expected}")

    @pytest.mark.parametrize("argv", [[], ["1"], ["1", "2", "3"]])
    def test_client_usage(self, world: ddes.World, argv: list[str]) -> None:
        start_node(world, "roscpp_tutorials", "add_two_ints_client", argv=argv)
        world.run(1)
        assert logs(world) == [("/add_two_ints_client", "INFO", "usage: add_two_ints_client X Y")]
        assert exits(world) == [("/add_two_ints_client", 1)]

    def test_client_without_a_server(self, world: ddes.World) -> None:
        start_node(world, "roscpp_tutorials", "add_two_ints_client", argv=["1", "2"])
        world.run(1)
        assert logs(world) == [("/add_two_ints_client", "ERROR",
                                "Failed to call service add_two_ints")]
        assert exits(world) == [("/add_two_ints_client", 1)]


class TestRospy:
    def test_server_and_client(self, world: ddes.World) -> None:
        start_node(world, "rospy_tutorials", "add_two_ints_server")
        client = start_node(world, "rospy_tutorials", "add_two_ints_client", argv=["4", "5"])
        world.run(1)
        assert [m for _, _, m in logs(world)] == ["Requesting 4+5", "Returning [4 + 5 = 9]",
                                                  "Returning [4 + 5 = 9]", "4 + 5 = 9"]
        assert exits(world) == [(client.name, 0)]
        assert client.name.startswith("/add_two_ints_client_")  # anonymous, as the script

    def test_client_waits_for_the_server(self, world: ddes.World) -> None:
        start_node(world, "rospy_tutorials", "add_two_ints_client", argv=["1", "1"])
        world.call_at(2_000_000_000, lambda: start_node(world, "rospy_tutorials",
                                                        "add_two_ints_server"))
        world.run(3)
        requesting = world.trace.filter(kind="log")[0]
        assert (requesting.t, requesting.details["msg"]) == (2_000_000_000, "Requesting 1+1")

    def test_random_arguments_come_from_the_seed(self) -> None:
        def run(seed: int) -> list[str]:
            world = ddes.World(seed)
            start_node(world, "rospy_tutorials", "add_two_ints_server")
            start_node(world, "rospy_tutorials", "add_two_ints_client")
            world.run(1)
            return [m for _, _, m in logs(world)]

        first = run(3)
        assert first == run(3)
        assert first != run(4)
        x, y = (int(v) for v in first[0].removeprefix("Requesting ").split("+"))
        assert -50000 <= x <= 50000 and -50000 <= y <= 50000
        assert first[-1] == f"{x} + {y} = {x + y}"

    @pytest.mark.parametrize("argv", [["1"], ["a", "b"], ["1", "2", "3"]])
    def test_usage(self, world: ddes.World, argv: list[str]) -> None:
        client = start_node(world, "rospy_tutorials", "add_two_ints_client", argv=argv)
        world.run(1)
        assert logs(world) == [(client.name, "INFO", "add_two_ints_client [x y]")]
        assert exits(world) == [(client.name, 1)]

    def test_service_failure_is_printed(self, world: ddes.World, add_two_ints: Any) -> None:
        Service(world.create_node("broken"), "add_two_ints", add_two_ints, lambda req: None)
        client = start_node(world, "rospy_tutorials", "add_two_ints_client", argv=["1", "2"])
        world.run(1)
        assert [m for _, _, m in logs(world)] == [
            "Requesting 1+2",
            "Service call failed: service [/add_two_ints] responded with an error: service cannot "
            "process request: service handler returned None",
            "1 + 2 = None"]
        assert exits(world) == [(client.name, 0)]


def test_example_script(capsys: pytest.CaptureFixture[str]) -> None:
    runpy.run_path(str(ROOT / "examples" / "services_add_two_ints.py"), run_name="__main__")
    out = capsys.readouterr().out
    assert out.startswith("t=0.500000 s: add_two_ints is available\n")
    assert "Sum: 15  (round trip 0.4 ms)\n" in out
    assert "persistent call 1: Sum: 2  (round trip 0.2 ms)\n" in out
    assert "Service call failed: service [/no_such_service] unavailable\n" in out
    assert "t=1.001800 s: service [/add_two_ints] call timed out after 0.5 s" in out
    assert "$ rosservice call /add_two_ints 20 22\n" in out and "sum: 42\n" in out
    assert "/add_two_ints: 7 calls, 6 answered, 1 timed out, 1 late response discarded\n" in out
