"""ddes: a deterministic discrete-event testbed and teaching kit for ROS 1.

Everything runs on a SimPy kernel in simulated time (integer nanoseconds):
same scenario + same seed = same trace, byte for byte.
"""

from ddes import errors
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
from ddes.graph.node import Node
from ddes.kernel.trace import Trace, TraceEvent
from ddes.kernel.world import World
from ddes.msg import get_message_class, get_service_class
from ddes.rosbag.bag import Bag
from ddes.services import Service, ServiceClient, ServiceProxy, wait_for_service
from ddes.time import (
    Duration,
    Rate,
    RoscppRate,
    Time,
    Timer,
    TimerEvent,
    WallDuration,
    WallRate,
    WallTime,
    duration_sleep,
    sleep,
)

__version__ = "0.1.0"

__all__ = [
    "Bag",
    "DdesError",
    "Duration",
    "Node",
    "ROSException",
    "ROSInitException",
    "ROSInterruptException",
    "ROSSerializationException",
    "ROSTimeMovedBackwardsException",
    "Rate",
    "RoscppRate",
    "Service",
    "ServiceClient",
    "ServiceException",
    "ServiceProxy",
    "ServiceTimeout",
    "Time",
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
    "sleep",
    "wait_for_service",
]
