"""``rosbag play`` as a node of a world: :class:`Player`.

It follows roscpp's player (ros_comm ``tools/rosbag/src/player.cpp``) on
the kernel clock, which is ddes's wall clock:

* an anonymous node ``/play_<n>`` (always on kernel time) advertises one
  publisher per (callerid, topic) of the bag, with the connection's type,
  md5sum and definition and ``latch`` from its ``latching`` header; it
  publishes the recorded bytes unchanged (no header rewriting), and it
  advertises ``/clock``;
* after advertising it waits ``delay`` (0.2 s), so subscribers connect;
* with ``start`` > 0 it first re-publishes, per (callerid, topic), the last
  latched message from before the start;
* **bag time maps onto kernel time scaled by** ``rate``: a message ``d``
  bag-seconds after the first of the view goes out ``d / rate`` seconds
  after playback starts (re-based after a pause, a step or a skip);
* ``clock=True`` publishes the bag time on ``/clock`` every ``1/hz`` kernel
  seconds while waiting, and — where ROS's clock lags by up to one tick —
  publishes the message's own time just before each message, so a node on
  simulated time reads exactly the recorded time when the message arrives;
* ``loop`` starts over at once after the last message: the clock jumps back,
  which simulated-time nodes see as ROS defines it (``Rate`` raises
  ``ROSTimeMovedBackwardsException`` unless ``reset=True``, timers restart);
* ``immediate`` publishes everything at once; ``skip_empty`` jumps over gaps
  longer than that; ``duration`` plays that many bag seconds; ``topics``
  selects topics; ``pause`` starts paused; :meth:`pause`, :meth:`resume`,
  :meth:`toggle_pause` and :meth:`step` are the keyboard's space and ``s``;
  ``keep_alive`` keeps the node (and its latched publishers) after the end;
  ``wait_for_subscribers`` waits until every publisher has a subscriber.

A loop that would take no simulated time (``immediate``, a bag spanning
zero time, or every gap skipped) raises ROSBagException instead of
publishing without end at one instant.  Not modelled: the
``~pause_playback`` service, ``--pause-topics``, ``--rate-control-topic``.

What it prints is play.cpp's: ``[ INFO] [t]: Opening x.bag`` (the node's
roscpp-style log, for every bag given as a path or a named Bag), then on
``out`` (standard output): an empty line, ``Waiting 0.2 seconds after
advertising topics... done.``, an empty line, ``Hit space to toggle paused,
or 's' to step.``, the status line and ``Done.``.  play.cpp rewrites its
status line `` [RUNNING]  Bag Time: ...   Duration: ... / ...`` in place
(``\r``) about every 0.1 s; a transcript shows it **once per pass over the
bag, as the terminal shows it when the pass ends** (the values of play.cpp's
last rewrite: the bag time where it last waited, 0.1 s ticks of the wall clock
scaled by the rate), and once more, with the time reached, when playback is
stopped (kill, Ctrl+C, the node shut down); no trailing blanks.  ``quiet``
drops the first empty line and the status lines, as ``-q`` does.  A stopped
player prints no ``Done.``.  With ``on_node`` the player runs on that node
(the ``rosbag/play`` node type); ``cwd`` is where relative bag paths start.
"""

from __future__ import annotations

import heapq
import math
import os
from collections.abc import Callable, Iterable, Iterator, Sequence
from fractions import Fraction
from typing import IO, TYPE_CHECKING, ClassVar, Union

from ddes.errors import DdesValueError, ROSBagException, ROSBagUnindexedException
from ddes.rosbag.bag import Bag
from ddes.rosbag.options import resolve_path
from ddes.rosbag.recorder import roscpp_duration_ns
from ddes.rosbag.records import ConnectionInfo
from ddes.time.rate import roscpp_period_ns
from ddes.time.rostime import Time
from ddes.time.units import ns_to_sec

if TYPE_CHECKING:
    import simpy
    from simpy.events import ProcessGenerator

    from ddes.graph.node import Node
    from ddes.graph.topics import Publisher
    from ddes.graph.world import World
    from ddes.msg.message import MessageClass

__all__ = ["NO_MESSAGES", "BagSource", "Player", "RawBytes", "raw_message_class"]

#: play.cpp's words (on standard error) when the view to play is empty.
NO_MESSAGES = "No messages to play on specified topics.  Exiting."

#: A bag to play: a :class:`~ddes.rosbag.Bag` or the path of a .bag/MCAP file.
BagSource = Union[Bag, str, "os.PathLike[str]"]


class RawBytes:
    """Base of :func:`raw_message_class`: recorded bytes, published unchanged."""

    __slots__ = ("_buff",)

    _type: ClassVar[str] = ""
    _md5sum: ClassVar[str] = ""
    _full_text: ClassVar[str] = ""
    _has_header: ClassVar[bool] = False
    _slot_types: ClassVar[list[str]] = []

    def __init__(self, buff: bytes = b"") -> None:
        self._buff = buff

    def _serialize_to_bytes(self) -> bytes:
        return self._buff

    def _deserialize_from(self, data: bytes) -> RawBytes:
        self._buff = bytes(data)
        return self

    def serialize(self, buff: IO[bytes]) -> None:
        buff.write(self._buff)


def raw_message_class(conn: ConnectionInfo) -> type[RawBytes]:
    """A class publishing a connection's recorded bytes unchanged (roscpp's ShapeShifter)."""
    name = conn.datatype.replace("/", "__") + "__Raw"
    return type(name, (RawBytes,), {
        "__slots__": (), "_type": conn.datatype, "_md5sum": conn.md5sum,
        "_full_text": conn.msg_def, "_has_header": False, "_slot_types": [],
        "__doc__": f"Recorded bytes of a {conn.datatype} message.",
    })


def _check_seconds(value: float, what: str, minimum: float | None = None,
                   strict: bool = False) -> float:
    """``value`` if it is a finite number of seconds (``>``/``>= minimum``), else DdesValueError."""
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        raise DdesValueError(f"{what} must be a finite number of seconds, got {value!r}")
    if minimum is not None and (value <= minimum if strict else value < minimum):
        raise DdesValueError(f"{what} must be {'>' if strict else '>='} {minimum}, got {value!r}")
    return value


#: play.cpp rewrites its status line every 0.1 s of wall time (``runClock(WallDuration(.1))``).
_STATUS_TICK_NS = 100_000_000


def _to_sec(ns: int) -> float:
    """``ros::Time::toSec()``/``Duration::toSec()``: ``sec + 1e-9 * nsec`` (nsec in [0, 1e9))."""
    sec, nsec = divmod(ns, 1_000_000_000)
    return float(sec) + 1e-9 * float(nsec)


def _scale(kernel_ns: int, rate: Fraction) -> int:
    """Bag nanoseconds that pass in ``kernel_ns`` at ``rate``."""
    return kernel_ns * rate.numerator // rate.denominator


class Player:
    """``rosbag play`` on a world; :attr:`done` fires when playback ends.

    ``bags`` is a :class:`~ddes.rosbag.Bag`, a path, or a list of them (their
    messages are merged by time).  Options mirror the command line (see the
    module docstring); ``out`` receives the lines ``rosbag play`` prints.
    """

    def __init__(self, world: World,
                 bags: BagSource | Sequence[BagSource], *, prefix: str = "",
                 quiet: bool = False,
                 immediate: bool = False, pause: bool = False, queue_size: int = 100,
                 clock: bool = False, hz: float = 100.0, delay: float = 0.2, rate: float = 1.0,
                 start: float = 0.0, duration: float | None = None,
                 skip_empty: float | None = None, loop: bool = False, keep_alive: bool = False,
                 topics: Iterable[str] = (), wait_for_subscribers: bool = False,
                 name: str = "play", out: Callable[[str], None] | None = None,
                 on_node: Node | None = None, cwd: str | None = None) -> None:
        items = [bags] if isinstance(bags, (Bag, str, os.PathLike)) else list(bags)
        if not items:
            raise DdesValueError("You must specify at least one bag file to play from")
        if isinstance(rate, bool) or not isinstance(rate, (int, float)) or not math.isfinite(rate) \
                or rate <= 0:
            raise DdesValueError(f"rate must be a finite factor > 0, got {rate!r}")
        if isinstance(hz, bool) or not isinstance(hz, (int, float)) or not math.isfinite(hz) \
                or hz <= 0:
            raise DdesValueError(f"hz must be a finite frequency > 0, got {hz!r}")
        self._tick_ns = max(1, roscpp_period_ns(hz))  # rosbag: WallDuration(1.0 / hz)
        self._delay_ns = roscpp_duration_ns(_check_seconds(delay, "delay", 0))
        start_ns = roscpp_duration_ns(_check_seconds(start, "start"))
        dur_ns = None if duration is None else roscpp_duration_ns(
            _check_seconds(duration, "Invalid duration", 0, strict=True))
        self._skip_ns = None if skip_empty is None else roscpp_duration_ns(
            _check_seconds(skip_empty, "skip_empty", 0, strict=True))
        self.world = world
        self.prefix = prefix
        self.immediate, self.loop, self.keep_alive = immediate, loop, keep_alive
        self.publish_clock = clock
        self.wait_for_subscribers = wait_for_subscribers
        self.queue_size = queue_size
        self.quiet = quiet
        self._out: Callable[[str], None] = out if out is not None else (lambda _line: None)
        self._rate = Fraction(rate)
        self.topics = list(topics)
        self.node = on_node if on_node is not None else world.create_node(
            name, anonymous=True, use_sim_time=False, log_style="roscpp")
        self._own_node = on_node is None
        try:
            self.bags = [self._open(b, cwd) for b in items]
            if prefix:
                self.node.loginfo("Using prefix '%s'' for topics ", prefix)
            if not quiet:
                self._out("")
            first_t, last_t, used = self._plan(start_ns, dur_ns)
        except BaseException:
            if self._own_node:
                self.node.shutdown("rosbag play could not start")
            raise
        #: The first and last message time of the view (play.cpp's start_time_ and bag_length_).
        self._view_begin, self._view_end = first_t, last_t
        from ddes.msg import get_message_class

        self._Clock = get_message_class("rosgraph_msgs/Clock")
        self._clock_pub = _clock_publisher(self.node, self._Clock, clock)
        self._raw: dict[tuple[str, str, str], type[RawBytes]] = {}
        self._pubs: dict[str, Publisher[type[RawBytes]]] = {}
        self._pub_classes: dict[str, type[RawBytes]] = {}
        for i, cid in used:
            self._advertise(self.bags[i]._connections[cid])
        self._paused = bool(pause)
        self._step = False
        self._stopped = False
        #: play.cpp's last status line: (paused, bag time ns), and whether it has been shown.
        self._status: tuple[bool, int] | None = None
        self._status_shown = True
        self._status_printed = False
        #: Where the wait for the next message began: (kernel ns, bag ns, rate); None: not waiting.
        self._anchor: tuple[int, int, Fraction] | None = None
        self._keep_alive_from: tuple[int, int] | None = None
        self._wake: simpy.Event = world.event()
        self._k_base = self._b_base = self._current = 0
        self._last_clock_k = -1
        self._last_clock_value = -1
        #: Messages published so far (not counting /clock).
        self.published = 0
        self._last_send_k = 0
        #: Completed passes over the bag.
        self.loops = 0
        #: Fires when playback has ended (or failed).
        self.done: simpy.Event = world.event()
        self.node.on_shutdown(self._node_shut_down)
        self.process = self.node.process(self._run())

    def _open(self, source: BagSource, cwd: str | None) -> Bag:
        """A bag of ``source``, logging play.cpp's ``Opening NAME`` first."""
        if isinstance(source, Bag):
            if source.filename is not None:
                self.node.loginfo("Opening %s", source.filename)
            return source
        label = os.fspath(source)
        self.node.loginfo("Opening %s", label)
        try:  # named as the user wrote it: "x.bag: no such bag file"
            return Bag(resolve_path(label, cwd), filename=label)
        except ROSBagUnindexedException:
            raise ROSBagUnindexedException(
                f"Bag file {label} is unindexed.  Run rosbag reindex.") from None

    def _plan(self, start_ns: int, dur_ns: int | None) -> tuple[int, int, dict[tuple[int, int], None]]:
        """The view to play: its first and last times and the (bag, connection) pairs used."""
        firsts = [b._span()[0] for b in self.bags if b.get_message_count()]
        if not firsts:
            raise ROSBagException(NO_MESSAGES)
        self._full_begin = min(firsts)
        self._initial = self._full_begin + start_ns
        self._finish = None if dur_ns is None else self._initial + dur_ns
        self._views = [b._select(self.topics or None) for b in self.bags]
        used: dict[tuple[int, int], None] = {}
        first_t = last_t = -1
        for t, i, cid, _data in self._view():
            if first_t < 0:
                first_t = t
            last_t = t
            used.setdefault((i, cid))
        if not used:
            raise ROSBagException(NO_MESSAGES)
        if self.loop and (self.immediate or last_t == first_t):
            raise ROSBagException(
                "--loop with " + ("--immediate" if self.immediate else "a view spanning no time")
                + " would publish without end at one simulated instant; drop --loop or play a "
                "longer span")
        return first_t, last_t, used

    # -- the view ---------------------------------------------------------------------------
    def _view(self, start: int | None = None, end: int | None = None,
              views: list[list[ConnectionInfo]] | None = None) -> Iterator[tuple[int, int, int, bytes]]:
        """(time, bag index, connection id, bytes) in time order (ties: bag, then connection)."""
        lo = self._initial if start is None else start
        hi = self._finish if end is None else end

        def tagged(i: int, conns: list[ConnectionInfo]) -> Iterator[tuple[int, int, int, bytes]]:
            for t, cid, data in self.bags[i]._entries(conns, lo, hi):
                yield t, i, cid, data

        parts = [tagged(i, conns) for i, conns in enumerate(views or self._views)]
        return heapq.merge(*parts, key=lambda e: e[0])

    def _key(self, i: int, cid: int) -> str:
        conn = self.bags[i]._connections[cid]
        return conn.callerid + conn.topic

    def _advertise(self, conn: ConnectionInfo) -> None:
        key = conn.callerid + conn.topic
        if key in self._pubs:
            return
        raw_key = (conn.datatype, conn.md5sum, conn.msg_def)
        cls = self._raw.get(raw_key)
        if cls is None:
            cls = self._raw[raw_key] = raw_message_class(conn)
        self._pub_classes[key] = cls
        self._pubs[key] = self.node.advertise(self.prefix + conn.topic, cls,
                                              queue_size=self.queue_size, latch=conn.latching)

    # -- controls -----------------------------------------------------------------------------
    def _poke(self) -> None:
        wake, self._wake = self._wake, self.world.event()
        if not wake.triggered:
            wake.succeed()

    @property
    def is_paused(self) -> bool:
        return self._paused

    def pause(self) -> None:
        """Pause playback (the bag clock freezes; /clock keeps repeating it)."""
        if not self._paused:
            self._current = self._bag_now()
            self._paused = True
            self._anchor = None
            if self._status is not None:
                self._set_status(True, self._current)
            self._poke()

    def resume(self) -> None:
        """Resume playback from the frozen bag time."""
        if self._paused:
            self._paused = False
            self._rebase(self.world.now, self._current)
            self._anchor = None
            self._poke()

    def toggle_pause(self) -> None:
        """The space bar."""
        if self._paused:
            self.resume()
        else:
            self.pause()

    def step(self) -> bool:
        """While paused, publish the next message now ('s'); False when not paused."""
        if not self._paused:
            return False
        self._step = True
        self._poke()
        return True

    def set_rate(self, rate: float) -> None:
        """Change the rate factor from now on (the keyboard's + and -)."""
        if isinstance(rate, bool) or not isinstance(rate, (int, float)) or not rate > 0 \
                or not math.isfinite(rate):
            raise DdesValueError(f"rate must be a finite factor > 0, got {rate!r}")
        if not self._paused:
            self._current = self._bag_now()
            self._rebase(self.world.now, self._current)
        self._rate = Fraction(rate)
        self._poke()

    def stop(self, reason: str = "stopped") -> None:
        """End playback now and shut the node down."""
        if self._stopped:
            return
        if reason != "done":
            self._show_status(final=True)  # play.cpp ends the status line it was rewriting
        self._stopped = True
        self.node.shutdown(f"rosbag play: {reason}")
        self.world.record("rosbag.done", self.node.name, reason=reason, published=self.published)
        self._poke()
        if not self.done.triggered:
            self.done.succeed(self.published)

    def _node_shut_down(self, reason: str) -> None:
        """The node went (rosnode kill, the launch's end): playback ends."""
        if not self._stopped:
            self.stop(f"node shut down: {reason}" if reason else "node shut down")

    # -- the status line ------------------------------------------------------------------------
    def status_line(self) -> str | None:
        """play.cpp's status line as it stands (None before playback has begun)."""
        if self._status is None:
            return None
        paused, b = self._status
        return (f" [{'PAUSED ' if paused else 'RUNNING'}]  Bag Time: {_to_sec(b):13.6f}   "
                f"Duration: {_to_sec(b - self._view_begin):.6f} / "
                f"{_to_sec(self._view_end - self._view_begin):.6f}")

    def _set_status(self, paused: bool, b: int) -> None:
        self._status = (paused, b)
        self._status_shown = False

    def _show_status(self, final: bool = False) -> None:
        """Print the status line unless it is shown already (or ``quiet``)."""
        if final and not self._paused:
            # stopped while waiting: the last 0.1 s rewrite before now
            since = self._keep_alive_from or (self._anchor[:2] if self._anchor else None)
            if since is not None:
                k0, b0 = since
                ticks = (self.world.now - k0) // _STATUS_TICK_NS
                self._set_status(False, b0 + _scale(ticks * _STATUS_TICK_NS, self._rate))
        if self._status is None or self._status_shown or self.quiet:
            return
        line = self.status_line()
        self._status_shown = True
        if line is not None:
            self._out(line)
            self._status_printed = True

    def _status_after_wait(self, t: int) -> None:
        """play.cpp printed the time every 0.1 s of the wait for a message at ``t``: the last."""
        anchor, self._anchor = self._anchor, None
        if anchor is None:
            return
        _k0, b0, rate = anchor
        step = rate * _STATUS_TICK_NS
        if t <= b0 or step <= 0:
            return
        ticks = -(-(t - b0) // step) - 1  # the last tick strictly before t
        self._set_status(False, b0 + math.floor(ticks * step))

    @property
    def bag_time(self) -> Time:
        """The player's current bag time (what /clock would say now)."""
        return Time._from_ns(self._bag_now())

    # -- time translation -----------------------------------------------------------------------
    def _rebase(self, k: int, b: int) -> None:
        self._k_base, self._b_base = k, b

    def _bag_now(self) -> int:
        if self._paused:
            return self._current
        r = self._rate
        return self._b_base + (self.world.now - self._k_base) * r.numerator // r.denominator

    def _kernel_at(self, b: int) -> int:
        r = self._rate
        return self._k_base - (-(b - self._b_base) * r.denominator // r.numerator)

    def _publish_clock(self, value: int) -> None:
        if self.publish_clock and not self._stopped:
            self._clock_pub.publish(self._Clock(clock=Time._from_ns(value)))
            self._last_clock_k = self._last_send_k = self.world.now
            self._last_clock_value = value

    def _emit(self, t: int, i: int, cid: int, data: bytes) -> None:
        self._current = t
        self._rebase(self.world.now, t)
        if self._last_clock_value != t or self._last_clock_k != self.world.now:
            self._publish_clock(t)
        self._send(self._key(i, cid), data)

    def _send(self, key: str, data: bytes) -> None:
        self._pubs[key].publish(self._pub_classes[key](data))
        self.published += 1
        self._last_send_k = self.world.now

    def _wait(self, until_k: int | None) -> simpy.Event:
        env = self.world.env
        wake = self._wake
        if until_k is None:
            return wake
        return env.any_of([env.timeout(max(0, until_k - env.now)), wake])

    # -- the process ------------------------------------------------------------------------------
    def _run(self) -> ProcessGenerator:
        import simpy

        try:
            yield from self._play()
        except simpy.Interrupt:
            self.stop("interrupted")
            return
        except ROSBagException as exc:
            self._stopped = True
            self.node.shutdown(f"rosbag play failed: {exc}")
            if not self.done.triggered:
                self.done.fail(exc)
            return
        if not self._stopped:
            yield from self._drain()
            if not self._status_printed:  # play.cpp ends its status line: without one, a blank
                self._out("")
            self._out("Done.")
            self.stop("done")

    def _drain(self) -> ProcessGenerator:
        """Wait until the messages already sent have arrived, then let the node go."""
        env = self.world.env
        horizon = env.now
        pubs: list[Publisher[MessageClass]] = [*self._pubs.values(), self._clock_pub]
        for pub in pubs:
            for conn in pub.connections:
                horizon = max(horizon, conn._last, self._last_send_k + conn._fixed)
        yield env.timeout(horizon - env.now)

    def _play(self) -> ProcessGenerator:
        env = self.world.env
        yield env.timeout(self._delay_ns)
        self._out(f"Waiting {ns_to_sec(self._delay_ns):g} seconds after advertising topics... "
                  "done.")
        self._out("")
        self._out("Hit space to toggle paused, or 's' to step.")
        if self._initial > self._full_begin:
            self._republish_latched()
        if self.wait_for_subscribers:
            self._out("Waiting for subscribers.")
            while not self._stopped and any(p.get_num_connections() == 0
                                            for p in self._pubs.values()):
                yield self.world.timeout(0.1)
            if not self._stopped:
                self._out("Finished waiting for subscribers.")
        self.world.record("rosbag.play", self.node.name, bags=len(self.bags),
                          rate=float(self._rate), clock=self.publish_clock)
        while not self._stopped:
            began = env.now
            view = self._view()
            first = True
            for t, i, cid, data in view:
                if self._stopped:
                    return
                if first:
                    first = False
                    self._current = t
                    self._rebase(env.now, t)
                yield from self._do_publish(t, i, cid, data)
            if self._stopped:
                return
            self.loops += 1
            self.world.record("rosbag.loop", self.node.name, loops=self.loops,
                              published=self.published)
            if self.keep_alive:
                yield from self._keep_alive()
                return
            self._show_status()
            if not self.loop:
                return
            if env.now == began:
                raise ROSBagException(
                    "--loop: a pass over the bag took no simulated time (every gap was skipped); "
                    "it would publish without end at one instant")

    def _republish_latched(self) -> None:
        latched = [[c for c in conns if c.latching] for conns in
                   (b._select(self.topics or None) for b in self.bags)]
        last: dict[tuple[str, str], tuple[int, int, int, bytes]] = {}
        for entry in self._view(self._full_begin, self._initial, latched):
            conn = self.bags[entry[1]]._connections[entry[2]]
            self._advertise(conn)
            last[(conn.callerid, conn.topic)] = entry
        for (callerid, topic) in sorted(last):
            self._send(callerid + topic, last[(callerid, topic)][3])

    def _do_publish(self, t: int, i: int, cid: int, data: bytes) -> ProcessGenerator:
        if self.immediate:
            self._emit(t, i, cid, data)
            self._set_status(False, t)
            return
        if self._skip_ns is not None and t - self._bag_now() > self._skip_ns and not self._paused:
            self._emit(t, i, cid, data)
            self._set_status(False, t)
            return
        env = self.world.env
        while not self._stopped:
            if self._paused:
                self._anchor = None
                if self._step:
                    self._step = False
                    self._emit(t, i, cid, data)
                    self._set_status(True, t)
                    return
                self._set_status(True, self._current)
                tick = self._last_clock_k + self._tick_ns if self.publish_clock else None
                if tick is not None and tick <= env.now:
                    self._publish_clock(self._current)
                    continue
                yield self._wait(tick)
                continue
            due = self._kernel_at(t)
            if due <= env.now:
                self._status_after_wait(t)
                self._emit(t, i, cid, data)
                return
            if self._anchor is None or self._anchor[2] != self._rate:
                self._anchor = (env.now, self._bag_now(), self._rate)
            tick = max(self._last_clock_k + self._tick_ns, env.now) if self.publish_clock else None
            if tick is not None and tick < due:
                if tick <= env.now:
                    self._publish_clock(min(self._bag_now(), t))
                    continue
                yield self._wait(tick)
                continue
            yield self._wait(due)

    def _keep_alive(self) -> ProcessGenerator:
        env = self.world.env
        self._keep_alive_from = (env.now, self._bag_now())
        while not self._stopped:
            if not self.publish_clock:
                yield self._wait(None)
                continue
            tick = self._last_clock_k + self._tick_ns
            if tick <= env.now:
                self._publish_clock(self._bag_now())
                continue
            yield self._wait(tick)

    def __repr__(self) -> str:
        state = "stopped" if self._stopped else ("paused" if self._paused else "playing")
        return f"<Player {self.node.name} {state}: {self.published} published>"


# Below the player on purpose: its log rows name their source lines (digests depend on them).
_SILENT_CLOCK_KEY = "rosbag.silent_clock"


def _new_silent(_world: object) -> list[Publisher[MessageClass]]:
    return []


def _clock_publisher(node: Node, clock_class: MessageClass, clock: bool
                     ) -> Publisher[MessageClass]:
    """play.cpp's ``/clock`` publisher, advertised whether or not it will publish (``--clock``);
    one that will not is remembered (:func:`silent_clock_publishers`)."""
    pub = node.advertise("clock", clock_class, queue_size=1)
    if not clock:
        silent_clock_publishers(node.world).append(pub)
    return pub


def silent_clock_publishers(world: World) -> list[Publisher[MessageClass]]:
    """The ``/clock`` publishers of ``world``'s live players without ``clock``: advertised, as
    play.cpp advertises ``/clock`` always, but never publishing (the console's simulated-time
    notice, :func:`ddes.console.tooling.sim_time_notice`, does not count them)."""
    silent: list[Publisher[MessageClass]] = world.extension(_SILENT_CLOCK_KEY, _new_silent)
    silent[:] = [p for p in silent if not p.node.is_shutdown()]
    return silent
