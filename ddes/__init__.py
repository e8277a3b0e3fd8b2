"""ddes: a deterministic discrete-event testbed and teaching kit for ROS 1.

Everything runs on a SimPy kernel in simulated time (integer nanoseconds):
same scenario + same seed = same trace, byte for byte.  One import gives a
lecture cell every name it needs::

    import ddes
    world = ddes.World(seed=1)
    node = world.create_node("talker")
    pub = ddes.Publisher(node, "chatter", ddes.get_message_class("std_msgs/String"),
                         queue_size=10)
"""

from ddes import errors
from ddes._version import __version__
from ddes.actionlib import (
    ActionClient,
    ActionServer,
    GoalStatus,
    SimpleActionClient,
    SimpleActionServer,
    plot_goals,
)
from ddes.errors import (
    DdesError,
    ROSException,
    ROSInitException,
    ROSInterruptException,
    ROSSerializationException,
    ROSTimeMovedBackwardsException,
    ServiceException,
    ServiceTimeout,
)
from ddes.graph.timer import Timer, TimerEvent
from ddes.graph.topics import AnyMsg, Publisher, Subscriber
from ddes.graph.waiting import wait_for_message
from ddes.kernel.trace import Trace, TraceEvent
from ddes.msg import get_message_class, get_service_class
from ddes.rosbag import Bag, Player, Recorder
from ddes.services import Service, ServiceClient, ServiceProxy, wait_for_service
from ddes.time import (
    Duration,
    DurationLike,
    Rate,
    RoscppRate,
    Time,
    TimeLike,
    WallDuration,
    WallRate,
    WallTime,
    duration_sleep,
    sleep,
)
from ddes.world import Console, Node, World

__all__ = [
    "ActionClient",
    "ActionServer",
    "AnyMsg",
    "Bag",
    "Console",
    "DdesError",
    "Duration",
    "DurationLike",
    "GoalStatus",
    "Node",
    "Player",
    "Publisher",
    "ROSException",
    "ROSInitException",
    "ROSInterruptException",
    "ROSSerializationException",
    "ROSTimeMovedBackwardsException",
    "Rate",
    "Recorder",
    "RoscppRate",
    "Service",
    "ServiceClient",
    "ServiceException",
    "ServiceProxy",
    "ServiceTimeout",
    "SimpleActionClient",
    "SimpleActionServer",
    "Subscriber",
    "Time",
    "TimeLike",
    "Timer",
    "TimerEvent",
    "Trace",
    "TraceEvent",
    "WallDuration",
    "WallRate",
    "WallTime",
    "World",
    "__version__",
    "duration_sleep",
    "errors",
    "get_message_class",
    "get_service_class",
    "plot_goals",
    "sleep",
    "wait_for_message",
    "wait_for_service",
]
