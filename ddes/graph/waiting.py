"""Waiting on the graph: ``wait_for_message`` as an event (rospy.wait_for_message)."""

from __future__ import annotations

from typing import TYPE_CHECKING

import simpy

from ddes.errors import ROSException
from ddes.time.units import DurationLike, duration_to_ns

if TYPE_CHECKING:
    from ddes.graph.node import Node
    from ddes.msg.message import MessageLike

__all__ = ["wait_for_message"]


def wait_for_message(node: Node, topic: str, data_class: type[MessageLike],
                     timeout: DurationLike | None = None) -> simpy.Event:
    """Event whose value is the next message on ``topic``.

    A temporary subscriber is created and removed once a message arrives.
    With ``timeout`` (ROS time of the node) the event fails with
    ``ROSException("timeout exceeded while waiting for message on topic ...")``,
    rospy's text.
    """
    from ddes.graph.topics import Subscriber

    env = node.world.env
    result = env.event()
    resolved = node.resolve_name(topic)

    def got(msg: MessageLike) -> None:
        if not result.triggered:
            sub.unregister()
            result.succeed(msg)

    sub = Subscriber(node, topic, data_class, got, queue_size=1, internal=True)
    if timeout is not None:
        ns = duration_to_ns(timeout, "timeout")
        start = node.clock.now_ns()
        expiry = node.clock.wait_until(start + ns)

        def expire(_ev: simpy.Event) -> None:
            if not result.triggered:
                sub.unregister()
                result.fail(ROSException(
                    f"timeout exceeded while waiting for message on topic {resolved}"))

        expiry.callbacks.append(expire)
    return result
