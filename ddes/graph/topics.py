"""Topics: publishers, subscribers and the connections between them.

How a message travels (each hop one function, each leaving one trace event):

1. ``Publisher.publish`` builds the message from its arguments (rospy's
   rules), sets ``header.seq`` as rospy does (only when a subscriber is
   connected; see :meth:`Publisher.publish`), and **serializes it once**
   (``topic.publish``).  The bytes are the snapshot: mutating the message
   afterwards changes nothing delivered or recorded, and a field of the
   wrong type fails here with ``ROSSerializationException``, as in ROS.
2. Each :class:`Connection` (one per publisher/subscriber pair) may lose the
   message (``topic.drop`` reason ``loss``) and schedules its arrival after
   the link's latency, never before the previous arrival on the same
   connection (TCP is FIFO).
3. On arrival the subscriber deserializes its own copy (as TCPROS does) and
   queues it for its node's spinner; a full queue **drops the oldest**
   message (``topic.drop`` reason ``queue_full``).
4. The node's spinner runs the callback (``topic.deliver``).

Connections appear ``world.connect_delay`` after both ends exist (default
1 ms, the order of a ROS connection handshake); messages published before
that are not delivered to that subscriber, as in ROS (ros_comm#176).  A
latched publisher sends its last message on every new connection.

One topic, one set of connections per node (rospy's ``_TopicManager``, roscpp's
``TopicManager``): the Publishers a node makes on one topic share a
:class:`Publication` (connections, ``seq``, latch, connection headers,
subscriber listeners), and its Subscribers of one topic a :class:`Subscription`
(connections, each message decoded once for all of them).  A second Publisher
sends on the connections the first one has, so a message published right after
creating it is delivered; a second Subscriber hears the next message at once and
is handed the latched message of each latched connection in the instant it is
made (rospy #1852).  The master knows one publisher and one subscriber per node and
topic: the first live handle of each.  A message already sent when its
publisher goes away still arrives (TCP delivers what was written before the
close); one in flight to a subscriber that went away is lost.
"""

from __future__ import annotations

import random
import struct
from collections import deque
from collections.abc import Callable
from typing import TYPE_CHECKING, Any, Generic, TypedDict, TypeVar

from ddes.errors import (
    DdesTypeError,
    DdesValueError,
    ROSException,
    ROSSerializationException,
    ROSTopicException,
)
from ddes.kernel.events import post
from ddes.msg.anymsg import AnyMsg
from ddes.time.rospy_calls import REQUIRED, is_node_like, node_first
from ddes.time.units import DurationLike, duration_to_ns

if TYPE_CHECKING:
    from simpy import Timeout

    from ddes.graph.node import Node
    from ddes.graph.world import World
    from ddes.kernel.events import Posted
    from ddes.msg.message import Message, MessageClass, MessageLike

__all__ = [
    "AnyMsg",
    "Connection",
    "LinkLatency",
    "LinkModel",
    "Publication",
    "Publisher",
    "PublisherOptions",
    "Subscriber",
    "SubscriberOptions",
    "Subscription",
    "args_kwds_to_message",
    "connect_later",
    "disconnect",
    "link_latency_ns",
]

_PUB_KEYS = ("topic", "seq", "connections", "data")
_new = object.__new__  # a message class defines no __new__ of its own
_DELIVER_KEYS = ("topic", "publisher", "seq")
_DROP_KEYS = ("topic", "publisher", "seq", "reason")

_M = TypeVar("_M", bound="MessageLike")
#: The data class of a publisher or subscriber: ``Publisher[type[String]]``,
#: ``Subscriber[type[AnyMsg]]``; ``Publisher[MessageClass]`` is any publisher.
_C_co = TypeVar("_C_co", bound="MessageClass", covariant=True)

#: A link latency: seconds or a Duration, or ``f(rng)`` returning one, drawn per message
#: from the connection's own seeded stream.
LinkLatency = DurationLike | Callable[[random.Random], DurationLike]


class PublisherOptions(TypedDict, total=False):
    """The keyword arguments ``node.advertise(...)`` passes on to :class:`Publisher`."""

    subscriber_listener: object
    tcp_nodelay: bool
    headers: dict[str, str] | None


class SubscriberOptions(TypedDict, total=False):
    """The keyword arguments ``node.subscribe(...)`` passes on to :class:`Subscriber`."""

    buff_size: int
    tcp_nodelay: bool
    internal: bool


def args_kwds_to_message(data_class: type[_M], args: tuple[Any, ...], kwds: dict[str, Any]) -> _M:
    """Build a message from publish/call arguments, with rospy's rules and texts."""
    if args and kwds:
        raise DdesTypeError("publish() can be called with arguments or keywords, but not both")
    if len(args) == 1 and hasattr(args[0], "_type") and hasattr(args[0], "_md5sum"):
        msg: _M = args[0]  # a message; of data_class's type once checked
        if msg._type != data_class._type:
            raise DdesTypeError(f"expected [{data_class._type}] but got [{msg._type}]")
        return msg
    if len(args) == 1 and isinstance(args[0], dict) and not kwds \
            and len(data_class.__slots__) != 1:  # type: ignore[attr-defined]  # fields
        raise DdesTypeError(
            f"a dict is not a {data_class._type} message: pass {data_class.__name__}(**d) or keywords"
        )
    try:
        return data_class(*args, **kwds)
    except TypeError as exc:
        raise DdesTypeError(f"cannot build a {data_class._type} from {args!r} {kwds!r}: {exc}") from None


class LinkModel:
    """Transport of one connection: latency (fixed or drawn) and loss probability.

    ``latency`` is seconds/Duration, or a callable ``f(rng) -> seconds|Duration``
    drawn per message from the connection's own seeded stream.
    """

    __slots__ = ("latency", "loss")

    def __init__(self, latency: LinkLatency = 0, loss: float = 0.0) -> None:
        if not callable(latency):
            link_latency_ns(latency)  # validate now
        if isinstance(loss, bool) or not isinstance(loss, (int, float)) or not 0.0 <= loss <= 1.0:
            raise DdesValueError(f"loss must be a probability in [0, 1], got {loss!r}")
        self.latency = latency
        self.loss = float(loss)


def link_latency_ns(value: DurationLike) -> int:
    """A link latency (seconds or Duration, >= 0) as integer nanoseconds."""
    if getattr(value, "to_nsec", None) is None and (
            isinstance(value, bool) or not isinstance(value, (int, float))):
        raise DdesTypeError(f"latency must be seconds or a Duration, got {value!r}")
    ns = duration_to_ns(value, "latency")
    if ns < 0:
        raise DdesValueError(f"latency must be >= 0, got {value!r}")
    return ns


class Connection:
    """One publisher→subscriber link, with its own FIFO order, loss stream and stats."""

    __slots__ = ("pub", "sub", "id", "world", "_fixed", "_draw", "_loss", "_rng", "_last",
                 "_sent", "_seq0", "lost", "received", "dropped", "delivered", "closed", "header",
                 "batchable", "pub_name", "latching", "last", "recv_bytes")

    _draw: Callable[[random.Random], DurationLike] | None
    _loss: float

    def __init__(self, world: World, pub: Publisher[MessageClass], sub: Subscriber[MessageClass],
                 link: LinkModel) -> None:
        self.world = world
        self.pub = pub
        self.sub = sub
        self.pub_name = pub.node.name
        self.id = world.next_id("connection")
        self._rng: random.Random | None = None
        self._last = 0
        self._sent = self.lost = self.received = self.dropped = self.delivered = 0
        self._seq0 = pub.published  # batched sends: the publishes since the connection opened
        self.closed = False
        #: Fixed latency, no loss, never re-linked: arrivals can share one
        #: kernel event per publish (FIFO holds trivially).
        self.batchable = False
        self.header = {
            "callerid": pub.node.name,
            "latching": "1" if pub.latch else "0",
            "md5sum": pub.md5sum,
            "message_definition": pub.data_class._full_text,
            "topic": pub.resolved_name,
            "type": pub.type,
        }
        extra = pub._pub.headers
        if extra:  # Publisher(headers=...): rospy's TCPROSPub lets them override its own fields
            self.header.update(extra)
        #: The publisher latches (the header says so): the subscriber keeps the last message.
        self.latching = self.header.get("latching") == "1"
        #: ``(data, seq)`` of the last message received on a latching connection (rospy's
        #: ``connection.latch``, handed to a Subscriber that joins the subscription).
        self.last: tuple[bytes, int] | None = None
        #: Bytes the subscriber's transport counted (its handshake header and each message
        #: with its length prefix), as rospy's ``stat_bytes`` (topic statistics).
        self.recv_bytes = 0
        self._fixed, self._draw, self._loss = 0, None, 0.0
        self.set_link(link)
        self.batchable = self._draw is None and not self._loss

    @property
    def sent(self) -> int:
        """Messages the publisher sent on this connection."""
        if self.batchable and not self.closed:
            return self._sent + self.pub.published - self._seq0
        return self._sent

    def set_link(self, link: LinkModel) -> None:
        """Change the transport model (applies to messages sent from now on)."""
        if self.batchable:
            self._sent += self.pub.published - self._seq0
            self.batchable = False  # messages may be in flight: keep FIFO per message
            self.pub._rebuild_fanout()
        if callable(link.latency):
            self._fixed, self._draw = 0, link.latency
        else:
            self._fixed, self._draw = link_latency_ns(link.latency), None
        self._loss = link.loss
        if (self._draw is not None or self._loss) and self._rng is None:
            self._rng = self.world.rng_for(
                f"link:{self.pub.resolved_name}:{self.pub.node.name}->{self.sub.node.name}:{self.id}")

    def send(self, data: bytes, seq: int) -> None:
        """Schedule the arrival of one serialized message (or lose it)."""
        self._sent += 1
        world = self.world
        env = world.env
        now: int = env.now_ns
        if self._loss and self._rng is not None and self._rng.random() < self._loss:
            self.lost += 1
            world.trace.append_row((now, "topic.drop", self.sub.node.name, _DROP_KEYS,
                                     self.pub.resolved_name, self.pub_name, seq, "loss"))
            return
        # _rng is set whenever _draw is (set_link)
        delay = self._fixed if self._draw is None else link_latency_ns(
            self._draw(self._rng))  # type: ignore[arg-type]
        at = now + delay
        if at < self._last:
            at = self._last  # FIFO per connection
        self._last = at
        post(env, at - now, (data, seq, self), self.sub._arrive_one)  # a group of one, alone


def _arrive_batch(ev: Posted[tuple[bytes, int, list[Connection]]]) -> None:
    """A batched publish's arrival on a group of connections of one latency: per connection,
    what :meth:`Subscriber._arrive_one` does, inline (one Python call fewer per subscriber).
    Keep the two step for step the same (tests/graph compare the paths)."""
    data, seq, conns = ev.payload
    now = ev.at_ns
    for conn in conns:
        sub = conn.sub
        if sub._closed:  # the subscription went away: lost with its connection
            continue
        conn.received += 1
        if conn.latching:
            conn.last = (data, seq)
        if sub._slow:
            _arrive_shared(sub._sub, conn, data, seq, now)
            continue
        if sub._any:
            msg: MessageLike = AnyMsg(data, dict(conn.header))
        else:
            msg = _new(sub.data_class)._deserialize_from(data)
            msg._connection_header = conn.header  # type: ignore[attr-defined]  # as rospy sets it
        cbq = sub._cbq
        if sub._internal or (cbq.free and not sub._queue and not sub.cb_active):
            conn.delivered += 1
            sub._trace.append_row((now, "topic.deliver", sub._node_name, _DELIVER_KEYS,
                                   sub.resolved_name, conn.pub_name, seq))
            cb = sub.callback
            if cb is not None:
                if sub.callback_args is None:
                    cbq.run1(cb, msg, sub)
                else:
                    cbq.run(cb, (msg, sub.callback_args), sub)
            continue
        sub._enqueue(conn, msg, seq)


class Publication:
    """What a node's Publishers of one topic share (rospy's ``_PublisherImpl``, one per node and
    topic): the connections, ``seq``, the latch, the connection headers and the subscriber
    listeners.  ``handles`` are the live Publishers, oldest first; the first is the one the
    master and the connections know."""

    __slots__ = ("handles", "connections", "count", "seqbox", "latch", "latched", "latched_seq",
                 "headers", "listeners", "closed")

    def __init__(self) -> None:
        self.handles: list[Publisher[MessageClass]] = []
        #: The open connections (every handle's ``connections`` is this list).
        self.connections: list[Connection] = []
        #: ``[n]``: messages published through any handle (every ``publish()`` call).
        self.count = [0]
        #: ``[seq]``: rospy's ``_PublisherImpl.seq``, messages sent on the topic by the node.
        self.seqbox = [0]
        self.latch = False
        self.latched: bytes | None = None
        self.latched_seq = 0
        #: Extra connection header fields (``Publisher(headers=...)``, later ones win).
        self.headers: dict[str, str] = {}
        #: ``rospy.SubscribeListener``s: ``peer_subscribe``/``peer_unsubscribe`` per connection.
        self.listeners: list[Any] = []
        self.closed = False


class Subscription:
    """What a node's Subscribers of one topic share (rospy's ``_SubscriberImpl``): the
    connections, each message decoded once for every handle, and the topic statistics of
    ``/enable_statistics``.  ``handles`` are the live Subscribers, oldest first."""

    __slots__ = ("handles", "connections", "stats", "closed")

    def __init__(self) -> None:
        self.handles: list[Subscriber[MessageClass]] = []
        #: The open connections (every handle's ``connections`` is this list).
        self.connections: list[Connection] = []
        #: rospy's ``SubscriberStatisticsLogger`` when ``/enable_statistics`` was set at the
        #: subscription's start (:mod:`ddes.graph.statistics`), else None.
        self.stats: Any = None
        self.closed = False


class Publisher(Generic[_C_co]):
    """``Publisher(node, name, data_class, queue_size=None, latch=False)`` (rospy.Publisher).

    A Publisher made on a topic its node already publishes joins that topic's
    :class:`Publication`: it publishes on the connections already open, with the same
    ``seq``; ``latch=True`` latches the topic, ``headers`` add to the connection headers
    of connections made from now on, and ``subscriber_listener`` (a ``rospy.SubscribeListener``)
    hears of each connection: ``peer_subscribe(topic, topic_publish, peer_publish)`` when a
    subscriber connects, ``peer_unsubscribe(topic, num_peers)`` when one goes away.
    """

    __slots__ = ("_closed", "data_class", "_count", "_roscpp", "_nconn", "_seqbox",
                 "_has_header", "latch", "_env", "_trace", "_node_name", "resolved_name",
                 "_fanout", "_single", "_pub", "node", "world", "name", "type",
                 "md5sum", "queue_size", "headers", "connections")

    def __init__(
        self,
        node: Node,
        name: str,
        data_class: _C_co = REQUIRED,
        subscriber_listener: object = None,
        tcp_nodelay: bool = False,
        latch: bool = False,
        headers: dict[str, str] | None = None,
        queue_size: int | None = None,
    ) -> None:
        if not is_node_like(node):
            # rospy.Publisher(name, data_class, ...): everything moved one place to the left
            kwargs: dict[str, object] = {
                k: v for k, v in (("latch", latch or None), ("queue_size", queue_size))
                if v is not None}
            node_first("Publisher", "pub = ", node, [name, data_class], kwargs,
                       "pub.publish(...)    # from the node's code", method="advertise")
        node.check_alive("create a publisher")
        _check_data_class(data_class, name)
        if queue_size is not None and (isinstance(queue_size, bool) or not isinstance(queue_size, int)
                                       or queue_size < 0):
            raise ROSException(f"queue_size must be None or an int >= 0, got {queue_size!r}")
        self.node = node
        self.world = node.world
        self.name = name
        self.resolved_name = node.resolve_name(name)
        self.data_class = data_class
        self.type: str = data_class._type
        self.md5sum: str = data_class._md5sum
        impl = node._pub_impls.get(self.resolved_name)
        first = impl is None
        if impl is None:
            impl = Publication()
        else:
            _check_same_type(impl.handles[0], self, "Publisher")
        self._pub = impl
        self.queue_size = queue_size
        self.headers = dict(headers or {})
        # rospy's _PublisherImpl.seq: one counter per node and topic, shared by every
        # Publisher of that topic in the node, counting messages actually sent.
        self._seqbox = impl.seqbox
        self._count = impl.count
        self.connections: list[Connection] = impl.connections
        #: header.seq counted as roscpp counts it (a node with client_library "roscpp").
        self._roscpp = node.client_library == "roscpp"
        self._closed = False
        #: Per fixed latency: (delay, the connection or the list of them, the arrival callback).
        # Tuples, rebuilt on every connect/disconnect: a publisher with no connection holds the
        # empty tuple, which the cyclic collector never tracks (a big world's publishers are
        # mostly unconnected, and each tracked object is walked by every full collection).
        self._fanout: tuple[tuple[int, Any, Callable[[Posted[Any]], None]], ...] = ()
        self._single: tuple[Connection, ...] = ()
        self._nconn = 0
        self._env = node.world.env
        self._trace = node.world.trace
        self._node_name = node.name
        self._has_header = bool(getattr(data_class, "_has_header", False))
        if queue_size is None:
            self.world.record("warning", node.name, topic=self.resolved_name,
                              text="The publisher should be created with an explicit keyword "
                                   "argument 'queue_size'.")
        if first:
            self.latch = bool(latch)
            impl.latch = self.latch
            self.world.master.register_publisher(self)  # raises on a type conflict
            node._pub_impls[self.resolved_name] = impl
            node._published.append(self)
        else:
            other = impl.handles[0]
            self._fanout, self._single, self._nconn = other._fanout, other._single, other._nconn
            if latch and not impl.latch:  # rospy's enable_latch: the topic latches from now on
                impl.latch = True
                for h in impl.handles:
                    h.latch = True
            self.latch = impl.latch
        impl.handles.append(self)
        if headers:
            impl.headers.update(headers)
        if subscriber_listener:
            impl.listeners.append(subscriber_listener)
        node.add_entity(self)
        self.world.record("topic.advertise", node.name, topic=self.resolved_name, type=self.type,
                          latch=self.latch)

    @property
    def published(self) -> int:
        """Messages published on this topic by the node's Publishers (every ``publish()``
        call; the Publishers of one topic in a node count together)."""
        return self._count[0]

    @property
    def seq(self) -> int:
        """rospy's ``seq``: messages sent on this topic by this node (the last ``header.seq``).

        Shared by every Publisher of the topic in the node; a publish with no
        subscriber connected does not count (rospy's ``_PublisherImpl.publish``).
        """
        return self._seqbox[0]

    def publish(self, *args: Any, **kwds: Any) -> None:
        """Publish a message instance, or the field values of a new one.

        ``header.seq`` is counted as the node's client library counts it
        (:attr:`Node.client_library`), by one counter per topic and node:

        * rospy (``_PublisherImpl.publish``): with no subscriber connected the
          message goes nowhere, the counter stays and ``header.seq`` is left
          as it is; otherwise the counter counts up and overwrites
          ``header.seq`` of the message object.
        * roscpp (``TopicManager::publish``): every publish counts, and the
          count is written into the sent bytes, not into the message object.

        ddes serializes the message in every case, so a bad field raises at
        once (rospy serializes only for a connected subscriber).
        """
        if self._closed:
            if self.node.is_shutdown():
                # rospy's _PublisherImpl.publish: a topic closed by the shutdown is a race with
                # the user's is_shutdown() test, and the message is dropped quietly
                return
            raise ROSException("publish() to an unregistered() handle")
        if len(args) == 1 and not kwds and type(args[0]) is self.data_class:
            msg: Any = args[0]  # a data_class instance: a Message, with a header if _has_header
        else:
            msg = args_kwds_to_message(self.data_class, args, kwds)
        self._count[0] += 1
        roscpp = self._roscpp
        if self._nconn or roscpp:
            box = self._seqbox
            seq = box[0] = box[0] + 1
            if self._has_header and not roscpp:
                msg.header.seq = seq
        else:
            seq = 0  # not sent: rospy returns before counting
        try:
            data = msg._serialize_to_bytes()
        except Exception:  # noqa: BLE001 - re-done with the checks that name the bad field
            data = _serialize_checked(msg)
        if roscpp and self._has_header:
            data = _with_seq(data, seq)
        if self.latch:
            impl = self._pub
            impl.latched = data
            impl.latched_seq = seq
        env = self._env
        self._trace.append_row((env.now_ns, "topic.publish", self._node_name, _PUB_KEYS,
                                self.resolved_name, seq, self._nconn, data))
        for delay, to, arrive in self._fanout:
            post(env, delay, (data, seq, to), arrive)
        for conn in self._single:
            conn.send(data, seq)

    def _publish_to(self, conn: Connection, message: Any) -> None:
        """Publish ``message`` on ``conn`` only (a SubscribeListener's ``peer_publish``)."""
        if self._pub.closed or conn.closed:
            return
        msg: Any = args_kwds_to_message(self.data_class, (message,), {})
        box = self._seqbox
        seq = box[0] = box[0] + 1
        if self._has_header and not self._roscpp:
            msg.header.seq = seq
        try:
            data = msg._serialize_to_bytes()
        except Exception:  # noqa: BLE001 - re-done with the checks that name the bad field
            data = _serialize_checked(msg)
        if self._roscpp and self._has_header:
            data = _with_seq(data, seq)
        if self.latch:
            self._pub.latched, self._pub.latched_seq = data, seq
        self._trace.append_row((self._env.now_ns, "topic.publish", self._node_name, _PUB_KEYS,
                                self.resolved_name, seq, 1, data))
        conn.send(data, seq)

    def _rebuild_fanout(self) -> None:
        """Group batchable connections by latency (one kernel event per group), for every
        Publisher of the topic in the node."""
        groups: dict[int, list[Connection]] = {}
        single: list[Connection] = []
        for conn in self.connections:
            if conn.batchable:
                groups.setdefault(conn._fixed, []).append(conn)
            else:
                single.append(conn)
        # A group of one connection arrives through its subscriber's _arrive_one (one Python
        # call fewer per message), a larger one through _arrive_batch.
        fanout = tuple([(delay, conns[0], conns[0].sub._arrive_one) if len(conns) == 1
                        else (delay, conns, _arrive_batch)
                        for delay, conns in groups.items()])
        singles = tuple(single)
        n = len(self.connections)
        for h in self._pub.handles or (self,):
            h._fanout, h._single, h._nconn = fanout, singles, n

    def get_num_connections(self) -> int:
        """Number of live subscriber connections."""
        return len(self.connections)

    def unregister(self) -> None:
        """Stop publishing; connections close with the topic's last Publisher in the node."""
        if self._closed:
            return
        self._closed = True
        impl = self._pub
        node = self.node
        if self in impl.handles:
            impl.handles.remove(self)
        node.remove_entity(self)
        if impl.handles:  # the node's other Publishers of the topic keep its connections
            _hand_over(node._published, self, impl.handles[0], self.world.master.topics)
            for conn in impl.connections:
                if conn.pub is self:
                    conn.pub = impl.handles[0]
            self.world.record("topic.unadvertise", node.name, topic=self.resolved_name)
            return
        impl.closed = True
        for conn in list(self.connections):
            disconnect(conn)
        self.world.master.unregister_publisher(self)
        if self in node._published:
            node._published.remove(self)
        if node._pub_impls.get(self.resolved_name) is impl:
            # rospy releases the topic's impl with its last Publisher: the count restarts
            del node._pub_impls[self.resolved_name]
        self.world.record("topic.unadvertise", node.name, topic=self.resolved_name)

    shutdown = unregister


def _check_same_type(first: Any, new: Any, what: str) -> None:
    """A second Publisher (Subscriber) of a topic in one node uses the first one's type."""
    if "*" in (first.type, new.type) or (first.type, first.md5sum) == (new.type, new.md5sum):
        return
    raise ROSTopicException(
        f"{what} of [{new.node.name}] wants topic {new.resolved_name} to have datatype/md5sum "
        f"[{new.type}/{new.md5sum}], but it already has [{first.type}/{first.md5sum}] in this "
        "node: use the same message type, or another topic name")


def _hand_over(own: list[Any], old: Any, new: Any, topics: dict[str, Any]) -> None:
    """``old`` left its topic's publication (subscription) and ``new`` now stands for it: in
    the node's list ``own`` and in the master's entry, at ``old``'s place."""
    if old in own:
        own[own.index(old)] = new
    entry = topics.get(old.resolved_name)
    if entry is not None:
        for registry in (entry.publishers, entry.subscribers):
            if old in registry:
                registry[registry.index(old)] = new


class PeerPublish:
    """A SubscribeListener's ``peer_publish``: publish to the one subscriber that connected
    (rospy's ``peer_publish``; roscpp's ``SingleSubscriberPublisher``), whose caller id is
    :attr:`subscriber`."""

    __slots__ = ("pub", "conn")

    def __init__(self, pub: Publisher[Any], conn: Connection) -> None:
        self.pub = pub
        self.conn = conn

    @property
    def subscriber(self) -> str:
        return str(self.conn.sub.node.name)

    def __call__(self, message: Any) -> None:
        self.pub._publish_to(self.conn, message)


def _decode(sub: Subscriber[MessageClass], conn: Connection, data: bytes) -> MessageLike:
    """The message ``sub`` hears from ``data`` (its own copy, as TCPROS deserializes)."""
    if sub._any:
        return AnyMsg(data, dict(conn.header))
    msg: Any = _new(sub.data_class)._deserialize_from(data)
    msg._connection_header = conn.header  # as rospy sets it
    return msg  # type: ignore[no-any-return]


def _arrive_shared(impl: Subscription, conn: Connection, data: bytes, seq: int, now: int) -> None:
    """An arrival for a subscription of several Subscribers (or with topic statistics): decoded
    once per data class, statistics first, then each Subscriber in the order they were made
    (rospy's ``_SubscriberImpl.receive_callback``)."""
    decoded: dict[Any, MessageLike] = {}
    stats = impl.stats
    for sub in tuple(impl.handles):
        if sub._closed:
            continue
        cls = sub.data_class
        msg = decoded.get(cls)
        if msg is None:
            msg = decoded[cls] = _decode(sub, conn, data)
        if stats is not None:
            stats.arrived(conn, msg, len(data))
            stats = None
        sub._deliver(conn, msg, seq, now)


class Subscriber(Generic[_C_co]):
    """``Subscriber(node, name, data_class, callback, callback_args, queue_size)`` (rospy).

    The Subscribers of one topic in a node share its :class:`Subscription`: one connection
    per publisher; a Subscriber made while the subscription has connections hears the next
    message at once, and the latched message of each latching connection in the instant it is
    made (rospy #1852; rospy hands it over inside the constructor, ddes just after it).  Each keeps its own callback, queue and callback thread.
    """

    __slots__ = ("_closed", "_any", "data_class", "_cbq", "_internal", "_queue", "cb_active",
                 "_trace", "_node_name", "resolved_name", "callback", "callback_args", "_env",
                 "queue_size", "node", "world", "name", "type", "md5sum", "connections",
                 "_sub", "_slow")

    def __init__(
        self,
        node: Node,
        name: str,
        data_class: _C_co = REQUIRED,
        callback: Callable[..., object] | None = None,
        callback_args: object = None,
        queue_size: int | None = None,
        buff_size: int = 65536,
        tcp_nodelay: bool = False,
        *,
        internal: bool = False,
    ) -> None:
        if not is_node_like(node):
            # rospy.Subscriber(name, data_class, callback, callback_args, ...), shifted left
            sub_kwargs: dict[str, object] = {} if queue_size is None else {"queue_size": queue_size}
            node_first("Subscriber", "sub = ", node, [name, data_class, callback], sub_kwargs,
                       method="subscribe")
        node.check_alive("create a subscriber")
        _check_data_class(data_class, name)
        if queue_size == -1:
            queue_size = None
        elif queue_size == 0:
            raise ROSException("queue size may not be set to zero")
        elif queue_size is not None and (type(queue_size) is not int or queue_size < 0):
            raise ROSException(f"queue size must be an integer (None or -1 for infinite), got {queue_size!r}")
        if callback is not None and not callable(callback):
            raise DdesTypeError(f"subscriber callback must be callable, got {callback!r}")
        self.node = node
        self.world = node.world
        self.name = name
        self.resolved_name = node.resolve_name(name)
        self.data_class = data_class
        self.type: str = data_class._type
        self.md5sum: str = data_class._md5sum
        self.callback = callback
        self.callback_args = callback_args
        self.queue_size = queue_size
        impl = node._sub_impls.get(self.resolved_name)
        first = impl is None
        if impl is None:
            impl = Subscription()
        else:
            _check_same_type(impl.handles[0], self, "Client")
        self._sub = impl
        self.connections: list[Connection] = impl.connections
        self._queue: deque[tuple[Connection, MessageLike, int]] = deque()
        self._closed = False
        self._internal = internal
        self._any = data_class is AnyMsg
        self._slow = False
        #: True while a callback of this subscription runs (the node's runner sets it).
        self.cb_active = False
        self._cbq = node.callbacks
        self._node_name = node.name
        self._env = node.world.env
        self._trace = node.world.trace
        if first:
            self.world.master.register_subscriber(self)  # raises on a type conflict
            node._sub_impls[self.resolved_name] = impl
            node._subscribed.append(self)
            from ddes.graph.statistics import statistics_for

            impl.stats = statistics_for(self)
        impl.handles.append(self)
        _update_slow(impl)
        node.add_entity(self)
        self.world.record("topic.subscribe", node.name, topic=self.resolved_name, type=self.type)
        if not first:  # rospy #1852: the latched message of each connection, at once
            latched = [(conn, conn.last) for conn in impl.connections if conn.last is not None]
            if latched:
                post(self._env, 0, latched, self._deliver_latched)

    def _deliver_latched(self, ev: Posted[list[tuple[Connection, tuple[bytes, int]]]]) -> None:
        """The latched messages a Subscriber joining a subscription is handed, in the instant
        it was made (rospy hands them over inside its constructor; here just after it, so the
        code that made it holds it when its callback runs)."""
        for conn, (data, seq) in ev.payload:
            if self._closed:
                return
            self._deliver(conn, _decode(self, conn, data), seq, ev.at_ns)

    def _arrive_one(self, ev: Posted[tuple[bytes, int, Connection]]) -> None:
        """The arrival of a message on one connection: a batched publish's group of one (the
        common case, one subscriber per latency) or a connection sending on its own (a drawn
        latency, loss).  ``_arrive_batch`` does the same per connection of a larger group;
        keep the two step for step the same (tests/graph compare the paths)."""
        data, seq, conn = ev.payload
        sub = conn.sub  # the subscription's first live Subscriber (self, unless self left it)
        if sub._closed:  # the subscription went away: lost with its connection
            return
        conn.received += 1
        if conn.latching:
            conn.last = (data, seq)
        if sub._slow:
            _arrive_shared(sub._sub, conn, data, seq, ev.at_ns)
            return
        if sub._any:
            msg: MessageLike = AnyMsg(data, dict(conn.header))
        else:
            msg = _new(sub.data_class)._deserialize_from(data)
            msg._connection_header = conn.header  # type: ignore[attr-defined]  # as rospy sets it
        cbq = sub._cbq
        if sub._internal or (cbq.free and not sub._queue and not sub.cb_active):
            conn.delivered += 1
            sub._trace.append_row((ev.at_ns, "topic.deliver", sub._node_name,
                                   _DELIVER_KEYS, sub.resolved_name, conn.pub_name, seq))
            cb = sub.callback
            if cb is not None:
                if sub.callback_args is None:
                    cbq.run1(cb, msg, sub)
                else:
                    cbq.run(cb, (msg, sub.callback_args), sub)
            return
        sub._enqueue(conn, msg, seq)

    def _deliver(self, conn: Connection, msg: MessageLike, seq: int, now: int) -> None:
        """Hand ``msg`` to this Subscriber: its callback now if the spinner is free for it,
        else its queue (the steps of :meth:`_arrive_one` after decoding)."""
        cbq = self._cbq
        if self._internal or (cbq.free and not self._queue and not self.cb_active):
            conn.delivered += 1
            self._trace.append_row((now, "topic.deliver", self._node_name, _DELIVER_KEYS,
                                    self.resolved_name, conn.pub_name, seq))
            cb = self.callback
            if cb is not None:
                if self.callback_args is None:
                    cbq.run1(cb, msg, self)
                else:
                    cbq.run(cb, (msg, self.callback_args), self)
            return
        self._enqueue(conn, msg, seq)

    def _enqueue(self, conn: Connection, msg: MessageLike, seq: int) -> None:
        """Queue a message the spinner cannot take now (dropping the oldest past queue_size)."""
        cbq = self._cbq
        q = self._queue
        q.append((conn, msg, seq))
        qs = self.queue_size
        if qs is not None and len(q) > qs:
            old_conn, _old, old_seq = q.popleft()
            old_conn.dropped += 1
            self._trace.append_row((self._env.now_ns, "topic.drop", self._node_name, _DROP_KEYS,
                                     self.resolved_name, old_conn.pub_name, old_seq, "queue_full"))
        cbq.enqueue(self._call_queued, (), self)

    def _call_queued(self) -> object:
        """The spinner's entry: deliver the oldest queued message (roscpp SubscriptionQueue::call)."""
        if not self._queue or self._closed:
            return None
        conn, msg, seq = self._queue.popleft()
        conn.delivered += 1
        self._trace.append_row((self._env.now_ns, "topic.deliver", self._node_name, _DELIVER_KEYS,
                                 self.resolved_name, conn.pub_name, seq))
        cb = self.callback
        if cb is None:
            return None
        return cb(msg) if self.callback_args is None else cb(msg, self.callback_args)

    def get_num_connections(self) -> int:
        """Number of live publisher connections."""
        return len(self.connections)

    def unregister(self) -> None:
        """Stop receiving; queued messages are discarded.  Connections close with the topic's
        last Subscriber in the node."""
        if self._closed:
            return
        self._closed = True
        self._queue.clear()
        impl = self._sub
        node = self.node
        if self in impl.handles:
            impl.handles.remove(self)
        node.remove_entity(self)
        if impl.handles:  # the node's other Subscribers of the topic keep its connections
            new = impl.handles[0]
            _hand_over(node._subscribed, self, new, self.world.master.topics)
            pubs: list[Publisher[MessageClass]] = []
            for conn in impl.connections:
                if conn.sub is self:
                    conn.sub = new
                    if conn.pub not in pubs:
                        pubs.append(conn.pub)
            for pub in pubs:  # their fanouts name the subscriber's arrival method
                pub._rebuild_fanout()
            _update_slow(impl)
            self.world.record("topic.unsubscribe", node.name, topic=self.resolved_name)
            return
        impl.closed = True
        for conn in list(self.connections):
            disconnect(conn)
        if impl.stats is not None:
            impl.stats.shutdown()
        self.world.master.unregister_subscriber(self)
        if self in node._subscribed:
            node._subscribed.remove(self)
        if node._sub_impls.get(self.resolved_name) is impl:
            del node._sub_impls[self.resolved_name]
        self.world.record("topic.unsubscribe", node.name, topic=self.resolved_name)

    shutdown = unregister


def _update_slow(impl: Subscription) -> None:
    """Arrivals take :func:`_arrive_shared` for several Subscribers or topic statistics."""
    slow = len(impl.handles) > 1 or impl.stats is not None
    for sub in impl.handles:
        sub._slow = slow


def _check_data_class(data_class: object, name: str) -> None:
    if data_class is AnyMsg:
        return
    if not isinstance(data_class, type) or not hasattr(data_class, "_type") \
            or not hasattr(data_class, "_md5sum"):
        raise DdesTypeError(
            f"topic {name!r}: data_class must be a message class (e.g. "
            f"get_message_class('std_msgs/String')), got {data_class!r}"
        )


def _serialize_checked(msg: Message) -> bytes:
    """Serialize after the fast path failed: the error names the bad field (ROS's exception)."""
    from ddes.msg.message import serialize_checked

    try:
        return serialize_checked(msg)
    except ROSSerializationException:
        raise
    except Exception as exc:  # noqa: BLE001 - anything else is a serialization failure too
        raise ROSSerializationException(f"cannot serialize {type(msg).__name__}: {exc}") from exc



def connect_later(world: World, pub: Publisher[MessageClass], sub: Subscriber[MessageClass],
                  delay_ns: int) -> None:
    """Connect ``pub``'s publication to ``sub``'s subscription after ``delay_ns`` (the ROS
    connection handshake)."""
    pub_impl, sub_impl = pub._pub, sub._sub

    def connect(_ev: Timeout) -> None:
        if pub_impl.closed or sub_impl.closed or not pub_impl.handles or not sub_impl.handles:
            return
        p, s = pub_impl.handles[0], sub_impl.handles[0]  # who stands for each now
        conn = Connection(world, p, s, world.link_for(p, s))
        p.connections.append(conn)
        s.connections.append(conn)
        p._rebuild_fanout()
        if sub_impl.stats is not None:
            conn.recv_bytes = sub_impl.stats.handshake_bytes(s)
        world.record("topic.connect", s.node.name, topic=p.resolved_name,
                     publisher=p.node.name, connection=conn.id)
        for listener in list(pub_impl.listeners):  # rospy's add_connection: before the latch
            p.node.callbacks.invoke(listener.peer_subscribe,
                                    (p.resolved_name, p.publish, PeerPublish(p, conn)))
        if pub_impl.latch and pub_impl.latched is not None:
            latched = pub_impl.latched
            if p._roscpp:  # roscpp sends the latched bytes as they were
                conn.send(latched, pub_impl.latched_seq)
            else:  # rospy publishes the latched message again on the connection: a new seq
                box = p._seqbox
                seq = box[0] = box[0] + 1
                conn.send(_with_seq(latched, seq) if p._has_header else latched, seq)

    post(world.env, delay_ns, None, connect)


def _with_seq(data: bytes, seq: int) -> bytes:
    """``data`` of a message with a header, its ``header.seq`` (the first 4 bytes) set to ``seq``."""
    return struct.pack("<I", seq & 0xFFFFFFFF) + data[4:]


def disconnect(conn: Connection) -> None:
    """Close a connection (either end went away)."""
    if conn.closed:
        return
    if conn.batchable:
        conn._sent += conn.pub.published - conn._seq0
        conn.batchable = False
    conn.closed = True
    if conn in conn.pub.connections:
        conn.pub.connections.remove(conn)
        conn.pub._rebuild_fanout()
    if conn in conn.sub.connections:
        conn.sub.connections.remove(conn)
    conn.world.record("topic.disconnect", conn.sub.node.name, topic=conn.pub.resolved_name,
                      publisher=conn.pub.node.name, connection=conn.id)
    pub = conn.pub
    left = len(pub.connections)
    for listener in list(pub._pub.listeners):  # rospy's remove_connection
        pub.node.callbacks.invoke(listener.peer_unsubscribe, (pub.resolved_name, left))
