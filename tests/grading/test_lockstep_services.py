"""Services across the sandbox boundary: a student's server called from the grader's world,
answers in zero or in simulated time, errors, and frames that are refused."""

from __future__ import annotations

import textwrap
from pathlib import Path
from typing import Any

from ddes.errors import ServiceException
from ddes.grading import Lockstep, Sandbox, protocol
from ddes.graph.world import World
from ddes.services.client import ServiceProxy

SERVER = textwrap.dedent("""\
    import rospy
    from std_srvs.srv import SetBool, SetBoolResponse
    rospy.init_node("estop")
    state = {"n": 0}
    def handle(req):
        state["n"] += 1
        if req.data and state["n"] == 3:
            raise rospy.ServiceException("third call refused")
        return SetBoolResponse(True, "stopped" if req.data else "running")
    def slow(req):
        rospy.sleep(0.25)
        return SetBoolResponse(req.data, "slow")
    rospy.Service("/estop", SetBool, handle)
    rospy.Service("/slow", SetBool, slow)
    rospy.spin()
""")


def _calls(tmp_path: Path) -> tuple[World, Lockstep, list[tuple[int, str, Any]]]:
    (tmp_path / "server.py").write_text(SERVER)
    world = World(0, wall_budget=None)
    setbool = world.messages.get_service_class("std_srvs/SetBool")
    node = world.create_node("/grader_client")
    got: list[tuple[int, str, Any]] = []

    def drive():  # type: ignore[no-untyped-def]
        yield node.sleep(0.5)
        for name, data in (("/estop", True), ("/estop", False), ("/slow", True),
                           ("/estop", True), ("/nothing", True)):
            proxy = ServiceProxy(node, name, setbool)
            try:
                resp = yield proxy.call(data)
                got.append((world.now, name, (resp.success, resp.message)))
            except ServiceException as exc:
                got.append((world.now, name, str(exc)))

    node.process(drive())
    lock = Lockstep(world, Sandbox(tmp_path, [("server.py", [])]))
    lock.run(2_000_000_000)
    return world, lock, got


def test_a_students_service_is_called_from_the_grader_world(tmp_path: Path) -> None:
    world, lock, got = _calls(tmp_path)
    assert lock.problems == []
    # each crossing call takes the default latencies of both worlds: 4 x 0.1 ms in each
    assert got == [
        (500_800_000, "/estop", (True, "stopped")),
        (501_600_000, "/estop", (True, "running")),
        (752_400_000, "/slow", (True, "slow")),  # the handler's 0.25 s of simulated time
        (753_200_000, "/estop", "service [/estop] responded with an error: service cannot "
                                "process request: third call refused"),
        (753_200_000, "/nothing", "service [/nothing] unavailable"),
    ]
    # the grader's master shows the student's services, with their type and node
    entry = world.master.lookup_service("/estop")
    assert entry is not None and entry.type == "std_srvs/SetBool" and entry.node.name == "/estop"


def test_a_sandboxed_service_run_is_deterministic(tmp_path: Path) -> None:
    a = _calls(tmp_path)
    b = _calls(tmp_path)
    assert a[2] == b[2] and a[0].digest() == b[0].digest()


def test_service_frames_from_the_child_are_validated() -> None:
    world = World(0, wall_budget=None)
    world.create_node("/grader")
    setbool = world.messages.get_service_class("std_srvs/SetBool")
    lock = Lockstep(world, Sandbox.__new__(Sandbox))
    lock._apply([
        protocol.Srv("/s", "/estop", "std_srvs/SetBool", "0" * 32),       # md5 differs
        protocol.Srv("/s", "/x", "std_srvs/NoSuch", setbool._md5sum),     # unknown type
        protocol.Srv("/s", "relative", "std_srvs/SetBool", setbool._md5sum),
        protocol.Srv("/s", "/ok", "std_srvs/SetBool", setbool._md5sum),
        protocol.Resp(7, True, b"\x01"),                                  # no such call
    ], 0)
    texts = [text for _t, text in lock.problems]
    assert len(texts) == 4
    assert "differs from the grader's" in texts[0] and "unknown service type" in texts[1]
    assert "illegal service name" in texts[2] and "not waiting" in texts[3]
    assert world.master.lookup_service("/ok") is not None
    assert world.master.lookup_service("/estop") is None
    # a response that is not one SetBool response reaches the caller as an error, refused
    server = lock._services["/ok"]

    class _Conn:
        server_gone = False
        persistent = False
        closed = False
        id = 1
        proxy = None

    sent: list[tuple[bool, Any]] = []
    server._send = lambda conn, call, ok, payload: sent.append((ok, payload))  # type: ignore[method-assign]
    lock._forward_call(server, _Conn(), type("C", (), {"data": b"\x01"})())
    assert lock._children[0].calls == [(1, "/ok", b"\x01")]
    lock._apply([protocol.Resp(1, True, b"\x01\x05\x00")], 0)
    assert sent and sent[0][0] is False and "not one std_srvs/SetBool response" in sent[0][1]


def test_service_frames_round_trip() -> None:
    def rt(data: bytes) -> object:
        kind, n = protocol.decode_header(data[:protocol.HEADER.size])
        return protocol.decode_frame(kind, data[protocol.HEADER.size:])

    assert rt(protocol.encode_call(3, "/estop", b"\x01")) == protocol.Call(3, "/estop", b"\x01")
    assert rt(protocol.encode_srv("/n", "/s", "std_srvs/SetBool", "ab")) == protocol.Srv(
        "/n", "/s", "std_srvs/SetBool", "ab")
    assert rt(protocol.encode_resp(4, False, "x" * 10_000)) == protocol.Resp(
        4, False, b"x" * protocol.MAX_ERROR)
