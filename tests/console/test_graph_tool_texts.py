"""``rosnode`` and ``rostopic`` on unknown names and fields print what the real tools print.

Recorded from Noetic (a rospy talker and listener on a real master):

* ``rosnode info /nope`` prints the empty description block, then ``cannot contact [/nope]:
  unknown node`` on stderr, and goes on to the next node (exit 0; ddes exits 1);
* ``rosnode ping /nope`` prints ``rosnode: node is [/nope]``, then ``cannot ping [/nope]:
  unknown node`` on stderr (exit 0; ddes exits 1);
* ``rosnode kill /nope`` prints ``ERROR: Unknown node(s):`` and `` * /nope`` on stderr, kills
  nothing, exit 1;
* ``rostopic type /chatter/nope`` prints ``unknown topic type [/chatter/nope]``, exit 1.
"""

from __future__ import annotations

import json
from typing import Any

import pytest

from ddes.console.shell import Console

from .rosref import run_with_master

EMPTY_INFO = ("-" * 80 + "\nNode [/nope]\nPublications: None\n\nSubscriptions: None\n\n"
              "Services: None\n\n")


def test_rosnode_info_of_an_unknown_node(chat: Console) -> None:
    result = chat.execute("rosnode info /nope")
    assert (result.code, result.out, result.err) == (
        1, EMPTY_INFO, "cannot contact [/nope]: unknown node\n")
    result = chat.execute("rosnode info -q /nope /talker_1")
    assert result.out.startswith(EMPTY_INFO + "-" * 80 + "\nNode [/talker_1]\nPublications: \n")
    assert (result.code, result.err) == (1, "cannot contact [/nope]: unknown node\n")


def test_rosnode_ping_of_an_unknown_node(chat: Console) -> None:
    result = chat.execute("rosnode ping -c 1 /nope")
    assert (result.code, result.out, result.err) == (
        1, "rosnode: node is [/nope]\n", "cannot ping [/nope]: unknown node\n")


def test_rosnode_kill_of_unknown_nodes_kills_nothing(chat: Console) -> None:
    result = chat.execute("rosnode kill /nope /talker_1 /gone")
    assert (result.code, result.out, result.err) == (
        1, "", "ERROR: Unknown node(s):\n * /nope\n * /gone\n")
    assert "/talker_1" in chat.world.nodes


def test_unknown_node_stops_a_script(chat: Console) -> None:
    code, text = chat.transcript(["rosnode kill /nope", "rosnode list"])
    assert code == 1
    assert text == "$ rosnode kill /nope\nERROR: Unknown node(s):\n * /nope\n"


@pytest.mark.parametrize("line, err", [
    ("rostopic type /chatter/nope", "unknown topic type [/chatter/nope]\n"),
    ("rostopic type /nope", "unknown topic type [/nope]\n"),
])
def test_rostopic_type_of_unknown_fields(chat: Console, line: str, err: str) -> None:
    result = chat.execute(line)
    assert (result.code, result.out, result.err) == (1, "", err)


def test_rostopic_type_find_info(chat: Console) -> None:
    chat.run("sleep 0.5")
    assert chat.run("rostopic type /rosout/header/stamp") == "rosgraph_msgs/Log header/stamp time\n"
    assert chat.run("rostopic type /rosout/topics") == "rosgraph_msgs/Log topics string[]\n"
    assert chat.run("rostopic find std_msgs/String") == "/chatter\n"
    assert chat.run("rostopic find nope/Nope") == "\n"


# -- the real tools, with the world's graph served by a fake master -----------------------------

_ROS_MAIN = r'''
import rosnode, rostopic
class StrictMaster(FakeMaster):
    def lookupNode(self, name):
        if name not in STATE["uris"]:
            raise rosgraph.MasterError("lookupNode: unknown node " + name)
        return STATE["uris"][name]
rosgraph.Master = StrictMaster
results = []
for argv in CASES:
    out, err = io.StringIO(), io.StringIO()
    code = 0
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        try:
            (rosnode.rosnodemain if argv[0] == "rosnode" else rostopic.rostopicmain)(argv)
        except SystemExit as exc:
            code = exc.code or 0
    results.append([code, out.getvalue(), err.getvalue()])
print(json.dumps(results))
'''

_CASES = [
    "rosnode info /nope",
    "rosnode info -q /nope /gone",
    "rosnode ping -c 1 /nope",
    "rosnode kill /nope /talker_1 /gone",
    "rostopic type /chatter",
    "rostopic type /chatter/data",
    "rostopic type /chatter/nope",
    "rostopic type /nope",
    "rostopic type /rosout/header/stamp",
    "rostopic type /rosout/topics",
    "rostopic find std_msgs/String",
    "rostopic find nope/Nope",
]


@pytest.mark.ros
def test_same_text_as_rosnode_and_rostopic(chat: Console, ros_python: Any) -> None:
    chat.run("sleep 0.5")
    script = f"CASES = {json.dumps([c.split() for c in _CASES])}\n" + _ROS_MAIN
    theirs = json.loads(run_with_master(ros_python, chat.world, script))
    for line, (code, out, err) in zip(_CASES, theirs):
        result = chat.execute(line)
        assert (line, result.out, result.err) == (line, out, err)
        # rosnode exits 0 after an unknown node in info/ping; ddes 1, so a script stops there
        assert result.code == (1 if line.startswith(("rosnode info", "rosnode ping")) else code)
