"""``rosnode``: list, info, kill, ping, against the formats of real rosnode."""

from __future__ import annotations

import json
from typing import Any

import pytest

from ddes.console.shell import Console
from ddes.console.toolkit import node_pid, node_uri

from .rosref import run_with_master


def test_list_variants(chat: Console) -> None:
    assert chat.run("rosnode list") == "/listener_2\n/rosout\n/talker_1\n"
    assert chat.run("rosnode list -u") == "".join(
        node_uri(n) + "\n" for n in ("/listener_2", "/rosout", "/talker_1"))
    assert chat.run("rosnode list -a").splitlines()[1] == f"{node_uri('/rosout')} \t/rosout"
    chat.run("rosrun --quiet rospy_tutorials talker __ns:=/robot &")
    assert chat.run("rosnode list /robot") == "/robot/talker_3\n"


def test_info_layout(chat: Console) -> None:
    chat.run("sleep 0.01")
    assert chat.run("rosnode info /talker_1") == (
        "-" * 80 + "\n"
        "Node [/talker_1]\n"
        "Publications: \n"
        " * /chatter [std_msgs/String]\n"
        " * /rosout [rosgraph_msgs/Log]\n"
        "\n"
        "Subscriptions: None\n"
        "\n"
        "Services: None\n"
        "\n"
        "\n"
        f"contacting node {node_uri('/talker_1')} ...\n"
        f"Pid: {node_pid('/talker_1')}\n"
        "Connections:\n"
        " * topic: /rosout\n"
        "    * to: /rosout\n"
        "    * direction: outbound\n"
        "    * transport: TCPROS\n"
        " * topic: /chatter\n"
        "    * to: /listener_2\n"
        "    * direction: outbound\n"
        "    * transport: TCPROS\n"
        "\n"
    )
    quiet = chat.run("rosnode info -q rosout")
    assert quiet.splitlines()[1:8] == [
        "Node [/rosout]", "Publications: ", " * /rosout_agg [rosgraph_msgs/Log]", "",
        "Subscriptions: ", " * /rosout [rosgraph_msgs/Log]", ""]
    assert "contacting" not in quiet


def test_kill(chat: Console) -> None:
    assert chat.run("rosnode kill /talker_1") == "killing /talker_1\nkilled\n"
    assert chat.run("rosnode list") == "/listener_2\n/rosout\n"
    assert chat.run("jobs") == (
        "[1]  Done                    rosrun --quiet rospy_tutorials talker\n"
        "[2]  Running                 rosrun --quiet rospy_tutorials listener &\n")
    assert chat.run("jobs") == "[2]  Running                 rosrun --quiet rospy_tutorials listener &\n"
    assert chat.run("rosnode kill -a") == "killing:\n * /listener_2\n * /rosout\nkilled\n"
    assert chat.run("rosnode list") == "\n"


def test_ping(chat: Console) -> None:
    out = chat.run("rosnode ping -c 3 talker_1")
    uri = node_uri("/talker_1")
    assert out == ("rosnode: node is [/talker_1]\n"
                   "pinging /talker_1 with a timeout of 3.0s\n"
                   + f"xmlrpc reply from {uri}\ttime=1.000000ms\n" * 3
                   + "ping average: 1.000000ms\n")
    assert chat.world.now == 2_001_000_000
    out = chat.run("rosnode ping --duration 1.5 /talker_1")
    assert out.count("xmlrpc reply") == 2


def test_ping_all(chat: Console) -> None:
    out = chat.run("rosnode ping --all")
    assert out.startswith("Will ping the following nodes: \n * /listener_2\n * /rosout\n"
                          " * /talker_1\n\n")
    assert out.count("xmlrpc reply from") == 3


@pytest.mark.parametrize("line, text", [
    ("rosnode kill", "give the node(s) to kill"),
    ("rosnode ping /talker_1", "runs until Ctrl+C"),
    ("rosnode info", "You must specify at least one node name"),
    ("rosnode frob", "unknown command 'rosnode frob'"),
])
def test_errors(chat: Console, line: str, text: str) -> None:
    result = chat.execute(line)
    assert result.code == 1
    assert result.err.startswith("ERROR: ") and text in result.err
    assert result.err.count("\n") == 1
    assert "/talker_1" in chat.world.nodes


def test_usage(console: Console) -> None:
    result = console.execute("rosnode")
    assert result.code == 64
    assert result.out.startswith("rosnode is a command-line tool for printing information about "
                                 "ROS Nodes.\n\nCommands:\n\trosnode ping\ttest connectivity")


_ROS_NODE = r'''
import rosnode
print(json.dumps({
    "talker": rosnode.get_node_info_description("/talker_1"),
    "rosout": rosnode.get_node_info_description("/rosout"),
    "listener": rosnode.get_node_info_description("/listener_2"),
}))
'''


@pytest.mark.ros
def test_info_matches_rosnode(chat: Console, ros_python: Any) -> None:
    chat.run("rostopic pub /flag std_msgs/Bool true &")
    theirs = json.loads(run_with_master(ros_python, chat.world, _ROS_NODE))
    for key, name in (("talker", "/talker_1"), ("rosout", "/rosout"),
                      ("listener", "/listener_2")):
        ours = chat.run(f"rosnode info -q {name}")
        assert ours == "-" * 80 + "\n" + theirs[key] + "\n"
