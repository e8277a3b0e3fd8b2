"""Logging: loginfo/logwarn/... recorded in the trace, published on /rosout.

Each log call (when its level is enabled for the node):

* appends a ``log`` trace event (level, text, caller file and line); a memory address in the
  text (``<X object at 0x7f…>``, which differs in every process) is shown as ``0x…`` here, on
  ``/rosout`` and in the printed line, so a run's digest does not depend on the process;
* publishes a ``rosgraph_msgs/Log`` on ``/rosout`` (stamp = the node's ROS
  time, level DEBUG=1, INFO=2, WARN=4, ERROR=8, FATAL=16, the node's name and
  published topics), as rospy does;
* prints the line as rospy formats it, ``[INFO] [12.500000]: text`` (the
  time is the kernel ("wall") time, followed by the ROS time for nodes on
  simulated time; roscpp-style nodes print ``[ INFO] [12.500000000]: text``);
* hands a :class:`logging.LogRecord` to the standard :mod:`logging` module,
  on the logger ``ddes.node`` + the node's name with ``/`` as ``.``
  (``/robot/talker`` logs on ``ddes.node.robot.talker``), so ``caplog``,
  handlers and levels work as for any Python library.

Where the line prints (:func:`emit_line`): a callable ``world.log_output``
(the console, ``ddes run``) receives it; with ``log_output`` None (the
default) or True, the handler ddes puts on the ``ddes.node`` logger
(:class:`RosStreamHandler`) prints it as rospy does, DEBUG and INFO on
standard output, WARN and above on standard error; ``log_output = False``
prints nothing.  The record reaches the ``logging`` module in every case
(``record.ddes_line`` is the printed line, ``record.ddes_t_ns`` the kernel
time, ``record.ddes_node`` the node).  The ``ddes.node`` logger's level is
DEBUG, so the node's own level (``set_logger_level``) decides what is
logged; raise the logger's level, or remove the handler, to silence lines.

``*_throttle(period, msg)`` logs at most once per ``period`` of the node's
ROS time per call site; ``*_once`` logs once per call site (rospy keys both
by the caller's file and line).
"""

from __future__ import annotations

import logging
import sys
from typing import TYPE_CHECKING, Any

from ddes.errors import DdesValueError
from ddes.kernel.trace import scrub_addresses

if TYPE_CHECKING:
    from ddes.graph.node import Node
    from ddes.graph.topics import Publisher
    from ddes.msg.message import Message
    from ddes.time.units import DurationLike

__all__ = ["DEBUG", "ERROR", "FATAL", "INFO", "LEVEL_NAMES", "LOGGER", "PYTHON_LEVELS", "WARN",
           "NodeLogger", "RosStreamHandler", "emit_line", "format_line", "format_line_roscpp",
           "logger_name", "show_paths"]

DEBUG, INFO, WARN, ERROR, FATAL = 1, 2, 4, 8, 16
LEVEL_NAMES = {DEBUG: "DEBUG", INFO: "INFO", WARN: "WARN", ERROR: "ERROR", FATAL: "FATAL"}
_BY_NAME = {"debug": DEBUG, "info": INFO, "warn": WARN, "warning": WARN, "error": ERROR,
            "fatal": FATAL}


#: The parent of every node's logger (``logging.getLogger("ddes.node")``).
LOGGER = "ddes.node"

#: ROS levels as :mod:`logging` levels (FATAL is CRITICAL).
PYTHON_LEVELS = {DEBUG: logging.DEBUG, INFO: logging.INFO, WARN: logging.WARNING,
                 ERROR: logging.ERROR, FATAL: logging.CRITICAL}


def logger_name(node_name: str) -> str:
    """The :mod:`logging` logger of a node: ``/robot/talker`` -> ``ddes.node.robot.talker``."""
    return LOGGER + node_name.replace("/", ".").rstrip(".")


class RosStreamHandler(logging.Handler):
    """Prints a node's line as rospy does (below WARN on stdout, else stderr), unless the world's
    ``log_output`` already printed it (or is False).

    ``sys.stdout``/``sys.stderr`` are looked up at each line, so redirections (pytest's capsys,
    ``contextlib.redirect_stdout``) see it.
    """

    def emit(self, record: logging.LogRecord) -> None:
        if getattr(record, "ddes_printed", False):
            return
        line = getattr(record, "ddes_line", None)
        if line is None:
            line = self.format(record)
        stream = sys.stderr if record.levelno >= logging.WARNING else sys.stdout
        try:
            stream.write(line + "\n")
            stream.flush()
        except BrokenPipeError:
            raise
        except Exception:  # noqa: BLE001 - logging's own policy for a failing handler
            self.handleError(record)


def _parent_logger() -> logging.Logger:
    """``ddes.node``, with its :class:`RosStreamHandler` and level DEBUG on first use."""
    parent = logging.getLogger(LOGGER)
    if not any(isinstance(h, RosStreamHandler) for h in parent.handlers):
        parent.addHandler(RosStreamHandler())
        if parent.level == logging.NOTSET:
            parent.setLevel(logging.DEBUG)
    return parent


def emit_line(node: Node, level: int, text: str, line: str, *, where: tuple[str, int, str] |
              None = None) -> None:
    """Print ``line`` (the formatted ``text`` of ``node`` at ROS ``level``) where the world's
    ``log_output`` says, and hand it to :mod:`logging` (see the module docstring)."""
    world = node.world
    out = world.log_output
    printed = out is False
    if callable(out):
        out(line, level)
        printed = True
    _parent_logger()
    logger = logging.getLogger(logger_name(node.name))
    py_level = PYTHON_LEVELS.get(level, logging.INFO)
    if not logger.isEnabledFor(py_level):
        return
    fn, lno, func = where if where is not None else ("", 0, "")
    record = logger.makeRecord(logger.name, py_level, fn, lno, text, (), None, func,
                               extra={"ddes_line": line, "ddes_printed": printed,
                                      "ddes_node": node.name, "ddes_t_ns": world.env.now})
    logger.handle(record)


def show_paths(text: str, paths: dict[str, str]) -> str:
    """``text`` with each folder of ``paths`` (``{real: shown}``, World.display_paths) shown
    under its name; longer folders first, so a folder inside another keeps its own name."""
    for real in sorted(paths, key=len, reverse=True):
        if real in text:
            text = text.replace(real, paths[real])
    return text


def level_from(value: str | int) -> int:
    """A level from its name (``"info"``) or number (2)."""
    if isinstance(value, str) and value.lower() in _BY_NAME:
        return _BY_NAME[value.lower()]
    if value in LEVEL_NAMES:
        return int(value)
    raise DdesValueError(f"unknown log level {value!r}; use one of debug, info, warn, error, fatal")


def format_line(level: int, text: str, wall_s: float, ros_s: float | None) -> str:
    """rospy's console line: ``[LEVEL] [wall(, ros)]: text``."""
    stamp = f"{wall_s:f}" if ros_s is None else f"{wall_s:f}, {ros_s:f}"
    return f"[{LEVEL_NAMES[level]}] [{stamp}]: {text}"


def format_line_roscpp(level: int, text: str, ros_ns: int) -> str:
    """roscpp's console line: ``[ INFO] [secs.nsecs]: text`` (ROS time, 9 decimals)."""
    secs, nsecs = divmod(ros_ns, 1_000_000_000)
    return f"[{LEVEL_NAMES[level]:>5}] [{secs}.{nsecs:09d}]: {text}"


class NodeLogger:
    """The logging state of one node (level, throttle and once memories)."""

    def __init__(self, node: Node, level: str | int = "info", rosout: bool = True,
                 style: str = "rospy") -> None:
        if style not in ("rospy", "roscpp"):
            raise DdesValueError(f"log style must be 'rospy' or 'roscpp', got {style!r}")
        self.style = style
        self.node = node
        self.level = level_from(level)
        self._last: dict[tuple[str, int], int] = {}
        self._once: set[tuple[str, int]] = set()
        #: The files the node's printed lines came from, in first-use order, each with the
        #: logger its line named (an external node's ``ros.<package>``; "" for Python code):
        #: what roscpp's ``~get_loggers`` lists as the loggers in use.
        self.sites: dict[str, str] = {}
        self._pub: Publisher[type[Message]] | None = None
        self._log_cls: type[Message] | None = None
        if rosout:
            from ddes.graph.topics import Publisher
            from ddes.msg import get_message_class

            self._log_cls = get_message_class("rosgraph_msgs/Log")
            self._pub = Publisher(node, "/rosout", self._log_cls, latch=True, queue_size=100)

    def set_level(self, level: str | int) -> None:
        """Change the node's logger level (rosconsole set_logger_level)."""
        self.level = level_from(level)

    def log(self, level: int, msg: object, args: tuple[object, ...], depth: int = 2,
            throttle: DurationLike | None = None, once: bool = False,
            qualify: bool = False) -> None:
        """Log one line (see module docstring); ``depth`` finds the caller.

        ``qualify`` names the caller on ``/rosout`` as rospy's logger does
        (``rosgraph.roslogging.RospyLogger.findCaller``): ``Class.method`` when the calling
        frame has a ``self``, else the function's name (``<module>`` at module level)."""
        if level < self.level:
            return
        frame = sys._getframe(depth)
        site = (frame.f_code.co_filename, frame.f_lineno)
        node = self.node
        if once:
            if site in self._once:
                return
            self._once.add(site)
        if throttle is not None:
            from ddes.time.units import duration_to_ns

            period = duration_to_ns(throttle, "throttle period")
            now = node.clock.now_ns()
            last = self._last.get(site)
            if last is not None and now - last < period:
                return
            self._last[site] = now
        text = str(msg) % args if args else str(msg)
        self._emit(level, text, frame.f_code.co_filename.rsplit("/", 1)[-1],
                   _qualified(frame) if qualify else frame.f_code.co_name, frame.f_lineno,
                   frame.f_code.co_filename)

    def log_at(self, level: int, text: str, file: str, function: str, line: int,
               logger: str = "", filtered: bool = False) -> None:
        """Log one line whose call site is given, not found on the stack: a line an external
        node (a C++ process, docs/external-nodes.md) logged, already formatted.  ``logger``
        (roscpp's ``ros.<package>``) is accepted for the record; ``filtered``: the caller
        applied its loggers' levels already (else this node's level decides)."""
        if not filtered and level < self.level:
            return
        if logger and file not in self.sites:
            self.sites[file] = logger
        self._emit(level, text, file.rsplit("/", 1)[-1], function, line, file)

    def _emit(self, level: int, text: str, file: str, function: str, line_no: int,
              path: str) -> None:
        node = self.node
        world = node.world
        if path not in self.sites:
            self.sites[path] = ""
        if world.display_paths:
            text = show_paths(text, world.display_paths)
        if "0x" in text:  # an address (<X object at 0x7f…>) differs in every process
            text = scrub_addresses(text)
        world.record("log", node.name, level=LEVEL_NAMES[level], msg=text, file=file,
                     line=line_no)
        if self._pub is not None and self._log_cls is not None and not node.is_shutdown():
            stamp = node.get_rostime()
            m = self._log_cls()
            m.header.stamp = stamp
            m.level = level
            m.name = node.name
            m.msg = text
            m.file = file
            m.function = function
            m.line = line_no
            m.topics = [p.resolved_name for p in node._published]
            self._pub.publish(m)
        if self.style == "roscpp":
            line = format_line_roscpp(level, text, node.clock.now_ns())
        else:
            wall = world.env.now / 1e9
            ros = node.get_time() if node.use_sim_time else None
            line = format_line(level, text, wall, ros)
        emit_line(node, level, text, line, where=(path, line_no, function))


def _qualified(frame: Any) -> str:
    """rospy's function name of a log call: ``Class.method`` when ``frame`` has a ``self``."""
    name: str = frame.f_code.co_name
    try:
        this = frame.f_locals["self"]
    except KeyError:  # a plain function (or a module): no class to name
        return name
    return f"{this.__class__.__name__}.{name}"
