"""Topic statistics: ``/enable_statistics`` makes subscriptions publish ``/statistics``.

rospy's ``rospy.impl.statistics``, step for step on the node's ROS time: when the parameter
``/enable_statistics`` is true as a rospy node's subscription starts, the subscription keeps one
logger per publishing node.  The first message from a publisher makes its logger (and the
logger's ``/statistics`` Publisher, ``queue_size=10``, in the subscribing node); every message
is counted (its arrival time, its header's age and a ``seq`` gap as a dropped message, its
bytes), and at the first arrival more than a publishing period after the last report the
logger publishes a ``rosgraph_msgs/TopicStatistics`` for the window since then and adapts the
period: doubled (up to ``/statistics_window_max_size``, 64 s) while a window holds fewer than
``/statistics_window_min_elements`` (10) messages, halved (down to
``/statistics_window_min_size``, 4 s) while it holds more than
``/statistics_window_max_elements`` (100).  The first period is 1 s.  Subscriptions to
``/clock`` and ``/statistics`` are not measured, as in rospy.

``traffic`` counts what rospy's transport counts (``stat_bytes``): the subscriber's handshake
header once, then each message with its 4-byte length.

Deviations: ddes's own subscribers (``internal``: a simulated clock's ``/clock``,
``wait_for_message``) and roscpp-style nodes keep no statistics.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

from ddes.time.rostime import Duration, Time

if TYPE_CHECKING:
    from ddes.graph.topics import Connection, Publisher, Subscriber
    from ddes.msg.message import MessageClass, MessageLike

__all__ = ["SubscriberStatistics", "handshake_size", "statistics_for"]


def statistics_for(sub: Subscriber[MessageClass]) -> SubscriberStatistics | None:
    """The statistics of the subscription ``sub`` starts, or None (not enabled, not a rospy
    node, a ddes-internal subscriber)."""
    node = sub.node
    if sub._internal or node.client_library != "rospy":
        return None
    params = node.world.master.params
    if not params.get_param("/enable_statistics", False):
        return None
    return SubscriberStatistics(sub)


def handshake_size(fields: dict[str, str]) -> int:
    """Bytes of a TCPROS handshake header with ``fields`` (rospy's
    ``encode_ros_handshake_header``: a length, then each ``key=value`` after its length)."""
    return 4 + sum(4 + len(f"{k}={v}".encode()) for k, v in fields.items())


class SubscriberStatistics:
    """rospy's ``SubscriberStatisticsLogger`` of one subscription: a logger per publisher."""

    def __init__(self, sub: Subscriber[MessageClass]) -> None:
        self.node = sub.node
        self.topic = sub.resolved_name
        get = self.node.world.master.params.get_param
        self.min_elements = get("/statistics_window_min_elements", 10)
        self.max_elements = get("/statistics_window_max_elements", 100)
        self.min_window = get("/statistics_window_min_size", 4)
        self.max_window = get("/statistics_window_max_size", 64)
        self.loggers: dict[str, _ConnectionStatistics] = {}

    def handshake_bytes(self, sub: Subscriber[MessageClass]) -> int:
        """What rospy's subscriber counts at the start of a connection: its own header."""
        cls: Any = sub.data_class
        return handshake_size({
            "topic": sub.resolved_name, "message_definition": getattr(cls, "_full_text", ""),
            "tcp_nodelay": "0", "md5sum": cls._md5sum, "type": cls._type,
            "callerid": sub.node.name})

    def arrived(self, conn: Connection, msg: MessageLike, size: int) -> None:
        """A message of ``size`` bytes arrived on ``conn`` (before the callbacks run)."""
        conn.recv_bytes += 4 + size
        if self.topic in ("/clock", "/statistics"):
            return
        publisher = conn.header.get("callerid", conn.pub_name)
        try:
            logger = self.loggers.get(publisher)
            if logger is None:
                logger = self.loggers[publisher] = _ConnectionStatistics(self, publisher)
            logger.callback(msg, conn.recv_bytes)
        except Exception as exc:  # noqa: BLE001 - rospy's own policy: log and go on
            self.node.logerr("Unexpected error during statistics measurement: %s", str(exc))

    def shutdown(self) -> None:
        for logger in self.loggers.values():
            logger.pub.unregister()
        self.loggers.clear()


class _ConnectionStatistics:
    """rospy's ``ConnectionStatisticsLogger``: one publisher's messages on one subscription."""

    def __init__(self, owner: SubscriberStatistics, publisher: str) -> None:
        from ddes.graph.topics import Publisher

        node = owner.node
        self.owner = owner
        self.node = node
        self.topic = owner.topic
        self.subscriber = node.name
        self.publisher = publisher
        self.cls: Any = node.world.messages.get_message_class("rosgraph_msgs/TopicStatistics")
        self.pub: Publisher[Any] = Publisher(node, "/statistics", self.cls, queue_size=10)
        self.last_pub_time = Time(0)
        self.pub_frequency = Duration(1.0)
        self.age_list: list[Duration] = []
        self.arrival_time_list: list[Time] = []
        self.last_seq = 0
        self.dropped_msgs = 0
        self.window_start = node.get_rostime()
        self.stat_bytes_last = 0
        self.stat_bytes_window = 0

    def callback(self, msg: Any, stat_bytes: int) -> None:
        arrival_time = self.node.get_rostime()
        self.arrival_time_list.append(arrival_time)
        self.stat_bytes_window = stat_bytes
        if getattr(msg, "_has_header", False):
            self.age_list.append(arrival_time - msg.header.stamp)
            if self.last_seq + 1 != msg.header.seq:
                self.dropped_msgs += 1
            self.last_seq = msg.header.seq
        if self.last_pub_time + Duration(1.0 / self.pub_frequency.to_sec()) < arrival_time:
            self.last_pub_time = arrival_time
            self.send()

    def send(self) -> None:
        """rospy's ``sendStatistics``: report the window, adapt the period, start a new one."""
        owner = self.owner
        curtime = self.node.get_rostime()
        msg = self.cls()
        msg.topic = self.topic
        msg.node_sub = self.subscriber
        msg.node_pub = self.publisher
        msg.window_start = self.window_start
        msg.window_stop = curtime
        msg.traffic = self.stat_bytes_window - self.stat_bytes_last
        msg.delivered_msgs = len(self.arrival_time_list)
        msg.dropped_msgs = self.dropped_msgs
        ages = self.age_list
        if ages:
            mean = Duration(_sum(ages).to_sec() / len(ages))
            variance = _sum([Duration((mean - v).to_sec() ** 2) for v in ages]) / len(ages)
            msg.stamp_age_mean = mean
            msg.stamp_age_stddev = Duration(math.sqrt(variance.to_sec()))
            msg.stamp_age_max = max(ages)
        else:
            msg.stamp_age_mean = msg.stamp_age_stddev = msg.stamp_age_max = Duration(0)
        arrivals = self.arrival_time_list
        if len(arrivals) > 1:
            periods = [j - i for i, j in zip(arrivals[:-1], arrivals[1:])]
            mean = Duration(_sum(periods).to_sec() / len(periods))
            variance = _sum([Duration((mean - v).to_sec() ** 2) for v in periods]) / len(periods)
            msg.period_mean = mean
            msg.period_stddev = Duration(math.sqrt(variance.to_sec()))
            msg.period_max = max(periods)
        else:
            msg.period_mean = msg.period_stddev = msg.period_max = Duration(0)
        self.pub.publish(msg)
        pub_period = 1.0 / self.pub_frequency.to_sec()
        if len(arrivals) > owner.max_elements and pub_period / 2 >= owner.min_window:
            self.pub_frequency *= 2
        if len(arrivals) < owner.min_elements and pub_period * 2 <= owner.max_window:
            self.pub_frequency /= 2
        self.age_list = []
        self.arrival_time_list = []
        self.dropped_msgs = 0
        self.window_start = curtime
        self.stat_bytes_last = self.stat_bytes_window


def _sum(values: list[Duration]) -> Duration:
    """``sum(values, Duration(0))``, left to right as rospy adds them."""
    total = Duration(0)
    for v in values:
        total = total + v
    return total
