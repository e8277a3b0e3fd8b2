"""Service clients: timing of the hops, every error with its text, persistence, timeouts."""

from __future__ import annotations

from collections.abc import Generator
from pathlib import Path
from typing import Any

import pytest

import ddes
from ddes.errors import (
    DdesTypeError,
    DdesValueError,
    ROSInterruptException,
    ROSSerializationException,
    ServiceException,
    ServiceTimeout,
)
from ddes.msg import MessageRegistry
from ddes.services import Service, ServiceClient, ServiceProxy
from ddes.time.clock import SimClock

L = 100_000
MS = 1_000_000
TRANSPORT = ("transport error completing service call: unable to receive data from sender, check "
             "sender's logs for details")


def adder(world: ddes.World, cls: Any, name: str = "s", node: str = "server",
          delay: float = 0.0) -> Service:
    server = world.nodes.get("/" + node) or world.create_node(node)

    def handler(req: Any) -> Generator[Any, Any, Any]:
        if delay:
            yield server.sleep(delay)
        return req.a + req.b

    return Service(server, name, cls, handler)


class TestTiming:
    def test_a_call_is_four_hops_on_a_new_connection(self, world: ddes.World, run_client: Any,
                                                     add_two_ints: Any) -> None:
        adder(world, add_two_ints)
        client = world.create_node("client")
        proxy = ServiceProxy(client, "s", add_two_ints)
        times: list[int] = []

        def main() -> Generator[Any, Any, None]:
            for i in range(3):
                assert (yield proxy(i, i)).sum == 2 * i
                times.append(world.now)

        run_client(world, client, main)
        assert times == [4 * L, 8 * L, 12 * L]
        kinds = [(e.t, e.kind, e.source) for e in world.trace.filter(prefix="service.")][1:4]
        assert kinds == [(0, "service.call", "/client"), (3 * L, "service.request", "/server"),
                         (4 * L, "service.response", "/client")]

    def test_a_persistent_connection_saves_the_header_exchange(
            self, world: ddes.World, run_client: Any, add_two_ints: Any) -> None:
        adder(world, add_two_ints)
        client = world.create_node("client")
        proxy = ServiceProxy(client, "s", add_two_ints, persistent=True)
        times: list[int] = []

        def main() -> Generator[Any, Any, None]:
            for i in range(3):
                yield proxy(i, i)
                times.append(world.now)

        run_client(world, client, main)
        assert times == [4 * L, 6 * L, 8 * L]
        assert proxy.headers == {"persistent": "1"}

    def test_link_rules(self, world: ddes.World, run_client: Any, add_two_ints: Any) -> None:
        adder(world, add_two_ints)
        adder(world, add_two_ints, name="other")
        world.set_service_link(latency=0.001)
        world.set_service_link("/s", latency=0.002)
        world.set_service_link("/s", client="/special", latency=ddes.Duration(0, 5 * MS))
        times: dict[str, int] = {}
        for who, name in (("plain", "s"), ("special", "s"), ("elsewhere", "other")):
            node = world.create_node(who)

            def main(node: ddes.Node = node, name: str = name) -> Generator[Any, Any, None]:
                yield ServiceProxy(node, name, add_two_ints)(1, 2)
                times[node.name] = world.now

            node.process(main())
        world.run()
        assert times == {"/plain": 8 * MS, "/special": 20 * MS, "/elsewhere": 4 * MS}

    def test_drawn_latencies_are_deterministic_and_fifo(self, add_two_ints: Any) -> None:
        def scenario(seed: int) -> tuple[list[int], str]:
            world = ddes.World(seed)
            adder(world, add_two_ints)
            world.set_service_link("/s", latency=lambda rng: rng.uniform(0.001, 0.01))
            client = world.create_node("client")
            proxy = ServiceProxy(client, "s", add_two_ints, persistent=True)
            got: list[int] = []

            def one(i: int) -> Generator[Any, Any, None]:
                got.append((yield proxy(i, 0)).sum)

            for i in range(20):
                client.process(one(i))
            world.run()
            return got, world.digest()

        a, b, c = scenario(1), scenario(1), scenario(2)
        assert a == b
        assert a[0] == list(range(20))  # one connection: requests and responses stay in order
        assert a[1] != c[1]

    def test_invalid_link(self, world: ddes.World) -> None:
        with pytest.raises(DdesValueError, match="latency must be >= 0"):
            world.set_service_link("/s", latency=-1.0)
        with pytest.raises(DdesTypeError, match="service must be a name or None"):
            world.set_service_link(3)  # type: ignore[arg-type]


class TestErrors:
    def test_unavailable(self, world: ddes.World, run_client: Any, add_two_ints: Any) -> None:
        client = world.create_node("client")

        def main() -> Generator[Any, Any, Any]:
            yield world.timeout(1)
            return (yield ServiceProxy(client, "missing", add_two_ints)(1, 2))

        out = run_client(world, client, main)
        assert isinstance(out.error, ServiceException)
        assert str(out.error) == "service [/missing] unavailable"
        assert out.t == 1_000_000_000
        [err] = world.trace.filter(kind="service.error")
        assert err.details == {"service": "/missing", "call": 1, "latency": 0,
                               "reason": "unavailable", "error": "service [/missing] unavailable"}

    def test_md5_mismatch(self, world: ddes.World, run_client: Any, add_two_ints: Any,
                          trigger: Any) -> None:
        adder(world, add_two_ints)
        client = world.create_node("client")
        out = run_client(world, client, lambda: (yield ServiceProxy(client, "s", trigger)()))
        assert str(out.error) == (
            "unable to connect to service: remote error reported: request from [/client]: md5sums "
            f"do not match: [{trigger._md5sum}] vs. [{add_two_ints._md5sum}]")
        assert out.t == 2 * L
        assert world.service_stats("/s")["errors"]["connect"] == 1

    def test_server_gone_before_the_header_arrives(self, world: ddes.World, run_client: Any,
                                                   add_two_ints: Any) -> None:
        srv = adder(world, add_two_ints)
        client = world.create_node("client")
        proxy = ServiceProxy(client, "s", add_two_ints)

        def main() -> Generator[Any, Any, Any]:
            ev = proxy(1, 2)
            srv.shutdown()  # the node lives on
            return (yield ev)

        out = run_client(world, client, main)
        assert str(out.error) == ("unable to connect to service: remote error reported: [/server] "
                                  "is not a provider of  [/s]")

    def test_server_node_dead_before_the_header_arrives(self, world: ddes.World, run_client: Any,
                                                        add_two_ints: Any) -> None:
        srv = adder(world, add_two_ints)
        client = world.create_node("client")
        proxy = ServiceProxy(client, "s", add_two_ints)

        def main() -> Generator[Any, Any, Any]:
            ev = proxy(1, 2)
            srv.node.shutdown()
            return (yield ev)

        out = run_client(world, client, main)
        assert str(out.error) == "unable to connect to service: [Errno 111] Connection refused"
        assert out.t == 2 * L

    def test_server_shut_down_mid_call(self, world: ddes.World, run_client: Any,
                                       add_two_ints: Any) -> None:
        srv = adder(world, add_two_ints, delay=1.0)
        client = world.create_node("client")
        world.call_at(500 * MS, lambda: srv.node.shutdown("killed"))
        out = run_client(world, client, lambda: (yield ServiceProxy(client, "s", add_two_ints)(1, 2)))
        assert str(out.error) == TRANSPORT
        assert out.t == 500 * MS + L
        [discard] = world.trace.filter(kind="service.discard")
        assert (discard.t, discard.details["reason"]) == (3 * L + 1000 * MS, "server shut down")
        stats = world.service_stats("/s")
        assert (stats["errors"]["transport"], stats["discarded"]) == (1, 1)

    def test_response_already_sent_still_arrives(self, world: ddes.World, run_client: Any,
                                                 add_two_ints: Any) -> None:
        srv = adder(world, add_two_ints)
        client = world.create_node("client")
        world.call_at(3 * L + L // 2, lambda: srv.node.shutdown("killed"))
        out = run_client(world, client, lambda: (yield ServiceProxy(client, "s", add_two_ints)(1, 2)))
        assert out.value.sum == 3

    def test_persistent_proxy_after_its_server_went_away(
            self, world: ddes.World, run_client: Any, add_two_ints: Any) -> None:
        srv = adder(world, add_two_ints)
        client = world.create_node("client")
        proxy = ServiceProxy(client, "s", add_two_ints, persistent=True)
        results: list[str] = []

        def main() -> Generator[Any, Any, None]:
            results.append(str((yield proxy(1, 2)).sum))
            srv.shutdown()
            adder(world, add_two_ints, node="server2")  # a new server under the same name
            for _ in range(2):
                try:
                    yield proxy(1, 2)
                except ServiceException as exc:
                    results.append(str(exc))
            results.append(str((yield ServiceProxy(client, "s", add_two_ints, True)(2, 2)).sum))

        run_client(world, client, main)
        gone = ("persistent connection to service [/s] was closed: the server went away; create "
                "a new ServiceProxy")
        assert results == ["3", gone, gone, "4"]
        assert world.service_stats("/s")["errors"]["closed"] == 2

    def test_close(self, world: ddes.World, run_client: Any, add_two_ints: Any) -> None:
        adder(world, add_two_ints, delay=1.0)
        client = world.create_node("client")
        persistent = ServiceProxy(client, "s", add_two_ints, persistent=True)
        plain = ServiceProxy(client, "s", add_two_ints)
        plain.close()  # no effect, as rospy
        world.call_at(500 * MS, persistent.close)
        out = run_client(world, client, lambda: (yield persistent(1, 2)))
        assert str(out.error) == TRANSPORT
        assert out.t == 500 * MS
        out2 = run_client(world, client, lambda: (yield plain(1, 2)))
        assert out2.value.sum == 3
        out3 = run_client(world, client, lambda: (yield persistent(1, 2)))
        assert str(out3.error) == ("persistent ServiceProxy for service [/s] was closed; create a "
                                   "new one")

    def test_client_node_shutdown_interrupts(self, world: ddes.World, run_client: Any,
                                             add_two_ints: Any) -> None:
        adder(world, add_two_ints, delay=1.0)
        client = world.create_node("client")
        world.call_at(200 * MS, lambda: client.shutdown("bye"))
        out = run_client(world, client, lambda: (yield ServiceProxy(client, "s", add_two_ints)(1, 2)))
        assert isinstance(out.error, ROSInterruptException)
        assert str(out.error) == "node shutdown interrupted service call"
        assert out.t == 200 * MS
        stats = world.service_stats("/s")
        assert (stats["errors"]["interrupted"], stats["discarded"], stats["served"]) == (1, 1, 1)

    def test_request_errors_are_raised_by_call_itself(self, world: ddes.World,
                                                      add_two_ints: Any, trigger: Any) -> None:
        adder(world, add_two_ints)
        proxy = ServiceProxy(world.create_node("client"), "s", add_two_ints)
        with pytest.raises(TypeError, match=r"expected \[int64\] but got \[std_srvs/TriggerRequest\]"):
            proxy(trigger._request_class())
        with pytest.raises(TypeError, match="but not both"):
            proxy(1, b=2)
        with pytest.raises(TypeError, match="Invalid number of arguments"):
            proxy(1)
        with pytest.raises(ROSSerializationException, match="a"):
            proxy("one", 2)
        assert world.trace.filter(kind="service.call") == []

    def test_bad_proxy_arguments(self, world: ddes.World, add_two_ints: Any) -> None:
        node = world.create_node("client")
        with pytest.raises(DdesTypeError, match="service_class must be a service class"):
            ServiceProxy(node, "s", add_two_ints._response_class)
        with pytest.raises(DdesValueError, match="service name is not a non-empty string"):
            ServiceProxy(node, "", add_two_ints)
        with pytest.raises(DdesValueError, match="^timeout must be non-zero$"):
            ServiceProxy(node, "s", add_two_ints, timeout=0)


class TestCallTimeout:
    def test_timeout_fires_at_the_exact_instant_and_the_server_keeps_working(
            self, world: ddes.World, run_client: Any, add_two_ints: Any) -> None:
        adder(world, add_two_ints, delay=0.5)
        client = world.create_node("client")
        proxy = ServiceProxy(client, "s", add_two_ints)
        out = run_client(world, client, lambda: (yield proxy.call(1, 2, timeout=0.2)))
        assert isinstance(out.error, ServiceTimeout) and isinstance(out.error, ServiceException)
        assert str(out.error) == (
            "service [/s] call timed out after 0.2 s of ROS time (a ddes extension: ROS 1 calls "
            "have no timeout); the server was not told and its late response will be discarded")
        assert out.t == 200 * MS
        [discard] = world.trace.filter(kind="service.discard")
        assert discard.t == 3 * L + 500 * MS
        assert discard.details == {"service": "/s", "call": 1, "client": "/client",
                                   "reason": "client gave up"}
        stats = world.service_stats("/s")
        assert (stats["errors"]["timeout"], stats["discarded"], stats["served"]) == (1, 1, 1)

    def test_later_calls_queue_behind_the_abandoned_one(self, world: ddes.World, run_client: Any,
                                                        add_two_ints: Any) -> None:
        adder(world, add_two_ints, delay=0.5)
        client = world.create_node("client")
        proxy = ServiceProxy(client, "s", add_two_ints, timeout=ddes.Duration(0, 200 * MS))
        events: list[tuple[str, int]] = []

        def main() -> Generator[Any, Any, None]:
            for _ in range(2):
                try:
                    yield proxy(1, 2)
                    events.append(("ok", world.now))
                except ServiceTimeout:
                    events.append(("timeout", world.now))
            events.append(("ok", (yield proxy.call(1, 2, timeout=None)).sum))

        run_client(world, client, main)
        # the second request waits for the first (0.5 s) before its own 0.5 s
        assert events == [("timeout", 200 * MS), ("timeout", 400 * MS), ("ok", 3)]

    def test_a_late_response_in_flight_is_discarded_on_arrival(
            self, world: ddes.World, run_client: Any, add_two_ints: Any) -> None:
        adder(world, add_two_ints)
        client = world.create_node("client")
        out = run_client(world, client, lambda: (yield ServiceProxy(client, "s", add_two_ints)
                                                 .call(1, 2, timeout=ddes.Duration(0, 3 * L + L // 2))))
        assert isinstance(out.error, ServiceTimeout)
        [discard] = world.trace.filter(kind="service.discard")
        assert (discard.t, discard.source) == (4 * L, "/client")

    def test_a_request_not_yet_sent_never_reaches_the_server(
            self, world: ddes.World, run_client: Any, add_two_ints: Any) -> None:
        adder(world, add_two_ints)
        client = world.create_node("client")
        out = run_client(world, client, lambda: (yield ServiceProxy(client, "s", add_two_ints)
                                                 .call(1, 2, timeout=ddes.Duration(0, L + 1))))
        assert isinstance(out.error, ServiceTimeout)
        assert world.trace.filter(kind="service.request") == []
        assert world.service_stats("/s")["served"] == 0

    def test_persistent_proxy_reconnects_after_a_timeout(
            self, world: ddes.World, run_client: Any, add_two_ints: Any) -> None:
        adder(world, add_two_ints, delay=0.001)
        client = world.create_node("client")
        proxy = ServiceProxy(client, "s", add_two_ints, persistent=True)
        times: list[Any] = []

        def main() -> Generator[Any, Any, None]:
            yield proxy(1, 1)
            times.append(world.now)
            try:
                yield proxy.call(1, 1, timeout=0.0005)
            except ServiceTimeout:
                times.append(world.now)
            yield proxy(1, 1)  # new connection: header exchange again
            times.append(world.now)

        run_client(world, client, main)
        t1 = 4 * L + MS
        t2 = t1 + 500_000
        # the new request queues behind the abandoned one (which ends at t1 + L + 1 ms)
        assert times == [t1, t2, t1 + L + MS + MS + L]

    def test_timeout_field_wins(self, tmp_path: Path, world: ddes.World, run_client: Any) -> None:
        srv_dir = tmp_path / "my_srvs" / "srv"
        srv_dir.mkdir(parents=True)
        (tmp_path / "my_srvs" / "package.xml").write_text(
            "<package><name>my_srvs</name><version>0.0.0</version></package>")
        (srv_dir / "Wait.srv").write_text("float64 timeout\n---\nbool ok\n")
        cls = MessageRegistry([tmp_path], use_env=False).get_service_class("my_srvs/Wait")
        Service(world.create_node("server"), "wait", cls, lambda req: req.timeout == 2.5)
        client = world.create_node("client")
        out = run_client(world, client, lambda: (yield ServiceProxy(client, "wait", cls)
                                                 .call(timeout=2.5)))
        assert out.value.ok is True

    def test_timeouts_run_on_the_nodes_ros_time(self, world: ddes.World, run_client: Any,
                                                add_two_ints: Any) -> None:
        adder(world, add_two_ints, delay=10.0)
        client = world.create_node("client", use_sim_time=True)
        clock = client.clock
        assert isinstance(clock, SimClock)

        def drive() -> Generator[Any, Any, None]:
            for k in range(1, 100):
                clock.update(k * 100 * MS * 2)  # /clock at 2x the kernel
                yield world.timeout(0.1)

        world.process(drive())
        out = run_client(world, client, lambda: (yield ServiceProxy(client, "s", add_two_ints)
                                                 .call(1, 2, timeout=1.0)), until=5)
        assert isinstance(out.error, ServiceTimeout)
        assert out.t == 500 * MS  # 1 s of ROS time after ROS time 0.2 s = kernel 0.5 s


class TestServiceClient:
    def test_true_fills_the_response(self, world: ddes.World, run_client: Any,
                                     two_ints: Any) -> None:
        adder(world, two_ints, name="add_two_ints")
        client = world.create_node("client")
        sc = ServiceClient(client, "add_two_ints", two_ints)
        resp = two_ints._response_class()
        out = run_client(world, client, lambda: (yield sc.call(two_ints._request_class(3, 4), resp)))
        assert (out.value, resp.sum) == (True, 7)
        assert sc.get_service() == "/add_two_ints" and not sc.is_persistent() and sc.is_valid()

    def test_false_on_failure_logging_only_server_texts(self, world: ddes.World, run_client: Any,
                                                        two_ints: Any) -> None:
        def handler(req: Any, res: Any) -> bool:
            if req.a < 0:
                raise RuntimeError("negative")
            return False

        Service(world.create_node("server"), "s", two_ints, handler, style="roscpp")
        client = world.create_node("client")
        sc = ServiceClient(client, "s", two_ints)
        missing = ServiceClient(client, "missing", two_ints)
        resp = two_ints._response_class()
        results: list[bool] = []

        def main() -> Generator[Any, Any, None]:
            for a in (1, -1):
                results.append((yield sc.call(two_ints._request_class(a, 0), resp)))
            results.append((yield missing.call(two_ints._request_class(0, 0), resp)))

        run_client(world, client, main)
        assert results == [False, False, False]
        client_errors = [e.details["msg"] for e in world.trace.filter(kind="log", source="/client")]
        assert client_errors == ["Service call failed: service [/s] responded with an error: negative"]

    def test_wait_for_existence(self, world: ddes.World, run_client: Any, two_ints: Any) -> None:
        client = world.create_node("client")
        sc = ServiceClient(client, "s", two_ints)
        world.call_at(300 * MS, lambda: adder(world, two_ints))
        results: list[Any] = []

        def main() -> Generator[Any, Any, None]:
            results.append(((yield sc.wait_for_existence(0.1)), world.now))
            results.append(((yield sc.wait_for_existence(0)), world.now))
            results.append(((yield sc.wait_for_existence(-1)), world.now))
            results.append(((yield sc.wait_for_existence()), world.now))
            results.append(sc.exists())

        run_client(world, client, main)
        assert results == [(False, 100 * MS), (False, 100 * MS), (True, 300 * MS),
                           (True, 300 * MS), True]
        msgs = [e.details["msg"] for e in world.trace.filter(kind="log", source="/client")]
        assert msgs == ["waitForService: Service [/s] has not been advertised, waiting..."] * 3 + [
            "waitForService: Service [/s] is now available."]

    def test_shutdown_and_validity(self, world: ddes.World, two_ints: Any) -> None:
        adder(world, two_ints)
        sc = ServiceClient(world.create_node("client"), "s", two_ints, persistent=True)
        assert sc.is_valid()
        sc.shutdown()
        assert not sc.is_valid()


class TestStatsAndTrace:
    def test_stats(self, world: ddes.World, run_client: Any, add_two_ints: Any) -> None:
        def handler(req: Any) -> Any:
            return None if req.a < 0 else req.a + req.b

        Service(world.create_node("server"), "s", add_two_ints, handler)
        client = world.create_node("client")

        def main() -> Generator[Any, Any, None]:
            persistent = ServiceProxy(client, "s", add_two_ints, persistent=True)
            for a in (1, -1, 2):
                try:
                    yield persistent(a, 0)
                except ServiceException:
                    pass

        run_client(world, client, main)
        assert world.service_stats("/s") == {
            "service": "/s", "calls": 3, "succeeded": 2, "failed": 1, "in_flight": 0,
            "errors": {"unavailable": 0, "connect": 0, "server": 1, "transport": 0, "closed": 0,
                       "timeout": 0, "interrupted": 0},
            "served": 3, "discarded": 0, "latency_min_ns": 2 * L, "latency_max_ns": 4 * L,
            "latency_mean_ns": 3 * L,
        }
        with pytest.raises(ddes.errors.ROSServiceException, match=r"no statistics for service \[s\]"):
            world.service_stats("s")

    def test_trace_records_snapshots_of_request_and_response(
            self, world: ddes.World, run_client: Any, add_two_ints: Any) -> None:
        adder(world, add_two_ints)
        client = world.create_node("client")
        req = add_two_ints._request_class(1, 2)
        proxy = ServiceProxy(client, "s", add_two_ints)

        def main() -> Generator[Any, Any, None]:
            ev = proxy(req)
            req.a = 100  # mutating after the call changes nothing sent or traced
            assert (yield ev).sum == 3

        run_client(world, client, main)
        [call] = world.trace.filter(kind="service.call")
        assert call.details["request"] == add_two_ints._request_class(1, 2)
        assert call.details["persistent"] is False
        line = world.trace.filter(kind="service.response")[0].to_json()
        assert '"response":{"_type":"rospy_tutorials/AddTwoIntsResponse","sum":3}' in line

    def test_same_seed_same_digest(self, add_two_ints: Any) -> None:
        def scenario() -> str:
            world = ddes.World(7)
            adder(world, add_two_ints, delay=0.01)
            for i in range(3):
                node = world.create_node(f"c{i}")
                node.process(_calls(node, add_two_ints, i))
            world.run()
            return world.digest()

        assert scenario() == scenario()


def _calls(node: ddes.Node, cls: Any, i: int) -> Generator[Any, Any, None]:
    proxy = ServiceProxy(node, "s", cls)
    for k in range(3):
        yield proxy(i, k)


def test_same_md5_other_type_connects_as_in_ros(world: ddes.World, run_client: Any,
                                                add_two_ints: Any, two_ints: Any) -> None:
    # the connection header carries the md5sum only: AddTwoInts and TwoInts are interchangeable
    Service(world.create_node("server"), "s", two_ints, lambda req: req.a * req.b)
    client = world.create_node("client")
    out = run_client(world, client, lambda: (yield ServiceProxy(client, "s", add_two_ints)(6, 7)))
    assert out.value.sum == 42
    assert type(out.value) is add_two_ints._response_class


def test_proxy_wait_for_service(world: ddes.World, run_client: Any, add_two_ints: Any) -> None:
    client = world.create_node("client", namespace="/ns")
    proxy = ServiceProxy(client, "s", add_two_ints)
    world.call_at(7 * MS, lambda: adder(world, add_two_ints, name="/ns/s"))
    out = run_client(world, client, lambda: (yield proxy.wait_for_service(timeout=1.0)))
    assert (out.error, out.t) == (None, 7 * MS)
    assert repr(proxy) == "<ServiceProxy /ns/s [rospy_tutorials/AddTwoInts] of /ns/client>"
