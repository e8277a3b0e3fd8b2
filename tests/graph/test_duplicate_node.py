"""A second node with a name already in use shuts the first down, as rosmaster and rospy do.

rosmaster (``registrations.py``, ``_register_node_api``) calls the old node's
``shutdown("/master", "[/name] Reason: new node registered with same name")``;
rospy (``impl/masterslave.py``, ``ROSHandler.shutdown``) prints ``shutdown
request: <msg>`` and signals shutdown with ``external shutdown request from
[/master]: [<msg>]``; roscpp logs two WARN lines.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import pytest

import ddes

from .rosmaster_script import MASTER

MSG = "[/dup] Reason: new node registered with same name"
REASON = f"external shutdown request from [/master]: [{MSG}]"


def _world_printing() -> tuple[ddes.World, list[str]]:
    world = ddes.World(seed=0)
    lines: list[str] = []
    world.log_output = lambda line, level: lines.append(line)
    return world, lines


def test_the_old_rospy_node_prints_rospys_line_and_shuts_down() -> None:
    world, lines = _world_printing()
    first = world.create_node("dup")
    reasons: list[str] = []
    first.on_shutdown(reasons.append)
    second = world.create_node("dup")
    assert first.is_shutdown() and not second.is_shutdown()
    assert world.nodes["/dup"] is second
    assert lines == [f"shutdown request: {MSG}"]
    assert reasons == [REASON]
    assert world.trace.filter(kind="node.shutdown")[0].details["reason"] == REASON


def test_the_old_roscpp_node_logs_roscpps_warnings() -> None:
    world, lines = _world_printing()
    world.create_node("dup", log_style="roscpp")
    world.create_node("dup")
    assert lines == ["[ WARN] [0.000000000]: Shutdown request received.",
                     f"[ WARN] [0.000000000]: Reason given for shutdown: [{MSG}]"]


def test_a_shutdown_request_without_a_message() -> None:
    world, lines = _world_printing()
    node = world.create_node("n")
    node.shutdown_request("/rosnode")
    node.shutdown_request("/rosnode", "again")  # a shut-down node ignores it
    assert lines == ["shutdown requst"]  # rospy's spelling
    assert world.trace.filter(kind="node.shutdown")[0].details["reason"] == \
        "external shutdown request from [/rosnode]: []"


def test_nodes_of_other_names_and_namespaces_live_on() -> None:
    world, lines = _world_printing()
    a = world.create_node("dup", namespace="/a")
    b = world.create_node("dup")
    world.create_node("dup", namespace="/b")
    assert not a.is_shutdown() and not b.is_shutdown() and lines == []


ROSPY_TWO_PROCESSES = MASTER + r'''
import json, sys, time
NODE = r"""
import sys, time, rospy
rospy.init_node("dup", disable_signals=True)
rospy.core.add_preshutdown_hook(lambda reason: print("hook reason: " + reason, flush=True))
print("started", flush=True)
deadline = time.time() + 30
while not rospy.is_shutdown() and time.time() < deadline:
    time.sleep(0.05)
print("shut down" if rospy.is_shutdown() else "still running", flush=True)
"""
first = start_process([sys.executable, "-c", NODE])
assert first.stdout.readline().strip() == "started"
second = start_process([sys.executable, "-c", NODE])
assert second.stdout.readline().strip() == "started"
out, err = first.communicate(timeout=60)
second_alive = second.poll() is None
print(json.dumps({"out": out.splitlines(), "second_alive": second_alive}))
'''


@pytest.mark.ros
def test_agrees_with_two_rospy_processes(ros_python: Callable[..., Any]) -> None:
    theirs = ros_python(ROSPY_TWO_PROCESSES, as_json=True, timeout=120)
    assert theirs["second_alive"]
    assert theirs["out"] == [f"shutdown request: {MSG}", f"hook reason: {REASON}", "shut down"]
    world, lines = _world_printing()
    first = world.create_node("dup")
    first.on_shutdown(lambda reason: lines.append(f"hook reason: {reason}"))
    second = world.create_node("dup")
    assert first.is_shutdown() and not second.is_shutdown()
    # ddes prints rospy's line after the shutdown hooks ran (docs/graph.md)
    assert sorted(lines) == sorted(theirs["out"][:2])
