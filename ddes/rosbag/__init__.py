"""rosbag for ddes: bags in memory, ROS bag v2.0 and MCAP files, record, play, info, filter.

Quick start::

    from ddes.rosbag import Bag
    from ddes import Time
    from ddes.msg import get_message_class

    String = get_message_class("std_msgs/String")
    with Bag("demo.bag", "w") as bag:              # written as demo.bag.active, then renamed
        bag.write("/chatter", String(data="hi"), Time(1, 0))
    for topic, msg, t in Bag("demo.bag").read_messages():
        print(topic, msg.data, t.to_sec())

:class:`Recorder` and :class:`Player` are ``rosbag record`` and ``rosbag
play`` as nodes of a world, on simulated time.  See docs/bags.md.
"""

from ddes.rosbag.bag import (
    Bag,
    BagMessage,
    BagMessageWithConnectionHeader,
    Compression,
    CompressionTuple,
    TopicTuple,
    TypesAndTopicsTuple,
)
from ddes.rosbag.ops import filter_bag
from ddes.rosbag.player import Player
from ddes.rosbag.recorder import Recorder, bag_filename
from ddes.rosbag.records import ConnectionInfo

__all__ = [
    "Bag",
    "BagMessage",
    "BagMessageWithConnectionHeader",
    "Compression",
    "CompressionTuple",
    "ConnectionInfo",
    "Player",
    "Recorder",
    "TopicTuple",
    "TypesAndTopicsTuple",
    "bag_filename",
    "filter_bag",
]
