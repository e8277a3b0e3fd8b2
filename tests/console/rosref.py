"""Scripts that run real ROS 1 tools (under the system Python) on a graph described as JSON.

The tools talk to a master over XML-RPC; here ``rosgraph.Master`` is replaced
by a fake answering from the JSON, so their own formatting functions print
what they would print for the same graph.
"""

from __future__ import annotations

import json
from typing import Any

from ddes.console.toolkit import node_uri
from ddes.graph.world import World

FAKE_MASTER = r'''
import contextlib, io, json, sys
import rosgraph
STATE = json.loads(sys.stdin.read())
class FakeMaster:
    def __init__(self, *args, **kwargs):
        pass
    def getSystemState(self):
        return STATE["state"]
    def getTopicTypes(self):
        return STATE["types"]
    def getPublishedTopics(self, subgraph):
        return [[t, ty] for t, ty in STATE["types"] if t in STATE["published"]]
    def lookupNode(self, name):
        return STATE["uris"][name]
rosgraph.Master = FakeMaster
def capture(fn, *args, **kwargs):
    buf = io.StringIO()
    with contextlib.redirect_stdout(buf):
        fn(*args, **kwargs)
    return buf.getvalue()
'''


def graph_json(world: World) -> str:
    """The master's state of ``world`` as the fake master serves it."""
    pubs, subs, srvs = world.master.get_system_state()
    nodes = sorted({n for part in (pubs, subs, srvs) for _, ns in part for n in ns})
    return json.dumps({
        "state": [pubs, subs, srvs],
        "types": world.master.get_topic_types(),
        "published": [t for t, _ in pubs],
        "uris": {n: node_uri(n) for n in nodes},
    })


def run_with_master(ros_python: Any, world: World, body: str) -> str:
    """Run ``body`` (which prints its result) under real ROS with the world's graph."""
    return str(ros_python(FAKE_MASTER + body, stdin=graph_json(world)))
