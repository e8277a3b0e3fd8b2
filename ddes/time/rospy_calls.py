"""Helpful errors for ROS calls written the rospy way: ddes has no global node.

rospy keeps one node per process (``rospy.init_node``), so its calls read
``rospy.Rate(10)``, ``rospy.sleep(0.5)``, ``rospy.Publisher("/t", String)``.
A ddes world holds many nodes, and every call takes its node (or world)
first: ``ddes.Rate(node, 10)``, ``yield node.sleep(0.5)``,
``ddes.Publisher(node, "/t", String, queue_size=10)``.  When a ddes class or
function is called the rospy way, it raises
:class:`~ddes.errors.MissingNodeError` (a ``TypeError`` and a
``ROSInitException``) whose message shows the ddes call to write.

This module (in the lowest room that needs it) holds the pieces every such
call site shares: :data:`REQUIRED`, the default of the argument a rospy-shaped
call leaves out, :func:`arg_text` to echo the user's arguments, and
:func:`missing_node` to build the error.
"""

from __future__ import annotations

import numbers
from collections.abc import Mapping, Sequence
from typing import Any, NoReturn

from ddes.errors import DdesTypeError, MissingNodeError

__all__ = ["COMPAT_HINT", "NODE_HINT", "REQUIRED", "arg_text", "call_text", "is_node_like", "missing_node",
           "node_first"]

#: Where a node comes from, the last line of every message.
NODE_HINT = 'where node = world.create_node("my_node") and world = ddes.World().'

#: The other answer, after every message: plain rospy code runs as a script node.
COMPAT_HINT = ("Or `from ddes.compat import rospy` to write plain rospy: a rospy script started "
               "as a node (rosrun PKG script.py) runs unchanged, its blocking calls on simulated "
               "time (docs/rospy.md).")


class _Required:
    """The default of an argument a rospy-shaped call leaves out (never a valid value)."""

    __slots__ = ()

    def __repr__(self) -> str:
        return "<required>"


#: The default of a required argument, so that a call without it can be told apart and
#: explained (``ddes.Rate(10)`` leaves ``hz`` out: the 10 went into ``node``).
REQUIRED: Any = _Required()


def arg_text(value: object) -> str:
    """Source text for an argument the user passed, for echoing it in a message."""
    if isinstance(value, (str, bool)) or value is None:
        return repr(value)
    if isinstance(value, numbers.Real):
        return repr(value)
    secs, nsecs = getattr(value, "secs", None), getattr(value, "nsecs", None)
    if isinstance(secs, int) and isinstance(nsecs, int):  # a Time or Duration
        kind = type(value).__name__
        return f"ddes.{kind}({secs})" if nsecs == 0 else f"ddes.{kind}({secs}, {nsecs})"
    name = getattr(value, "__name__", None)
    if isinstance(name, str) and name != "<lambda>":
        return name  # a class or a function
    if callable(value):
        return "callback"
    return type(value).__name__.lower()


def call_text(name: str, args: list[object], kwargs: dict[str, object] | None = None) -> str:
    """``name(arg, ..., key=value)`` with each argument echoed by :func:`arg_text`."""
    parts = [arg_text(a) for a in args]
    parts += [f"{k}={arg_text(v)}" for k, v in (kwargs or {}).items()]
    return f"{name}({', '.join(parts)})"


def is_node_like(value: object) -> bool:
    """True for a node (anything with the node's ``check_alive``)."""
    return callable(getattr(value, "check_alive", None))


def missing_node(call: str, *lines: str) -> MissingNodeError:
    """The error for ``call`` (as the user wrote it) made without the node ddes needs.

    ``lines`` are the ddes code to write instead (a line may end in a
    ``# comment`` naming an alternative).
    """
    code = "".join(f"\n    {line}" for line in lines)
    return MissingNodeError(
        f"{call} is rospy's spelling: ddes has no global node (there is no rospy.init_node), "
        f"so ROS calls take their node first. Write:{code}\n{NODE_HINT}\n{COMPAT_HINT}"
    )


def node_first(cls: str, lead: str, first: object, rest: Sequence[object],
               kwargs: Mapping[str, object], *more: str, method: str | None = None) -> NoReturn:
    """Raise the error for ``ddes.<cls>(name, ...)`` called rospy's way, its node left out.

    rospy's arguments all moved one place to the left: ``first`` (the name
    rospy takes first) went into ``node``.  ``rest`` and ``kwargs`` are the
    user's other arguments as rospy reads them (:data:`REQUIRED` and None
    are dropped); the message shows ``<lead>ddes.<cls>(node, ...)`` (``lead``
    is ``"pub = "``, ``"yield "`` ...), the node method ``method`` as an
    alternative, and the lines ``more``.
    """
    if not isinstance(first, str):
        raise DdesTypeError(f"ddes.{cls}(node, ...) needs a node first, got {first!r}")
    args = [first, *[a for a in rest if a is not REQUIRED and a is not None]]
    inner = ", ".join([arg_text(a) for a in args]
                      + [f"{k}={arg_text(v)}" for k, v in kwargs.items()])
    line = f"{lead}ddes.{cls}(node, {inner})"
    if method is not None:
        line += f"    # or node.{method}({inner})"
    raise missing_node(call_text(f"ddes.{cls}", args, dict(kwargs)), line, *more)
