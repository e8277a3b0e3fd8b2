"""``rosbag record`` as a node of a world: :class:`Recorder`.

It follows roscpp's recorder (ros_comm ``tools/rosbag/src/recorder.cpp``,
``record.cpp``):

* an anonymous node ``/record_<n>`` logging as roscpp does
  (``[ INFO] [t]: Subscribing to /chatter``, ``Recording to 'x.bag'.``), or
  the node it is given (``on_node``: the ``rosbag/record`` node type, named
  as rosrun or roslaunch name it); each topic is subscribed as ``AnyMsg``
  (raw bytes plus the publisher's connection header) with a queue of 100;
* **the record time is the recorder's ROS time at receipt** (simulated time
  under ``/use_sim_time``), not the header stamp;
* explicit topics (sorted, de-duplicated) are subscribed at once; with
  ``all``, ``regex`` or ``node`` the master is checked at start and then every
  second of ROS time, so topics that appear later are picked up (messages
  sent before that check are not recorded, as in ROS);
* ``exclude`` (a regex, full match) subtracts from ``all``/``regex``, and
  without either implies ``all``;
* ``limit=N`` records N messages per topic, then unsubscribes it; when every
  topic is done the recording stops;
* ``duration`` stops the recording once ROS time is more than ``duration``
  past the start (the start is the first valid ROS time);
* each distinct connection header gets its own connection, so a latched
  publisher is recorded with ``latching: 1`` and two publishers on a topic
  show as two connections; the header is the publisher's (callerid, topic,
  type, md5sum, message_definition, latching), as record.cpp writes it;
* when the node shuts down (``rosnode kill``, the end of a launch, Ctrl+C)
  the recording stops and the bag is written, as record.cpp does on
  shutdown; like it, nothing more is printed (record.cpp's ``Closing``
  line comes after ``ros::shutdown()`` and never shows), and ``-q`` changes
  nothing (record.cpp reads the flag but never uses it).

Messages go into an in-memory :class:`~ddes.rosbag.Bag`
(:attr:`Recorder.bag`) and, unless ``in_memory``, into the file
``NAME.bag.active`` as they arrive, the way rosbag writes it: a v2.0 bag
whose chunks are written out when they pass ``chunksize`` KB and on every
:meth:`Recorder.flush` (the console flushes after each command), so a
killed process leaves a file ``rosbag reindex`` recovers.  When the
recording stops the index is written and the file renamed to ``NAME.bag``
(a symlink ``NAME.bag`` is followed: its target gets the bag).
:func:`close_recordings` stops every open recording of a world (the
console calls it at the end of a script, on Ctrl+D, SIGINT and SIGTERM).  File names follow ``-O``/``-o``:
``output_name`` gives exactly ``NAME.bag``; ``output_prefix`` gives
``PREFIX_YYYY-MM-DD-HH-MM-SS.bag``; neither gives the date alone.  A relative
name is written in ``cwd`` (the program's directory; None: the process's).

The date.  rosbag reads the machine's clock; ddes has no wall clock, so the
date is **the recording date of kernel time 0 plus the world's kernel time**
when the recording starts, in UTC (or ``tz``) so names never depend on ``TZ``.
Kernel time 0 is ``Recorder(date=...)``, else the world's (:func:`set_record_date`),
else its fallback (:func:`set_fallback_record_date`, the console's start), else
1970-01-01 00:00:00 (a plain world at 0 s records ``1970-01-01-00-00-00.bag``).  The
console's ``rosbag record`` and the ``rosbag/record`` node type take ``DDES_BAG_DATE``
before the fallback (:func:`default_record_date`).  Dates are written as rosbag
writes them (``2024-03-01-12-00-00``) or in ISO form (``2024-03-01T12:00:00``).

Not modelled: ``--split``/``--size``/``--max-splits``, ``--buffsize`` (nothing
is queued, so nothing is dropped), ``--min-space``, ``--repeat-latched``,
snapshots.
"""

from __future__ import annotations

import datetime
import os
import re
from collections.abc import Iterable, Mapping
from typing import IO, TYPE_CHECKING

from ddes.errors import DdesTypeError, DdesValueError, ROSBagException
from ddes.rosbag.bag import Bag, open_active, write_target
from ddes.rosbag.bagfile import StreamWriter
from ddes.rosbag.options import bag_date_from_environment, resolve_path
from ddes.time.rostime import Time
from ddes.time.units import DurationLike, HasNsec, ns_to_sec, to_ns

if TYPE_CHECKING:
    import simpy
    from simpy.events import ProcessGenerator

    from ddes.graph.node import Node
    from ddes.graph.topics import AnyMsg, Subscriber
    from ddes.graph.world import World

__all__ = ["Recorder", "bag_filename", "close_recordings", "default_record_date",
           "fallback_record_date", "flush_recordings", "open_recordings", "parse_duration",
           "parse_record_date", "record_date", "roscpp_duration_ns", "set_fallback_record_date",
           "set_record_date"]

_REGISTRY = "rosbag.recorders"


def _registry(world: World) -> list[Recorder]:
    return world.extension(_REGISTRY, lambda _w: [])


def open_recordings(world: World) -> list[Recorder]:
    """The recorders of ``world`` still recording, oldest first."""
    return [r for r in _registry(world) if r.is_recording]


def flush_recordings(world: World) -> None:
    """Write the open chunk of every open recording of ``world`` to its ``.active`` file."""
    if _REGISTRY not in world.extensions:
        return
    for rec in open_recordings(world):
        rec.flush()


def close_recordings(world: World, reason: str = "closed") -> list[Recorder]:
    """Stop every open recording of ``world`` (index written, file renamed); returns them."""
    if _REGISTRY not in world.extensions:
        return []
    stopped = open_recordings(world)
    for rec in stopped:
        rec.stop(reason)
    return stopped


def roscpp_duration_ns(seconds: float) -> int:
    """Seconds as ns the way rosbag (C++) takes them: ``ros::Duration(double)`` rounds to the
    nearest nanosecond.

    Not :func:`ddes.time.units.to_ns`, which truncates as genpy does: 1.2 s would be
    1199999999 ns, and a 10 Hz message at exactly ``--duration 1.2`` would be cut.  units.py has
    no rounding converter, so this one-liner stays (used by :class:`Recorder` and the Player).
    """
    return int(round(float(seconds) * 1e9))


def parse_duration(value: DurationLike | str) -> int:
    """``--duration``: seconds, a Duration, or text ``"30"``, ``"30s"``, ``"5m"``, ``"1h"``; ns > 0."""
    if isinstance(value, HasNsec):
        ns = to_ns(value, "duration")
    elif isinstance(value, (int, float)) and not isinstance(value, bool):
        ns = roscpp_duration_ns(value)
    elif isinstance(value, str):
        m = re.fullmatch(r"\s*([-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)\s*(\S*)\s*", value)
        if m is None:
            raise DdesValueError(f"Duration must start with a floating point number: {value!r}")
        unit = m.group(2)
        scale = {"": 1.0, "s": 1.0, "m": 60.0, "h": 3600.0}.get(unit)
        if scale is None:
            raise DdesValueError(f"Duration unit must be s, m, or h (got {unit!r} in {value!r})")
        ns = roscpp_duration_ns(float(m.group(1)) * scale)
    else:
        raise DdesTypeError(f"duration must be seconds, a Duration or text like '5m', got {value!r}")
    if ns <= 0:
        raise DdesValueError(f"Duration must be positive (got {value!r})")
    return ns


def bag_filename(output_prefix: str | None = None, output_name: str | None = None,
                 stamp_ns: int = 0, tz: datetime.tzinfo | None = None) -> str:
    """The file ``rosbag record`` writes: ``-O NAME`` → ``NAME.bag``; ``-o P`` → ``P_<date>.bag``.

    A trailing ``.bag`` is stripped from the name or prefix first.  The date
    (``%Y-%m-%d-%H-%M-%S``) is ``stamp_ns`` read as seconds since the epoch
    in ``tz`` (default: UTC, so the name never depends on the ``TZ`` of the machine).
    """
    if output_prefix is not None and output_name is not None:
        raise DdesValueError("Can't set both prefix and name.")
    prefix, append_date = (output_name, False) if output_name is not None else (output_prefix, True)
    prefix = prefix or ""
    if prefix.endswith(".bag"):
        prefix = prefix[:-4]
    parts = [prefix] if prefix else []
    if append_date:
        secs = Time.from_nsec(stamp_ns).secs
        zone = datetime.timezone.utc if tz is None else tz
        parts.append(datetime.datetime.fromtimestamp(secs, zone).strftime("%Y-%m-%d-%H-%M-%S"))
    if not parts:
        raise ROSBagException("Bag filename is empty (neither of these was specified: prefix, "
                              "append_date, split)")
    return "_".join(parts) + ".bag"


_DATE_KEY = "rosbag.record_date"
_DATE_FORMS = ("give it as rosbag names files, YYYY-MM-DD-HH-MM-SS (2024-03-01-12-00-00), or in "
               "ISO form (2024-03-01T12:00:00, 2024-03-01)")
_EPOCH = datetime.datetime(1970, 1, 1, tzinfo=datetime.timezone.utc)


def parse_record_date(value: str | datetime.datetime, tz: datetime.tzinfo | None = None) -> int:
    """A recording date as nanoseconds since the epoch.

    ``value`` is a :class:`datetime.datetime` or text: ``YYYY-MM-DD-HH-MM-SS`` (the form of
    rosbag's file names), or ISO (``2024-03-01T12:00:00``, ``2024-03-01 12:00``,
    ``2024-03-01``, with an optional ``Z``/``+01:00``).  A date without a zone is in ``tz``
    (default UTC), so ``2024-03-01-12-00-00`` names a file ``..._2024-03-01-12-00-00.bag``.
    """
    if isinstance(value, datetime.datetime):
        when = value
    elif isinstance(value, str):
        text = value.strip()
        m = re.fullmatch(r"(\d{4})-(\d{2})-(\d{2})-(\d{2})-(\d{2})-(\d{2})", text)
        try:
            if m is not None:
                year, month, day, hour, minute, second = (int(g) for g in m.groups())
                when = datetime.datetime(year, month, day, hour, minute, second)
            else:
                when = datetime.datetime.fromisoformat(re.sub(r"[zZ]$", "+00:00", text))
        except ValueError as exc:
            raise DdesValueError(f"recording date {value!r} is not a date ({exc}); "
                                 f"{_DATE_FORMS}") from None
    else:
        raise DdesTypeError(f"recording date must be text or a datetime, got {value!r}; "
                            f"{_DATE_FORMS}")
    if when.tzinfo is None:
        when = when.replace(tzinfo=datetime.timezone.utc if tz is None else tz)
    delta = when - _EPOCH
    if delta < datetime.timedelta(0):
        raise DdesValueError(f"recording date {value!r} is before 1970-01-01 (the epoch); "
                             "give a later date")
    return (delta.days * 86_400 + delta.seconds) * 1_000_000_000 + delta.microseconds * 1000


def _new_date_table(_world: object) -> dict[str, object]:
    return {}


def set_record_date(world: World, date: str | datetime.datetime | None,
                    tz: datetime.tzinfo | None = None) -> None:
    """Set the date of kernel time 0 for the default names of ``world``'s recordings.

    A recording that starts ``t`` kernel seconds later is named that date plus ``t``.
    None clears it (back to 1970-01-01, or ``DDES_BAG_DATE`` in the console).
    """
    table: dict[str, object] = world.extension(_DATE_KEY, _new_date_table)
    if date is None:
        table.pop("ns", None)
    else:
        table["ns"] = parse_record_date(date, tz)


def record_date(world: World) -> int | None:
    """The date of kernel time 0 set with :func:`set_record_date` (ns since the epoch), or None."""
    table = world.extensions.get(_DATE_KEY)
    value = table.get("ns") if isinstance(table, dict) else None
    return value if isinstance(value, int) else None


def default_record_date(world: World, environ: Mapping[str, str]) -> str | None:
    """The ``date`` the programs give a Recorder: None when the world has its own
    (:func:`set_record_date`), else ``DDES_BAG_DATE`` of ``environ`` (None when unset)."""
    if record_date(world) is not None:
        return None
    return bag_date_from_environment(environ)


class Recorder:
    """``rosbag record`` on a world (see the module docstring for the rules).

    Parameters mirror the command line: ``topics`` (positional), ``all``
    (``-a``), ``regex`` (``-e``), ``exclude`` (``-x``), ``limit`` (``-l``),
    ``duration`` (``--duration``), ``node`` (``--node``), ``output_name``
    (``-O``), ``output_prefix`` (``-o``), ``compression`` (``-j``/``--lz4``),
    ``chunksize`` in KB, ``publish`` (``-p``: latched ``begin_write`` with the
    file name), ``quiet`` (``-q``: accepted; it changes nothing, as in
    record.cpp).  ``in_memory=True`` writes no file; ``name`` is the node's
    base name (made anonymous).  ``on_node`` records on that node instead of
    a new one (the ``rosbag/record`` node type); ``cwd`` is the directory
    relative file names start at; ``date`` the date of kernel time 0 for
    default names (see the module docstring).
    """

    def __init__(self, world: World, topics: Iterable[str] = (), *, all: bool = False,
                 regex: bool = False, exclude: str | None = None, limit: int = 0,
                 duration: DurationLike | str | None = None, node: str | None = None,
                 output_name: str | None = None,
                 output_prefix: str | None = None, compression: str = "none",
                 chunksize: int = 768, publish: bool = False, quiet: bool = False,
                 in_memory: bool = False, name: str = "record",
                 tz: datetime.tzinfo | None = None, on_node: Node | None = None,
                 cwd: str | None = None,
                 date: str | datetime.datetime | None = None) -> None:
        if isinstance(topics, str):
            topics = [topics]
        self.topics = sorted(set(topics))
        if isinstance(limit, bool) or not isinstance(limit, int) or limit < 0:
            raise DdesValueError(f"limit must be an int >= 0, got {limit!r}")
        if exclude and not (all or regex):
            all = True  # rosbag: "Exclusion regex given ... Adding implicit 'record all'"
        if not self.topics:
            if limit > 0:
                raise DdesValueError("Specifying a count is not valid with automatic topic "
                                     "subscription.")
            if not all and not node:
                raise DdesValueError("No topics specified: give topics, all=True or node=...")
        try:
            self._exclude = re.compile(exclude) if exclude else None
            self._patterns = [re.compile(t) for t in self.topics] if regex else []
        except re.error as exc:
            raise DdesValueError(f"bad regular expression: {exc}") from None
        self.world = world
        self.all, self.regex, self.limit, self.node_filter = all, regex, limit, node
        self._duration_ns = None if duration is None else parse_duration(duration)
        date_ns = parse_record_date(date, tz) if date is not None else _date_of_zero(world, tz)
        self.node = on_node if on_node is not None else world.create_node(
            name, anonymous=True, log_style="roscpp")
        self._own_node = on_node is None
        #: The recording, in memory.
        self.bag = Bag(None, "w", compression=compression, chunk_threshold=1024 * chunksize,
                       clock=self.node)
        #: The file written when the recording stops, as rosbag names it (None with ``in_memory``).
        self.path: str | None = None if in_memory else bag_filename(
            output_prefix, output_name, date_ns + world.now, tz)
        #: Where that file is on disk: :attr:`path` from ``cwd``.
        self.file_path: str | None = None if self.path is None else resolve_path(self.path, cwd)
        self._recording: set[str] = set()
        self._subs: dict[str, Subscriber[type[AnyMsg]]] = {}
        self._counts: dict[str, int] = {}
        self._active = 0
        self._start_ns: int | None = None
        self._stopped = False
        #: Why the recording stopped ("limit", "duration", "stopped", ...), or None.
        self.stop_reason: str | None = None
        #: Fires (with the bag) when the recording has stopped and the file is written.
        self.done: simpy.Event = world.event()
        self._begin_pub = None
        if publish:
            from ddes.msg import get_message_class

            self._begin_pub = self.node.advertise("begin_write",
                                                  get_message_class("std_msgs/String"),
                                                  queue_size=1, latch=True)
        self._file: IO[bytes] | None = None
        self._writer: StreamWriter | None = None
        if self.file_path is not None:
            active = self.file_path + ".active"
            try:
                write_target(self.file_path)  # refuses a directory, FIFO or device, early
                self._file = open_active(active)
                self._writer = StreamWriter(self._file, compression=compression,
                                            chunk_threshold=1024 * chunksize)
            except (OSError, ROSBagException) as exc:
                if self._file is not None:
                    self._file.close()
                if self._own_node:
                    self.node.shutdown("cannot open the bag file")
                why = exc.strerror if isinstance(exc, OSError) else str(exc)
                raise ROSBagException(f"Error writing: {self.path}.active: {why}") from None
        _registry(world).append(self)
        self.node.on_shutdown(self._node_shut_down)
        if not regex:
            for topic in self.topics:
                self._subscribe(self.node.resolve_name(topic))
        #: The recorder's main process; interrupting it stops the recording.
        self.process = self.node.process(self._run())

    # -- lifecycle -------------------------------------------------------------------------
    def _run(self) -> ProcessGenerator:
        import simpy

        node = self.node
        try:
            yield node.clock.wait_valid()
            if self._stopped:
                return
            self._start_ns = node.clock.now_ns()
            target = self.path if self.path is not None else "memory"
            node.loginfo("Recording to '%s'.", target)
            self.world.record("rosbag.record", node.name, path=target, topics=self.topics)
            if self._begin_pub is not None:
                self._begin_pub.publish(data=target)
            if self.all or self.regex or self.node_filter:
                self._check_master()
                node.create_timer(1.0, lambda _ev: self._check_master())
            if self._duration_ns is not None:
                deadline = node.clock.wait_until(self._start_ns + self._duration_ns + 1)
                yield self.done | deadline
                if not self._stopped:
                    self.stop("duration")
            else:
                yield self.done
        except simpy.Interrupt:
            self.stop("interrupted")

    def stop(self, reason: str = "stopped") -> None:
        """Stop recording: unsubscribe, shut the node down, write the file."""
        if self._stopped:
            return
        self._stopped = True
        self.stop_reason = reason
        try:
            self.node.shutdown(f"rosbag record: {reason}")
        finally:  # the file is closed even if printing fails (a closed pipe)
            reg = _registry(self.world)
            if self in reg:
                reg.remove(self)
            if self.file_path is not None:
                self._close_file()
        self.world.record("rosbag.stop", self.node.name, reason=reason,
                          messages=self.bag.get_message_count())
        if not self.done.triggered:
            self.done.succeed(self.bag)

    def _node_shut_down(self, reason: str) -> None:
        """The node went (rosnode kill, the launch's end): write the bag, as record.cpp does."""
        if not self._stopped:
            self.stop(f"node shut down: {reason}" if reason else "node shut down")

    def flush(self) -> None:
        """Write the open chunk to ``NAME.bag.active`` now (what a killed process keeps)."""
        if self._writer is not None and not self._stopped:
            try:
                self._writer.flush()
            except OSError as exc:
                raise ROSBagException(f"Error writing: {self.path}.active: {exc.strerror}; "
                                      "free some space or record elsewhere") from None

    def _close_file(self) -> None:
        assert self.file_path is not None and self._writer is not None
        assert self._file is not None
        active = self.file_path + ".active"
        try:
            try:
                self._writer.close()
            finally:
                self._file.close()
            os.replace(active, write_target(self.file_path))
        except OSError as exc:
            raise ROSBagException(f"Error closing {active} as {self.path}: {exc.strerror}; the "
                                  f"chunks written so far stay in {active} (rosbag reindex "
                                  "recovers them)") from None

    @property
    def is_recording(self) -> bool:
        return not self._stopped

    @property
    def start_time(self) -> float | None:
        """ROS time (float seconds) the recording started, or None before a valid time."""
        return None if self._start_ns is None else ns_to_sec(self._start_ns)

    @property
    def recording(self) -> list[str]:
        """Topics subscribed so far (including ones whose limit was reached), sorted."""
        return sorted(self._recording)

    # -- subscriptions -------------------------------------------------------------------------
    def _subscribe(self, topic: str) -> None:
        from ddes.graph.topics import AnyMsg

        self.node.loginfo("Subscribing to %s", topic)
        self._subs[topic] = self.node.subscribe(topic, AnyMsg, self._on_message,
                                                callback_args=topic, queue_size=100)
        self._counts[topic] = self.limit
        self._recording.add(topic)
        self._active += 1

    def _should_subscribe(self, topic: str, from_node: bool = False) -> bool:
        if topic in self._recording:
            return False
        if self._exclude is not None and self._exclude.fullmatch(topic):
            return False
        if self.all or from_node:
            return True
        if self.regex:
            return any(p.fullmatch(topic) for p in self._patterns)
        return topic in self.topics

    def _check_master(self) -> None:
        if self._stopped:
            return
        master = self.world.master
        for topic, _type in master.get_published_topics():
            if self._should_subscribe(topic):
                self._subscribe(topic)
        if self.node_filter:
            who = self.node.resolve_name(self.node_filter)
            for entry in list(master.topics.values()):
                if who in entry.subscriber_nodes() and self._should_subscribe(entry.name, True):
                    self._subscribe(entry.name)

    def _on_message(self, msg: AnyMsg, topic: str) -> None:
        if self._stopped:
            return
        t = self.node.clock.now_ns()
        if self._start_ns is not None and self._duration_ns is not None \
                and t - self._start_ns > self._duration_ns:
            self.stop("duration")
            return
        bag = self.bag
        bag._write_raw(topic, msg._connection_header, msg._buff, t)
        if self._writer is not None:
            cid = bag._log[-1][1]
            try:
                self._writer.add(t, bag._connections[cid], msg._buff)
            except OSError as exc:
                raise ROSBagException(f"Error writing: {self.path}.active: {exc.strerror}; "
                                      "free some space or record elsewhere") from None
        left = self._counts.get(topic, 0)
        if left > 0:
            left -= 1
            self._counts[topic] = left
            if left == 0:
                self._subs[topic].unregister()
                self._active -= 1
                if self._active == 0:
                    self.stop("limit")

    def __repr__(self) -> str:
        state = "recording" if not self._stopped else f"stopped ({self.stop_reason})"
        return (f"<Recorder {self.node.name} {state} -> {self.path or 'memory'}: "
                f"{self.bag.get_message_count()} messages>")


# Below the recorder on purpose: its log rows name their source lines (digests depend on them).
def set_fallback_record_date(world: World, date: str | None) -> None:
    """Set the date of kernel time 0 that ``world``'s recordings use when nothing else gives
    one: no ``Recorder(date=...)``, no :func:`set_record_date`, no ``DDES_BAG_DATE`` (for the
    programs, :func:`default_record_date`).  The console sets its documented start here
    (``ddes.console.shell.CONSOLE_RECORD_DATE``); None clears it (back to 1970-01-01)."""
    if date is not None:
        parse_record_date(date)  # a bad date fails here, not at the first recording
    table: dict[str, object] = world.extension(_DATE_KEY, _new_date_table)
    if date is None:
        table.pop("fallback", None)
    else:
        table["fallback"] = date


def fallback_record_date(world: World) -> str | None:
    """The date set with :func:`set_fallback_record_date`, or None."""
    table = world.extensions.get(_DATE_KEY)
    value = table.get("fallback") if isinstance(table, dict) else None
    return value if isinstance(value, str) else None


def _date_of_zero(world: World, tz: datetime.tzinfo | None) -> int:
    """The date of kernel time 0 of a Recorder given none: the world's, else its fallback."""
    own = record_date(world)
    if own is not None:
        return own
    fallback = fallback_record_date(world)
    return 0 if fallback is None else parse_record_date(fallback, tz)
