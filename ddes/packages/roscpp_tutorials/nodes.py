"""Node types of ``roscpp_tutorials`` (``rosrun roscpp_tutorials talker``).

Each mirrors the C++ tutorial of the same name in ros/ros_tutorials
(``roscpp_tutorials/talker/talker.cpp``, ``listener/listener.cpp``): same
node name (not anonymous), same topics and queue sizes, log lines printed
as roscpp prints them (``[ INFO] [secs.nsecs]: ...``).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from ddes.msg import get_message_class
from ddes.nodes import NodeType
from ddes.services import Service

if TYPE_CHECKING:
    from simpy.events import ProcessGenerator

    from ddes.graph.node import Node
    from ddes.msg.message import Message


def talker(node: Node) -> ProcessGenerator:
    """Publish ``hello world <count>`` on ``chatter`` at 10 Hz, logging each (ROS_INFO)."""
    string = get_message_class("std_msgs/String")
    chatter_pub = node.advertise("chatter", string, queue_size=1000)
    loop_rate = node.create_roscpp_rate(10)
    count = 0
    while not node.is_shutdown():
        msg = string()
        msg.data = f"hello world {count}"
        node.loginfo("%s", msg.data)
        chatter_pub.publish(msg)
        yield loop_rate.sleep()
        count += 1


def listener(node: Node) -> None:
    """Log ``I heard: [<data>]`` for every message on ``chatter`` (then ros::spin())."""
    string = get_message_class("std_msgs/String")

    def chatter_callback(msg: Message) -> None:
        node.loginfo("I heard: [%s]", msg.data)

    node.subscribe("chatter", string, chatter_callback, queue_size=1000)


def add_two_ints_server(node: Node) -> None:
    """Serve ``add_two_ints`` (roscpp_tutorials/TwoInts) with a bool callback (then ros::spin())."""
    from ddes.msg import get_service_class

    def add(req: Message, res: Message) -> bool:
        res.sum = req.a + req.b
        node.loginfo("request: x=%ld, y=%ld", req.a, req.b)
        node.loginfo("  sending back response: [%ld]", res.sum)
        return True

    Service(node, "add_two_ints", get_service_class("roscpp_tutorials/TwoInts"), add,
            style="roscpp")


def _atoll(text: str) -> int:
    """C ``atoll``: the leading integer of ``text`` (0 if none), saturated to int64."""
    import re

    m = re.match(r"\s*([+-]?\d+)", text)
    if m is None:
        return 0
    return max(-(2**63), min(2**63 - 1, int(m.group(1))))


def add_two_ints_client(node: Node) -> ProcessGenerator:
    """``add_two_ints_client X Y``: call ``add_two_ints`` once, log ``Sum: <X+Y>``; exit code 1 on failure."""
    from ddes.msg import get_service_class
    from ddes.services import ServiceClient

    if len(node.argv) != 2:
        node.loginfo("usage: add_two_ints_client X Y")
        return 1
    two_ints = get_service_class("roscpp_tutorials/TwoInts")
    client = ServiceClient(node, "add_two_ints", two_ints)
    request, response = two_ints._request_class(), two_ints._response_class()
    request.a = _atoll(node.argv[0])
    request.b = _atoll(node.argv[1])
    ok = yield client.call(request, response)
    if ok:
        node.loginfo("Sum: %ld", response.sum)
    else:
        node.logerr("Failed to call service add_two_ints")
        return 1
    return 0


NODES: dict[str, NodeType] = {
    "talker": NodeType(talker, name="talker", log_style="roscpp", doc=talker.__doc__ or ""),
    "listener": NodeType(listener, name="listener", log_style="roscpp",
                         doc=listener.__doc__ or ""),
    "add_two_ints_server": NodeType(add_two_ints_server, name="add_two_ints_server",
                                    log_style="roscpp", doc=add_two_ints_server.__doc__ or ""),
    "add_two_ints_client": NodeType(add_two_ints_client, name="add_two_ints_client",
                                    log_style="roscpp", doc=add_two_ints_client.__doc__ or ""),
}
