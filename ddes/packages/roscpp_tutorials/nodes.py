"""Node types of ``roscpp_tutorials`` (``rosrun roscpp_tutorials talker``).

Each mirrors the C++ tutorial of the same name in ros/ros_tutorials
(``roscpp_tutorials/talker/talker.cpp``, ``listener/listener.cpp``): same
node name (not anonymous), same topics and queue sizes, log lines printed
as roscpp prints them (``[ INFO] [secs.nsecs]: ...``).
"""

from __future__ import annotations

from collections.abc import Generator
from typing import Any

from ddes.msg import get_message_class
from ddes.nodes import NodeType


def talker(node: Any) -> Generator[Any, Any, None]:
    """Publish ``hello world <count>`` on ``chatter`` at 10 Hz, logging each (ROS_INFO)."""
    string = get_message_class("std_msgs/String")
    chatter_pub = node.advertise("chatter", string, queue_size=1000)
    loop_rate = node.create_roscpp_rate(10)
    count = 0
    while not node.is_shutdown():
        msg = string()
        msg.data = "hello world %d" % count
        node.loginfo("%s", msg.data)
        chatter_pub.publish(msg)
        yield loop_rate.sleep()
        count += 1


def listener(node: Any) -> None:
    """Log ``I heard: [<data>]`` for every message on ``chatter`` (then ros::spin())."""
    string = get_message_class("std_msgs/String")

    def chatter_callback(msg: Any) -> None:
        node.loginfo("I heard: [%s]", msg.data)

    node.subscribe("chatter", string, chatter_callback, queue_size=1000)


NODES: dict[str, NodeType] = {
    "talker": NodeType(talker, name="talker", log_style="roscpp", doc=talker.__doc__ or ""),
    "listener": NodeType(listener, name="listener", log_style="roscpp",
                         doc=listener.__doc__ or ""),
}
