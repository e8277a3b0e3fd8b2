"""Nodes: the owners of every ROS entity.

A node is created through its world (``world.create_node("talker")``) and
creates its entities (timers, rates, publishers, services, ...).  When it
shuts down, they go away with it.  ROS time for the node comes from its
:attr:`clock`: the kernel clock, or a :class:`~ddes.time.clock.SimClock`
following ``/clock`` when the node uses simulated time.

Callbacks (timer fires, and later message deliveries and service
requests) run through :meth:`Node._invoke`: a plain function runs to
completion at once; a generator function runs as a SimPy process, so a
callback may take simulated time (``yield node.sleep(0.1)``).
"""

from __future__ import annotations

import traceback
from collections.abc import Callable, Generator
from types import GeneratorType
from typing import TYPE_CHECKING, Any

import simpy

from ddes.errors import DdesTypeError, NodeShutdownError
from ddes.time.clock import Clock, SimClock
from ddes.time.rate import Rate, RoscppRate, WallRate
from ddes.time.rostime import Time, WallTime
from ddes.time.sleep import duration_sleep, sleep
from ddes.time.timer import Timer, TimerEvent

if TYPE_CHECKING:
    from ddes.kernel.world import World

__all__ = ["Node"]


class Node:
    """A ROS node inside a :class:`~ddes.kernel.world.World`.

    Parameters
    ----------
    world:
        The owning world.
    name:
        The node name (``"talker"`` or ``"/ns/talker"``).
    use_sim_time:
        Follow ``/clock`` instead of kernel time.  ``None`` reads the
        ``/use_sim_time`` parameter when the node starts, as rospy does.
    """

    def __init__(self, world: World, name: str, *, use_sim_time: bool | None = None) -> None:
        if not isinstance(name, str) or not name:
            raise DdesTypeError(f"node name must be a non-empty string, got {name!r}")
        self.world = world
        self.name = name if name.startswith("/") else "/" + name
        if use_sim_time is None:
            use_sim_time = bool(world.get_use_sim_time())
        self.use_sim_time = bool(use_sim_time)
        self.clock: Clock = SimClock(world) if self.use_sim_time else world.kernel_clock
        self._entities: list[Any] = []
        #: True while callbacks must wait (a callback is running in simulated
        #: time under a single-threaded spinner); timers then take the slow path.
        self._busy = False
        self._shutdown = False
        self._shutdown_hooks: list[Callable[[str], Any]] = []
        old = world._nodes.get(self.name)
        if old is not None:
            old.shutdown("new node registered with same name")
        world._nodes[self.name] = self
        world.record("node.start", self.name, use_sim_time=self.use_sim_time)

    # -- lifecycle --------------------------------------------------------------
    def is_shutdown(self) -> bool:
        """True once :meth:`shutdown` ran."""
        return self._shutdown

    def on_shutdown(self, hook: Callable[[str], Any]) -> None:
        """Call ``hook(reason)`` when the node shuts down (rospy.on_shutdown)."""
        self._shutdown_hooks.append(hook)

    def shutdown(self, reason: str = "") -> None:
        """Shut the node down: its entities stop and it leaves the world."""
        if self._shutdown:
            return
        self._shutdown = True
        for ent in reversed(list(self._entities)):
            ent.shutdown()
        self._entities.clear()
        if self.world._nodes.get(self.name) is self:
            del self.world._nodes[self.name]
        self.world.record("node.shutdown", self.name, reason=reason)
        for hook in self._shutdown_hooks:
            hook(reason)

    def _check_alive(self, what: str) -> None:
        if self._shutdown:
            raise NodeShutdownError(
                f"cannot {what}: node {self.name} is shut down; create a new node"
            )

    def _add_entity(self, ent: Any) -> None:
        self._entities.append(ent)

    def _remove_entity(self, ent: Any) -> None:
        if ent in self._entities:
            self._entities.remove(ent)

    # -- callbacks ----------------------------------------------------------------
    def _invoke(
        self,
        fn: Callable[..., Any],
        args: tuple[Any, ...],
        on_done: Callable[[], Any] | None = None,
    ) -> None:
        """Run a callback of this node; a generator result runs as a process."""
        try:
            result = fn(*args)
        except Exception as exc:  # noqa: BLE001 - reported, then policy decides
            self._callback_error(fn, exc)
            if on_done is not None:
                on_done()
            return
        if type(result) is GeneratorType:
            proc = self.world.env.process(self._run_generator(fn, result))
            if on_done is not None:
                proc.callbacks.append(lambda _p: on_done())
        elif on_done is not None:
            on_done()

    def _run_generator(self, fn: Callable[..., Any], gen: Generator[Any, Any, Any]) -> Generator[Any, Any, Any]:
        try:
            return (yield from gen)
        except Exception as exc:  # noqa: BLE001
            self._callback_error(fn, exc)
            return None

    def _callback_error(self, fn: Callable[..., Any], exc: BaseException) -> None:
        name = getattr(fn, "__qualname__", repr(fn))
        self.world.record(
            "callback.exception",
            self.name,
            callback=name,
            error=f"{type(exc).__name__}: {exc}",
        )
        self.world.callback_errors.append((self.name, name, exc, traceback.format_exc()))
        if self.world.raise_callback_errors:
            raise exc

    def process(self, generator: Generator[Any, Any, Any]) -> simpy.Process:
        """Start a process belonging to this node (e.g. its main loop)."""
        self._check_alive("start a process")
        return self.world.env.process(generator)

    # -- time ---------------------------------------------------------------------
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

    def sleep(self, duration: Any) -> simpy.Event:
        """rospy.sleep on this node's clock: ``yield node.sleep(0.5)``."""
        self._check_alive("sleep")
        return sleep(self.clock, duration)

    def duration_sleep(self, duration: Any) -> simpy.Event:
        """roscpp Duration::sleep: the event's value says whether it slept."""
        return duration_sleep(self.clock, duration)

    def wall_sleep(self, duration: Any) -> simpy.Event:
        """Sleep on the kernel clock, whatever the node's clock (WallDuration::sleep)."""
        return sleep(self.world.kernel_clock, duration)

    def create_rate(self, hz: float, reset: bool = False) -> Rate:
        """rospy.Rate on this node's clock."""
        self._check_alive("create a rate")
        return Rate(self, hz, reset)

    def create_roscpp_rate(self, hz: float) -> RoscppRate:
        """roscpp ros::Rate on this node's clock."""
        self._check_alive("create a rate")
        return RoscppRate(self, hz)

    def create_wall_rate(self, hz: float) -> WallRate:
        """ros::WallRate: a rate on the kernel clock."""
        self._check_alive("create a rate")
        return WallRate(self.world, hz)

    def create_timer(
        self,
        period: Any,
        callback: Callable[[TimerEvent], Any],
        oneshot: bool = False,
        reset: bool = False,
    ) -> Timer:
        """A periodic or one-shot :class:`~ddes.time.timer.Timer`."""
        return Timer(self, period, callback, oneshot, reset)

    def __repr__(self) -> str:
        state = "shutdown" if self._shutdown else "running"
        return f"<Node {self.name} {state}>"

