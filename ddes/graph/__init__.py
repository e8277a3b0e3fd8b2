"""The ROS graph on the kernel: the World, nodes, the callback runner, timers,
topics and their links, the master, names, parameters and rosout."""

from ddes.graph.callbacks import CallbackQueue
from ddes.graph.node import Node
from ddes.graph.timer import Timer, TimerEvent
from ddes.graph.topics import AnyMsg, Publisher, Subscriber
from ddes.graph.waiting import wait_for_message
from ddes.graph.world import World

__all__ = [
    "AnyMsg",
    "CallbackQueue",
    "Node",
    "Publisher",
    "Subscriber",
    "Timer",
    "TimerEvent",
    "World",
    "wait_for_message",
]
