"""A timeline of action goals from a world's trace (matplotlib).

:func:`goal_timelines` reads the ``action.*`` events of a trace into one
:class:`GoalTimeline` per goal: the server-side status intervals (PENDING,
ACTIVE, PREEMPTING, RECALLING), the terminal instant and status, feedback
ticks, cancel requests received, preempt requests and client-side LOST marks.
:func:`plot_goals` draws them, one row per goal, over simulated time::

    from ddes.actionlib import plot_goals
    fig = plot_goals(world.trace, ns="/fibonacci")
    fig.savefig("goals.png")          # or just `fig` as the last line of a notebook cell

The figure is built without pyplot (no global figure state), so it works
the same under any backend; notebooks display the returned Figure.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field
from types import MappingProxyType
from typing import TYPE_CHECKING

from ddes.actionlib.states import TERMINAL_STATUSES, GoalStatus
from ddes.time.units import TimeLike, ns_to_sec, time_to_ns

if TYPE_CHECKING:
    from matplotlib.artist import Artist
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

    from ddes.kernel.trace import Trace, TraceEvent

__all__ = ["STATUS_COLORS", "GoalTimeline", "goal_timelines", "plot_goals"]

#: Colour of each status in the plot (bars for the live ones, markers for the terminal ones).
STATUS_COLORS: Mapping[str, str] = MappingProxyType({
    "PENDING": "#bdbdbd",
    "ACTIVE": "#4c9be8",
    "PREEMPTING": "#f2a541",
    "RECALLING": "#c9a0dc",
    "SUCCEEDED": "#2e9d4f",
    "ABORTED": "#d62728",
    "PREEMPTED": "#ff7f0e",
    "REJECTED": "#8c564b",
    "RECALLED": "#9467bd",
    "LOST": "#000000",
})
_TERMINAL_NAMES = frozenset(s.name for s in TERMINAL_STATUSES)


@dataclass
class GoalTimeline:
    """What happened to one goal, in kernel nanoseconds.

    ``segments`` are ``(start, end, status)`` for the non-terminal statuses;
    ``end`` is None while the goal was still in that status at the end of
    the trace.  ``terminal`` is ``(t, status)`` once the goal finished.
    """

    goal_id: str
    ns: str
    first_seen: int
    segments: list[tuple[int, int | None, str]] = field(default_factory=list)
    terminal: tuple[int, str] | None = None
    feedback: list[int] = field(default_factory=list)
    cancels: list[int] = field(default_factory=list)
    preempts: list[int] = field(default_factory=list)
    lost: list[int] = field(default_factory=list)

    def _enter(self, t: int, status: str) -> None:
        if self.segments and self.segments[-1][1] is None:
            start, _, old = self.segments[-1]
            self.segments[-1] = (start, t, old)
        if status in _TERMINAL_NAMES:
            self.terminal = (t, status)
        else:
            self.segments.append((t, None, status))

    @property
    def status(self) -> str:
        """The last status the server gave the goal."""
        if self.terminal is not None:
            return self.terminal[1]
        return self.segments[-1][2] if self.segments else GoalStatus.PENDING.name


def goal_timelines(trace: Trace | Iterable[TraceEvent], ns: str | None = None,
                   source: str | None = None) -> list[GoalTimeline]:
    """One timeline per goal id, in order of first appearance.

    ``ns`` keeps one action namespace (``"/fibonacci"``); ``source`` keeps
    the events of one server node (client events are kept whatever their node).
    """
    goals: dict[tuple[str, str], GoalTimeline] = {}

    def get(ev: TraceEvent, gid: str) -> GoalTimeline:
        key = (ev.details.get("ns", ""), gid)
        tl = goals.get(key)
        if tl is None:
            tl = goals[key] = GoalTimeline(gid, key[0], ev.t)
        return tl

    for ev in trace:
        kind = ev.kind
        if not kind.startswith("action."):
            continue
        d = ev.details
        if ns is not None and d.get("ns") != ns:
            continue
        server_side = kind.startswith("action.server.") or kind.startswith("action.simple.")
        if server_side and source is not None and ev.source != source:
            continue
        gid: str = d.get("id") or ""
        if kind == "action.server.goal":
            if d["arrival"] in ("new", "canceled_by_stamp"):
                get(ev, gid)._enter(ev.t, GoalStatus.PENDING.name)
        elif kind == "action.server.transition":
            tl = get(ev, gid)
            if d["after"] == GoalStatus.PREEMPTING.name:
                tl.preempts.append(ev.t)
            tl._enter(ev.t, d["after"])
        elif kind == "action.server.cancel":
            for matched in d["matched"]:
                get(ev, matched).cancels.append(ev.t)
            if d.get("placeholder"):
                tl = get(ev, gid)
                tl.cancels.append(ev.t)
                tl._enter(ev.t, GoalStatus.RECALLING.name)
        elif kind == "action.server.feedback":
            get(ev, gid).feedback.append(ev.t)
        elif kind == "action.simple.preempt_request" and gid:
            get(ev, gid).preempts.append(ev.t)
        elif kind == "action.client.lost":
            get(ev, gid).lost.append(ev.t)
    return list(goals.values())


def plot_goals(trace: Trace | Iterable[TraceEvent], ns: str | None = None, *,
               source: str | None = None, ax: Axes | None = None, until: TimeLike | None = None,
               title: str | None = None) -> Figure:
    """Draw the goals of ``trace`` over simulated time; returns the Figure.

    Bars: the server-side status of each goal; diamonds: terminal statuses;
    ``|`` ticks: feedback; ``x`` (above the bar): cancel requests received;
    ``^`` (below): preempt requests; black squares: the client marked the goal LOST.  ``until``
    (seconds or a Time) ends the bars of unfinished goals; by default the
    last event of the trace.  Pass ``ax`` to draw into existing axes.
    """
    from matplotlib.figure import Figure
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch

    events = list(trace)
    end = (events[-1].t if events else 0) if until is None else time_to_ns(until, "until")
    timelines = goal_timelines(events, ns, source)
    if ax is None:
        fig = Figure(figsize=(9.0, 1.2 + 0.45 * max(1, len(timelines))))
        ax = fig.add_subplot(1, 1, 1)
    else:
        fig = ax.figure  # type: ignore[assignment]
    used: set[str] = set()
    for row, tl in enumerate(timelines):
        y = len(timelines) - 1 - row
        for start, stop, status in tl.segments:
            stop_t = end if stop is None else stop
            bar = (ns_to_sec(start), ns_to_sec(max(stop_t - start, 0)))
            ax.broken_barh([bar], (y - 0.3, 0.6),
                           facecolors=STATUS_COLORS[status], edgecolors="none")
            used.add(status)
        if tl.terminal is not None:
            t, status = tl.terminal
            ax.plot([ns_to_sec(t)], [y], marker="D", color=STATUS_COLORS[status], markersize=8,
                    linestyle="none")
            ax.annotate(status, (ns_to_sec(t), y), xytext=(6, 6), textcoords="offset points",
                        fontsize=7)
            used.add(status)
        if tl.feedback:
            ax.plot([ns_to_sec(t) for t in tl.feedback], [y] * len(tl.feedback), marker="|",
                    color="#333333", markersize=12, linestyle="none")
        if tl.cancels:
            ax.plot([ns_to_sec(t) for t in tl.cancels], [y + 0.38] * len(tl.cancels), marker="x",
                    color="#d62728", linestyle="none")
        if tl.preempts:
            ax.plot([ns_to_sec(t) for t in tl.preempts], [y - 0.4] * len(tl.preempts), marker="^",
                    color="#f2a541", linestyle="none")
        if tl.lost:
            ax.plot([ns_to_sec(t) for t in tl.lost], [y] * len(tl.lost), marker="s", color="black",
                    linestyle="none")
    ax.set_yticks(list(range(len(timelines))))
    ax.set_yticklabels([tl.goal_id for tl in reversed(timelines)], fontsize=7)
    ax.set_ylim(-0.8, max(len(timelines), 1) - 0.2)
    start = min((tl.first_seen for tl in timelines), default=0)
    span = max(end - start, 1)
    width = ns_to_sec(span)
    ax.set_xlim(ns_to_sec(start) - 0.02 * width, ns_to_sec(end) + 0.12 * width)
    ax.set_xlabel("simulated time [s]")
    ax.set_title(title if title is not None else f"goals of {ns}" if ns else "action goals")
    handles: list[Artist] = [Patch(color=STATUS_COLORS[s], label=s)
                          for s in STATUS_COLORS if s in used]
    handles += [
        Line2D([], [], marker="|", color="#333333", linestyle="none", markersize=10,
               label="feedback"),
        Line2D([], [], marker="x", color="#d62728", linestyle="none", label="cancel received"),
        Line2D([], [], marker="^", color="#f2a541", linestyle="none", label="preempt request"),
    ]
    ax.legend(handles=handles, loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=7,
              frameon=False)
    fig.tight_layout()
    return fig
