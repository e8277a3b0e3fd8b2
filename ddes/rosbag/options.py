"""The command lines of ``rosbag record`` and ``rosbag play``, defined once.

Two programs read them.  ``rosbag record ...`` typed in the console is
``rosbag_main.py``'s wrapper (argparse usage errors, exit 2); a launch file's
``<node pkg="rosbag" type="record" args="-a -O out.bag"/>`` or ``rosrun rosbag
record -a`` runs the C++ program itself (``record.cpp``, ``play.cpp``), which
logs ``Error reading options: ...`` and exits 1.  Both take the same options,
so both use:

* :func:`add_record_arguments` / :func:`add_play_arguments`: the options, on
  any ``argparse.ArgumentParser`` (the console's writes through its sinks);
* :func:`record_options` / :func:`play_options`: the parsed namespace as a
  :class:`RecordOptions` / :class:`PlayOptions`, with the checks both
  programs make (:class:`BagOptionsError` says what is wrong);
* :func:`parse_record_args` / :func:`parse_play_args`: the C++ programs' way,
  for the ``rosbag`` node types (boost's texts for unknown options and
  missing or bad values);
* :func:`resolve_path`: a user's file name as the program opens it
  (relative names start at the program's directory);
* :func:`bag_date_from_environment`: ``DDES_BAG_DATE``, the date of default
  recording names (see :mod:`ddes.rosbag.recorder`).
"""

from __future__ import annotations

import argparse
import os
import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, NoReturn

from ddes.errors import DdesValueError

if TYPE_CHECKING:
    from _typeshed import SupportsWrite

__all__ = ["BAG_DATE_ENV", "BagOptionsError", "PlayOptions", "RecordOptions",
           "add_play_arguments", "add_record_arguments", "bag_date_from_environment",
           "parse_play_args", "parse_record_args", "play_options", "record_options",
           "resolve_path"]

#: The environment variable giving the date of default recording names (``rosbag record -a``).
BAG_DATE_ENV = "DDES_BAG_DATE"


class BagOptionsError(DdesValueError):
    """A ``rosbag record``/``play`` command line that cannot run (what is wrong, and the fix)."""


# -- the options ----------------------------------------------------------------------------------

def add_record_arguments(p: argparse.ArgumentParser) -> None:
    """``rosbag record``'s options (rosbag_main.py ``record_cmd``; record.cpp takes the same)."""
    p.add_argument("topics", nargs="*")
    p.add_argument("-a", "--all", action="store_true", help="record all topics")
    p.add_argument("-e", "--regex", action="store_true", help="match topics using regular expressions")
    p.add_argument("-p", "--publish", action="store_true", help="publish a msg when the record begin")
    p.add_argument("-x", "--exclude", dest="exclude_regex", default="",
                   help="exclude topics matching the follow regular expression")
    p.add_argument("-q", "--quiet", action="store_true",
                   help="suppress console output (the C++ recorder prints its lines anyway)")
    p.add_argument("-o", "--output-prefix", dest="prefix", help="prepend PREFIX to beginning of bag name")
    p.add_argument("-O", "--output-name", dest="name", help="record to bag with name NAME.bag")
    p.add_argument("--split", action="store_true", help="(not modelled by ddes)")
    p.add_argument("--max-splits", type=int, help="(not modelled by ddes)")
    p.add_argument("--size", type=int, help="(not modelled by ddes)")
    p.add_argument("--duration", help="record a bag of maximum duration DURATION in seconds, "
                                      "unless 'm', or 'h' is appended")
    p.add_argument("-b", "--buffsize", type=int, default=256,
                   help="internal buffer in MB (ddes queues nothing, so nothing is dropped)")
    p.add_argument("--chunksize", type=int, default=768, help="Record to chunks of SIZE KB")
    p.add_argument("-l", "--limit", dest="num", type=int, default=0,
                   help="only record NUM messages on each topic")
    p.add_argument("--node", help="record all topics subscribed to by a specific node")
    p.add_argument("-j", "--bz2", dest="compression", action="store_const", const="bz2",
                   help="use BZ2 compression")
    p.add_argument("--lz4", dest="compression", action="store_const", const="lz4",
                   help="use LZ4 compression")
    p.add_argument("--tcpnodelay", action="store_true", help="(no effect in ddes)")
    p.add_argument("--udp", action="store_true", help="(no effect in ddes)")
    p.add_argument("--repeat-latched", action="store_true", help="(not modelled by ddes)")


def add_play_arguments(p: argparse.ArgumentParser) -> None:
    """``rosbag play``'s options (rosbag_main.py ``play_cmd``; play.cpp takes the same)."""
    p.add_argument("bagfiles", nargs="*")
    p.add_argument("-p", "--prefix", default="", help="prefix all output topics")
    p.add_argument("-q", "--quiet", action="store_true", help="suppress console output")
    p.add_argument("-i", "--immediate", action="store_true",
                   help="play back all messages without waiting")
    p.add_argument("--pause", action="store_true", help="start in paused mode")
    p.add_argument("--queue", type=int, default=100, help="use an outgoing queue of size SIZE")
    p.add_argument("--clock", action="store_true", help="publish the clock time")
    p.add_argument("--hz", type=float, default=100.0,
                   help="use a frequency of HZ when publishing clock time")
    p.add_argument("-d", "--delay", type=float, default=0.2,
                   help="sleep SEC seconds after every advertise call")
    p.add_argument("-r", "--rate", type=float, default=1.0,
                   help="multiply the publish rate by FACTOR")
    p.add_argument("-s", "--start", type=float, default=0.0,
                   help="start SEC seconds into the bag files")
    p.add_argument("-u", "--duration", type=float, help="play only SEC seconds from the bag files")
    p.add_argument("--skip-empty", type=float,
                   help="skip regions in the bag with no messages for more than SEC seconds")
    p.add_argument("-l", "--loop", action="store_true", help="loop playback")
    p.add_argument("-k", "--keep-alive", action="store_true",
                   help="keep alive past end of bag (useful for publishing latched topics)")
    p.add_argument("--try-future-version", action="store_true", help="(no effect in ddes)")
    p.add_argument("--topics", nargs="+", default=[], help="topics to play back")
    p.add_argument("--pause-topics", nargs="+", default=[], help="(not modelled by ddes)")
    p.add_argument("--bags", action="append", default=[], help="bags files to play back from")
    p.add_argument("--wait-for-subscribers", action="store_true",
                   help="wait for at least one subscriber on each topic before publishing")
    p.add_argument("--rate-control-topic", default="", help="(not modelled by ddes)")
    p.add_argument("--rate-control-max-delay", type=float, default=1.0, help="(not modelled)")


@dataclass
class RecordOptions:
    """A parsed ``rosbag record`` command line."""

    topics: list[str] = field(default_factory=list)
    all: bool = False
    regex: bool = False
    exclude: str | None = None
    quiet: bool = False
    prefix: str | None = None
    name: str | None = None
    duration: str | None = None
    limit: int = 0
    node: str | None = None
    compression: str = "none"
    chunksize: int = 768
    publish: bool = False
    #: Options ddes does not model that the command line asked for (``--split`` ...).
    unsupported: list[str] = field(default_factory=list)

    @property
    def ends_by_itself(self) -> str | None:
        """How the recording ends without Ctrl+C (``--duration``, ``--limit``), or None."""
        if self.duration:
            return "the end of --duration"
        return "--limit messages" if self.limit else None

    def recorder_kwargs(self) -> dict[str, Any]:
        """The keyword arguments of :class:`~ddes.rosbag.Recorder` for these options."""
        return {"all": self.all, "regex": self.regex, "exclude": self.exclude,
                "limit": self.limit, "duration": self.duration, "node": self.node,
                "output_name": self.name, "output_prefix": self.prefix,
                "compression": self.compression, "chunksize": self.chunksize,
                "publish": self.publish, "quiet": self.quiet}


def record_options(a: argparse.Namespace, *, wrapper: bool = True) -> RecordOptions:
    """Check a parsed ``rosbag record`` namespace.

    ``wrapper``: also rosbag_main.py's checks (a topic or ``-a``; not both ``-o`` and ``-O``),
    which record.cpp does not make.
    """
    if wrapper and not a.topics and not a.all and not a.node:
        raise BagOptionsError("You must specify a topic name or else use the '-a' option.")
    if wrapper and a.prefix is not None and a.name is not None:
        raise BagOptionsError("Can't set both prefix and name.")
    if a.split and not a.duration and not a.size:
        raise BagOptionsError("Split specified without giving a maximum duration or size")
    if a.chunksize < 0:
        raise BagOptionsError("Chunk size must be 0 or positive")
    if a.buffsize < 0:
        raise BagOptionsError("Buffer size must be 0 or positive")
    unsupported = [o for o, on in (("--split", a.split), ("--size", a.size),
                                   ("--max-splits", a.max_splits),
                                   ("--repeat-latched", a.repeat_latched)) if on]
    return RecordOptions(list(a.topics), a.all, a.regex, a.exclude_regex or None, a.quiet,
                         a.prefix, a.name, a.duration, a.num, a.node,
                         a.compression or "none", a.chunksize, a.publish, unsupported)


@dataclass
class PlayOptions:
    """A parsed ``rosbag play`` command line."""

    bags: list[str] = field(default_factory=list)
    prefix: str = ""
    quiet: bool = False
    immediate: bool = False
    pause: bool = False
    queue: int = 100
    clock: bool = False
    hz: float = 100.0
    delay: float = 0.2
    rate: float = 1.0
    start: float = 0.0
    duration: float | None = None
    skip_empty: float | None = None
    loop: bool = False
    keep_alive: bool = False
    topics: list[str] = field(default_factory=list)
    wait_for_subscribers: bool = False
    #: Options ddes does not model that the command line asked for (``--pause-topics`` ...).
    unsupported: list[str] = field(default_factory=list)

    @property
    def endless(self) -> list[str]:
        """The options that may keep playback going until Ctrl+C."""
        return [o for o, on in (("--loop", self.loop), ("--keep-alive", self.keep_alive),
                                ("--pause", self.pause),
                                ("--wait-for-subscribers", self.wait_for_subscribers)) if on]

    def player_kwargs(self) -> dict[str, Any]:
        """The keyword arguments of :class:`~ddes.rosbag.Player` for these options."""
        return {"prefix": self.prefix, "quiet": self.quiet, "immediate": self.immediate,
                "pause": self.pause, "queue_size": self.queue, "clock": self.clock,
                "hz": self.hz, "delay": self.delay, "rate": self.rate, "start": self.start,
                "duration": self.duration, "skip_empty": self.skip_empty, "loop": self.loop,
                "keep_alive": self.keep_alive, "topics": list(self.topics),
                "wait_for_subscribers": self.wait_for_subscribers}


def play_options(a: argparse.Namespace) -> PlayOptions:
    """A parsed ``rosbag play`` namespace as :class:`PlayOptions` (the bags may be none yet)."""
    unsupported = [o for o, on in (("--pause-topics", a.pause_topics),
                                   ("--rate-control-topic", a.rate_control_topic)) if on]
    return PlayOptions(a.bagfiles + a.bags, a.prefix, a.quiet, a.immediate, a.pause, a.queue,
                       a.clock, a.hz, a.delay, a.rate, a.start, a.duration, a.skip_empty,
                       a.loop, a.keep_alive, list(a.topics), a.wait_for_subscribers, unsupported)


# -- the C++ programs' parsing (the rosbag node types) ------------------------------------------------

class _HelpAsked(Exception):
    def __init__(self, text: str) -> None:
        super().__init__(text)
        self.text = text


class _ProgramParser(argparse.ArgumentParser):
    """argparse reporting as boost::program_options does in record.cpp/play.cpp: no exit."""

    def error(self, message: str) -> NoReturn:
        raise BagOptionsError(_boost_text(message))

    def exit(self, status: int = 0, message: str | None = None) -> NoReturn:
        raise BagOptionsError((message or "").strip() or f"exit {status}")

    def print_help(self, file: SupportsWrite[str] | None = None) -> None:
        raise _HelpAsked(self.format_help().rstrip())


def _boost_text(message: str) -> str:
    """argparse's wording of an option error in boost::program_options' words."""
    m = re.match(r"argument (\S+): expected one argument", message)
    if m:
        return f"the required argument for option '{_long(m.group(1))}' is missing"
    m = re.match(r"argument (\S+): invalid \w+ value: '(.*)'", message)
    if m:
        return f"the argument ('{m.group(2)}') for option '{_long(m.group(1))}' is invalid"
    return message


def _long(flags: str) -> str:
    return flags.split("/")[-1]


def _parse_program(prog: str, add: Any, argv: Sequence[str]) -> argparse.Namespace | str:
    p = _ProgramParser(prog=prog, add_help=True, allow_abbrev=True)
    add(p)
    try:
        ns, extra = p.parse_known_args(list(argv))
    except _HelpAsked as asked:
        return asked.text
    unknown = [x for x in extra if x.startswith("-")]
    if unknown:
        raise BagOptionsError(f"unrecognised option '{unknown[0]}'")
    if extra:
        raise BagOptionsError(f"too many positional options have been specified on the command "
                              f"line ({extra[0]!r})")
    return ns


def parse_record_args(argv: Sequence[str]) -> RecordOptions | str:
    """record.cpp's command line: :class:`RecordOptions`, or the help text for ``-h``.

    Raises :class:`BagOptionsError` (the program logs ``Error reading options: ...`` and exits 1).
    No topics at all is not an error here: the recorder itself says ``No topics specified.``.
    As in record.cpp, ``-O`` wins over ``-o``.
    """
    ns = _parse_program("record", add_record_arguments, argv)
    if isinstance(ns, str):
        return ns
    if ns.name is not None:
        ns.prefix = None
    return record_options(ns, wrapper=False)


def parse_play_args(argv: Sequence[str]) -> PlayOptions | str:
    """play.cpp's command line: :class:`PlayOptions`, or the help text for ``-h``.

    Raises :class:`BagOptionsError` (the program logs ``Error reading options: ...`` and exits 1),
    also for a command line without a bag, in play.cpp's words.
    """
    ns = _parse_program("play", add_play_arguments, argv)
    if isinstance(ns, str):
        return ns
    opts = play_options(ns)
    if not opts.bags:
        if opts.topics or ns.pause_topics:
            raise BagOptionsError("When using --topics or --pause-topics, --bags should be "
                                  "specified to list bags.")
        raise BagOptionsError("You must specify at least one bag to play back.")
    return opts


# -- files and dates -------------------------------------------------------------------------------

def resolve_path(path: str, cwd: str | None) -> str:
    """``path`` as a program started in ``cwd`` opens it (``~`` expanded; None: the process's)."""
    expanded = os.path.expanduser(path)
    if cwd is None or os.path.isabs(expanded):
        return expanded
    return os.path.join(cwd, expanded)


def bag_date_from_environment(environ: Mapping[str, str]) -> str | None:
    """``DDES_BAG_DATE`` of ``environ`` (None when unset or empty); the recorder parses it."""
    value = environ.get(BAG_DATE_ENV, "")
    return value or None
