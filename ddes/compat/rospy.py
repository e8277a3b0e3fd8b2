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

import linecache
import logging
import sys
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
from ddes.graph.names import NameResolver, get_ros_namespace
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
from ddes.time.rostime import Duration as _Duration
from ddes.time.rostime import Time as _Time

if TYPE_CHECKING:
    from ddes.graph.node import Node
    from ddes.time.units import DurationLike

__all__ = [
    "DEBUG", "ERROR", "FATAL", "INFO", "WARN",
    "AnyMsg", "Duration", "Header", "Publisher", "ROSException", "ROSInitException",
    "ROSInterruptException", "ROSSerializationException", "ROSTimeMovedBackwardsException",
    "Rate", "Service", "ServiceException", "ServiceProxy", "SubscribeListener", "Subscriber",
    "Time", "Timer", "TimerEvent",
    "delete_param", "get_caller_id", "get_name", "get_namespace", "get_param", "get_param_cached",
    "get_param_names", "get_rostime", "get_time", "has_param", "init_node", "is_shutdown",
    "logdebug", "logdebug_once", "logdebug_throttle", "logerr", "logerr_once", "logerr_throttle",
    "logfatal", "logfatal_once", "logfatal_throttle", "loginfo", "loginfo_once",
    "loginfo_throttle", "logout", "logwarn", "logwarn_once", "logwarn_throttle", "myargv",
    "core", "names", "on_shutdown", "resolve_name", "rostime", "search_param", "set_param",
    "signal_shutdown",
    "sleep", "spin",
    "wait_for_message", "wait_for_service",
]

#: rospy's log levels (rosgraph_msgs/Log's constants).
DEBUG, INFO, WARN, ERROR, FATAL = 1, 2, 4, 8, 16
_LEVEL_NAMES = {DEBUG: "debug", INFO: "info", WARN: "warn", ERROR: "error", FATAL: "fatal"}

#: rospy.Header: std_msgs/Header.
Header = get_message_class("std_msgs/Header")


class Duration(_Duration):
    """rospy.Duration: ddes's Duration (genpy's algebra), shown as rospy shows it
    (``rospy.Duration[2000000003]``)."""

    __slots__ = ()

    def __repr__(self) -> str:
        return f"rospy.Duration[{self.to_nsec()}]"


class _GenpyDuration(_Duration):
    """What ``rospy.Time - rospy.Time`` gives: genpy's Duration (rospy.Time inherits genpy's
    ``__sub__``), shown as ``genpy.Duration[...]``."""

    __slots__ = ()

    def __repr__(self) -> str:
        return f"genpy.Duration[{self.to_nsec()}]"


class Time(_Time):
    """rospy.Time: ddes's Time (genpy's algebra), shown as rospy shows it
    (``rospy.Time[1000000005]``); ``Time.now()`` reads the node of the running code."""

    __slots__ = ()

    def __repr__(self) -> str:
        return f"rospy.Time[{self.to_nsec()}]"

    def __sub__(self, other: Any) -> Any:
        result = super().__sub__(other)
        if type(result) is _Duration:  # Time - Time: genpy's Duration, as rospy's
            return _GenpyDuration._from_ns(result.to_nsec())
        return result

    @classmethod
    def now(cls, clock: Any = None) -> Time:  # type: ignore[override]
        """rospy.Time.now(): the ROS time of this script's node."""
        source = clock if clock is not None else _time_node()
        return cls._from_ns(source.get_rostime().to_nsec())

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
    """rospy.get_name: the node's name (``/unnamed`` before init_node, as rospy, in the
    script's namespace)."""
    node = _current()
    if node is not None:
        return node.name
    return _Unnamed.of(current_task()).name if current_task() is not None else "/unnamed"


get_caller_id = get_name


def get_namespace() -> str:
    """rospy.get_namespace."""
    node = _current()
    if node is not None:
        return node.get_namespace()
    task = current_task()
    return _Unnamed.of(task).namespace if task is not None else "/"


def resolve_name(name: str, caller_id: str | None = None) -> str:
    """rospy.resolve_name with the node's namespace and remappings."""
    node = _current()
    if caller_id is None and node is not None:
        return node.resolve_name(name)
    base = (caller_id or "/unnamed").rsplit("/", 1)
    return NameResolver(base[1], base[0] or "/", {}).resolve(name)


# -- lifecycle -----------------------------------------------------------------------------------
def is_shutdown() -> bool:
    """rospy.is_shutdown (False before init_node, and in a shutdown hook, as rospy)."""
    node = _current()
    return node.is_shutdown() if node is not None else False


def is_shutdown_requested() -> bool:
    """rospy.core.is_shutdown_requested: True from the start of the shutdown (in the hooks)."""
    node = _current()
    return node.is_shutdown_requested() if node is not None else False


def on_shutdown(h: Callable[[], object]) -> None:
    """rospy.on_shutdown: ``h()`` (no argument, as rospy calls client hooks) when the node
    starts to shut down, before its topics close: a message it publishes is delivered, and
    ``is_shutdown()`` is still False there (``is_shutdown_requested()`` True), as in rospy.
    Before ``init_node`` the hook waits for the node."""
    node = _current()
    if node is not None:
        node.on_preshutdown(h)
        return
    task = current_task()
    if task is None:
        raise ROSInitException("client code must call rospy.init_node() first" + _HOW)
    _context_of(task).before_init.append(_LaterHook(h))


class _LaterHook:
    """An ``on_shutdown`` hook given before ``init_node``: registered with the node."""

    def __init__(self, hook: Callable[[], object]) -> None:
        self._hook = hook

    def _make(self) -> None:
        _node().on_preshutdown(self._hook)


def signal_shutdown(reason: str) -> None:
    """rospy.signal_shutdown: shut this node down."""
    _node().signal_shutdown(reason)


def spin() -> None:
    """rospy.spin: block until the node shuts down (its callbacks run meanwhile)."""
    node = _node()
    wait(node.spin(), "rospy.spin()", interruptible=False)


# -- time ------------------------------------------------------------------------------------------
def get_rostime() -> Time:
    """rospy.get_rostime (a ``rospy.Time``)."""
    return Time._from_ns(_time_node().clock.now_ns())


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
    """rospy.sleep: block this node for ``duration`` of ROS time (seconds or Duration).

    Before ``init_node`` rospy sleeps on the wall clock: here the kernel clock."""
    node = _current()
    task = current_task()
    if node is None and task is not None:
        from ddes.time.sleep import sleep as _sleep

        wait(_sleep(task.world.kernel_clock, duration), "rospy.sleep()")
        return
    node = _blocking_node("rospy.sleep()")
    if node.clock.is_sim:  # rospy/timer.py: raises ROSInterruptException at shutdown
        wait(node.sleep(duration), "rospy.sleep()")
        return
    # on the wall clock rospy.sleep is time.sleep: a shutdown does not cut it short, and a
    # sleep after it sleeps (the loop then ends at its is_shutdown() check)
    from ddes.time.sleep import sleep as _sleep

    wait(_sleep(node.world.kernel_clock, duration), "rospy.sleep()", interruptible=False)


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
        # on the wall clock rospy's Rate.sleep is time.sleep: a shutdown does not end it
        wait_ns(self._env, remaining if remaining > 0 else 0, "rate.sleep()",
                interruptible=False)

    def remaining(self) -> Duration:
        """Time left in the current cycle."""
        return Duration._from_ns(self._rate.remaining().to_nsec())

    @property
    def sleep_dur(self) -> _Duration:
        return self._rate.sleep_dur

    @property
    def last_time(self) -> _Duration:
        return self._rate.last_time


class Timer(_Timer):
    """rospy.Timer on this node (rospy's schedule, ddes.Timer); the callback may block."""

    def __init__(self, period: DurationLike, callback: Callable[[TimerEvent], object],
                 oneshot: bool = False, reset: bool = False) -> None:
        super().__init__(_node(), period, callback, oneshot, reset)


# -- topics and services ----------------------------------------------------------------------------
class _BeforeInit:
    """A publisher, subscriber, service or service proxy a script creates before
    ``rospy.init_node`` (rospy allows it, and its tutorials do it): the real one is made when
    the node exists; until then using it raises rospy's "ROS node has not been initialized
    yet" text (a proxy's ``wait_for_service`` works, as rospy's does)."""

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
            if name == "wait_for_service" and self._cls is ServiceProxy:
                service = self._args[0] if self._args else self._kwargs.get("name")
                return lambda timeout=None: wait_for_service(str(service), timeout)
            if self._cls is ServiceProxy and name in ("call", "resolved_name", "request_class",
                                                      "response_class", "close"):
                return getattr(self._unnamed_proxy(), name)
            raise ROSException("ROS node has not been initialized yet. Please call init_node() "
                               "first")
        value = getattr(real, name)
        if callable(value) and not name.startswith("_"):
            self.__dict__[name] = value  # a method: found directly from now on (publish)
        return value

    def __call__(self, *args: Any, **kwds: Any) -> Any:
        real = self.__dict__.get("_real")
        if real is None:
            if self._cls is ServiceProxy:
                return self._unnamed_proxy()(*args, **kwds)
            raise ROSInitException("ROS node has not been initialized yet. Please call "
                                   "init_node() first")
        return real(*args, **kwds)  # type: ignore[operator]

    def _unnamed_proxy(self) -> ServiceProxy:
        """The proxy this ServiceProxy calls through before ``init_node``: rospy's calls
        then go out with the caller id ``/unnamed`` (in the script's namespace), from no
        registered node."""
        proxy = self.__dict__.get("_unnamed")
        if proxy is None:
            task = current_task()
            if task is None:
                raise ROSInitException("ROS node has not been initialized yet. Please call "
                                       "init_node() first")
            proxy = ServiceProxy._on(_unnamed_node(task), *self._args, **self._kwargs)
            self.__dict__["_unnamed"] = proxy
        return proxy

    def __repr__(self) -> str:
        real = self.__dict__.get("_real")
        return repr(real) if real is not None else f"<{self._cls.__name__} before init_node>"


def _unnamed_node(task: Any) -> Node:
    """The caller a script's service calls go out from before ``init_node``: ``/unnamed`` in
    its namespace, a node the master does not list (rospy registers nothing until
    ``init_node``), one per script."""
    context = _context_of(task)
    node = context.__dict__.get("_unnamed_node")
    if node is None:
        from ddes.graph.node import Node as _Node

        unnamed = _Unnamed.of(task)
        node = _Node(task.world, unnamed.name, spinner="rospy", disable_rosout=True,
                    registered=False)
        context.__dict__["_unnamed_node"] = node
    return node


def _context_of(task: Any) -> Any:
    """The script context of ``task`` (one is made for code spawned without a script)."""
    if task.context is None:
        from ddes.compat.scripts import ScriptContext

        task.context = ScriptContext(path=Path(), argv=[])
    return task.context


def _pending(cls: type, args: tuple[object, ...], kwargs: dict[str, object]) -> Any:
    """A :class:`_BeforeInit` when a script has no node yet, else None (create it now)."""
    task = current_task()
    if task is None or task.node is not None:
        return None
    later = _BeforeInit(cls, args, kwargs)
    _context_of(task).before_init.append(later)
    return later


#: rospy's warning for a Publisher without ``queue_size`` (a ``SyntaxWarning``).
QUEUE_SIZE_WARNING = ("The publisher should be created with an explicit keyword argument "
                      "'queue_size'. Please see "
                      "http://wiki.ros.org/rospy/Overview/Publishers%20and%20Subscribers for "
                      "more information.")


def _warn_queue_size(depth: int) -> None:
    """Print rospy's ``SyntaxWarning`` as Python's ``warnings`` does, once per line of the
    script (the default filter), on the script's standard error."""
    task = current_task()
    if task is None:
        return
    context = _context_of(task)
    frame = sys._getframe(depth)
    if frame.f_code.co_filename == __file__:  # made at init_node: warned when it was asked for
        return
    site = (frame.f_code.co_filename, frame.f_lineno)
    seen = context.__dict__.setdefault("_warned", set())
    if site in seen:
        return
    seen.add(site)
    text = f"{site[0]}:{site[1]}: SyntaxWarning: {QUEUE_SIZE_WARNING}"
    line = linecache.getline(site[0], site[1]).strip()
    if line:
        text += "\n  " + line
    paths = task.world.display_paths
    if paths:
        from ddes.graph.rosout import show_paths

        text = show_paths(text, paths)
    printer = getattr(context, "print_line", None)
    if printer is not None:
        printer(text, True)
    else:
        sys.stderr.write(text + "\n")


class SubscribeListener:
    """rospy.SubscribeListener: give one to ``Publisher(..., subscriber_listener=l)`` to hear
    of each subscriber connecting (``peer_subscribe(topic_name, topic_publish,
    peer_publish)``: publish to all, or to that subscriber only) and going
    (``peer_unsubscribe(topic_name, num_peers)``), on the publishing node's callbacks."""

    def peer_subscribe(self, topic_name: str, topic_publish: Callable[[Any], None],
                       peer_publish: Callable[[Any], None]) -> None:
        pass

    def peer_unsubscribe(self, topic_name: str, num_peers: int) -> None:
        pass


class Publisher(_Publisher):  # type: ignore[type-arg]
    """rospy.Publisher on this node (ddes.Publisher with the node of the running script).

    A second Publisher on a topic the node publishes shares its connections (rospy's one
    topic impl per node and name); without ``queue_size`` rospy's ``SyntaxWarning`` is
    printed on the script's standard error, once per line."""

    def __new__(cls, *args: Any, **kwargs: Any) -> Any:
        queue_size = kwargs.get("queue_size", args[6] if len(args) > 6 else None)
        if queue_size is None:
            _warn_queue_size(2)
        return _pending(cls, args, kwargs) or super().__new__(cls)

    def __init__(self, name: str, data_class: Any, subscriber_listener: object = None,
                 tcp_nodelay: bool = False, latch: bool = False,
                 headers: dict[str, str] | None = None, queue_size: int | None = None) -> None:
        super().__init__(_node("ROS node has not been initialized yet. Please call init_node() "
                               "first"), name, data_class, subscriber_listener, tcp_nodelay,
                         latch, headers, queue_size)


class Subscriber(_Subscriber):  # type: ignore[type-arg]
    """rospy.Subscriber on this node; its callbacks run on greenlets and may block.  The
    Subscribers of one topic share its connections (and a latched message reaches a new one
    at once, in its constructor, as rospy #1852)."""

    def __new__(cls, *args: Any, **kwargs: Any) -> Any:
        return _pending(cls, args, kwargs) or super().__new__(cls)

    def __init__(self, name: str, data_class: Any, callback: Callable[..., object] | None = None,
                 callback_args: object = None, queue_size: int | None = None,
                 buff_size: int = 65536, tcp_nodelay: bool = False) -> None:
        super().__init__(_node(), name, data_class, callback, callback_args, queue_size,
                         buff_size, tcp_nodelay)


class Service(_Service):
    """rospy.Service on this node; the handler may block.  Made before ``init_node``, it is
    registered when the node starts, as rospy's."""

    def __new__(cls, *args: Any, **kwargs: Any) -> Any:
        return _pending(cls, args, kwargs) or super().__new__(cls)

    def __init__(self, name: str, service_class: Any, handler: Callable[..., object],
                 buff_size: int = 65536,
                 error_handler: Callable[..., object] | None = None) -> None:
        super().__init__(_node(), name, service_class, handler, buff_size, error_handler)


class ServiceProxy:
    """rospy.ServiceProxy: ``resp = proxy(req)`` blocks this node until the response.

    Made before ``init_node``, it is made for the node when it starts; its
    ``wait_for_service`` works before then too (a call needs the node: a deviation)."""

    def __new__(cls, *args: Any, **kwargs: Any) -> Any:
        return _pending(cls, args, kwargs) or super().__new__(cls)

    def __init__(self, name: str, service_class: Any, persistent: bool = False,
                 headers: dict[str, str] | None = None) -> None:
        self._setup(_node(), name, service_class, persistent, headers)

    @classmethod
    def _on(cls, node: Node, *args: Any, **kwargs: Any) -> ServiceProxy:
        """A proxy of ``node`` (not the running script's), made with rospy's arguments."""
        proxy = object.__new__(cls)
        proxy._setup(node, *args, **kwargs)
        return proxy

    def _setup(self, node: Node, name: str, service_class: Any, persistent: bool = False,
               headers: dict[str, str] | None = None) -> None:
        self._proxy = _ServiceProxy(node, name, service_class, persistent, headers)
        self.resolved_name = self._proxy.resolved_name
        self.request_class = self._proxy.request_class
        self.response_class = self._proxy.response_class
        self._error_prefix = f"service [{self.resolved_name}] responded with an error: "

    def __call__(self, *args: Any, **kwds: Any) -> Any:
        try:
            return wait(self._proxy.call(*args, **kwds), "proxy(request)")
        except ServiceException as exc:
            text = str(exc)
            prefix = self._error_prefix
            if not text.startswith(prefix) or type(exc) is not ServiceException:
                raise
            # rospy puts the server's bytes in its text as Python 3 shows bytes: b'...'
            raise ServiceException(
                prefix + repr(text[len(prefix):].encode("utf-8"))) from None

    call = __call__

    def wait_for_service(self, timeout: DurationLike | None = None) -> None:
        wait(self._proxy.wait_for_service(timeout), "proxy.wait_for_service()")

    def close(self) -> None:
        self._proxy.close()


def wait_for_service(service: str, timeout: DurationLike | None = None) -> None:
    """rospy.wait_for_service: block until ``service`` is registered (ROSException on timeout).

    Before ``init_node`` it waits as rospy's does then: the name resolved as ``/unnamed``'s,
    the timeout on the wall clock (the kernel clock)."""
    task = current_task()
    if task is not None and task.node is None:
        _wait_for_service_unnamed(task, service, timeout)
        return
    node = _blocking_node("rospy.wait_for_service()")
    wait(_wait_for_service(node, service, timeout), "rospy.wait_for_service()")


def _wait_for_service_unnamed(task: Any, service: str, timeout: DurationLike | None) -> None:
    from ddes.services.network import network_of
    from ddes.services.server import check_service_name
    from ddes.services.waiting import check_nonzero_timeout
    from ddes.time.units import duration_to_ns

    check_service_name(service, "wait_for_service")
    timeout_ns = None if timeout is None else duration_to_ns(timeout, "timeout")
    check_nonzero_timeout(timeout_ns)
    world = task.world
    name = _Unnamed.of(task).resolve_name(service)
    event = world.env.event()
    expired = ROSException(f"timeout exceeded while waiting for service {name}")
    if timeout_ns is not None and timeout_ns < 0:
        raise expired
    if world.master.lookup_service(name) is not None:
        return
    net = network_of(world)

    def registered() -> None:
        if not event.triggered:
            event.succeed(None)

    def expire(_ev: object) -> None:
        if not event.triggered:
            net.remove_waiter(name, registered)
            event.fail(expired)

    net.add_waiter(name, registered)
    if timeout_ns is not None:
        clock = world.kernel_clock
        clock.wait_until(clock.now_ns() + timeout_ns).callbacks.append(expire)
    wait(event, "rospy.wait_for_service()")


def wait_for_message(topic: str, topic_type: Any, timeout: DurationLike | None = None) -> Any:
    """rospy.wait_for_message: block until the next message on ``topic`` (a subscription the
    node has on it is shared: its latched message comes at once)."""
    node = _blocking_node("rospy.wait_for_message()")
    return wait(node.wait_for_message(topic, topic_type, timeout), "rospy.wait_for_message()")


# -- parameters ---------------------------------------------------------------------------------------
_UNSPECIFIED: Any = object()


class _Unnamed:
    """What a script is before ``init_node``: rospy's process without a node, whose caller id
    is ``/unnamed`` in its namespace and whose names resolve without remappings (rospy reads
    parameters and waits for services then, through the master)."""

    def __init__(self, world: Any, namespace: str) -> None:
        self.world = world
        self._resolver = NameResolver("unnamed", namespace, {})
        self.name = self._resolver.name
        self.namespace = self._resolver.namespace

    @staticmethod
    def of(task: Any) -> _Unnamed:
        context = task.context
        argv = list(getattr(context, "argv", None) or [])
        namespace = get_ros_namespace({"ROS_NAMESPACE": getattr(context, "namespace", "/")},
                                      argv)
        return _Unnamed(task.world, namespace)

    def resolve_name(self, name: str) -> str:
        return self._resolver.resolve(name)

    def get_param(self, name: str, default: Any = _UNSPECIFIED) -> Any:
        key = self.resolve_name(name)
        params = self.world.master.params
        observer = self.world.param_observer
        if observer is not None:
            observer(self.name, key, params.has_param(key))
        return params.get_param(key) if default is _UNSPECIFIED else params.get_param(key, default)

    def set_param(self, name: str, value: Any) -> None:
        self.world.master.params.set_param(self.resolve_name(name), value, caller_id=self.name)

    def has_param(self, name: str) -> bool:
        return bool(self.world.master.params.has_param(self.resolve_name(name)))

    def delete_param(self, name: str) -> None:
        self.world.master.params.delete_param(self.resolve_name(name))

    def search_param(self, name: str) -> str | None:
        key = self._resolver.search_key(name)
        if not key or key.startswith("~"):
            return None
        return self.world.master.params.search_param(self.name, key)  # type: ignore[no-any-return]

    def get_param_names(self) -> list[str]:
        return list(self.world.master.params.get_param_names())


def _param_owner() -> Any:
    """The node, or before ``init_node`` the script as ``/unnamed`` (rospy's parameter calls
    work then)."""
    node = _current()
    if node is not None:
        return node
    task = current_task()
    if task is None:
        return _node()  # outside any script: rospy's text and the ddes fix
    return _Unnamed.of(task)


def get_param(param_name: str, default: Any = _UNSPECIFIED) -> Any:
    """rospy.get_param (``KeyError`` of the name as given without a default, as rospy's)."""
    owner = _param_owner()
    if default is not _UNSPECIFIED:
        return owner.get_param(param_name, default)
    try:
        return owner.get_param(param_name)
    except KeyError:
        raise KeyError(param_name) from None


get_param_cached = get_param


def set_param(param_name: str, param_value: Any) -> None:
    """rospy.set_param."""
    _param_owner().set_param(param_name, param_value)


def has_param(param_name: str) -> bool:
    """rospy.has_param (False for a name that is not set)."""
    return bool(_param_owner().has_param(param_name))


def delete_param(param_name: str) -> None:
    """rospy.delete_param (``KeyError`` of the name as given when it is not set)."""
    try:
        _param_owner().delete_param(param_name)
    except KeyError:
        raise KeyError(param_name) from None


def search_param(param_name: str) -> str | None:
    """rospy.search_param."""
    return _param_owner().search_param(param_name)  # type: ignore[no-any-return]


def get_param_names() -> list[str]:
    """rospy.get_param_names."""
    return list(_param_owner().get_param_names())


# -- logging ------------------------------------------------------------------------------------------
_PY_LEVELS = {_DEBUG: logging.DEBUG, _INFO: logging.INFO, _WARN: logging.WARNING,
              _ERROR: logging.ERROR, _FATAL: logging.CRITICAL}


def _log(level: int, msg: object, args: tuple[object, ...], throttle: DurationLike | None = None,
         once: bool = False) -> None:
    node = _current()
    if node is None:  # rospy before init_node: its Python logger, no /rosout
        logging.getLogger("rosout").log(_PY_LEVELS[level], str(msg), *args)
        return
    node.log.log(level, msg, args, depth=3, throttle=throttle, once=once, qualify=True)


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


def get_mappings() -> dict[str, str]:
    """rospy.names.get_mappings: the script's command-line remappings as given
    (``__name:=`` and the other special ones too, as rosgraph loads them)."""
    from ddes.graph.names import load_mappings

    task = current_task()
    return load_mappings(list(getattr(task.context if task else None, "argv", None) or [])[1:])


def get_resolved_mappings() -> dict[str, str]:
    """rospy.names.get_resolved_mappings: the node's remappings, resolved ({} before
    init_node, as rospy)."""
    node = _current()
    return dict(node.remappings) if node is not None else {}


def _names_module() -> Any:
    import types

    from ddes.graph import names as graph_names

    mod = types.ModuleType("rospy.names", "rospy.names: ROS names of the script's node "
                                          "(rosgraph.names' functions, and the node's own)")
    for name in ("SEP", "GLOBALNS", "REMAP", "ANYTYPE", "PRIV_NAME", "canonicalize_name",
                 "get_ros_namespace", "is_global", "is_private", "is_legal_name",
                 "is_legal_base_name", "load_mappings", "make_caller_id", "make_global_ns",
                 "namespace", "ns_join", "anonymous_name"):
        setattr(mod, name, getattr(graph_names, name))
    for name, value in (("get_caller_id", get_caller_id), ("get_name", get_name),
                        ("get_namespace", get_namespace), ("resolve_name", resolve_name),
                        ("get_mappings", get_mappings),
                        ("get_resolved_mappings", get_resolved_mappings),
                        ("TOPIC_ANYTYPE", "*"), ("SERVICE_ANYTYPE", "*"),
                        ("ROSException", ROSException), ("ROSInitException", ROSInitException)):
        setattr(mod, name, value)
    return mod


def is_initialized() -> bool:
    """rospy.core.is_initialized: True once this script's node exists."""
    return _current() is not None


def _core_module() -> Any:
    import types

    mod = types.ModuleType("rospy.core", "rospy.core: the node's life (is_shutdown, "
                                         "is_shutdown_requested, signal_shutdown ...)")
    for name, value in (("is_shutdown", is_shutdown),
                        ("is_shutdown_requested", is_shutdown_requested),
                        ("is_initialized", is_initialized), ("signal_shutdown", signal_shutdown),
                        ("on_shutdown", on_shutdown), ("get_caller_id", get_caller_id),
                        ("logdebug", logdebug), ("loginfo", loginfo), ("logwarn", logwarn),
                        ("logerr", logerr), ("logfatal", logfatal), ("logout", logout)):
        setattr(mod, name, value)
    return mod


#: ``rospy.rostime`` (``import rospy; rospy.rostime.wallsleep(1.0)``, ``from rospy.rostime import
#: wallsleep``): get_rostime, get_time, is_wallclock, wallsleep, Time, Duration.
rostime = _rostime_module()

#: ``rospy.names`` (``from rospy.names import ns_join``): rosgraph's name functions and the
#: node's own (get_caller_id, get_namespace, resolve_name, get_mappings ...).
names = _names_module()

#: ``rospy.core`` (``rospy.core.is_shutdown_requested()``).
core = _core_module()
