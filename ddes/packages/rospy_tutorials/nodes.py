"""Node types of ``rospy_tutorials`` (``rosrun rospy_tutorials talker``).

Each mirrors the script of the same name in ros/ros_tutorials
(``rospy_tutorials/001_talker_listener/``): same node name (anonymous, as
``rospy.init_node(..., anonymous=True)``), same topics, same log texts.
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
    """Publish ``hello world <rospy.get_time()>`` on ``chatter`` at 10 Hz, logging each."""
    string = get_message_class("std_msgs/String")
    pub = node.advertise("chatter", string, queue_size=10)
    rate = node.create_rate(10)
    while not node.is_shutdown():
        hello_str = f"hello world {node.get_time()}"
        node.loginfo(hello_str)
        pub.publish(hello_str)
        yield rate.sleep()


def listener(node: Node) -> None:
    """Log ``<caller id>I heard <data>`` for every message on ``chatter`` (then spin)."""
    string = get_message_class("std_msgs/String")

    def callback(data: Message) -> None:
        node.loginfo(node.get_name() + "I heard %s", data.data)

    node.subscribe("chatter", string, callback)


def add_two_ints_server(node: Node) -> None:
    """Serve ``add_two_ints`` (rospy_tutorials/AddTwoInts), logging ``Returning [a + b = sum]``.

    As ``005_add_two_ints/add_two_ints_server``; its ``print`` lines are
    logged with loginfo, so they reach the trace and the console.
    """
    from ddes.msg import get_service_class

    add_two_ints = get_service_class("rospy_tutorials/AddTwoInts")

    def handle(req: Message) -> Message:
        node.loginfo("Returning [%s + %s = %s]", req.a, req.b, (req.a + req.b))
        return add_two_ints._response_class(req.a + req.b)

    Service(node, "add_two_ints", add_two_ints, handle)


def _add_two_ints(node: Node, x: int, y: int) -> ProcessGenerator:
    from ddes.errors import ServiceException
    from ddes.msg import get_service_class
    from ddes.services import ServiceProxy, wait_for_service

    add_two_ints_class = get_service_class("rospy_tutorials/AddTwoInts")
    yield wait_for_service(node, "add_two_ints")
    try:
        add_two_ints = ServiceProxy(node, "add_two_ints", add_two_ints_class)
        node.loginfo("Requesting %s+%s", x, y)
        resp1 = yield add_two_ints(x, y)  # simplified style
        resp2 = yield add_two_ints.call(add_two_ints_class._request_class(x, y))  # formal style
        if not resp1.sum == (x + y):
            raise Exception(f"test failure, returned sum was {resp1.sum}")
        if not resp2.sum == (x + y):
            raise Exception(f"test failure, returned sum was {resp2.sum}")
        return resp1.sum
    except ServiceException as e:
        node.loginfo("Service call failed: %s", e)
        return None


def add_two_ints_client(node: Node) -> ProcessGenerator:
    """``add_two_ints_client [x y]``: wait for ``add_two_ints``, call it twice, log ``x + y = sum``.

    Without arguments x and y are drawn in [-50000, 50000] from the world's
    seeded generator (the script uses ``random``); bad arguments log the usage
    and exit with code 1.  ``print`` lines are logged with loginfo.
    """
    argv = node.argv
    usage = "add_two_ints_client [x y]"
    if len(argv) == 0:
        rng = node.world.rng_for(node.name + ":random")
        x = rng.randint(-50000, 50000)
        y = rng.randint(-50000, 50000)
    elif len(argv) == 2:
        try:
            x = int(argv[0])
            y = int(argv[1])
        except ValueError:
            node.loginfo(usage)
            return 1
    else:
        node.loginfo(usage)
        return 1
    result = yield from _add_two_ints(node, x, y)
    node.loginfo("%s + %s = %s", x, y, result)
    return 0


def param_talker(node: Node) -> ProcessGenerator:
    """Read global, relative, private and default parameters, set some, then publish ``utterance`` at 1 Hz."""
    string = get_message_class("std_msgs/String")
    global_example = node.get_param("/global_example")
    node.loginfo("%s is %s", node.resolve_name("/global_example"), global_example)
    utterance = node.get_param("utterance")
    node.loginfo("%s is %s", node.resolve_name("utterance"), utterance)
    topic_name = node.get_param("~topic_name")
    node.loginfo("%s is %s", node.resolve_name("~topic_name"), topic_name)
    default_param = node.get_param("default_param", "default_value")
    node.loginfo("%s is %s", node.resolve_name("default_param"), default_param)
    gains = node.get_param("gains")
    p, i, d = gains["P"], gains["I"], gains["D"]
    node.loginfo("gains are %s, %s, %s", p, i, d)
    node.loginfo("setting parameters...")
    node.set_param("list_of_floats", [1.0, 2.0, 3.0, 4.0])
    node.set_param("bool_True", True)
    node.set_param("~private_bar", 1 + 2)
    node.set_param("to_delete", "baz")
    node.loginfo("...parameters have been set")
    if node.has_param("to_delete"):
        node.delete_param("to_delete")
        node.loginfo(f"deleted {node.resolve_name('to_delete')} parameter")
    else:
        node.loginfo(f"parameter {node.resolve_name('to_delete')} was already deleted")
    param_name = node.search_param("global_example")
    node.loginfo(f"found global_example parameter under key: {param_name}")
    pub = node.advertise(topic_name, string, queue_size=10)
    while not node.is_shutdown():
        pub.publish(utterance)
        node.loginfo(utterance)
        yield node.sleep(1)


NODES: dict[str, NodeType] = {
    "talker": NodeType(talker, name="talker", anonymous=True, doc=talker.__doc__ or ""),
    "listener": NodeType(listener, name="listener", anonymous=True, doc=listener.__doc__ or ""),
    "add_two_ints_server": NodeType(add_two_ints_server, name="add_two_ints_server",
                                    doc=add_two_ints_server.__doc__ or ""),
    "add_two_ints_client": NodeType(add_two_ints_client, name="add_two_ints_client",
                                    anonymous=True, doc=add_two_ints_client.__doc__ or ""),
}
# The scripts are also installed with their file names (``rosrun rospy_tutorials talker.py``).
NODES["talker.py"] = NODES["talker"]
NODES["listener.py"] = NODES["listener"]
NODES["param_talker"] = NodeType(param_talker, name="param_talker", doc=param_talker.__doc__ or "")
NODES["param_talker.py"] = NODES["param_talker"]
