"""Goal id generation in actionlib's two formats, with a counter per generator.

actionlib makes goal ids in two places, with two formats:

* the server (``goal_id_generator.py``), for a goal that arrives with an empty
  id: ``"<name>-<count>-<secs>.<nsecs>"``, where ``nsecs`` is printed as a
  plain integer (not zero-padded: 5 s + 5 µs gives ``"5.5000"``);
* the client (``action_client.GoalManager._generate_id``):
  ``"%s-%i-%.3f" % (callerid, count, now.to_sec())``.

In both the first id has count 1 and the stamp of the new id is ``now``.

Deliberate deviation: ROS keeps each counter in a module-level global, shared
by every generator of the process.  ddes keeps it in the generator instance;
the owner (a world or a node) holds one generator, so two worlds in one
process never interfere and the same scenario always makes the same ids.
"""

from __future__ import annotations

from enum import Enum
from typing import NamedTuple

from ddes.errors import DdesTypeError, DdesValueError

__all__ = ["GoalIdGenerator", "GoalIdStamp", "GoalIdStyle", "check_ns"]

_NS = 1_000_000_000


def check_ns(value: int, what: str, *, instant: bool = True) -> int:
    """``value`` unchanged if it is an ``int`` of nanoseconds (>= 0 for an ``instant``).

    The pure actionlib core takes every time as int nanoseconds, in parameters
    and fields named ``*_ns``; anything else is a typed error that says how to
    convert (:mod:`ddes.time.units` is the one converter).
    """
    if isinstance(value, bool) or not isinstance(value, int):
        raise DdesTypeError(
            f"{what} must be int nanoseconds, got {value!r} ({type(value).__name__}); convert a "
            "Time, a Duration or seconds with ddes.time.units.to_ns(...)"
        )
    if instant and value < 0:
        raise DdesValueError(f"{what} must be >= 0 nanoseconds (a ROS time), got {value}")
    return value


class GoalIdStyle(str, Enum):
    """Which of actionlib's two id formats a generator produces."""

    SERVER = "server"
    CLIENT = "client"


class GoalIdStamp(NamedTuple):
    """A generated goal id and its stamp (int nanoseconds): an ``actionlib_msgs/GoalID``."""

    id: str
    stamp_ns: int


class GoalIdGenerator:
    """Make unique goal ids for the node ``name`` (its fully qualified name, e.g. ``"/fib"``).

    ``style`` picks the server format (the default, as in
    ``actionlib.goal_id_generator.GoalIDGenerator``) or the client format.
    """

    __slots__ = ("_count", "name", "style")

    def __init__(self, name: str, style: GoalIdStyle | str = GoalIdStyle.SERVER) -> None:
        if not isinstance(name, str):
            raise DdesTypeError(f"goal id generator name must be a str (a node name), got {name!r}")
        try:
            self.style = GoalIdStyle(style)
        except ValueError:
            raise DdesValueError(
                f"unknown goal id style {style!r}; use 'server' or 'client'"
            ) from None
        self.name = name
        self._count = 0

    @property
    def count(self) -> int:
        """How many ids this generator has made."""
        return self._count

    def generate_id(self, now_ns: int) -> GoalIdStamp:
        """A new id stamped ``now_ns`` (int nanoseconds of ROS time)."""
        if type(now_ns) is not int or now_ns < 0:
            check_ns(now_ns, "now_ns (the goal id time)")
        self._count += 1
        secs, nsecs = divmod(now_ns, _NS)  # rospy.Time's fields
        if self.style is _SERVER:
            text = f"{self.name}-{self._count}-{secs}.{nsecs}"
        else:  # rospy: "%s-%i-%.3f" % (name, count, now.to_sec()), to_sec() as genpy computes it
            text = f"{self.name}-{self._count:d}-{float(secs) + float(nsecs) / 1e9:.3f}"
        return GoalIdStamp(text, now_ns)

    def __repr__(self) -> str:
        return f"GoalIdGenerator({self.name!r}, style={self.style.value!r}, count={self._count})"


_SERVER = GoalIdStyle.SERVER  # a plain global for the hot path
