"""rospy's ``message_filters`` on ddes: ``import message_filters`` in a rospy script.

Follows Noetic's ``message_filters/__init__.py`` (ros/ros_comm, the Python module):

* :class:`SimpleFilter`: ``registerCallback(cb, *args)`` returns a connection id (0, 1, ...)
  and ``signalMessage(*msgs)`` calls every callback with the messages then its ``args``, in
  the order they were registered;
* :class:`Subscriber`: a ``rospy.Subscriber`` (the script's, :class:`ddes.compat.rospy.Subscriber`,
  same arguments; its ``callback`` argument is replaced) whose messages it signals; ``sub``,
  ``getTopic()``, ``unregister()`` and every other attribute of the subscriber;
* :class:`Cache`: the last ``cache_size`` messages of its input in arrival order, with
  ``getInterval``, ``getElemAfterTime``, ``getElemBeforeTime``, ``getLatestTime`` (and its old
  spelling ``getLastestTime``), ``getOldestTime``, ``getLast``; it signals each message it adds;
* :class:`TimeSynchronizer`: one message per input with exactly the same ``header.stamp``; the
  sets complete at an input's message are signalled oldest stamp first; each input keeps at
  most ``queue_size`` stamps (the oldest is dropped);
* :class:`ApproximateTimeSynchronizer`: Noetic's (simple) approximate policy: at each message,
  the other inputs' stamps within ``slop`` of it are tried nearest first (a product over the
  inputs, the first input varying slowest), and the first set spanning less than ``slop`` is
  signalled and removed; a message goes to its input's queue (the newest of one stamp replaces
  the older) before the queue is cut to ``queue_size``; all queues are cleared when ROS time
  went backwards since the last message;
* ``allow_headerless`` (Cache, ApproximateTimeSynchronizer) stamps a message without
  ``header.stamp`` with ``rospy.Time.now()``; without it such a message is dropped with rospy's
  warning; ``reset=True`` clears an input's queue when its ``/clock`` time jumped back.

Deliberate deviations:

* no locks: Noetic takes a ``threading.Lock`` in the synchronizers' ``add``; ddes runs a world's
  callbacks one at a time, so a filter's state is never shared with a concurrent call and
  nothing is locked (no ``lock`` attribute);
* the sets common to all queues are found in the first queue's order then sorted by stamp (the
  same sets and order as Noetic's set intersection, without iterating a set);
* ``signalMessage`` calls the callbacks registered when it starts (a callback registering
  another does not break it; Noetic's raises "dictionary changed size during iteration");
* :class:`Subscriber` also takes the topic as the keyword ``name=``; ``__getattr__`` of a
  subscriber not yet made raises AttributeError instead of recursing.

There is no ``Chain``: Noetic's Python module has none (only the C++ library).
"""

from __future__ import annotations

import itertools
from collections.abc import Callable, Sequence
from typing import Any

from ddes.compat import rospy as _rospy
from ddes.time.rostime import Duration, Time

__all__ = ["ApproximateTimeSynchronizer", "Cache", "SimpleFilter", "Subscriber",
           "TimeSynchronizer"]

_HEADERLESS = ("Cannot use message filters with non-stamped messages. Use the 'allow_headerless' "
               "constructor option to auto-assign ROS time to headerless messages.")


def _stamp_of(msg: Any) -> Time | None:
    """``msg.header.stamp``, or None for a message without one."""
    header = getattr(msg, "header", None)
    if header is None or not hasattr(header, "stamp"):
        return None
    stamp: Time = header.stamp
    return stamp


def _stamp_or_now(msg: Any, allow_headerless: bool) -> Time | None:
    """The stamp a filter files ``msg`` under: its header's, ROS time now for a headerless one
    when ``allow_headerless``, else None after rospy's warning (the message is not used)."""
    stamp = _stamp_of(msg)
    if stamp is None:
        if not allow_headerless:
            _rospy.logwarn(_HEADERLESS)
            return None
        stamp = Time.now()
    return stamp


class SimpleFilter:
    """A filter's output: callbacks registered on it, called with what it signals."""

    def __init__(self) -> None:
        self.callbacks: dict[int, tuple[Callable[..., object], tuple[Any, ...]]] = {}

    def registerCallback(self, cb: Callable[..., object], *args: Any) -> int:
        """Call ``cb(*msgs, *args)`` at each output of this filter; returns the connection id."""
        conn = len(self.callbacks)
        self.callbacks[conn] = (cb, args)
        return conn

    def signalMessage(self, *msg: Any) -> None:
        """Pass ``msg`` to every registered callback, in registration order."""
        for cb, args in list(self.callbacks.values()):
            cb(*msg, *args)


class Subscriber(SimpleFilter):
    """A ROS subscription as a filter: the same arguments as ``rospy.Subscriber``."""

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        super().__init__()
        self.topic = args[0] if args else kwargs["name"]
        kwargs["callback"] = self.callback
        self.sub = _rospy.Subscriber(*args, **kwargs)

    def callback(self, msg: Any) -> None:
        """The subscriber's callback: signal ``msg``."""
        self.signalMessage(msg)

    def getTopic(self) -> str:
        """The topic as given (not resolved)."""
        topic: str = self.topic
        return topic

    def unregister(self) -> None:
        """Unsubscribe (``rospy.Subscriber.unregister``)."""
        self.sub.unregister()

    def __getattr__(self, key: str) -> Any:
        """The rospy.Subscriber's attributes (``resolved_name``, ``get_num_connections`` ...)."""
        sub = self.__dict__.get("sub")
        if sub is None:
            raise AttributeError(key)
        return getattr(sub, key)


class Cache(SimpleFilter):
    """The last ``cache_size`` messages of the input filter ``f``, with their stamps."""

    def __init__(self, f: SimpleFilter, cache_size: int = 1,
                 allow_headerless: bool = False) -> None:
        super().__init__()
        self.connectInput(f)
        self.cache_size = cache_size
        self.cache_msgs: list[Any] = []
        self.cache_times: list[Time] = []
        self.allow_headerless = allow_headerless

    def connectInput(self, f: SimpleFilter) -> None:
        """Take the messages of filter ``f``."""
        self.incoming_connection = f.registerCallback(self.add)

    def add(self, msg: Any) -> None:
        """Cache ``msg`` (dropping the oldest beyond ``cache_size``) and signal it."""
        stamp = _stamp_or_now(msg, self.allow_headerless)
        if stamp is None:
            return
        self.cache_times.append(stamp)
        self.cache_msgs.append(msg)
        if len(self.cache_msgs) > self.cache_size:
            del self.cache_msgs[0]
            del self.cache_times[0]
        self.signalMessage(msg)

    def getInterval(self, from_stamp: Time, to_stamp: Time) -> list[Any]:
        """The cached messages stamped in ``[from_stamp, to_stamp]``, oldest first."""
        assert from_stamp <= to_stamp
        return [m for m, t in zip(self.cache_msgs, self.cache_times)
                if from_stamp <= t <= to_stamp]

    def getElemAfterTime(self, stamp: Time) -> Any:
        """The first cached message stamped at or after ``stamp``, or None."""
        for m, t in zip(self.cache_msgs, self.cache_times):
            if t >= stamp:
                return m
        return None

    def getElemBeforeTime(self, stamp: Time) -> Any:
        """The last cached message stamped at or before ``stamp``, or None."""
        found = None
        for m, t in zip(self.cache_msgs, self.cache_times):
            if t <= stamp:
                found = m
        return found

    def getLatestTime(self) -> Time | None:
        """The stamp of the newest cached message, or None."""
        return self.cache_times[-1] if self.cache_times else None

    def getLastestTime(self) -> Time | None:
        """:meth:`getLatestTime` (rospy's old spelling, kept as Noetic keeps it)."""
        return self.getLatestTime()

    def getOldestTime(self) -> Time | None:
        """The stamp of the oldest cached message, or None."""
        return self.cache_times[0] if self.cache_times else None

    def getLast(self) -> Any:
        """The first cached message stamped at or after the newest stamp, or None."""
        latest = self.getLatestTime()
        return None if latest is None else self.getElemAfterTime(latest)


class TimeSynchronizer(SimpleFilter):
    """Signals ``(msg_1, ..., msg_N)``, one message of each filter of ``fs``, whenever the
    inputs hold messages of one ``header.stamp``; each input keeps ``queue_size`` stamps."""

    def __init__(self, fs: Sequence[SimpleFilter], queue_size: int, reset: bool = False) -> None:
        super().__init__()
        self.connectInput(fs)
        self.queue_size = queue_size
        self.enable_reset = reset

    def connectInput(self, fs: Sequence[SimpleFilter]) -> None:
        """Take the messages of the filters ``fs``, one queue each."""
        self.queues: list[dict[Time, Any]] = [{} for _ in fs]
        self.latest_stamps: list[Time] = [Time(0) for _ in fs]
        self.input_connections = [f.registerCallback(self.add, q, i)
                                  for i, (f, q) in enumerate(zip(fs, self.queues))]

    def _clock_jumped(self, my_queue: dict[Time, Any], my_queue_index: int | None,
                      now: Time, simtime: bool) -> None:
        """``reset``: clear the queue of an input whose ROS time went back."""
        if simtime and self.enable_reset and my_queue_index is not None:
            if now < self.latest_stamps[my_queue_index]:
                _rospy.logdebug("Detected jump back in time. Clearing message filter queue")
                my_queue.clear()
            self.latest_stamps[my_queue_index] = now

    def _waiting_for_others(self, now: Time, simtime: bool) -> bool:
        """``reset``: another input's clock is ahead (its time has not come here yet)."""
        return simtime and self.enable_reset and max(self.latest_stamps) != now

    def _trim(self, my_queue: dict[Time, Any]) -> None:
        while len(my_queue) > self.queue_size:
            del my_queue[min(my_queue)]

    def add(self, msg: Any, my_queue: dict[Time, Any], my_queue_index: int | None = None) -> None:
        """Queue ``msg`` of one input; signal every set now complete, oldest stamp first."""
        now = Time.now()
        simtime = not _rospy.is_wallclock()
        self._clock_jumped(my_queue, my_queue_index, now, simtime)
        my_queue[msg.header.stamp] = msg
        self._trim(my_queue)
        if self._waiting_for_others(now, simtime):
            return
        first, *others = self.queues
        common = sorted(t for t in first if all(t in q for q in others))
        for t in common:
            msgs = [q[t] for q in self.queues]
            self.signalMessage(*msgs)
            for q in self.queues:
                del q[t]


class ApproximateTimeSynchronizer(TimeSynchronizer):
    """:class:`TimeSynchronizer` whose sets may span less than ``slop`` seconds (Noetic's
    Python policy, see the module docstring)."""

    def __init__(self, fs: Sequence[SimpleFilter], queue_size: int, slop: float,
                 allow_headerless: bool = False, reset: bool = False) -> None:
        super().__init__(fs, queue_size)
        self.slop = Duration.from_sec(slop)
        self.allow_headerless = allow_headerless
        self.last_added = Time()
        self.enable_reset = reset

    def add(self, msg: Any, my_queue: dict[Time, Any], my_queue_index: int | None = None) -> None:
        """Queue ``msg`` of one input; signal the first set around it within ``slop``."""
        stamp = _stamp_or_now(msg, self.allow_headerless)
        if stamp is None:
            return
        now = Time.now()
        simtime = not _rospy.is_wallclock()
        self._clock_jumped(my_queue, my_queue_index, now, simtime)
        my_queue[stamp] = msg

        now = Time.now()
        if now < self.last_added:
            _rospy.loginfo("ApproximateTimeSynchronizer: Detected jump back in time. Clearing "
                           "buffer.")
            for q in self.queues:
                q.clear()
        self.last_added = now

        self._trim(my_queue)
        if self._waiting_for_others(now, simtime):
            return

        if my_queue_index is None:
            search = list(self.queues)
        else:
            search = self.queues[:my_queue_index] + self.queues[my_queue_index + 1:]
        candidates: list[list[Time]] = []
        for q in search:
            near = [(t, abs(t - stamp)) for t in q]
            near = [(t, d) for t, d in near if not d > self.slop]
            if not near:
                return
            near.sort(key=lambda td: td[1])
            candidates.append([t for t, _ in near])
        for combo in itertools.product(*candidates):
            stamps = list(combo)
            if my_queue_index is not None:
                stamps.insert(my_queue_index, stamp)
            pairs = list(zip(self.queues, stamps))
            if max(stamps) - min(stamps) < self.slop and all(t in q for q, t in pairs):
                msgs = [q[t] for q, t in pairs]
                self.signalMessage(*msgs)
                for q, t in pairs:
                    del q[t]
                break
