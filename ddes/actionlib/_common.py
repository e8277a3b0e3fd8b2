"""What the action servers and clients share: the action's types, parameters, trace helpers.

* :class:`ActionTypes` unpacks an ``ActionSpec`` (``FooAction``) into its six
  message classes, as rospy's ``ActionServer``/``ActionClient`` do with
  ``type(ActionSpec().action_goal)`` and friends;
* :func:`queue_size_param` reads ``actionlib_*_queue_size`` with ROS's
  defaults and its rule that a negative value means the default;
* :func:`run_user_callbacks` calls user callbacks, so a callback that is a
  generator (it ``yield``\\ s simulated time) runs as part of the node's
  callback, as a slow callback does in ROS: the subscriber or timer callback
  that called it returns the generator, and the node's callback runner
  (:meth:`ddes.graph.callbacks.CallbackQueue.run`) holds the spinner until it
  ends;
* :func:`misuse` logs a misuse with ROS's text and records it as an
  ``action.misuse`` trace event, so a grader can count it;
* :func:`no_node` explains a server or client made the rospy way, without
  its node (``SimpleActionServer("fib", FibonacciAction, ...)``).
"""

from __future__ import annotations

from collections.abc import Callable, Generator, Iterable
from dataclasses import dataclass
from types import GeneratorType
from typing import TYPE_CHECKING, Any, NoReturn, TypeAlias, cast

import simpy

from ddes.actionlib.goal_id import GoalIdGenerator, GoalIdStamp, GoalIdStyle
from ddes.errors import ROSActionException
from ddes.graph.rosout import ERROR, WARN
from ddes.msg.message import Message
from ddes.time.rospy_calls import node_first

if TYPE_CHECKING:
    from ddes.graph.node import Node

__all__ = [
    "ActionTypes",
    "CallbackChain",
    "CallbackGenerator",
    "NodeGoalIds",
    "UserCall",
    "check_message",
    "misuse",
    "no_node",
    "queue_size_param",
    "run_user_callbacks",
]

def no_node(cls: str, var: str, ns: object, args: list[object],
            kwargs: dict[str, object], *, start: bool | None = None) -> NoReturn:
    """Raise the error for ``ddes.<cls>(ns, ...)`` made the rospy way, without the node.

    ``args`` and ``kwargs`` are the user's arguments after the namespace, as
    rospy reads them; the message shows the ddes call with ``node`` first,
    and ``server.start()`` when the server will not start by itself
    (``start``; by default when ``auto_start=False`` was given).
    """
    if start is None:
        start = kwargs.get("auto_start") is False
    more = ["server.start()    # the server starts when you say so"] if start else []
    node_first(cls, f"{var} = ", ns, args, kwargs, *more)


#: The rest of a callback that takes simulated time: a generator of events to wait for.
CallbackGenerator: TypeAlias = Generator[simpy.Event, Any, None]
#: One user callback to call and its arguments (a None callback is skipped).
UserCall: TypeAlias = "tuple[Callable[..., object] | None, tuple[object, ...]]"


class NodeGoalIds(GoalIdGenerator):
    """A :class:`GoalIdGenerator` whose counter belongs to the node, kept in its world.

    ROS counts goal ids in a module global, one counter per process for the
    servers and one for the clients; a ddes node stands for a process, so
    every generator of a node shares the node's counter (two clients of one
    node never make the same id), and two worlds never interfere.
    """

    __slots__ = ("_key", "_world")

    def __init__(self, node: Node, style: GoalIdStyle) -> None:
        super().__init__(node.name, style)
        self._world = node.world
        self._key = f"actionlib.goal_id.{style.value}:{node.name}"

    def generate_id(self, now_ns: int) -> GoalIdStamp:
        self._count = self._world.next_id(self._key) - 1
        return super().generate_id(now_ns)


@dataclass(frozen=True)
class ActionTypes:
    """The message classes of one action: ``FooAction`` and the six it contains.

    ``ActionTypes.of(spec)`` accepts the ``FooAction`` class (as rospy does)
    or its name ``"pkg/FooAction"``.  Anything else raises
    :class:`~ddes.errors.ROSActionException` with rospy's text
    ``"Type is not an action spec: ..."``.
    """

    spec: type[Message]
    action_goal: type[Message]
    action_result: type[Message]
    action_feedback: type[Message]
    goal: type[Message]
    result: type[Message]
    feedback: type[Message]

    @classmethod
    def of(cls, spec: object) -> ActionTypes:
        """The types of ``spec`` (a ``FooAction`` class or ``"pkg/FooAction"``; anything else
        raises)."""
        if isinstance(spec, str):
            from ddes.msg import get_message_class

            try:
                spec = get_message_class(spec)
            except Exception as exc:  # noqa: BLE001 - reported as the ROS error below
                raise ROSActionException(
                    f"Type is not an action spec: {spec} ({exc}); pass the generated "
                    "FooAction class, e.g. get_message_class('actionlib_tutorials/FibonacciAction')"
                ) from None
        try:
            action = cast("type[Message]", spec)  # whatever it is: a failure below says so
            a = action()
            ag, ar, af = a.action_goal, a.action_result, a.action_feedback
            types = cls(action, type(ag), type(ar), type(af), type(ag.goal), type(ar.result),
                        type(af.feedback))
        except Exception:  # noqa: BLE001 - rospy catches AttributeError; any failure means the same
            raise ROSActionException(
                f"Type is not an action spec: {spec!r}; pass the generated FooAction class, "
                "e.g. get_message_class('actionlib_tutorials/FibonacciAction')"
            ) from None
        return types

    @property
    def name(self) -> str:
        """The action's type name without the ``Action`` suffix (``pkg/Foo``)."""
        t: str = self.spec._type
        return t[: -len("Action")] if t.endswith("Action") else t


def check_message(value: object, cls: type[Message], what: str, fix: str) -> None:
    """Raise ROSActionException unless ``value`` is a ``cls`` message (same type and md5)."""
    if getattr(value, "_type", None) == cls._type and getattr(value, "_md5sum", None) == cls._md5sum:
        return
    got = getattr(value, "_type", None) or type(value).__name__
    raise ROSActionException(f"{what} must be a {cls._type}, got {got} ({value!r:.80}); {fix}")


def queue_size_param(node: Node, name: str, default: int) -> int | None:
    """``actionlib_<name>_queue_size`` (searched in the node's namespace) with ROS's defaults.

    Publishers: a negative value means ``default``.  Subscribers (default -1):
    a negative value means unbounded (None).
    """
    value = node.get_param(name, default)
    if isinstance(value, bool) or not isinstance(value, int):
        node.logwarn("Parameter %s must be an int, got %r; using %d", name, value, default)
        value = default
    if value < 0:
        return None if default < 0 else default
    return value


class CallbackChain:
    """User callbacks called in order, as one callback of the node.

    :meth:`call` calls a callback at once, until one of them turns out to be
    a generator (it takes simulated time); from then on the later ones wait
    for it.  :meth:`rest` is None if everything finished, else the generator
    that runs what is left, one after the other: the node's callback that
    made the calls returns it, and the callback runner holds the spinner
    until it ends.
    """

    __slots__ = ("_pending",)

    def __init__(self) -> None:
        self._pending: list[Generator[simpy.Event, Any, object]] = []

    def call(self, fn: Callable[..., object] | None, *args: object) -> None:
        """Call ``fn(*args)`` now, or after the generator callbacks before it (None: skip)."""
        if fn is None:
            return
        if self._pending:
            self._pending.append(_deferred(fn, args))
            return
        result = fn(*args)
        if type(result) is GeneratorType:
            self._pending.append(result)

    def rest(self) -> CallbackGenerator | None:
        """What is left to run (None: nothing, every callback finished at once)."""
        return _chain(self._pending) if self._pending else None


def run_user_callbacks(calls: Iterable[UserCall]) -> CallbackGenerator | None:
    """Call each ``fn(*args)`` in order (see :class:`CallbackChain`); what is left, or None.

    Returns None when every callback finished at once; otherwise a generator
    that runs the generator callbacks one after the other (the node runs it
    as the rest of the current callback, so it takes simulated time).
    """
    if type(calls) is list and len(calls) == 1:  # one call (the hot path): no chain
        fn, args = calls[0]
        result = None if fn is None else fn(*args)
        return _chain([result]) if type(result) is GeneratorType else None
    chain = CallbackChain()
    for fn, args in calls:
        chain.call(fn, *args)
    return chain.rest()


def _deferred(fn: Callable[..., object], args: tuple[object, ...]) -> CallbackGenerator:
    result = fn(*args)
    if type(result) is GeneratorType:
        yield from result


def _chain(gens: list[Generator[simpy.Event, Any, object]]) -> CallbackGenerator:
    for gen in gens:
        yield from gen


def misuse(node: Node, ns: str, text: str, *, level: int = ERROR, **details: object) -> None:
    """Log ``text`` as ROS does (``logerr``/``logwarn``) and record ``action.misuse``."""
    node.world.record("action.misuse", node.name, ns=ns, level="WARN" if level == WARN else "ERROR",
                      text=text, **details)
    node.log.log(level, text, (), depth=2)
