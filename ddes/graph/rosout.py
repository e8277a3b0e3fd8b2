"""Logging: loginfo/logwarn/... recorded in the trace, published on /rosout.

Each log call (when its level is enabled for the node):

* appends a ``log`` trace event (level, text, caller file and line);
* publishes a ``rosgraph_msgs/Log`` on ``/rosout`` (stamp = the node's ROS
  time, level DEBUG=1, INFO=2, WARN=4, ERROR=8, FATAL=16, the node's name and
  published topics), as rospy does;
* prints the line as rospy formats it, ``[INFO] [12.500000]: text`` (the
  time is the kernel ("wall") time, followed by the ROS time for nodes on
  simulated time), if the world has a console (``world.log_output``).

``*_throttle(period, msg)`` logs at most once per ``period`` of the node's
ROS time per call site; ``*_once`` logs once per call site (rospy keys both
by the caller's file and line).
"""

from __future__ import annotations

import sys
from collections.abc import Callable
from typing import TYPE_CHECKING

from ddes.errors import DdesValueError

if TYPE_CHECKING:
    from ddes.graph.node import Node
    from ddes.graph.topics import Publisher
    from ddes.msg.message import Message
    from ddes.time.units import DurationLike

__all__ = ["DEBUG", "ERROR", "FATAL", "INFO", "LEVEL_NAMES", "WARN", "NodeLogger", "format_line",
           "format_line_roscpp"]

DEBUG, INFO, WARN, ERROR, FATAL = 1, 2, 4, 8, 16
LEVEL_NAMES = {DEBUG: "DEBUG", INFO: "INFO", WARN: "WARN", ERROR: "ERROR", FATAL: "FATAL"}
_BY_NAME = {"debug": DEBUG, "info": INFO, "warn": WARN, "warning": WARN, "error": ERROR,
            "fatal": FATAL}


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
            throttle: DurationLike | None = None, once: bool = False) -> None:
        """Log one line (see module docstring); ``depth`` finds the caller."""
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
        world = node.world
        world.record("log", node.name, level=LEVEL_NAMES[level], msg=text,
                     file=frame.f_code.co_filename.rsplit("/", 1)[-1], line=frame.f_lineno)
        if self._pub is not None and self._log_cls is not None and not node.is_shutdown():
            stamp = node.get_rostime()
            m = self._log_cls()
            m.header.stamp = stamp
            m.level = level
            m.name = node.name
            m.msg = text
            m.file = frame.f_code.co_filename.rsplit("/", 1)[-1]
            m.function = frame.f_code.co_name
            m.line = frame.f_lineno
            m.topics = [p.resolved_name for p in node._published]
            self._pub.publish(m)
        out: Callable[[str, int], object] | None = world.log_output
        if out is not None:
            if self.style == "roscpp":
                out(format_line_roscpp(level, text, node.clock.now_ns()), level)
            else:
                wall = world.env.now / 1e9
                ros = node.get_time() if node.use_sim_time else None
                out(format_line(level, text, wall, ros), level)
