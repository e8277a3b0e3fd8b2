"""The world side of the external-node protocol, driven by a Python stand-in for a C++ node
(tests/roscpp/fake_node.py speaks the frames as ddes's roscpp library does)."""

from __future__ import annotations

import os
import sys
from pathlib import Path

import ddes
from ddes.roscpp.host import ExternalNode

FAKE = Path(__file__).with_name("fake_node.py")
ROOT = str(Path(ddes.__file__).resolve().parents[1])


def _node(world: ddes.World, scenario: str, out: list[str], **kw: object) -> ExternalNode:
    env = dict(os.environ, DDES_FAKE_NODE_PATH=ROOT)
    host = ExternalNode(world, [sys.executable, str(FAKE), scenario], env=env,
                        print_line=lambda t, e: out.append(("E " if e else "") + t),
                        **kw)  # type: ignore[arg-type]
    host.start()
    return host


def _logs(world: ddes.World) -> list[str]:
    lines: list[str] = []
    world.log_output = lambda line, _level: lines.append(line)
    return lines


def test_a_talker_and_a_listener_talk_in_lockstep() -> None:
    world = ddes.World(seed=3)
    lines = _logs(world)
    out: list[str] = []
    listener = _node(world, "listener", out)
    talker = _node(world, "talker", out)
    world.run(until=1.0)
    assert talker.exit_code == 0 and "talker done" in out
    heard = [line for line in lines if "I heard" in line]
    # the first message leaves before the connection is made, as in ROS
    assert heard == [f"[ INFO] [0.{i}00000000]: I heard: [hello world {i}]" for i in range(1, 5)]
    said = [line for line in lines if "]: hello world" in line]
    assert said[0] == "[ INFO] [0.000000000]: hello world 0"
    assert listener.node is not None and listener.node.name == "/listener"
    listener.close()


def test_the_digest_is_the_same_every_run() -> None:
    digests = []
    for _ in range(2):
        world = ddes.World(seed=5)
        world.log_output = False
        hosts = [_node(world, "listener", []), _node(world, "talker", [])]
        world.run(until=1.0)
        digests.append(world.digest())
        for h in hosts:
            h.close()
    assert digests[0] == digests[1]


def test_a_python_node_hears_the_external_talker() -> None:
    world = ddes.World()
    world.log_output = False
    got: list[str] = []
    py = world.create_node("py_listener")
    py.subscribe("chatter", world.messages.get_message_class("std_msgs/String"),
                 lambda m: got.append(m.data), queue_size=10)
    _node(world, "talker", [])
    world.run(until=1.0)
    assert got == [f"hello world {i}" for i in range(1, 5)]


def test_a_service_between_two_external_nodes() -> None:
    world = ddes.World()
    lines = _logs(world)
    server = _node(world, "server", [])
    client = _node(world, "client", [])
    world.run(until=1.0)
    assert client.exit_code == 0
    assert any(line.endswith("]: request: x=3, y=4") for line in lines)
    assert any(line.endswith("]: Sum: 7") for line in lines)
    server.close()


def test_a_node_that_never_hands_back_is_stopped_with_a_verdict() -> None:
    world = ddes.World()
    world.log_output = False
    out: list[str] = []
    host = _node(world, "spinner", out, step_wall_s=0.5)
    world.run(until=1.0)
    assert "did not hand back within 0.5 s" in host.verdict
    assert host.exit_code == -9
    assert any("did not hand back" in line for line in out)
    assert host.node is not None and host.node.is_shutdown()


def test_a_crash_is_a_node_death_with_roslaunchs_text() -> None:
    world = ddes.World()
    world.log_output = False
    host = _node(world, "crash", [])
    other = world.create_node("other")
    world.run(until=1.0)
    assert host.exit_code == -11
    assert host.death_text().startswith(f"process has died [pid {host.pid}, exit code -11, cmd ")
    assert not other.is_shutdown()
    assert host.node is not None and host.node.is_shutdown()


def test_an_exception_in_a_callback_leaves_spin_as_in_roscpp() -> None:
    world = ddes.World()
    world.log_output = False
    out: list[str] = []
    host = _node(world, "thrower", out)
    pub = world.create_node("py").advertise(
        "chatter", world.messages.get_message_class("std_msgs/String"), queue_size=10)
    world.run(until=0.1)
    pub.publish(data="x")
    world.run(until=0.2)
    assert "spin raised: interrupted by an exception in a callback" in out
    assert host.exit_code == 3


def test_bytes_that_are_no_message_end_the_process_not_the_world() -> None:
    world = ddes.World()
    world.log_output = False
    out: list[str] = []
    host = _node(world, "garbage", out)
    other = world.create_node("other")
    world.run(until=1.0)
    assert host.verdict.startswith("protocol error: PUBLISH of std_msgs/String: cannot deserialize")
    assert host.node is not None and host.node.is_shutdown() and not other.is_shutdown()
