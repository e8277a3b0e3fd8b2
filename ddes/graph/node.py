"""Nodes: the owners of every ROS entity, and their callback queues.

A node is created through its world (``world.create_node("talker")``) and
creates its entities: publishers, subscribers, timers, rates, services...
When it shuts down they go away with it.  A second node registering the same
name shuts the first down, as the ROS master does.

Names resolve as rosgraph resolves them (:mod:`ddes.graph.names`), with the
node's namespace and remappings (``argv=["chatter:=/talk", "_rate:=5"]``
works as on a ``rosrun`` command line).  ROS time comes from :attr:`clock`:
the kernel clock, or a :class:`~ddes.time.clock.SimClock` following
``/clock`` when the node uses simulated time (``/use_sim_time``).

Callbacks and the spinner.  Every callback of a node (message, timer,
service request, action and dynamic_reconfigure callbacks) goes through the
node's one callback queue, :attr:`Node.callbacks`
(:class:`~ddes.graph.callbacks.CallbackQueue`).  ``spinner=`` picks the
policy: ``"single"`` (default, roscpp's ``ros::spin()``: one callback at a
time; a generator callback holds the spinner while it takes simulated time),
an int N (``AsyncSpinner(N)``), ``"rospy"`` (a thread per subscription,
timer and service connection, concurrent with the node's main), or
``"manual"`` (callbacks wait for ``yield node.spin_once()``).

The entity contract.  Rooms above the graph (services, actionlib, rosbag,
tf2, sim) attach their entities to a node through :meth:`Node.check_alive`,
:meth:`Node.add_entity` and :meth:`Node.remove_entity`; the node calls each
entity's ``shutdown()`` when it shuts down.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import TYPE_CHECKING, Any, Protocol, TypedDict, TypeVar

import simpy

from ddes.errors import DdesTypeError, DdesValueError, NodeShutdownError, ROSParamException
from ddes.graph.callbacks import CallbackQueue, SpinnerPolicy
from ddes.graph.failures import NODE_OF_PROCESS
from ddes.graph.names import (
    NameResolver,
    anonymous_name,
    is_legal_base_name,
    is_private,
    parse_node_args,
)
from ddes.graph.rosout import DEBUG, ERROR, FATAL, INFO, WARN, NodeLogger
from ddes.graph.timer import RoscppTimer, Timer, TimerEvent
from ddes.time.clock import Clock, SimClock
from ddes.time.rate import Rate, RoscppRate, WallRate
from ddes.time.rostime import Time, WallTime
from ddes.time.sleep import duration_sleep, must_yield, sleep
from ddes.time.units import DurationLike

if TYPE_CHECKING:
    from simpy.events import ProcessGenerator
    from typing_extensions import Unpack

    from ddes.graph.topics import (
        Publication,
        Publisher,
        PublisherOptions,
        Subscriber,
        SubscriberOptions,
        Subscription,
    )
    from ddes.graph.world import World
    from ddes.msg.message import MessageClass, MessageLike

__all__ = ["Entity", "Node", "NodeOptions"]

_C = TypeVar("_C", bound="MessageClass")

class Entity(Protocol):
    """What a node owns: anything with ``shutdown()`` (publishers, timers, services...)."""

    def shutdown(self) -> object: ...


class NodeOptions(TypedDict, total=False):
    """The keyword arguments of :class:`Node` (``world.create_node(name, **options)``)."""

    namespace: str
    argv: Sequence[str]
    remappings: dict[str, str] | None
    anonymous: bool
    use_sim_time: bool | None
    spinner: SpinnerPolicy
    log_level: str | int
    log_style: str
    disable_rosout: bool


_UNSET = object()


class Node:
    """A ROS node inside a :class:`~ddes.graph.world.World`.

    Parameters
    ----------
    world:
        The owning world.
    name:
        The node's base name (``"talker"``), or a global name (``"/ns/talker"``).
    namespace:
        The node's namespace (like ``ROS_NAMESPACE``); default ``/``.
    argv:
        A ``rosrun``-style command line: ``from:=to`` remaps, ``_p:=v`` sets
        private parameter ``~p``, ``__name:=``/``__ns:=`` rename; the rest is
        kept in :attr:`argv` (rospy.myargv).
    remappings:
        Extra ``{from: to}`` remappings (a launch file's ``<remap>``).
    anonymous:
        Append a unique, deterministic suffix to the name (rospy's anonymous).
    use_sim_time:
        Follow ``/clock``; ``None`` reads ``/use_sim_time`` at start, as rospy.
    spinner:
        ``"single"``, ``"manual"``, ``"rospy"`` or a number of threads (see module docstring).
    log_level:
        The logger level (``"debug"``, ``"info"`` ...).
    log_style:
        How log lines print: ``"rospy"`` (default) or ``"roscpp"``.
    disable_rosout:
        Do not publish log lines on ``/rosout``.
    registered:
        ``False`` keeps the node out of the master's node list (no ``node.start``): a
        caller without a node, as a rospy script is before ``init_node`` (its service calls
        go out as ``/unnamed``).
    """

    def __init__(
        self,
        world: World,
        name: str,
        *,
        namespace: str = "/",
        argv: Sequence[str] = (),
        remappings: dict[str, str] | None = None,
        anonymous: bool = False,
        use_sim_time: bool | None = None,
        spinner: SpinnerPolicy = "single",
        log_level: str | int = "info",
        log_style: str = "rospy",
        disable_rosout: bool = False,
        registered: bool = True,
    ) -> None:
        if not isinstance(name, str) or not name:
            raise DdesTypeError(f"node name must be a non-empty string, got {name!r}")
        args = parse_node_args(list(argv))
        base = args.name or name
        if anonymous and not args.name:  # rospy: __name:= turns anonymous off
            base = anonymous_name(base, world.next_id("anonymous"))
        if not base.startswith("/") and not is_legal_base_name(base):
            raise DdesValueError(
                f"node name {base!r} must be a legal base name (letters, digits, _ ; no '/'); "
                "put namespaces in namespace= or use a global name '/ns/name'"
            )
        remaps = dict(remappings or {})
        remaps.update(args.remappings)
        self._resolver = NameResolver(base, args.ns or namespace, remaps)
        self.world = world
        #: The client library the node behaves as, ``"rospy"`` or ``"roscpp"`` (its
        #: ``log_style``): publishers count ``header.seq`` as that library does.
        self.client_library: str = "roscpp" if log_style == "roscpp" else "rospy"
        #: The node's fully-qualified name (its caller id).
        self.name: str = self._resolver.name
        #: The command line without ROS arguments (rospy.myargv).
        self.argv: list[str] = list(args.args)
        master = world.master
        if use_sim_time is None:
            use_sim_time = bool(master.params.get_param("/use_sim_time", False))
        self.use_sim_time = bool(use_sim_time)
        self.clock: Clock = SimClock(world.env) if self.use_sim_time else world.kernel_clock
        self._entities: list[Entity] = []
        self._published: list[Publisher[MessageClass]] = []
        self._subscribed: list[Subscriber[MessageClass]] = []
        #: What the node's Publishers (Subscribers) of one topic share, by topic: rospy's
        #: ``_PublisherImpl`` (``_SubscriberImpl``), one per node and topic.
        self._pub_impls: dict[str, Publication] = {}
        self._sub_impls: dict[str, Subscription] = {}
        self._shutdown = False
        self._in_shutdown = False
        self._shutdown_hooks: list[Callable[[str], object]] = []
        self._preshutdown_hooks: list[Callable[[], object]] = []
        self._shutdown_event: simpy.Event | None = None
        #: The node's callback queue and spinner (:mod:`ddes.graph.callbacks`).
        self.callbacks = CallbackQueue(self, spinner)
        self.spinner = spinner
        #: The node is in the master's node list (False: a caller with no node, as a rospy
        #: script before ``init_node``, whose calls go out as ``/unnamed``).
        self.registered = bool(registered)
        if registered:
            world.register_node(self)
            world.record("node.start", self.name, use_sim_time=self.use_sim_time)
        for key, value in args.params.items():
            master.params.set_param(self.resolve_name("~" + key), value)
        self.log = NodeLogger(self, log_level, rosout=not disable_rosout, style=log_style)
        if self.use_sim_time:
            from ddes.graph.topics import Subscriber
            from ddes.msg import get_message_class

            sim_clock = self.clock
            assert isinstance(sim_clock, SimClock)
            Subscriber(self, "/clock", get_message_class("rosgraph_msgs/Clock"),
                       lambda m: sim_clock.update(m.clock), queue_size=1, internal=True)

    # -- names ----------------------------------------------------------------------------
    @property
    def namespace(self) -> str:
        """The node's namespace, with a trailing ``/``."""
        return self._resolver.namespace

    def resolve_name(self, name: str) -> str:
        """Resolve a topic/service/parameter name with this node's remappings."""
        return self._resolver.resolve(name)

    def get_name(self) -> str:
        """The fully-qualified node name (rospy.get_name)."""
        return self.name

    def get_namespace(self) -> str:
        """The node's namespace (rospy.get_namespace)."""
        return self._resolver.namespace

    @property
    def remappings(self) -> dict[str, str]:
        """The resolved remappings of this node."""
        return self._resolver.remappings

    # -- lifecycle ------------------------------------------------------------------------
    def is_shutdown(self) -> bool:
        """True once :meth:`shutdown` ran."""
        return self._shutdown

    def on_shutdown(self, hook: Callable[[str], object]) -> None:
        """Call ``hook(reason)`` when the node has shut down (its entities are gone)."""
        self._shutdown_hooks.append(hook)

    def on_preshutdown(self, hook: Callable[[], object]) -> None:
        """Call ``hook()`` when the node starts to shut down, before anything stops: rospy's
        ``on_shutdown`` (client hooks), which may still publish (the message is delivered) and
        see :meth:`is_shutdown` False and :meth:`is_shutdown_requested` True, as in rospy."""
        self._preshutdown_hooks.append(hook)

    def is_shutdown_requested(self) -> bool:
        """True from the start of the shutdown (rospy.core.is_shutdown_requested)."""
        return self._in_shutdown or self._shutdown

    def signal_shutdown(self, reason: str) -> None:
        """rospy.signal_shutdown: shut this node down."""
        self.shutdown(reason)

    def shutdown(self, reason: str = "") -> None:
        """Shut the node down: its entities stop and it leaves the world."""
        if self._shutdown or self._in_shutdown:
            return
        self._in_shutdown = True
        failed: list[tuple[Callable[[], object], Exception]] = []
        hooks, self._preshutdown_hooks = self._preshutdown_hooks, []
        for pre in hooks:  # rospy's client hooks: before the shutdown flag, everything alive
            try:
                pre()
            except Exception as exc:  # noqa: BLE001 - reported once the node is down, as rospy
                failed.append((pre, exc))
        self._shutdown = True
        self.callbacks.close()
        for ent in reversed(list(self._entities)):
            ent.shutdown()
        self._entities.clear()
        self.world.unregister_node(self)
        self.world.record("node.shutdown", self.name, reason=reason)
        for hook in self._shutdown_hooks:
            hook(reason)
        if self._shutdown_event is not None and not self._shutdown_event.triggered:
            self._shutdown_event.succeed(reason)
        for pre, error in failed:
            self.callbacks.report_error(pre, error)

    def shutdown_request(self, caller_id: str, msg: str = "") -> None:
        """The slave API's ``shutdown(caller_id, msg)``: what rosmaster and ``rosnode kill`` call.

        A rospy node prints ``shutdown request: <msg>`` (rospy's
        ``ROSHandler.shutdown``) and shuts down with the reason ``external
        shutdown request from [<caller_id>]: [<msg>]``, which its
        ``on_shutdown`` hooks receive; a roscpp node logs ``Shutdown request
        received.`` and ``Reason given for shutdown: [<msg>]`` at WARN
        (roscpp's ``shutdownCallback``).  The printed rospy line goes to the
        world's ``log_output``, like log lines, after the node has shut down
        (rospy prints it before its shutdown hooks run).
        """
        if self._shutdown:
            return
        if self.client_library == "roscpp":
            self.logwarn("Shutdown request received.")
            self.logwarn("Reason given for shutdown: [%s]", msg)
            self.shutdown(msg)
            return
        self.shutdown(f"external shutdown request from [{caller_id}]: [{msg}]")
        from ddes.graph.rosout import emit_line

        # printed last, so the trace's latest event is this node's; "requst" is rospy's typo
        line = f"shutdown request: {msg}" if msg else "shutdown requst"
        emit_line(self, INFO, line, line)

    def spin(self) -> simpy.Event:
        """Event that fires when the node shuts down (``yield node.spin()``)."""
        if self._shutdown_event is None:
            self._shutdown_event = self.world.env.event()
            if self._shutdown:
                self._shutdown_event.succeed("")
        return self._shutdown_event

    # -- the entity contract (services, actionlib, rosbag, tf2 and sim use these) -------
    def check_alive(self, what: str) -> None:
        """Raise :class:`NodeShutdownError` if the node is shut down ("cannot {what}: ...")."""
        if self._shutdown:
            raise NodeShutdownError(
                f"cannot {what}: node {self.name} is shut down; create a new node"
            )

    def add_entity(self, ent: Entity) -> None:
        """Own ``ent``: its ``shutdown()`` is called when the node shuts down."""
        self._entities.append(ent)

    def remove_entity(self, ent: Entity) -> None:
        """Stop owning ``ent`` (it shut down on its own)."""
        if ent in self._entities:
            self._entities.remove(ent)

    @property
    def entities(self) -> list[Entity]:
        """The entities the node owns, oldest first (a copy)."""
        return list(self._entities)

    # -- callbacks and spinning ---------------------------------------------------------------
    def spin_once(self) -> simpy.Event:
        """Run the callbacks queued now, one at a time (roscpp ``spinOnce``).

        Meant for ``spinner="manual"`` nodes: ``yield node.spin_once()`` in the
        node's main loop.  The event fires when they have all finished.
        """
        return self.callbacks.spin_once()

    def process(self, generator: ProcessGenerator) -> simpy.Process:
        """Start a process belonging to this node (e.g. its main loop).

        ``generator`` is what calling a generator function returns: ``node.process(main())``.
        The function itself, or what a function without ``yield`` returned, is refused with a
        :class:`~ddes.errors.DdesTypeError` naming the fix."""
        self.check_alive("start a process")
        if not hasattr(generator, "throw"):
            raise DdesTypeError(_not_a_generator(generator))
        proc = self.world.env.process(generator)
        setattr(proc, NODE_OF_PROCESS, self)  # its failure is this node's crash
        return proc

    def report_crash(self, exc: BaseException) -> None:
        """The node's main raised: log it as a dying rospy script would, and shut down.

        Records ``node.exit`` with ``code=1``; the other nodes keep running.
        """
        from ddes.graph.failures import user_traceback

        text = (f"process has died: the main of {self.name} raised {type(exc).__name__}; "
                f"the node shuts down\n{user_traceback(exc)}")
        self.logerr("%s", text)
        self.world.record("node.exit", self.name, code=1, error=f"{type(exc).__name__}: {exc}")
        self.shutdown(f"main raised {type(exc).__name__}: {exc}")

    # -- topics ----------------------------------------------------------------------------------
    def advertise(self, name: str, data_class: _C, queue_size: int | None = None,
                  latch: bool = False, **kwargs: Unpack[PublisherOptions]) -> Publisher[_C]:
        """A :class:`~ddes.graph.topics.Publisher` (rospy.Publisher; roscpp advertise)."""
        from ddes.graph.topics import Publisher

        return Publisher(self, name, data_class, latch=latch, queue_size=queue_size, **kwargs)

    create_publisher = advertise

    def subscribe(self, name: str, data_class: _C,
                  callback: Callable[..., object] | None = None, callback_args: object = None,
                  queue_size: int | None = None,
                  **kwargs: Unpack[SubscriberOptions]) -> Subscriber[_C]:
        """A :class:`~ddes.graph.topics.Subscriber` (rospy.Subscriber; roscpp subscribe)."""
        from ddes.graph.topics import Subscriber

        return Subscriber(self, name, data_class, callback, callback_args, queue_size, **kwargs)

    create_subscriber = subscribe

    def wait_for_message(self, topic: str, data_class: type[MessageLike],
                         timeout: DurationLike | None = None) -> simpy.Event:
        """Event whose value is the next message on ``topic`` (rospy.wait_for_message).

        With ``timeout`` (ROS time), the event fails with ROSException when it expires.
        """
        from ddes.graph.waiting import wait_for_message

        return must_yield(wait_for_message(self, topic, data_class, timeout),
                          "node.wait_for_message(...)")

    # -- parameters --------------------------------------------------------------------------------
    def get_param(self, name: str, default: Any = _UNSET) -> Any:
        """rospy.get_param: KeyError (DdesKeyError) without a default."""
        key = self.resolve_name(name)
        params = self.world.master.params
        observer = self.world.param_observer
        if observer is not None:
            observer(self.name, key, params.has_param(key))
        return params.get_param(key) if default is _UNSET else params.get_param(key, default)

    def set_param(self, name: str, value: Any) -> None:
        """rospy.set_param."""
        self.world.master.params.set_param(self.resolve_name(name), value, caller_id=self.name)

    def has_param(self, name: str) -> bool:
        """rospy.has_param."""
        key = self.resolve_name(name)
        found = self.world.master.params.has_param(key)
        observer = self.world.param_observer
        if observer is not None:
            observer(self.name, key, found)
        return found

    def delete_param(self, name: str) -> None:
        """rospy.delete_param: KeyError if missing."""
        self.world.master.params.delete_param(self.resolve_name(name))

    def search_param(self, name: str) -> str | None:
        """rospy.search_param: the closest key up the namespace tree, or None.

        As rospy and rosmaster: ``""`` finds nothing (the master's
        ``searchParam`` refuses an empty key, rospy returns None); a private
        ``~key`` raises ROSException ("cannot search for parameter: Internal
        failure: invalid key"); a global key is returned if it is set.
        """
        key = self._resolver.search_key(name)
        if not key:
            return None
        if is_private(key):
            raise ROSParamException(
                f"cannot search for parameter: Internal failure: invalid key ({key!r} is private: "
                f"search_param looks a relative name up from the node's namespace upwards, e.g. "
                f"search_param({key[1:].lstrip('/') or 'name'!r}); read the node's own with "
                f"get_param({key!r}))"
            )
        return self.world.master.params.search_param(self.name, key)

    def get_param_names(self) -> list[str]:
        """rospy.get_param_names."""
        return self.world.master.params.get_param_names()

    # -- logging -----------------------------------------------------------------------------------
    def logdebug(self, msg: object, *args: object) -> None:
        self.log.log(DEBUG, msg, args)

    def loginfo(self, msg: object, *args: object) -> None:
        self.log.log(INFO, msg, args)

    def logwarn(self, msg: object, *args: object) -> None:
        self.log.log(WARN, msg, args)

    def logerr(self, msg: object, *args: object) -> None:
        self.log.log(ERROR, msg, args)

    def logfatal(self, msg: object, *args: object) -> None:
        self.log.log(FATAL, msg, args)

    def logdebug_throttle(self, period: DurationLike, msg: object, *args: object) -> None:
        self.log.log(DEBUG, msg, args, throttle=period)

    def loginfo_throttle(self, period: DurationLike, msg: object, *args: object) -> None:
        self.log.log(INFO, msg, args, throttle=period)

    def logwarn_throttle(self, period: DurationLike, msg: object, *args: object) -> None:
        self.log.log(WARN, msg, args, throttle=period)

    def logerr_throttle(self, period: DurationLike, msg: object, *args: object) -> None:
        self.log.log(ERROR, msg, args, throttle=period)

    def logfatal_throttle(self, period: DurationLike, msg: object, *args: object) -> None:
        self.log.log(FATAL, msg, args, throttle=period)

    def logdebug_once(self, msg: object, *args: object) -> None:
        self.log.log(DEBUG, msg, args, once=True)

    def loginfo_once(self, msg: object, *args: object) -> None:
        self.log.log(INFO, msg, args, once=True)

    def logwarn_once(self, msg: object, *args: object) -> None:
        self.log.log(WARN, msg, args, once=True)

    def logerr_once(self, msg: object, *args: object) -> None:
        self.log.log(ERROR, msg, args, once=True)

    def logfatal_once(self, msg: object, *args: object) -> None:
        self.log.log(FATAL, msg, args, once=True)

    # -- time ---------------------------------------------------------------------------------
    def get_rostime(self) -> Time:
        """Current ROS time of this node (rospy.get_rostime)."""
        return self.clock.get_rostime()

    now = get_rostime

    def get_time(self) -> float:
        """Current ROS time as float seconds (rospy.get_time)."""
        return self.clock.now_ns() / 1e9

    def get_walltime(self) -> WallTime:
        """Kernel ("wall") time, whatever the node's clock (ros::WallTime::now)."""
        return WallTime._from_ns(self.world.env.now)

    def sleep(self, duration: DurationLike) -> simpy.Event:
        """rospy.sleep on this node's clock: ``yield node.sleep(0.5)``."""
        self.check_alive("sleep")
        return must_yield(sleep(self.clock, duration), "node.sleep(...)")

    def duration_sleep(self, duration: DurationLike) -> simpy.Event:
        """roscpp Duration::sleep: the event's value says whether it slept."""
        return duration_sleep(self.clock, duration)

    def wall_sleep(self, duration: DurationLike) -> simpy.Event:
        """Sleep on the kernel clock, whatever the node's clock (WallDuration::sleep)."""
        return sleep(self.world.kernel_clock, duration)

    def create_rate(self, hz: float, reset: bool = False) -> Rate:
        """rospy.Rate on this node's clock."""
        self.check_alive("create a rate")
        return Rate(self, hz, reset)

    def create_roscpp_rate(self, hz: float) -> RoscppRate:
        """roscpp ros::Rate on this node's clock."""
        self.check_alive("create a rate")
        return RoscppRate(self, hz)

    def create_wall_rate(self, hz: float) -> WallRate:
        """ros::WallRate: a rate on the kernel clock."""
        self.check_alive("create a rate")
        return WallRate(self.world, hz)

    def create_timer(
        self,
        period: DurationLike,
        callback: Callable[[TimerEvent], object],
        oneshot: bool = False,
        reset: bool = False,
    ) -> Timer:
        """A periodic or one-shot :class:`~ddes.graph.timer.Timer` (rospy's schedule)."""
        return Timer(self, period, callback, oneshot, reset)

    def create_roscpp_timer(
        self,
        period: DurationLike,
        callback: Callable[[TimerEvent], object],
        oneshot: bool = False,
    ) -> RoscppTimer:
        """roscpp's ``ros::Timer`` (:class:`~ddes.graph.timer.RoscppTimer`, roscpp's schedule)."""
        return RoscppTimer(self, period, callback, oneshot)

    def __repr__(self) -> str:
        state = "shutdown" if self._shutdown else "running"
        return f"<Node {self.name} {state}>"


def _not_a_generator(value: object) -> str:
    """Why ``node.process(value)`` is refused, and the fix."""
    if callable(value):
        name = getattr(value, "__name__", "main")
        code = getattr(value, "__code__", None)
        if code is not None and code.co_flags & 0x20:  # CO_GENERATOR: it only was not called
            return (f"node.process({name}) got the function itself: call it, "
                    f"node.process({name}())")
        return (f"node.process({name}) got a function without `yield`: a node's process is a "
                f"generator that yields its waits (yield rate.sleep(), yield node.sleep(0.5)); "
                f"put a yield in {name} and start it with node.process({name}())")
    if value is None:
        return ("node.process(None): the function called returned None, so it has no `yield`; "
                "a node's process is a generator that yields its waits (yield rate.sleep(), "
                "yield node.sleep(0.5)): put a yield in it and pass node.process(main())")
    return (f"node.process() needs a generator (node.process(main()) with a `yield` in main), "
            f"got {type(value).__name__} {value!r:.60}")
