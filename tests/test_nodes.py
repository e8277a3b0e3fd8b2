"""Node types started by package and name (ddes.nodes)."""

from __future__ import annotations

from pathlib import Path

import pytest

import ddes
from ddes.nodes import NodeTypeNotFound, start_node
from ddes.rospack import RosPack

NODES_PY = '''
from ddes.nodes import NodeType

def counter(node):
    for _ in range(3):
        yield node.sleep(0.1)
    return 7

def crasher(node):
    yield node.sleep(0.1)
    raise RuntimeError("boom")

def spinner(node):
    node.create_timer(0.5, lambda e: None)

NODES = {"counter": NodeType(counter, name="counter"),
         "crasher": NodeType(crasher, name="crasher"),
         "spinner": NodeType(spinner, name="spinner")}
'''


@pytest.fixture
def rospack(tmp_path: Path) -> RosPack:
    pkg = tmp_path / "mypkg"
    pkg.mkdir()
    (pkg / "package.xml").write_text("<package><name>mypkg</name></package>")
    (pkg / "nodes.py").write_text(NODES_PY)
    return RosPack([tmp_path], use_env=False, bundled=False)


def test_generator_main_exits_with_code(world: ddes.World, rospack: RosPack) -> None:
    node = start_node(world, "mypkg", "counter", rospack=rospack)
    spin = start_node(world, "mypkg", "spinner", rospack=rospack, name="renamed")
    world.run(until=1)
    assert node.is_shutdown() and not spin.is_shutdown() and spin.name == "/renamed"
    exits = world.trace.filter(kind="node.exit")
    assert [(e.source, e.details["code"]) for e in exits] == [("/counter", 7)]


def test_crashing_main_is_reported(world: ddes.World, rospack: RosPack) -> None:
    world.raise_callback_errors = False
    node = start_node(world, "mypkg", "crasher", rospack=rospack)
    world.run(until=1)
    exits = world.trace.filter(kind="node.exit")
    assert node.is_shutdown()
    assert exits[0].details == {"code": 1, "error": "RuntimeError: boom"}


def test_unknown_node_type(world: ddes.World, rospack: RosPack) -> None:
    with pytest.raises(NodeTypeNotFound, match="counter, crasher, spinner"):
        start_node(world, "mypkg", "nope", rospack=rospack)

