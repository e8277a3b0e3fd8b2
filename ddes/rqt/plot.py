"""``rqt_plot``: numeric message fields over time, as rqt_plot draws them.

A field is named as rqt_plot names it: the topic, then the field path, with ``[i]`` for an
array element and ``a:b`` for sibling fields (``/odom/twist/twist/linear/x``,
``/scan/ranges[180]``, ``/turtle1/pose/x:y``).  The topic is the longest known topic that
is a prefix of the name.  Values: numbers, bools (0/1), times and durations (seconds).

Time on x, in seconds: like rqt_plot, the message's ``header.stamp`` when its type has a
header, else when it was published (a world's kernel time; a bag's record time).

Sources: a world reads its trace (every ``topic.publish`` event holds the message bytes, so
no recorder needs to run first, but a trace that was switched off or filtered holds
nothing); a :class:`~ddes.rosbag.Bag` or a bag path reads the bag.
"""

from __future__ import annotations

import difflib
import re
from collections.abc import Sequence
from typing import Any, NamedTuple

from ddes.errors import DdesValueError
from ddes.rqt.messages import iter_fields, topic_messages, topic_names

__all__ = ["Series", "expand_fields", "field_series", "rqt_plot", "split_field"]

_INDEX = re.compile(r"^([A-Za-z_][A-Za-z0-9_]*)((?:\[\d+\])*)$")


class Series(NamedTuple):
    """One curve: its name (``/odom/twist/twist/linear/x``), times (s) and values."""

    name: str
    t: list[float]
    y: list[float]


def expand_fields(spec: str) -> list[str]:
    """``/a/b/x:y`` -> ``['/a/b/x', '/a/b/y']`` (rqt_plot's sibling syntax)."""
    if ":" not in spec:
        return [spec]
    head, _, last = spec.rpartition("/")
    return [f"{head}/{name}" for name in last.split(":") if name]


def split_field(name: str, topics: list[str]) -> tuple[str, list[str]]:
    """``(topic, [field, ...])`` of a field name: the longest topic that is its prefix."""
    if not name.startswith("/"):
        name = "/" + name
    best = ""
    for topic in topics:
        if (name == topic or name.startswith(topic + "/") or name.startswith(topic + "[")) \
                and len(topic) > len(best):
            best = topic
    if not best:
        scored = []
        for topic in topics:  # compare each topic with as many of the name's parts
            head = "/".join(name.split("/")[:topic.count("/") + 1])
            scored.append((difflib.SequenceMatcher(None, head, topic).ratio(), topic))
        near = [t for r, t in sorted(scored, key=lambda rt: -rt[0]) if r >= 0.6][:1]
        hint = f"; did you mean a field of {near[0]!r}?" if near else ""
        raise DdesValueError(f"rqt_plot: no topic is a prefix of {name!r}{hint} "
                             f"(topics: {', '.join(topics) or 'none'})")
    rest = name[len(best):]
    if rest.startswith("["):  # /topic[3]: an array message (std_msgs/Float64MultiArray is not)
        raise DdesValueError(f"rqt_plot: {name!r} indexes the topic itself; name a field")
    return best, [p for p in rest.split("/") if p]


def _value(msg: Any, topic: str, path: list[str]) -> float:
    value = msg
    walked = topic
    for part in path:
        m = _INDEX.match(part)
        if m is None:
            raise DdesValueError(f"rqt_plot: bad field name {part!r} in {topic}/{'/'.join(path)}")
        slot, indices = m.group(1), m.group(2)
        if slot not in getattr(value, "__slots__", ()):
            fields = list(getattr(value, "__slots__", ()))
            raise DdesValueError(f"rqt_plot: {walked} has no field {slot!r} "
                                 f"(fields: {', '.join(fields) or 'none'})")
        value = getattr(value, slot)
        walked += "/" + slot
        for index in re.findall(r"\[(\d+)\]", indices):
            i = int(index)
            if not hasattr(value, "__getitem__") or isinstance(value, str) or i >= len(value):
                raise DdesValueError(f"rqt_plot: {walked}[{i}] is out of range "
                                     f"(length {len(value) if hasattr(value, '__len__') else 0})")
            value = value[i]
            walked += f"[{i}]"
    if isinstance(value, bool):
        return 1.0 if value else 0.0
    if isinstance(value, (int, float)):
        return float(value)
    if hasattr(value, "to_sec"):
        return float(value.to_sec())
    if isinstance(value, (list, tuple, bytes)):
        raise DdesValueError(f"rqt_plot: {walked} is an array of {len(value)}; "
                             f"plot one element, e.g. {walked}[0]")
    leaves = [f"{walked}/{f}" for f in iter_fields(value)][:8]
    raise DdesValueError(f"rqt_plot: {walked} is not a number ({type(value).__name__}); "
                         f"numeric fields under it: {', '.join(leaves) or 'none'}")


def field_series(source: Any, name: str, *, time: str = "auto") -> Series:
    """The curve of one field name of ``source`` (a world, a Bag or a bag path).

    ``time``: ``"auto"`` (header stamp when the type has a header, else publish time, as
    rqt_plot), ``"header"`` or ``"publish"``.
    """
    if time not in ("auto", "header", "publish"):
        raise DdesValueError(f"time must be 'auto', 'header' or 'publish', got {time!r}")
    topic, path = split_field(name, topic_names(source))
    _, messages = topic_messages(source, topic)
    has_header = bool(messages) and hasattr(messages[0].msg, "header") and hasattr(
        messages[0].msg.header, "stamp")
    if time == "header" and not has_header:
        raise DdesValueError(f"rqt_plot: {topic} has no header; use time='publish'")
    use_stamp = has_header and time != "publish"
    if not path:
        path = []
    ts: list[float] = []
    ys: list[float] = []
    for p in messages:
        ys.append(_value(p.msg, topic, path))
        ts.append(p.msg.header.stamp.to_sec() if use_stamp else p.t_ns / 1e9)
    return Series(topic + "".join("/" + part for part in path), ts, ys)


def rqt_plot(source: Any, *fields: str, time: str = "auto", ax: Any = None,
             title: str | None = None, ylabel: str | None = None,
             right: Sequence[str] = (), right_ylabel: str | None = None) -> Any:
    """Draw ``fields`` of ``source`` over time on one axes; returns the figure.

    ``rqt_plot(world, "/odom/twist/twist/linear/x", "/cmd_vel/linear/x")``; each field is
    one line, labelled with its name (``a:b`` gives two).  ``source`` is a world, a Bag or a
    bag file path.  A new figure is a :class:`ddes.display.figure.DisplayFigure` (a notebook
    shows it); pass ``ax`` to draw into existing axes.  ``ylabel`` names the y-axis (with its
    unit: ``"speed [m/s]"``; rqt_plot itself has none).  Fields of another unit go in
    ``right``: they are drawn against a second y-axis on the right (``ax.twinx()``), named
    ``right_ylabel``; one legend lists the curves of both.
    """
    from ddes.display.figure import new_figure

    if not fields:
        raise DdesValueError("rqt_plot: name at least one field, e.g. /odom/twist/twist/linear/x")
    if isinstance(right, str):
        right = (right,)
    names = [n for spec in fields for n in expand_fields(spec)]
    others = [n for spec in right for n in expand_fields(spec)]
    curves = [field_series(source, n, time=time) for n in names]
    twins = [field_series(source, n, time=time) for n in others]
    if ax is None:
        fig = new_figure(figsize=(8.0, 4.0))
        ax = fig.add_subplot(1, 1, 1)
    else:
        fig = ax.figure
    handles = [ax.plot(c.t, c.y, label=c.name, linewidth=1.3, gid=f"series:{c.name}")[0]
               for c in curves]
    ax.set_xlabel("time [s]")
    if ylabel is not None:
        ax.set_ylabel(ylabel)
    ax.grid(True, color="0.88")
    top = ax
    if twins:
        top = twin = ax.twinx()
        colors = [f"C{i % 10}" for i in range(len(curves), len(curves) + len(twins))]
        handles += [twin.plot(c.t, c.y, label=c.name, linewidth=1.3, color=color,
                              linestyle="--", gid=f"series:{c.name}")[0]
                    for c, color in zip(twins, colors, strict=True)]
        if right_ylabel is not None:
            twin.set_ylabel(right_ylabel)
    top.legend(handles=handles, loc="best", fontsize=9)  # on the upper axes: never hidden
    ax.set_title(title if title is not None else ", ".join(names + others), fontsize=11)
    return fig
