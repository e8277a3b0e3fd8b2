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

from ddes.actionlib._nanos import time_ns
from ddes.errors import DdesTypeError, DdesValueError
from ddes.time.rostime import Time

__all__ = ["GoalIdGenerator", "GoalIdStamp", "GoalIdStyle"]

_NS = 1_000_000_000


class GoalIdStyle(str, Enum):
    """Which of actionlib's two id formats a generator produces."""

    SERVER = "server"
    CLIENT = "client"


class GoalIdStamp(NamedTuple):
    """A generated goal id and its stamp (int nanoseconds): an ``actionlib_msgs/GoalID``."""

    id: str
    stamp: int


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

    def generate_id(self, now: int | Time) -> GoalIdStamp:
        """A new id stamped ``now`` (int nanoseconds or a ``Time``)."""
        ns = time_ns(now, "goal id time")
        self._count += 1
        secs, nsecs = divmod(ns, _NS)
        if self.style is GoalIdStyle.SERVER:
            text = f"{self.name}-{self._count}-{secs}.{nsecs}"
        else:
            to_sec = float(secs) + float(nsecs) / 1e9  # genpy's Time.to_sec()
            text = f"{self.name}-{self._count:d}-{to_sec:.3f}"  # rospy: "%s-%i-%.3f"
        return GoalIdStamp(text, ns)

    def __repr__(self) -> str:
        return f"GoalIdGenerator({self.name!r}, style={self.style.value!r}, count={self._count})"
