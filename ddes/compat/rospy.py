"""rospy's module-level API on simulated time: ``from ddes.compat import rospy``.

The same names and behaviour as rospy (``init_node``, ``Publisher``, ``Rate``,
``sleep``, ``spin``, ``ServiceProxy`` ...), but every call acts on the node of
the running greenlet (:func:`ddes.graph.blocking.current_node`) instead of a
process-global node: a ddes world holds many rospy nodes at once, each its
own script on its own greenlet.  Blocking calls (``rate.sleep()``,
``rospy.sleep()``, ``rospy.spin()``, ``proxy(req)``, ``wait_for_service``,
``wait_for_message``) block only the calling node and let simulated time pass.

This module keeps no state of its own: a node's rospy state (its init
arguments) lives in the world's extension slots, keyed by node.

A script runs as a node when ddes starts it (``rosrun PKG talker.py``, launch
``type="talker.py"``, :func:`ddes.compat.scripts.run_script`); there,
``import rospy`` resolves to this module.  See docs/rospy.md.
"""

from __future__ import annotations

import logging
from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING, Any

from ddes.errors import (
    BlockingOutsideNodeError,
    ROSException,
    ROSInitException,
    ROSInterruptException,
    ROSSerializationException,
    ROSTimeMovedBackwardsException,
    ServiceException,
)
from ddes.graph.blocking import INIT_TEXT, attach, current_task, wait, wait_ns
from ddes.graph.names import NameResolver
from ddes.graph.rosout import DEBUG as _DEBUG
from ddes.graph.rosout import ERROR as _ERROR
from ddes.graph.rosout import FATAL as _FATAL
from ddes.graph.rosout import INFO as _INFO
from ddes.graph.rosout import WARN as _WARN
from ddes.graph.timer import Timer as _Timer
from ddes.graph.timer import TimerEvent
from ddes.graph.topics import AnyMsg
from ddes.graph.topics import Publisher as _Publisher
from ddes.graph.topics import Subscriber as _Subscriber
from ddes.msg import get_message_class
from ddes.services import Service as _Service
from ddes.services import ServiceProxy as _ServiceProxy
from ddes.services import wait_for_service as _wait_for_service
from ddes.time.rate import Rate as _Rate
from ddes.time.rostime import Duration, Time

if TYPE_CHECKING:
    from ddes.graph.node import Node
    from ddes.time.units import DurationLike

__all__ = [
    "DEBUG", "ERROR", "FATAL", "INFO", "WARN",
    "AnyMsg", "Duration", "Header", "Publisher", "ROSException", "ROSInitException",
    "ROSInterruptException", "ROSSerializationException", "ROSTimeMovedBackwardsException",
    "Rate", "Service", "ServiceException", "ServiceProxy", "Subscriber", "Time", "Timer",
    "TimerEvent",
    "delete_param", "get_caller_id", "get_name", "get_namespace", "get_param", "get_param_cached",
    "get_param_names", "get_rostime", "get_time", "has_param", "init_node", "is_shutdown",
    "logdebug", "logdebug_once", "logdebug_throttle", "logerr", "logerr_once", "logerr_throttle",
    "logfatal", "logfatal_once", "logfatal_throttle", "loginfo", "loginfo_once",
    "loginfo_throttle", "logout", "logwarn", "logwarn_once", "logwarn_throttle", "myargv",
    "on_shutdown", "resolve_name", "rostime", "search_param", "set_param", "signal_shutdown",
    "sleep", "spin",
    "wait_for_message", "wait_for_service",
]

#: rospy's log levels (rosgraph_msgs/Log's constants).
DEBUG, INFO, WARN, ERROR, FATAL = 1, 2, 4, 8, 16
_LEVEL_NAMES = {DEBUG: "debug", INFO: "info", WARN: "warn", ERROR: "error", FATAL: "fatal"}

#: rospy.Header: std_msgs/Header.
Header = get_message_class("std_msgs/Header")

#: The fix appended to a ROSInitException raised outside any node.
_HOW = (" (ddes: a rospy call acts on the node of the code that makes it; this code runs outside "
        "any rospy node. Start the script as a node — rosrun PKG script.py, a launch file's "
        "<node type=\"script.py\">, ddes.compat.scripts.run_script — and call rospy.init_node "
        "first; in yield-style code use the node's own methods: node.get_time(), "
        "yield node.sleep(0.5))")

_INIT_ARGS_KEY = "compat.rospy.init_args"


# -- the node of the running code -------------------------------------------------------------
def _current() -> Node | None:
    task = current_task()
    return task.node if task is not None else None


def _node(text: str = "client code must call rospy.init_node() first") -> Node:
    node = _current()
    if node is None:
        raise ROSInitException(text + _HOW)
    return node


def _time_node() -> Node:
    """The node for a call that reads ROS time (rospy's "time is not initialized" before init)."""
    return _node(INIT_TEXT)


def _blocking_node(what: str) -> Node:
    node = _current()
    if node is None:
        raise BlockingOutsideNodeError(
            f"{what}: {INIT_TEXT} A blocking rospy call needs the node of a running rospy script "
            "(after rospy.init_node); in yield-style code write `yield node.sleep(0.5)`, "
            "`yield rate.sleep()` instead (or `from ddes.compat import rospy` in a script node "
            "to write plain rospy).")
    return node


# -- initialisation ----------------------------------------------------------------------------
def init_node(name: str, argv: list[str] | None = None, anonymous: bool = False,
              log_level: int | None = None, disable_rostime: bool = False,
              disable_rosout: bool = False, disable_signals: bool = False,
              xmlrpc_port: int = 0, tcpros_port: int = 0) -> None:
    """rospy.init_node: this script's node registers with the master.

    ``argv`` defaults to the script's own command line (its ``sys.argv``: remappings, ``_param:=``,
    ``__name:=``, ``__ns:=``). A second call with the same arguments does nothing; with
    different ones it raises rospy's ROSException.
    """
    task = current_task()
    if task is None:
        raise ROSInitException(
            "rospy.init_node() outside any script node: ddes runs a rospy script as a node "
            "when it starts it (rosrun PKG script.py, a launch file, or "
            "ddes.compat.scripts.run_script(world, path)); the script's code then calls "
            "init_node. To write nodes in Python around a world, use world.create_node(name).")
    context: Any = task.context
    if argv is None:
        argv = list(getattr(context, "argv", None) or [name])
    if not name:
        raise ValueError("name must not be empty")
    if "/" in name:
        raise ValueError("namespaces are not allowed in node names")
    args = (name, argv, anonymous, log_level, disable_rostime, disable_signals)
    if task.node is not None:
        table = task.world.extension(_INIT_ARGS_KEY, _new_args)
        if table.get(task.node) != args:
            raise ROSException("rospy.init_node() has already been called with different "
                               "arguments: " + str(table.get(task.node)))
        return
    level = _LEVEL_NAMES.get(log_level, "info") if log_level is not None else "info"
    node = task.world.create_node(
        name, namespace=getattr(context, "namespace", "/"), argv=list(argv[1:]),
        remappings=getattr(context, "remappings", None), anonymous=anonymous, spinner="rospy",
        log_level=level, disable_rosout=disable_rosout)
    task.world.extension(_INIT_ARGS_KEY, _new_args)[node] = args
    attach(task, node)
    if context is not None and hasattr(context, "node"):
        context.node = node
        for later in context.before_init:
            later._make()
        context.before_init.clear()


def _new_args(_world: object) -> dict[Node, tuple[object, ...]]:
    return {}


def myargv(argv: list[str] | None = None) -> list[str]:
    """rospy.myargv: the command line without remapping arguments (``a:=b``)."""
    if argv is None:
        task = current_task()
        argv = list(getattr(task.context if task else None, "argv", None) or [])
    return [a for a in argv if ":=" not in a]


def get_name() -> str:
    """rospy.get_name: the node's name (``/unnamed`` before init_node, as rospy)."""
    node = _current()
    return node.name if node is not None else "/unnamed"


get_caller_id = get_name


def get_namespace() -> str:
    """rospy.get_namespace."""
    node = _current()
    return node.get_namespace() if node is not None else "/"


def resolve_name(name: str, caller_id: str | None = None) -> str:
    """rospy.resolve_name with the node's namespace and remappings."""
    node = _current()
    if caller_id is None and node is not None:
        return node.resolve_name(name)
    base = (caller_id or "/unnamed").rsplit("/", 1)
    return NameResolver(base[1], base[0] or "/", {}).resolve(name)


# -- lifecycle -----------------------------------------------------------------------------------
def is_shutdown() -> bool:
    """rospy.is_shutdown (False before init_node, as rospy)."""
    node = _current()
    return node.is_shutdown() if node is not None else False


def on_shutdown(h: Callable[[], object]) -> None:
    """rospy.on_shutdown: ``h()`` (no argument, as rospy calls client hooks) at shutdown."""
    _node().on_shutdown(lambda _reason: h())


def signal_shutdown(reason: str) -> None:
    """rospy.signal_shutdown: shut this node down."""
    _node().signal_shutdown(reason)


def spin() -> None:
    """rospy.spin: block until the node shuts down (its callbacks run meanwhile)."""
    node = _node()
    wait(node.spin(), "rospy.spin()", interruptible=False)


# -- time ------------------------------------------------------------------------------------------
def get_rostime() -> Time:
    """rospy.get_rostime."""
    return _time_node().get_rostime()


def get_time() -> float:
    """rospy.get_time."""
    return _time_node().get_time()


def is_wallclock() -> bool:
    """rospy.rostime.is_wallclock: True when this node's ROS time is the wall clock (the kernel
    clock: no ``/use_sim_time``), False when it follows ``/clock``."""
    return not _time_node().use_sim_time


def wallsleep(duration: float) -> None:
    """rospy.rostime.wallsleep: block this node for ``duration`` seconds of wall time (rospy's
    is ``time.sleep``; here the kernel clock, which goes on while ``/clock`` stands still)."""
    node = _blocking_node("rospy.rostime.wallsleep()")
    wait(node.wall_sleep(duration), "rospy.rostime.wallsleep()")


def _rostime_module() -> Any:
    import types

    mod = types.ModuleType("rospy.rostime", "rospy.rostime: ROS time and wall time (ddes: the "
                                            "kernel clock plays the wall clock)")
    for name, value in (("Time", Time), ("Duration", Duration), ("get_rostime", get_rostime),
                        ("get_time", get_time), ("is_wallclock", is_wallclock),
                        ("wallsleep", wallsleep)):
        setattr(mod, name, value)
    return mod


def sleep(duration: DurationLike) -> None:
    """rospy.sleep: block this node for ``duration`` of ROS time (seconds or Duration)."""
    node = _blocking_node("rospy.sleep()")
    wait(node.sleep(duration), "rospy.sleep()")


class Rate:
    """rospy.Rate: ``rate.sleep()`` blocks this node until the end of the cycle."""

    def __init__(self, hz: float, reset: bool = False) -> None:
        node = _time_node()
        self._rate = _Rate(node, hz, reset)
        self._env = node.world.env

    def sleep(self) -> None:
        """Block until the end of the current cycle (rospy's algorithm, ddes.Rate)."""
        rate = self._rate
        clock = rate._clock
        if clock.is_sim:  # /clock time: ddes.Rate's own wait for the clock to get there
            wait(rate.sleep(), "rate.sleep()")
            return
        # ddes.Rate.sleep's steps on the kernel's clock, without its forgotten-yield label
        # (a blocking call cannot forget to wait): this is every rospy loop's hot path.
        curr = clock.now_ns()
        remaining = rate._remaining(curr)
        rate._advance(curr)
        wait_ns(self._env, remaining if remaining > 0 else 0, "rate.sleep()")

    def remaining(self) -> Duration:
        """Time left in the current cycle."""
        return self._rate.remaining()

    @property
    def sleep_dur(self) -> Duration:
        return self._rate.sleep_dur

    @property
    def last_time(self) -> Duration:
        return self._rate.last_time


class Timer(_Timer):
    """rospy.Timer on this node (rospy's schedule, ddes.Timer); the callback may block."""

    def __init__(self, period: DurationLike, callback: Callable[[TimerEvent], object],
                 oneshot: bool = False, reset: bool = False) -> None:
        super().__init__(_node(), period, callback, oneshot, reset)


# -- topics and services ----------------------------------------------------------------------------
class _BeforeInit:
    """A publisher or subscriber a script creates before ``rospy.init_node`` (rospy allows it,
    and its tutorials do it): the real one is made when the node exists; until then using it
    raises rospy's "ROS node has not been initialized yet" text."""

    def __init__(self, cls: type, args: tuple[object, ...], kwargs: dict[str, object]) -> None:
        self._cls = cls
        self._args = args
        self._kwargs = kwargs
        self._real: object = None

    def _make(self) -> None:
        self._real = self._cls(*self._args, **self._kwargs)

    def __getattr__(self, name: str) -> Any:
        real = self.__dict__.get("_real")
        if real is None:
            raise ROSException("ROS node has not been initialized yet. Please call init_node() "
                               "first")
        value = getattr(real, name)
        if callable(value) and not name.startswith("_"):
            self.__dict__[name] = value  # a method: found directly from now on (publish)
        return value

    def __repr__(self) -> str:
        real = self.__dict__.get("_real")
        return repr(real) if real is not None else f"<{self._cls.__name__} before init_node>"


def _pending(cls: type, args: tuple[object, ...], kwargs: dict[str, object]) -> Any:
    """A :class:`_BeforeInit` when a script has no node yet, else None (create it now)."""
    task = current_task()
    if task is None or task.node is not None:
        return None
    if task.context is None:  # code spawned without a script: a context to hold them
        from ddes.compat.scripts import ScriptContext

        task.context = ScriptContext(path=Path(), argv=[])
    later = _BeforeInit(cls, args, kwargs)
    context: Any = task.context
    context.before_init.append(later)
    return later


class Publisher(_Publisher):  # type: ignore[type-arg]
    """rospy.Publisher on this node (ddes.Publisher with the node of the running script)."""

    def __new__(cls, *args: Any, **kwargs: Any) -> Any:
        return _pending(cls, args, kwargs) or super().__new__(cls)

    def __init__(self, name: str, data_class: Any, subscriber_listener: object = None,
                 tcp_nodelay: bool = False, latch: bool = False,
                 headers: dict[str, str] | None = None, queue_size: int | None = None) -> None:
        super().__init__(_node("ROS node has not been initialized yet. Please call init_node() "
                               "first"), name, data_class, subscriber_listener, tcp_nodelay,
                         latch, headers, queue_size)


class Subscriber(_Subscriber):  # type: ignore[type-arg]
    """rospy.Subscriber on this node; its callbacks run on greenlets and may block."""

    def __new__(cls, *args: Any, **kwargs: Any) -> Any:
        return _pending(cls, args, kwargs) or super().__new__(cls)

    def __init__(self, name: str, data_class: Any, callback: Callable[..., object] | None = None,
                 callback_args: object = None, queue_size: int | None = None,
                 buff_size: int = 65536, tcp_nodelay: bool = False) -> None:
        super().__init__(_node(), name, data_class, callback, callback_args, queue_size,
                         buff_size, tcp_nodelay)


class Service(_Service):
    """rospy.Service on this node; the handler may block."""

    def __init__(self, name: str, service_class: Any, handler: Callable[..., object],
                 buff_size: int = 65536,
                 error_handler: Callable[..., object] | None = None) -> None:
        super().__init__(_node(), name, service_class, handler, buff_size, error_handler)


class ServiceProxy:
    """rospy.ServiceProxy: ``resp = proxy(req)`` blocks this node until the response."""

    def __init__(self, name: str, service_class: Any, persistent: bool = False,
                 headers: dict[str, str] | None = None) -> None:
        self._proxy = _ServiceProxy(_node(), name, service_class, persistent, headers)
        self.resolved_name = self._proxy.resolved_name
        self.request_class = self._proxy.request_class
        self.response_class = self._proxy.response_class

    def __call__(self, *args: Any, **kwds: Any) -> Any:
        return wait(self._proxy.call(*args, **kwds), "proxy(request)")

    call = __call__

    def wait_for_service(self, timeout: DurationLike | None = None) -> None:
        wait(self._proxy.wait_for_service(timeout), "proxy.wait_for_service()")

    def close(self) -> None:
        self._proxy.close()


def wait_for_service(service: str, timeout: DurationLike | None = None) -> None:
    """rospy.wait_for_service: block until ``service`` is registered (ROSException on timeout)."""
    node = _blocking_node("rospy.wait_for_service()")
    wait(_wait_for_service(node, service, timeout), "rospy.wait_for_service()")


def wait_for_message(topic: str, topic_type: Any, timeout: DurationLike | None = None) -> Any:
    """rospy.wait_for_message: block until the next message on ``topic``."""
    node = _blocking_node("rospy.wait_for_message()")
    return wait(node.wait_for_message(topic, topic_type, timeout), "rospy.wait_for_message()")


# -- parameters ---------------------------------------------------------------------------------------
_UNSPECIFIED: Any = object()


def get_param(param_name: str, default: Any = _UNSPECIFIED) -> Any:
    """rospy.get_param (KeyError without a default)."""
    node = _node()
    return node.get_param(param_name) if default is _UNSPECIFIED \
        else node.get_param(param_name, default)


get_param_cached = get_param


def set_param(param_name: str, param_value: Any) -> None:
    """rospy.set_param."""
    _node().set_param(param_name, param_value)


def has_param(param_name: str) -> bool:
    """rospy.has_param."""
    return _node().has_param(param_name)


def delete_param(param_name: str) -> None:
    """rospy.delete_param."""
    _node().delete_param(param_name)


def search_param(param_name: str) -> str | None:
    """rospy.search_param."""
    return _node().search_param(param_name)


def get_param_names() -> list[str]:
    """rospy.get_param_names."""
    return _node().get_param_names()


# -- logging ------------------------------------------------------------------------------------------
_PY_LEVELS = {_DEBUG: logging.DEBUG, _INFO: logging.INFO, _WARN: logging.WARNING,
              _ERROR: logging.ERROR, _FATAL: logging.CRITICAL}


def _log(level: int, msg: object, args: tuple[object, ...], throttle: DurationLike | None = None,
         once: bool = False) -> None:
    node = _current()
    if node is None:  # rospy before init_node: its Python logger, no /rosout
        logging.getLogger("rosout").log(_PY_LEVELS[level], str(msg), *args)
        return
    node.log.log(level, msg, args, depth=3, throttle=throttle, once=once)


def logdebug(msg: object, *args: object) -> None:
    _log(_DEBUG, msg, args)


def loginfo(msg: object, *args: object) -> None:
    _log(_INFO, msg, args)


logout = loginfo


def logwarn(msg: object, *args: object) -> None:
    _log(_WARN, msg, args)


def logerr(msg: object, *args: object) -> None:
    _log(_ERROR, msg, args)


def logfatal(msg: object, *args: object) -> None:
    _log(_FATAL, msg, args)


def logdebug_throttle(period: DurationLike, msg: object, *args: object) -> None:
    _log(_DEBUG, msg, args, throttle=period)


def loginfo_throttle(period: DurationLike, msg: object, *args: object) -> None:
    _log(_INFO, msg, args, throttle=period)


def logwarn_throttle(period: DurationLike, msg: object, *args: object) -> None:
    _log(_WARN, msg, args, throttle=period)


def logerr_throttle(period: DurationLike, msg: object, *args: object) -> None:
    _log(_ERROR, msg, args, throttle=period)


def logfatal_throttle(period: DurationLike, msg: object, *args: object) -> None:
    _log(_FATAL, msg, args, throttle=period)


def logdebug_once(msg: object, *args: object) -> None:
    _log(_DEBUG, msg, args, once=True)


def loginfo_once(msg: object, *args: object) -> None:
    _log(_INFO, msg, args, once=True)


def logwarn_once(msg: object, *args: object) -> None:
    _log(_WARN, msg, args, once=True)


def logerr_once(msg: object, *args: object) -> None:
    _log(_ERROR, msg, args, once=True)


def logfatal_once(msg: object, *args: object) -> None:
    _log(_FATAL, msg, args, once=True)


#: ``rospy.rostime`` (``import rospy; rospy.rostime.wallsleep(1.0)``, ``from rospy.rostime import
#: wallsleep``): get_rostime, get_time, is_wallclock, wallsleep, Time, Duration.
rostime = _rostime_module()
