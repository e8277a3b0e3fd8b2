"""Waiting on the graph: ``wait_for_message`` as an event (rospy.wait_for_message)."""

from __future__ import annotations

from typing import TYPE_CHECKING

import simpy

from ddes.errors import DdesTypeError, ROSException
from ddes.time.rospy_calls import REQUIRED, arg_text, call_text, is_node_like, missing_node
from ddes.time.units import DurationLike, duration_to_ns

if TYPE_CHECKING:
    from ddes.graph.node import Node
    from ddes.msg.message import MessageLike

__all__ = ["wait_for_message"]


def wait_for_message(node: Node, topic: str, data_class: type[MessageLike] = REQUIRED,
                     timeout: DurationLike | None = None) -> simpy.Event:
    """Event whose value is the next message on ``topic``.

    A temporary subscriber is created and removed once a message arrives.
    With ``timeout`` (ROS time of the node) the event fails with
    ``ROSException("timeout exceeded while waiting for message on topic ...")``,
    rospy's text (the topic as given, not resolved).  A subscription the node already has
    on the topic is shared (rospy's one subscription per topic and node): the next message
    it hears, or its latched one at once.
    """
    from ddes.graph.topics import Subscriber

    if not is_node_like(node):
        if not isinstance(node, str):
            raise DdesTypeError(f"ddes.wait_for_message(node, topic, data_class) needs a node "
                                f"first, got {node!r}")
        # rospy.wait_for_message(topic, topic_type, timeout): shifted one place left
        args: list[object] = [node, topic] + ([data_class] if data_class is not REQUIRED else [])
        kwargs: dict[str, object] = {"timeout": timeout} if timeout is not None else {}
        inner = ", ".join([arg_text(a) for a in args]
                          + [f"{k}={arg_text(v)}" for k, v in kwargs.items()])
        raise missing_node(call_text("ddes.wait_for_message", args, kwargs),
                           f"msg = yield node.wait_for_message({inner})    # in the node's process")

    env = node.world.env
    result = env.event()
    made: list[Subscriber[type[MessageLike]]] = []

    def got(msg: MessageLike) -> None:
        if not result.triggered:
            if made:
                made[0].unregister()
            result.succeed(msg)

    # a latched message of a subscription the node already has arrives in the constructor
    sub = Subscriber(node, topic, data_class, got, queue_size=1, internal=True)
    made.append(sub)
    if result.triggered:
        sub.unregister()
        return result
    if timeout is not None:
        ns = duration_to_ns(timeout, "timeout")
        start = node.clock.now_ns()
        expiry = node.clock.wait_until(start + ns)

        def expire(_ev: simpy.Event) -> None:
            if not result.triggered:
                sub.unregister()
                result.fail(ROSException(  # rospy's text names the topic as given
                    f"timeout exceeded while waiting for message on topic {topic}"))

        expiry.callbacks.append(expire)
    return result
