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

from typing import TYPE_CHECKING

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

#: rospy's module functions, which ddes has on the node or the world (there is no global
#: node): the ddes code to write instead of each.
_ROSPY_FUNCTIONS: dict[str, tuple[str, ...]] = {
    "init_node": ("world = ddes.World(seed=0)",
                  'node = world.create_node("my_node")    # anonymous=, argv=, use_sim_time= too',
                  "node.process(main(node))    # main is a generator: yield node.sleep(1.0) ...",
                  "world.run(until=10.0)    # ten simulated seconds"),
    "spin": ("world.run(until=10.0)    # callbacks run while the world runs",
             "yield node.spin()    # or, in a node's process: wait until the node shuts down"),
    "spin_once": ("yield node.spin_once()    # a node made with spinner=\"manual\"",),
    "get_time": ("node.get_time()",),
    "get_rostime": ("node.get_rostime()    # or ddes.Time.now(node)",),
    "is_shutdown": ("node.is_shutdown()",),
    "signal_shutdown": ("node.signal_shutdown(reason)",),
    "on_shutdown": ("node.on_shutdown(hook)    # hook(reason)",),
    "get_name": ("node.get_name()",),
    "get_caller_id": ("node.get_name()",),
    "get_namespace": ("node.get_namespace()",),
    "resolve_name": ("node.resolve_name(name)",),
    "remap_name": ("node.resolve_name(name)",),
    "myargv": ("node.argv    # the node's command line without ROS arguments",),
    "get_param_cached": ("node.get_param(name)",),
    "get_published_topics": ("world.master.get_published_topics()",),
    "get_master": ("world.master",),
}
for _name in ("get_param", "set_param", "has_param", "delete_param", "search_param",
              "get_param_names"):
    _ROSPY_FUNCTIONS[_name] = (f"node.{_name}(...)",)
for _level in ("debug", "info", "warn", "err", "fatal"):
    for _suffix in ("", "_throttle", "_once"):
        _ROSPY_FUNCTIONS[f"log{_level}{_suffix}"] = (f"node.log{_level}{_suffix}(...)",)
    _ROSPY_FUNCTIONS[f"log{_level}_throttle_identical"] = (
        f"node.log{_level}_throttle(period, ...)    # ddes has no _throttle_identical",)
del _name, _level, _suffix

if not TYPE_CHECKING:  # type checkers report these names as missing, as they are
    def __getattr__(name: str) -> object:
        """``ddes.init_node`` and the other rospy functions: say what to write in ddes."""
        lines = _ROSPY_FUNCTIONS.get(name)
        message = f"module 'ddes' has no attribute {name!r}"
        if lines is None:
            raise AttributeError(message, name=name)
        code = "".join(f"\n    {line}" for line in lines)
        from ddes.time.rospy_calls import COMPAT_HINT, NODE_HINT

        raise errors.NoGlobalFunctionError(
            f"{message}: rospy.{name} works on rospy's one global node, and ddes has none "
            f"(there is no rospy.init_node); a ddes world holds many nodes. Write:{code}"
            + ("" if name == "init_node" else f"\n{NODE_HINT}") + f"\n{COMPAT_HINT}",
            name=name)
