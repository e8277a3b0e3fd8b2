"""The messages a picture reads: a topic's publications in a world's trace, or in a bag.

Every ``topic.publish`` event of a world's trace holds the message's serialized bytes
(docs/trace.md), so a world needs no recorder started before the run: what was published
while the trace stored events can be read back, decoded with the topic's type (from its
``topic.advertise`` event, else from the master).  A bag (a :class:`ddes.rosbag.Bag` or a
path) is read with ``read_messages``.
"""

from __future__ import annotations

import difflib
import os
from collections.abc import Iterator
from typing import Any, NamedTuple

from ddes.errors import DdesTypeError, DdesValueError
from ddes.rosbag.bag import Bag

__all__ = ["Published", "is_world", "topic_messages", "topic_names"]


class Published(NamedTuple):
    """One message of a topic: when it was published (world kernel ns, or the bag's record
    time in ns) and the message."""

    t_ns: int
    msg: Any


def is_world(source: Any) -> bool:
    """A ddes world (it has a trace and a master)."""
    return hasattr(source, "trace") and hasattr(source, "master")


def topic_names(source: Any) -> list[str]:
    """The topics ``source`` has messages or registrations for, sorted."""
    if is_world(source):
        names = {str(ev.details.get("topic")) for ev in source.trace.select(kind="topic.advertise")}
        names.update(name for name, _ in source.master.get_topic_types())
        return sorted(names)
    with _open_bag(source) as bag:
        return sorted(bag.get_type_and_topic_info().topics)


def _type_in_world(world: Any, topic: str) -> str | None:
    first = world.trace.select(kind="topic.advertise", topic=topic).first()
    if first is not None:
        return str(first.details["type"])
    entry = world.master.topics.get(topic)
    return None if entry is None or entry.type == "*" else str(entry.type)


def _unknown(topic: str, known: list[str], where: str) -> DdesValueError:
    near = difflib.get_close_matches(topic, known, n=1)
    hint = f"; did you mean {near[0]!r}?" if near else ""
    return DdesValueError(f"topic {topic!r} has no messages in {where}{hint} "
                          f"(topics: {', '.join(known) or 'none'})")


class _open_bag:  # noqa: N801 - a context manager used like a function
    """A Bag given as it is (left open), or a path opened for reading (closed after)."""

    def __init__(self, source: Any) -> None:
        if isinstance(source, Bag):
            self.bag, self.owned = source, False
        elif isinstance(source, (str, os.PathLike)):
            self.bag, self.owned = Bag(source), True
        else:
            raise DdesTypeError(f"expected a ddes World, a Bag or a bag file path, got "
                                f"{type(source).__name__}")

    def __enter__(self) -> Bag:
        return self.bag

    def __exit__(self, *exc: object) -> None:
        if self.owned:
            self.bag.close()


def topic_messages(source: Any, topic: str) -> tuple[str, list[Published]]:
    """``(type, [Published(t_ns, msg), ...])`` of ``topic`` in ``source``, in order.

    ``source``: a world (its trace's ``topic.publish`` events), a :class:`~ddes.rosbag.Bag`
    or a bag file path.  A topic with no messages raises :class:`DdesValueError` naming the
    topics there are.
    """
    if is_world(source):
        world = source
        type_name = _type_in_world(world, topic)
        events = world.trace.select(kind="topic.publish", topic=topic)
        if type_name is None or not events:
            where = "this world's trace"
            if not world.trace.complete:
                where += " (it does not store every event: recording off or filtered)"
            raise _unknown(topic, topic_names(world), where)
        cls = world.messages.get_message_class(type_name)
        return type_name, [Published(ev.t, cls().deserialize(ev.details["data"]))
                           for ev in events]
    with _open_bag(source) as bag:
        info = bag.get_type_and_topic_info().topics
        if topic not in info:
            raise _unknown(topic, sorted(info), f"bag {bag.filename!r}")
        out = [Published(t.to_nsec(), m) for _, m, t in bag.read_messages(topics=[topic])]
        return str(info[topic].msg_type), out


def iter_fields(msg: Any, prefix: str = "") -> Iterator[str]:
    """The numeric leaf field paths of ``msg`` (``twist/twist/linear/x`` ...), for hints."""
    for slot in getattr(msg, "__slots__", ()):
        value = getattr(msg, slot)
        path = f"{prefix}{slot}"
        if hasattr(value, "__slots__") and not hasattr(value, "to_nsec"):
            yield from iter_fields(value, path + "/")
        elif isinstance(value, (int, float)) or hasattr(value, "to_nsec"):
            yield path
