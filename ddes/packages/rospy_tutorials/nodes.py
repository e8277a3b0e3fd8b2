"""Node types of ``rospy_tutorials`` (``rosrun rospy_tutorials talker``).

Each mirrors the script of the same name in ros/ros_tutorials
(``rospy_tutorials/001_talker_listener/``): same node name (anonymous, as
``rospy.init_node(..., anonymous=True)``), same topics, same log texts.
"""

from __future__ import annotations

from collections.abc import Generator
from typing import Any

from ddes.msg import get_message_class
from ddes.nodes import NodeType


def talker(node: Any) -> Generator[Any, Any, None]:
    """Publish ``hello world <rospy.get_time()>`` on ``chatter`` at 10 Hz, logging each."""
    string = get_message_class("std_msgs/String")
    pub = node.advertise("chatter", string, queue_size=10)
    rate = node.create_rate(10)
    while not node.is_shutdown():
        hello_str = "hello world %s" % node.get_time()
        node.loginfo(hello_str)
        pub.publish(hello_str)
        yield rate.sleep()


def listener(node: Any) -> None:
    """Log ``<caller id>I heard <data>`` for every message on ``chatter`` (then spin)."""
    string = get_message_class("std_msgs/String")

    def callback(data: Any) -> None:
        node.loginfo(node.get_name() + "I heard %s", data.data)

    node.subscribe("chatter", string, callback)


NODES: dict[str, NodeType] = {
    "talker": NodeType(talker, name="talker", anonymous=True, doc=talker.__doc__ or ""),
    "listener": NodeType(listener, name="listener", anonymous=True, doc=listener.__doc__ or ""),
}
