"""Service servers: handler rules end to end, roscpp callbacks, registration, serving model."""

from __future__ import annotations

from collections.abc import Callable, Generator
from typing import Any

import pytest

import ddes
from ddes.errors import (
    DdesTypeError,
    DdesValueError,
    NodeShutdownError,
    ROSNameException,
    ServiceException,
)
from ddes.services import Service, ServiceProxy

L = 100_000


def logs(world: ddes.World, level: str | None = None) -> list[tuple[str, str]]:
    return [(e.source, e.details["msg"]) for e in world.trace.filter(kind="log")
            if level is None or e.details["level"] == level]


def call_once(world: ddes.World, run_client: Any, srv_class: Any, *args: Any,
              name: str = "s", client: str = "client", until: float | None = None) -> Any:
    node = world.create_node(client) if client not in world.nodes else world.nodes["/" + client]

    def main() -> Generator[Any, Any, Any]:
        return (yield ServiceProxy(node, name, srv_class)(*args))

    return run_client(world, node, main, until)


class TestHandlerRulesEndToEnd:
    @pytest.mark.parametrize(("handler", "expected"), [
        (lambda req: req.a + req.b, 3),
        (lambda req: {"sum": req.a * 10}, 10),
        (lambda req: [req.b], 2),
        (lambda req: (7,), 7),
    ])
    def test_valid_returns(self, world: ddes.World, run_client: Any, add_two_ints: Any,
                           handler: Callable[[Any], Any], expected: int) -> None:
        Service(world.create_node("server"), "s", add_two_ints, handler)
        out = call_once(world, run_client, add_two_ints, 1, 2)
        assert out.error is None
        assert out.value.sum == expected
        assert out.t == 4 * L

    @pytest.mark.parametrize(("handler", "text"), [
        (lambda req: None, "service handler returned None"),
        (lambda req: {"total": 1},
         "handler returned invalid value: total is not an attribute of AddTwoIntsResponse; its "
         "fields are sum"),
        (lambda req: (1, 2),
         "handler returned wrong number of values: Invalid number of arguments, args should be "
         "['sum'] args are(1, 2); pass all 1 fields in order, or use keyword arguments"),
    ])
    def test_invalid_returns_reach_the_client(self, world: ddes.World, run_client: Any,
                                              add_two_ints: Any, handler: Any, text: str) -> None:
        Service(world.create_node("server"), "s", add_two_ints, handler)
        out = call_once(world, run_client, add_two_ints, 1, 2)
        assert isinstance(out.error, ServiceException)
        assert str(out.error) == f"service [/s] responded with an error: service cannot process " \
                                 f"request: {text}"
        assert out.t == 4 * L
        assert not world.trace.filter(kind="service.exception")  # a ServiceException is not logged

    def test_bare_bool_for_a_two_field_response(self, world: ddes.World, run_client: Any,
                                                set_bool: Any) -> None:
        Service(world.create_node("server"), "stop", set_bool, lambda req: True)
        out = call_once(world, run_client, set_bool, True, name="stop")
        assert str(out.error).startswith(
            "service [/stop] responded with an error: service cannot process request: handler "
            "returned invalid value: Invalid number of arguments, args should be ['success', "
            "'message'] args are(True,)")

    def test_service_exception(self, world: ddes.World, run_client: Any, add_two_ints: Any) -> None:
        def handler(req: Any) -> Any:
            raise ServiceException("busy")

        Service(world.create_node("server"), "s", add_two_ints, handler)
        out = call_once(world, run_client, add_two_ints, 1, 2)
        assert str(out.error) == ("service [/s] responded with an error: service cannot process "
                                  "request: busy")
        assert logs(world, "ERROR") == []

    def test_other_exception_is_logged_and_traced(self, world: ddes.World, run_client: Any,
                                                  add_two_ints: Any) -> None:
        def handler(req: Any) -> Any:
            raise ZeroDivisionError("division by zero")

        Service(world.create_node("server"), "s", add_two_ints, handler)
        out = call_once(world, run_client, add_two_ints, 1, 2)
        assert str(out.error) == ("service [/s] responded with an error: error processing "
                                  "request: division by zero")
        assert logs(world, "ERROR") == [("/server", "Error processing request: division by zero")]
        [exc] = world.trace.filter(kind="service.exception")
        assert exc.t == 3 * L
        assert exc.details == {"service": "/s", "call": 1,
                               "error": "ZeroDivisionError: division by zero"}
        assert world.callback_errors == []

    def test_error_handler_replaces_the_log(self, world: ddes.World, run_client: Any,
                                            add_two_ints: Any) -> None:
        seen: list[Any] = []

        def handler(req: Any) -> Any:
            raise KeyError("k")

        Service(world.create_node("server"), "s", add_two_ints, handler,
                error_handler=lambda e, t, v, tb: seen.append((e, t, v)))
        out = call_once(world, run_client, add_two_ints, 1, 2)
        assert str(out.error) == "service [/s] responded with an error: error processing request: 'k'"
        assert len(seen) == 1 and seen[0][1] is KeyError and seen[0][0] is seen[0][2]
        assert logs(world, "ERROR") == []

    def test_a_failing_handler_does_not_take_the_server_down(
            self, world: ddes.World, run_client: Any, add_two_ints: Any) -> None:
        def handler(req: Any) -> Any:
            if req.a == 0:
                raise RuntimeError("zero")
            return req.a + req.b

        server = world.create_node("server")
        Service(server, "s", add_two_ints, handler)
        client = world.create_node("client")
        proxy = ServiceProxy(client, "s", add_two_ints)
        results: list[Any] = []

        def main() -> Generator[Any, Any, None]:
            for a in (0, 1, 0, 2):
                try:
                    results.append((yield proxy(a, 10)).sum)
                except ServiceException as exc:
                    results.append(str(exc))

        run_client(world, client, main)
        err = "service [/s] responded with an error: error processing request: zero"
        assert results == [err, 11, err, 12]
        assert not server.is_shutdown()

    def test_generator_handler_takes_simulated_time(self, world: ddes.World, run_client: Any,
                                                    add_two_ints: Any) -> None:
        server = world.create_node("server")

        def handler(req: Any) -> Generator[Any, Any, Any]:
            yield server.sleep(0.25)
            return {"sum": req.a + req.b}

        Service(server, "s", add_two_ints, handler)
        out = call_once(world, run_client, add_two_ints, 2, 3)
        assert out.value.sum == 5
        assert out.t == 4 * L + 250_000_000

    def test_generator_handler_failure(self, world: ddes.World, run_client: Any,
                                       add_two_ints: Any) -> None:
        server = world.create_node("server")

        def handler(req: Any) -> Generator[Any, Any, Any]:
            yield server.sleep(0.1)
            raise ValueError("late failure")

        Service(server, "s", add_two_ints, handler)
        out = call_once(world, run_client, add_two_ints, 2, 3)
        assert str(out.error) == ("service [/s] responded with an error: error processing "
                                  "request: late failure")
        assert out.t == 4 * L + 100_000_000

    def test_response_is_a_snapshot(self, world: ddes.World, run_client: Any,
                                    add_two_ints: Any) -> None:
        kept = add_two_ints._response_class(1)

        def handler(req: Any) -> Any:
            kept.sum = req.a
            return kept

        Service(world.create_node("server"), "s", add_two_ints, handler)
        out = call_once(world, run_client, add_two_ints, 5, 0)
        kept.sum = 99
        assert out.value.sum == 5
        assert out.value is not kept
        assert world.trace.filter(kind="service.response")[0].details["response"].sum == 5

    def test_unserializable_response(self, world: ddes.World, run_client: Any,
                                     add_two_ints: Any) -> None:
        Service(world.create_node("server"), "s", add_two_ints, lambda req: {"sum": "text"})
        out = call_once(world, run_client, add_two_ints, 1, 2)
        assert str(out.error).startswith(
            "service [/s] responded with an error: error processing request: ")
        assert "sum" in str(out.error)


class TestRoscppStyle:
    def test_true_sends_the_filled_response(self, world: ddes.World, run_client: Any,
                                            two_ints: Any) -> None:
        def add(req: Any, res: Any) -> bool:
            res.sum = req.a + req.b
            return True

        world.create_node("server").advertise_service("add_two_ints", two_ints, add, style="roscpp")
        out = call_once(world, run_client, two_ints, 10, 5, name="add_two_ints")
        assert out.value.sum == 15

    def test_false_is_an_empty_error(self, world: ddes.World, run_client: Any, two_ints: Any) -> None:
        Service(world.create_node("server"), "s", two_ints, lambda req, res: False, style="roscpp")
        out = call_once(world, run_client, two_ints, 1, 2)
        assert str(out.error) == "service [/s] responded with an error: "
        assert logs(world) == []

    def test_exception_sends_its_text_and_logs(self, world: ddes.World, run_client: Any,
                                               two_ints: Any) -> None:
        def add(req: Any, res: Any) -> bool:
            raise RuntimeError("Lookup would require extrapolation into the past")

        Service(world.create_node("server"), "s", two_ints, add, style="roscpp")
        out = call_once(world, run_client, two_ints, 1, 2)
        assert str(out.error) == ("service [/s] responded with an error: Lookup would require "
                                  "extrapolation into the past")
        assert logs(world, "ERROR") == [
            ("/server", "Exception thrown while processing service call: Lookup would require "
                        "extrapolation into the past")]

    def test_a_callback_must_return_a_bool(self, world: ddes.World, run_client: Any,
                                           two_ints: Any) -> None:
        Service(world.create_node("server"), "s", two_ints, lambda req, res: None, style="roscpp")
        out = call_once(world, run_client, two_ints, 1, 2)
        assert str(out.error).startswith("service [/s] responded with an error: a roscpp-style "
                                         "service callback must return True or False (bool), got None")

    def test_generator_callback(self, world: ddes.World, run_client: Any, two_ints: Any) -> None:
        server = world.create_node("server")

        def add(req: Any, res: Any) -> Generator[Any, Any, bool]:
            yield server.sleep(1)
            res.sum = req.a - req.b
            return True

        Service(server, "s", two_ints, add, style="roscpp")
        out = call_once(world, run_client, two_ints, 10, 4)
        assert (out.value.sum, out.t) == (6, 1_000_000_000 + 4 * L)


class TestRegistration:
    def test_registers_with_the_master(self, world: ddes.World, add_two_ints: Any) -> None:
        node = world.create_node("server", namespace="/robot")
        srv = node.create_service("add", add_two_ints, lambda r: 0)
        entry = world.master.lookup_service("/robot/add")
        assert entry is not None
        assert (entry.type, entry.md5sum, entry.node, entry.server) == (
            "rospy_tutorials/AddTwoInts", add_two_ints._md5sum, node, srv)
        assert world.master.get_system_state()[2] == [("/robot/add", ["/robot/server"])]
        assert srv.uri == "rosrpc://localhost:40000"
        [adv] = world.trace.filter(kind="service.advertise")
        assert adv.details == {"service": "/robot/add", "type": "rospy_tutorials/AddTwoInts",
                               "style": "rospy", "uri": "rosrpc://localhost:40000"}

    def test_names_resolve_privately_and_with_remapping(self, world: ddes.World,
                                                        add_two_ints: Any) -> None:
        node = world.create_node("server", argv=["add:=/math/add"])
        assert Service(node, "~get", add_two_ints, lambda r: 0).resolved_name == "/server/get"
        assert Service(node, "add", add_two_ints, lambda r: 0).resolved_name == "/math/add"

    def test_one_uri_per_node(self, world: ddes.World, add_two_ints: Any) -> None:
        a, b = world.create_node("a"), world.create_node("b")
        s1 = Service(a, "one", add_two_ints, lambda r: 0)
        s2 = Service(b, "two", add_two_ints, lambda r: 0)
        s3 = Service(a, "three", add_two_ints, lambda r: 0)
        assert (s1.uri, s2.uri, s3.uri) == ("rosrpc://localhost:40000", "rosrpc://localhost:40001",
                                            "rosrpc://localhost:40000")

    def test_advertising_twice(self, world: ddes.World, add_two_ints: Any) -> None:
        node = world.create_node("server")
        Service(node, "s", add_two_ints, lambda r: 0)
        with pytest.raises(ServiceException, match=r"^service \[/s\] already registered; "):
            Service(node, "s", add_two_ints, lambda r: 0)
        with pytest.raises(ServiceException,
                           match=r"^service \[/s\] already registered by node \[/server\]; "):
            Service(world.create_node("other"), "/s", add_two_ints, lambda r: 0)

    def test_shutdown_unregisters_and_allows_a_new_server(self, world: ddes.World,
                                                          add_two_ints: Any) -> None:
        node = world.create_node("server")
        srv = Service(node, "s", add_two_ints, lambda r: 0)
        srv.shutdown()
        srv.shutdown()  # idempotent
        assert world.master.lookup_service("/s") is None
        Service(world.create_node("other"), "s", add_two_ints, lambda r: 0)
        assert world.master.lookup_service("/s").node.name == "/other"  # type: ignore[union-attr]
        assert [e.kind for e in world.trace.filter(prefix="service.")] == [
            "service.advertise", "service.unadvertise", "service.advertise"]

    def test_node_shutdown_unregisters(self, world: ddes.World, add_two_ints: Any) -> None:
        node = world.create_node("server")
        Service(node, "s", add_two_ints, lambda r: 0)
        node.shutdown()
        assert world.master.lookup_service("/s") is None
        with pytest.raises(NodeShutdownError):
            Service(node, "s", add_two_ints, lambda r: 0)

    @pytest.mark.parametrize("name", ["1bad", "a-b", "sp ace", "a/b.c"])
    def test_illegal_names(self, world: ddes.World, add_two_ints: Any, name: str) -> None:
        with pytest.raises(ROSNameException, match=r"Graph Resource Name"):
            Service(world.create_node("server"), name, add_two_ints, lambda r: 0)

    def test_bad_arguments(self, world: ddes.World, add_two_ints: Any) -> None:
        node = world.create_node("server")
        with pytest.raises(DdesValueError, match="service name is not a non-empty string"):
            Service(node, "", add_two_ints, lambda r: 0)
        with pytest.raises(DdesTypeError, match="service_class must be a service class"):
            Service(node, "s", add_two_ints._request_class, lambda r: 0)
        with pytest.raises(DdesTypeError, match="handler must be callable"):
            Service(node, "s", add_two_ints, "not callable")  # type: ignore[arg-type]
        with pytest.raises(DdesValueError, match="style must be 'rospy' or 'roscpp'"):
            Service(node, "s", add_two_ints, lambda r: 0, style="rclpy")


class TestServingModel:
    def _server(self, world: ddes.World, add_two_ints: Any, **kwargs: Any) -> ddes.Node:
        server = world.create_node("server", **kwargs)

        def handler(req: Any) -> Generator[Any, Any, Any]:
            yield server.sleep(req.a / 1000)
            return req.b

        Service(server, "s", add_two_ints, handler)
        return server

    def _fire(self, world: ddes.World, add_two_ints: Any, calls: list[tuple[int, int]],
              persistent: bool = False) -> list[tuple[int, int]]:
        client = world.create_node("client")
        proxy = ServiceProxy(client, "s", add_two_ints, persistent=persistent)
        done: list[tuple[int, int]] = []

        def one(ms: int, tag: int) -> Generator[Any, Any, None]:
            done.append(((yield proxy(ms, tag)).sum, world.now))

        for ms, tag in calls:
            client.process(one(ms, tag))
        world.run()
        return done

    def test_single_spinner_serves_one_at_a_time_in_arrival_order(
            self, world: ddes.World, add_two_ints: Any) -> None:
        self._server(world, add_two_ints)
        done = self._fire(world, add_two_ints, [(30, 1), (10, 2), (20, 3)])
        ms = 1_000_000
        assert done == [(1, 3 * L + 30 * ms + L), (2, 3 * L + 40 * ms + L),
                        (3, 3 * L + 60 * ms + L)]

    def test_spinner_n_serves_concurrently(self, world: ddes.World, add_two_ints: Any) -> None:
        self._server(world, add_two_ints, spinner=2)
        done = self._fire(world, add_two_ints, [(30, 1), (10, 2), (20, 3)])
        ms = 1_000_000
        assert done == [(2, 4 * L + 10 * ms), (1, 4 * L + 30 * ms), (3, 4 * L + 30 * ms)]

    def test_one_persistent_connection_is_served_in_order_even_with_threads(
            self, world: ddes.World, add_two_ints: Any) -> None:
        # rospy: one thread per connection; a persistent connection's requests queue
        self._server(world, add_two_ints, spinner=4)
        done = self._fire(world, add_two_ints, [(30, 1), (10, 2)], persistent=True)
        ms = 1_000_000
        assert done == [(1, 4 * L + 30 * ms), (2, 4 * L + 40 * ms)]

    def test_manual_spinner_serves_on_spin_once(self, world: ddes.World, run_client: Any,
                                                add_two_ints: Any) -> None:
        server = world.create_node("server", spinner="manual")
        Service(server, "s", add_two_ints, lambda req: req.a + req.b)

        def loop() -> Generator[Any, Any, None]:
            while True:
                yield server.sleep(0.1)
                yield server.spin_once()

        server.process(loop())
        out = call_once(world, run_client, add_two_ints, 1, 2, until=1)
        assert out.value.sum == 3
        assert out.t == 100_000_000 + L


def test_spin_is_the_node_spin(world: ddes.World, add_two_ints: Any) -> None:
    node = world.create_node("server")
    srv = Service(node, "s", add_two_ints, lambda r: 0)
    ev = srv.spin()
    node.shutdown("bye")
    world.run()
    assert ev.processed
    assert "Service /s" in repr(srv) and "closed" in repr(srv)
