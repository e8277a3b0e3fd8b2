"""A stand-in for a C++ node, in Python: speaks docs/external-nodes.md's frames as ddes's
roscpp library does, so the world side is tested without a compiler.  Scenarios by argv[1]."""

from __future__ import annotations

import os
import struct
import sys

sys.path.insert(0, os.environ["DDES_FAKE_NODE_PATH"])
from ddes.roscpp import protocol as P  # noqa: E402

R, W = (int(x) for x in os.environ["DDES_NODE_FDS"].split(","))
state = {"req": 0, "now": 0, "ok": True}
callbacks: dict[int, object] = {}


def send(kind: int, payload: bytes) -> None:
    os.write(W, P.frame(kind, payload))


def read_exact(n: int) -> bytes:
    out = b""
    while len(out) < n:
        chunk = os.read(R, n - len(out))
        if not chunk:
            sys.exit(0)
        out += chunk
    return out


def read() -> tuple[int, bytes]:
    kind, size = P.split_header(read_exact(P.HEADER_SIZE))
    return kind, read_exact(size) if size else b""


def request(kind: int, w: P.Writer, blocking: bool = False) -> P.Reader:
    """Send a request carrying a fresh req id (already first in ``w``) and wait for its REPLY,
    running callbacks meanwhile."""
    req = state["req_of"]
    send(kind, w.payload())
    while True:
        k, payload = read()
        if k == P.REPLY:
            r = P.Reader(payload, "REPLY")
            got, now, _wall, status = r.u32(), r.i64(), r.i64(), r.u8()
            assert got == req, (got, req)
            state["now"] = now
            if status:
                raise RuntimeError(r.string())
            return r
        if k == P.SHUTDOWN_NOTICE:
            state["ok"] = False
            continue
        if k == P.CALLBACK:
            r = P.Reader(payload, "CALLBACK")
            cb, what, entity, now, _wall = r.u32(), r.u8(), r.u32(), r.i64(), r.i64()
            state["now"] = now
            result = callbacks[entity](what, r)  # type: ignore[operator]
            ok, data = result if isinstance(result, tuple) else (1, b"")
            send(P.CB_DONE, P.Writer().u32(cb).u8(ok).blob(data).payload())


def new_req() -> P.Writer:
    state["req"] += 1
    state["req_of"] = state["req"]
    return P.Writer().u32(state["req"])


def log(text: str, level: int = 1) -> None:
    send(P.LOG, P.Writer().u8(level).string("ros.fake").string(text).string("/src/fake.cpp")
         .string("main").u32(7).payload())


def hello(name: str) -> P.Reader:
    w = P.Writer().u32(P.VERSION).string(name).u32(0).u32(len(sys.argv))
    for a in sys.argv:
        w.string(a)
    state["req_of"] = 0
    return request(P.HELLO, w)


def string_bytes(text: str) -> bytes:
    raw = text.encode()
    return struct.pack("<I", len(raw)) + raw


def talker() -> None:
    hello("talker")
    r = request(P.ADVERTISE, new_req().string("/").string("chatter").string("std_msgs/String")
                .string("992ce8a1687cec8c8bd883ec73ca41d1").string("string data\n").u32(1000).u8(0)
                .u8(0))
    pub = r.u32()
    count = 0
    start = state["now"]
    while state["ok"] and count < 5:
        log(f"hello world {count}")
        send(P.PUBLISH, P.Writer().u32(pub).blob(string_bytes(f"hello world {count}"))
             .payload())
        r = request(P.SLEEP_UNTIL, new_req().u8(0).i64(start + (count + 1) * 100_000_000))
        count += 1
    print("talker done", flush=True)


def listener() -> None:
    hello("listener")

    def heard(what: int, r: P.Reader) -> None:
        _caller, _t = r.string(), r.i64()
        data = r.blob()
        log("I heard: [" + data[4:].decode() + "]")

    r = request(P.SUBSCRIBE, new_req().string("/").string("chatter").string("std_msgs/String")
                .string("992ce8a1687cec8c8bd883ec73ca41d1").u32(1000))
    callbacks[r.u32()] = heard
    request(P.SPIN, new_req())


def server() -> None:
    hello("add_two_ints_server")

    def add(what: int, r: P.Reader) -> tuple[int, bytes]:
        _caller = r.string()
        a, b = struct.unpack("<qq", r.blob())
        log(f"request: x={a}, y={b}")
        return 1, struct.pack("<q", a + b)

    r = request(P.ADVERTISE_SERVICE, new_req().string("/").string("add_two_ints")
                .string("roscpp_tutorials/TwoInts").string("6a2e34150c00229791cc89ff309fff21")
                .string("roscpp_tutorials/TwoIntsRequest").string("roscpp_tutorials/TwoIntsResponse"))
    callbacks[r.u32()] = add
    request(P.SPIN, new_req())


def client() -> None:
    hello("add_two_ints_client")
    request(P.WAIT_FOR_SERVICE, new_req().string("/").string("add_two_ints").i64(-1))
    r = request(P.CALL, new_req().string("/").string("add_two_ints").string("roscpp_tutorials/TwoInts")
                .string("6a2e34150c00229791cc89ff309fff21").blob(struct.pack("<qq", 3, 4)).u8(0))
    ok = r.u8()
    log(f"Sum: {struct.unpack('<q', r.blob())[0]}" if ok else "Failed to call service")


def thrower() -> None:
    """A subscriber callback that throws: the exception leaves ros::spin(), the node exits 3."""
    hello("thrower")

    def boom(what: int, r: P.Reader) -> tuple[int, bytes]:
        return 2, b"std::runtime_error: boom"

    r = request(P.SUBSCRIBE, new_req().string("/").string("chatter").string("std_msgs/String")
                .string("992ce8a1687cec8c8bd883ec73ca41d1").u32(10))
    callbacks[r.u32()] = boom
    try:
        request(P.SPIN, new_req())
    except RuntimeError as exc:
        print("spin raised:", exc, flush=True)
        sys.exit(3)


def garbage() -> None:
    """Publishes bytes that are no std_msgs/String (a length past the end)."""
    hello("garbage")
    r = request(P.ADVERTISE, new_req().string("/").string("chatter").string("std_msgs/String")
                .string("992ce8a1687cec8c8bd883ec73ca41d1").string("string data\n").u32(10)
                .u8(0).u8(0))
    send(P.PUBLISH, P.Writer().u32(r.u32()).blob(b"\xff\xff\xff\x7f").payload())
    request(P.SPIN, new_req())


def spinner() -> None:
    """A node that never hands back (the watchdog's case)."""
    hello("spinner")
    while True:
        pass


def crash() -> None:
    hello("crash")
    os.kill(os.getpid(), 11)


SCENARIOS = {"garbage": garbage, "thrower": thrower, "talker": talker, "listener": listener, "server": server, "client": client,
             "spinner": spinner, "crash": crash}

if __name__ == "__main__":
    SCENARIOS[sys.argv[1]]()
