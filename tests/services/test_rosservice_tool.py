"""The rosservice and rossrv world tools: output, errors and exit codes as ROS prints them."""

from __future__ import annotations

from typing import Any

import pytest

import ddes
from ddes.console.tooling import CommandResult, ToolContext, run_command, run_command_result
from ddes.errors import ROSConsoleError
from ddes.nodes import start_node
from ddes.services import Service

L = 100_000


@pytest.fixture
def lecture(world: ddes.World) -> ddes.World:
    """The lecture 4 setup: ``rosrun roscpp_tutorials add_two_ints_server &``."""
    start_node(world, "roscpp_tutorials", "add_two_ints_server")
    return world


def run(world: ddes.World, line: str) -> CommandResult:
    return run_command_result(ToolContext(world), line)


class TestIntrospection:
    def test_list(self, lecture: ddes.World, add_two_ints: Any) -> None:
        Service(lecture.create_node("calc", namespace="/robot"), "sum", add_two_ints, lambda r: 0)
        assert run_command(lecture, "rosservice list") == "/add_two_ints\n/robot/sum\n"
        assert run_command(lecture, "rosservice list -n") == (
            "/add_two_ints /add_two_ints_server\n/robot/sum /robot/calc\n")
        assert run_command(lecture, "rosservice list /robot") == "/robot/sum\n"
        assert run_command(lecture, "rosservice list robot") == "/robot/sum\n"
        assert run_command(lecture, "rosservice list /rob") == ""

    def test_type_uri_node_args_info_find(self, lecture: ddes.World) -> None:
        assert run_command(lecture, "rosservice type /add_two_ints") == "roscpp_tutorials/TwoInts\n"
        assert run_command(lecture, "rosservice type add_two_ints") == "roscpp_tutorials/TwoInts\n"
        assert run_command(lecture, "rosservice uri /add_two_ints") == "rosrpc://localhost:40000\n"
        assert run_command(lecture, "rosservice node /add_two_ints") == "/add_two_ints_server\n"
        assert run_command(lecture, "rosservice args /add_two_ints") == "a b\n"
        assert run_command(lecture, "rosservice info /add_two_ints") == (
            "Node: /add_two_ints_server\nURI: rosrpc://localhost:40000\n"
            "Type: roscpp_tutorials/TwoInts\nArgs: a b\n")
        assert run_command(lecture, "rosservice find roscpp_tutorials/TwoInts") == "/add_two_ints\n"
        assert run_command(lecture, "rosservice find std_srvs/Empty") == "\n"

    @pytest.mark.parametrize(("line", "code", "err"), [
        ("rosservice type /nope", 1, "Unknown service [/nope]\n"),
        ("rosservice uri /nope", 1, "Unknown service: /nope\n"),
        ("rosservice node /nope", 1, "Unknown service: /nope\n"),
        ("rosservice info /nope", 1, "ERROR: unknown service\n"),
        ("rosservice args /nope", 2, "ERROR: Service [/nope] is not available.\n"),
        ("rosservice type", 2,
         "Usage: rosservice type /service\n\nrosservice: error: service must be specified\n"),
        ("rosservice type /a /b", 2, "Usage: rosservice type /service\n\nrosservice: error: you "
                                     "may only specify one input service\n"),
        ("rosservice info", 2, "Usage: rosservice info /service\n\nrosservice: error: you must "
                               "specify a service name\n"),
        ("rosservice find", 2, "Usage: rosservice find msg-type\n\nrosservice: error: please "
                               "specify a message type\n"),
        ("rosservice list /a /b", 2, "Usage: rosservice list [/namespace]\n\nrosservice: error: "
                                     "you may only specify one input namespace\n"),
    ])
    def test_errors(self, lecture: ddes.World, line: str, code: int, err: str) -> None:
        result = run(lecture, line)
        assert (result.code, result.out, result.err) == (code, "", err)

    def test_usage(self, lecture: ddes.World) -> None:
        for line in ("rosservice", "rosservice frobnicate"):
            result = run(lecture, line)
            assert result.code == 64
            assert result.out.startswith("Commands:\n\trosservice args\tprint service arguments\n")
            assert result.out.endswith("e.g. 'rosservice call -h'\n")

    def test_help(self, lecture: ddes.World) -> None:
        result = run(lecture, "rosservice call -h")
        assert result.code == 0
        assert result.out.startswith("Usage: rosservice call /service [args...]\n")
        assert "--wait" in result.out


class TestCall:
    @pytest.mark.parametrize("args", ['"a: 10\nb: 5"', r'"a: 10\nb: 5"', "'{a: 10, b: 5}'",
                                      "10 5", "'{b: 5, a: 10}'"])
    def test_argument_forms(self, lecture: ddes.World, args: str) -> None:
        assert run_command(lecture, f"rosservice call /add_two_ints {args}") == "sum: 15\n"

    def test_the_call_takes_simulated_time(self, lecture: ddes.World) -> None:
        lecture.run(1.0)
        run_command(lecture, "rosservice call /add_two_ints 1 2")
        assert lecture.now == 1_000_000_000 + 4 * L
        logs = [e.details["msg"] for e in lecture.trace.filter(kind="log",
                                                               source="/add_two_ints_server")]
        assert logs == ["request: x=1, y=2", "  sending back response: [3]"]
        # the caller was a temporary anonymous node, gone now
        assert sorted(lecture.nodes) == ["/add_two_ints_server"]
        assert lecture.env.peek() == float("inf")  # nothing left scheduled

    def test_verbose(self, lecture: ddes.World) -> None:
        assert run_command(lecture, "rosservice call -v /add_two_ints 10 5") == (
            "a: 10\nb: 5\n---\nsum: 15\n")

    def test_empty_and_trigger_services(self, world: ddes.World, trigger: Any) -> None:
        from ddes.msg import get_service_class

        empty = get_service_class("std_srvs/Empty")
        Service(world.create_node("a"), "reset", empty, lambda req: [])
        Service(world.create_node("b"), "get_average", trigger, lambda req: (True, "3.5"))
        assert run_command(world, "rosservice call /reset") == "\n"
        assert run_command(world, "rosservice call /get_average") == (
            'success: True\nmessage: "3.5"\n')
        assert run_command(world, "rosservice call /reset '{}'") == "\n"

    def test_now_and_auto_keys(self, world: ddes.World) -> None:
        from ddes.msg import get_service_class

        set_map = get_service_class("nav_msgs/SetMap")
        seen: list[Any] = []

        def handler(req: Any) -> Any:
            seen.append((req.map.header.stamp.to_nsec(), req.initial_pose.header.stamp.to_nsec()))
            return {"success": True}

        Service(world.create_node("map_server"), "set_map", set_map, handler)
        world.run(2.5)
        out = run_command(world, "rosservice call /set_map "
                                 "'{map: {header: auto}, initial_pose: {header: {stamp: now}}}'")
        assert out == "success: True\n"
        assert seen == [(2_500_000_000, 2_500_000_000)]

    def test_server_error(self, world: ddes.World, set_bool: Any) -> None:
        Service(world.create_node("robot"), "stop", set_bool, lambda req: True)
        result = run(world, "rosservice call /stop true")
        assert result.code == 2
        assert result.err.startswith(
            "ERROR: service [/stop] responded with an error: service cannot process request: "
            "handler returned invalid value: Invalid number of arguments")

    def test_roscpp_false(self, world: ddes.World, two_ints: Any) -> None:
        Service(world.create_node("server"), "s", two_ints, lambda req, res: False, style="roscpp")
        result = run(world, "rosservice call /s 1 2")
        assert (result.code, result.err) == (2, "ERROR: service [/s] responded with an error: \n")

    @pytest.mark.parametrize(("args", "err"), [
        ("1", "ERROR: Incompatible arguments to call service:\nNot enough arguments:\n * Given: [1]"
              "\n * Expected: ['a', 'b']\nProvided arguments are:\n * 1 (type int)\n\nService "
              "arguments are: [a b]\n"),
        ("1 2 3", "ERROR: Incompatible arguments to call service:\nToo many arguments:\n * Given: "
                  "[1, 2, 3]\n * Expected: ['a', 'b']\nProvided arguments are:\n * 1 (type int)\n"
                  " * 2 (type int)\n * 3 (type int)\n\nService arguments are: [a b]\n"),
        ("'{c: 1}'", "ERROR: Incompatible arguments to call service:\nNo field name [c]\nProvided "
                     "arguments are:\n * {'c': 1} (type dict)\n\nService arguments are: [a b]\n"),
    ])
    def test_incompatible_arguments(self, lecture: ddes.World, args: str, err: str) -> None:
        result = run(lecture, f"rosservice call /add_two_ints {args}")
        assert (result.code, result.err) == (2, err)

    def test_a_bad_field_value(self, lecture: ddes.World) -> None:
        result = run(lecture, "rosservice call /add_two_ints one 2")
        assert result.code == 2
        assert result.err.startswith("ERROR: Unable to send request. One of the fields has an "
                                     "incorrect type:\n")
        assert result.err.endswith("srv file:\nint64 a\nint64 b\n---\nint64 sum\n\n")

    def test_unknown_service_and_missing_arguments(self, lecture: ddes.World) -> None:
        assert run(lecture, "rosservice call /nope 1 2").err == (
            "ERROR: Service [/nope] is not available.\n")
        result = run(lecture, "rosservice call /add_two_ints")
        assert (result.code, result.err) == (2, "Usage: rosservice call /service [args...]\n\n"
                                                "rosservice: error: Please specify service "
                                                "arguments\n")
        assert run(lecture, "rosservice call").err.endswith("error: service must be specified\n")

    def test_invalid_yaml(self, lecture: ddes.World) -> None:
        result = run(lecture, "rosservice call /add_two_ints '{a: [1'")
        assert result.code == 2
        assert result.err.startswith("ERROR: Invalid YAML in argument [{a: [1]: ")

    def test_wait(self, world: ddes.World, two_ints: Any) -> None:
        world.call_at(3_000_000_000, lambda: Service(world.create_node("late"), "s", two_ints,
                                                     lambda req: req.a + req.b))
        assert run_command(world, "rosservice call --wait /s 2 2") == "sum: 4\n"
        assert world.now == 3_000_000_000 + 4 * L

    def test_wait_for_a_service_that_never_comes(self, world: ddes.World) -> None:
        result = run(world, "rosservice call --wait /never 1")
        assert result.code == 2
        assert result.err == ("ERROR: still waiting for service [/never] to be advertised, and the "
                              "world has nothing left to do (ROS would wait until Ctrl+C)\n")

    def test_a_server_that_never_answers(self, world: ddes.World, two_ints: Any) -> None:
        server = world.create_node("server")

        def handler(req: Any) -> Any:
            yield server.sleep(10_000)
            return 0

        Service(server, "slow", two_ints, handler)
        result = run(world, "rosservice call /slow 1 2")
        assert result.err == ("ERROR: still waiting for the response of [/slow] after 600 "
                              "simulated seconds (ROS would wait until Ctrl+C)\n")
        assert world.now == 600_000_000_000
        world.run()  # the abandoned call ends quietly: the server's response is discarded
        assert [e.details["reason"] for e in world.trace.filter(kind="service.discard")] == [
            "client gave up"]

    def test_run_command_raises_on_failure(self, lecture: ddes.World) -> None:
        with pytest.raises(ROSConsoleError, match=r"Service \[/nope\] is not available"):
            run_command(lecture, "rosservice call /nope 1 2")


class TestRossrv:
    def test_show(self, world: ddes.World) -> None:
        assert run_command(world, "rossrv show roscpp_tutorials/TwoInts") == (
            "int64 a\nint64 b\n---\nint64 sum\n\n")
        assert run_command(world, "rossrv show std_srvs/SetBool") == (
            "bool data\n---\nbool success\nstring message\n\n")

    def test_bare_type_and_md5(self, world: ddes.World) -> None:
        assert run_command(world, "rossrv show TwoInts") == (
            "[roscpp_tutorials/TwoInts]:\nint64 a\nint64 b\n---\nint64 sum\n\n")
        assert run_command(world, "rossrv md5 roscpp_tutorials/TwoInts") == (
            "6a2e34150c00229791cc89ff309fff21\n")

    def test_unknown_type(self, world: ddes.World) -> None:
        result = run(world, "rossrv show nope/Nope")
        assert result.code == 1
        assert result.err.startswith("Unknown srv type [nope/Nope]: ")

    def test_usage_error(self, world: ddes.World) -> None:
        result = run(world, "rossrv show")  # the console's rossrv is the rosmsg tool's twin
        assert result.code == 1
        assert "give the service type" in result.err and "usage: rossrv show" in result.err
