"""roscpp's logger services: every roscpp node's ``~get_loggers`` and ``~set_logger_level``.

roscpp (``init.cpp``, ``start()``) advertises them on every node, served by rosconsole on
log4cxx: ``rosservice call /talker/get_loggers`` lists the node's loggers, sorted by name, each
with its effective level (``debug`` ... ``fatal``); ``rosservice call /talker/set_logger_level
ros.roscpp_tutorials debug`` sets one (the level in any case; an unknown level logs ``Unknown
logger level [X]`` and the call fails with an empty error text, as roscpp's handler returns
false).  ddes models rosconsole's logger tree as roscpp shows it:

* always there: ``ros`` (info), ``ros.roscpp``, ``ros.roscpp.roscpp_internal``,
  ``ros.roscpp.roscpp_internal.connections`` (inheriting) and ``ros.roscpp.superdebug`` (warn);
* ``ros.<package>`` once the node has printed a line from a file of that package (roscpp
  creates a log statement's logger when the statement first runs): a file in a package on the
  world's package path, an external node's ``logger`` (docs/external-nodes.md), or a file of a
  ddes room named as a bundled package (``ddes/rosbag/recorder.py``: ``ros.rosbag``);
* every logger a ``set_logger_level`` named (log4cxx creates it).

A logger's level is its own, else its nearest dotted ancestor's, else debug (log4cxx's root).
The node's one level (:attr:`NodeLogger.level <ddes.graph.rosout.NodeLogger.level>`) is that of
its package logger: setting ``ros.<package>``, or ``ros`` while the package logger has no level
of its own, changes what the node prints, and a level the node's code set shows as its package
logger's.  Deviations: lines the node's level hides create no logger (roscpp creates it even for
a disabled statement), and a package logger set before the node's first line takes effect at the
next ``set_logger_level``.

:func:`advertise_logger_services` gives one node the two services; :func:`roscpp_logger_services`
gives them to every roscpp-style node of a world, now and later (the console calls it).  They are
library services (:class:`~ddes.services.server.LibraryService`): listed by the master,
``rosservice`` and ``rosnode info`` as any other, not traced when they come and go (a world's
digest does not depend on them), their URI handed out when first asked for, and a service the
node's own code advertises under one of the names replaces it.
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Any

from ddes.graph.rosout import DEBUG, ERROR, FATAL, INFO, WARN
from ddes.services.server import LibraryService

if TYPE_CHECKING:
    from ddes.graph.node import Node
    from ddes.graph.world import World
    from ddes.rospack import RosPack

__all__ = ["ROSCPP_LOGGERS", "LoggerTree", "advertise_logger_services", "roscpp_logger_services"]

#: The loggers every roscpp node has, with the levels rosconsole's configuration gives them
#: (None: inherited).
ROSCPP_LOGGERS: dict[str, int | None] = {
    "ros": INFO,
    "ros.roscpp": None,
    "ros.roscpp.roscpp_internal": None,
    "ros.roscpp.roscpp_internal.connections": None,
    "ros.roscpp.superdebug": WARN,
}

#: ``set_logger_level``'s level words (roscpp upper-cases the request's level first).
_LEVEL_WORDS = {"DEBUG": DEBUG, "INFO": INFO, "WARN": WARN, "ERROR": ERROR, "FATAL": FATAL}
#: ``get_loggers``' level words.
_LEVEL_NAMES = {DEBUG: "debug", INFO: "info", WARN: "warn", ERROR: "error", FATAL: "fatal"}
#: ddes's own folder: a file in one of its rooms named as a bundled package logs as that package.
_DDES_DIR = Path(__file__).resolve().parents[1]
_KEY = "services.roscpp_logger_services"


class LoggerTree:
    """The rosconsole loggers of one roscpp node (see the module docstring)."""

    def __init__(self, node: Node, extra: tuple[str, ...] = ()) -> None:
        self.node = node
        #: Loggers with a level of their own.
        self.levels: dict[str, int] = {k: v for k, v in ROSCPP_LOGGERS.items() if v is not None}
        #: Loggers made besides the fixed ones (``set_logger_level``, ``extra``), in order.
        self.made: dict[str, None] = dict.fromkeys(extra)
        self._packages: dict[str, str | None] = {}  # file -> package (None: none)

    def effective(self, name: str) -> int:
        """The level of logger ``name``: its own, else its nearest ancestor's, else debug."""
        while True:
            level = self.levels.get(name)
            if level is not None:
                return level
            if "." not in name:
                return DEBUG
            name = name.rsplit(".", 1)[0]

    def package_loggers(self) -> list[str]:
        """``ros.<package>`` of the files the node has printed lines from, in first-use order."""
        found: dict[str, None] = {}
        rospack = self.node.world.rospack
        for path, logger in self.node.log.sites.items():
            if logger:
                found[logger] = None
                continue
            if path not in self._packages:
                self._packages[path] = _package_of(path, rospack)
            package = self._packages[path]
            if package is not None:
                found[f"ros.{package}"] = None
        return list(found)

    def loggers(self) -> dict[str, int]:
        """Every logger with its level, sorted by name (rosconsole's ``std::map``)."""
        own = self.package_loggers()
        names = {*ROSCPP_LOGGERS, *self.made, *own}
        node_level = self.node.log.level
        return {n: node_level if n in own else self.effective(n) for n in sorted(names)}

    def set_level(self, name: str, level: int) -> None:
        """``set_logger_level``: ``name`` gets ``level``; the node follows its package logger."""
        own = self.package_loggers()
        for logger in own:  # a level the node's code set is its package logger's own
            if logger not in self.levels and self.effective(logger) != self.node.log.level:
                self.levels[logger] = self.node.log.level
        self.levels[name] = level
        if name not in ROSCPP_LOGGERS:
            self.made[name] = None
        self.node.log.set_level(self.effective(own[0] if own else "ros"))


def _package_of(path: str, rospack: RosPack) -> str | None:
    """The package a source file belongs to: a package folder above it on the package path,
    else the bundled package named as the ddes room it is in."""
    try:
        file = Path(path).resolve()
    except (OSError, RuntimeError, ValueError):
        return None
    folders: dict[Path, str] = {}
    for name in rospack.list():
        try:
            folders[rospack.get_path(name).resolve()] = name
        except Exception:  # noqa: BLE001 - an unreadable package is no package of this file
            continue
    for parent in file.parents:
        if parent in folders:
            return folders[parent]
    try:
        room = file.relative_to(_DDES_DIR).parts[0]
    except (ValueError, IndexError):
        return None
    return room if room != "packages" and room in rospack else None


def advertise_logger_services(node: Node, extra: tuple[str, ...] = ()) -> LoggerTree:
    """Advertise ``~get_loggers`` and ``~set_logger_level`` on ``node``, served as roscpp serves
    them; ``extra`` names loggers the node has from the start.  Returns the node's logger tree."""
    world = node.world
    get_loggers = world.messages.get_service_class("roscpp/GetLoggers")
    set_logger_level = world.messages.get_service_class("roscpp/SetLoggerLevel")
    logger_class = world.messages.get_message_class("roscpp/Logger")
    tree = LoggerTree(node, extra)

    def get(_request: Any, response: Any) -> bool:
        response.loggers = [logger_class(name=name, level=_LEVEL_NAMES.get(level, "debug"))
                            for name, level in tree.loggers().items()]
        return True

    def put(request: Any, _response: Any) -> bool:
        word = str(request.level).upper()
        level = _LEVEL_WORDS.get(word)
        if level is None:
            node.logerr("Unknown logger level [%s]", word)
            return False
        tree.set_level(str(request.logger), level)
        return True

    LibraryService(node, "~get_loggers", get_loggers, get)
    LibraryService(node, "~set_logger_level", set_logger_level, put)
    return tree


def _observe(node: Node) -> None:
    if node.client_library != "roscpp" or node.is_shutdown():
        return
    master = node.world.master
    if master.lookup_service(node.resolve_name("~get_loggers")) is not None:
        return
    # the roscore's /rosout node is rosout's program (package rosout), which has logged
    advertise_logger_services(node, ("ros.rosout",) if node.name == "/rosout" else ())


def roscpp_logger_services(world: World) -> None:
    """Give every roscpp-style node of ``world`` (``log_style="roscpp"``, now and from now on)
    roscpp's logger services; calling it again changes nothing."""
    installed: dict[str, bool] = world.extension(_KEY, lambda _w: {"on": False})
    if installed["on"]:
        return
    installed["on"] = True
    world.node_observers.append(_observe)
    for node in list(world.nodes.values()):
        _observe(node)
