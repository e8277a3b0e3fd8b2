"""A timeline of action goals from a world's trace (matplotlib).

:func:`goal_timelines` reads the ``action.*`` events of a trace into one
:class:`GoalTimeline` per goal: the server-side status intervals (PENDING,
ACTIVE, PREEMPTING, RECALLING), the terminal instant and status, feedback
ticks, cancel requests received, preempt requests and client-side LOST marks.
:func:`plot_goals` draws them, one row per goal, over simulated time::

    from ddes.actionlib import plot_goals
    fig = plot_goals(world, ns="/fibonacci")   # or world.trace
    fig.savefig("goals.png")          # or just `fig` as the last line of a notebook cell

The figure is a :class:`ddes.display.figure.DisplayFigure`, built without
pyplot (no global figure state, no GUI backend): a notebook shows it with no
``%matplotlib inline``.  matplotlib is imported only when a plot is drawn.
"""

from __future__ import annotations

import difflib
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field
from types import MappingProxyType
from typing import TYPE_CHECKING

from ddes.actionlib.states import TERMINAL_STATUSES, GoalStatus
from ddes.errors import DdesValueError
from ddes.time.units import TimeLike, ns_to_sec, time_to_ns

if TYPE_CHECKING:
    from matplotlib.artist import Artist
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

    from ddes.kernel.kernel import Kernel
    from ddes.kernel.trace import Trace, TraceEvent

__all__ = ["FONT_SIZES", "MARK_COLORS", "STATUS_COLORS", "GoalTimeline", "goal_timelines",
           "plot_goals"]

#: Colour of each status in the plot (bars for the live ones, markers for the terminal ones).
STATUS_COLORS: Mapping[str, str] = MappingProxyType({
    "PENDING": "#bdbdbd",
    "ACTIVE": "#4c9be8",
    "PREEMPTING": "#f6d55c",
    "RECALLING": "#c9a0dc",
    "SUCCEEDED": "#2e9d4f",
    "ABORTED": "#d62728",
    "PREEMPTED": "#e8710a",
    "REJECTED": "#8c564b",
    "RECALLED": "#7b4fa6",
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


#: Font sizes of the plot, in points (labels at least 9 pt).
FONT_SIZES: Mapping[str, float] = MappingProxyType({
    "title": 12.0, "axis": 10.0, "ticks": 9.0, "labels": 9.0, "legend": 9.0, "message": 11.0})
#: Colours of the marks drawn over the bars.
MARK_COLORS: Mapping[str, str] = MappingProxyType({
    "feedback": "#222222", "cancel": "#b2182b", "preempt": "#8a6d00", "LOST": "#000000"})
#: Feedback of one goal is drawn as a band (not one tick each) when it is denser than
#: one message per this fraction of the x-axis.
DENSE_FEEDBACK = 0.01

#: Rows of a goal: the bar spans y ± _BAR; marks sit above/below it.
_BAR = 0.26


def _resolve(trace: Trace | Kernel | Iterable[TraceEvent], until: TimeLike | None,
             ) -> tuple[list[TraceEvent], int, int, bool]:
    """(events, start ns, end ns, trace complete) of what plot_goals was given."""
    now: int | None = None
    complete = True
    inner = getattr(trace, "trace", None)
    if inner is not None and isinstance(getattr(trace, "now", None), int):  # a World/Kernel
        now = trace.now  # type: ignore[union-attr]
        trace = inner
    complete = bool(getattr(trace, "complete", True))
    events = list(trace)  # type: ignore[arg-type]
    start = events[0].t if events else 0
    if until is not None:
        end = time_to_ns(until, "until")
    elif now is not None:
        end = now
    else:
        end = events[-1].t if events else 0
    return events, min(start, end), end, complete


def _namespaces_with_goals(events: Iterable[TraceEvent]) -> list[str]:
    return sorted({tl.ns for tl in goal_timelines(events)})


def _no_goals_message(events: list[TraceEvent], ns: str | None, source: str | None,
                      complete: bool) -> str:
    where = f" on {ns}" if ns else ""
    by = f" from server node {source}" if source else ""
    started = [ev for ev in events if ev.kind == "action.server.start"
               and (ns is None or ev.details.get("ns") == ns)
               and (source is None or ev.source == source)]
    lines = [f"no action goals{where}{by} in this trace"]
    if started:
        ev = started[0]
        lines.append(f"(the action server on {ev.details.get('ns')} started at "
                     f"{ns_to_sec(ev.t):g} s and received no goal)")
    elif not events:
        lines.append("(the trace is empty: send goals, then world.run(...), then plot)")
    else:
        lines.append("(no action server or client ran: send goals, then world.run(...))")
    if not complete:
        lines.append("note: this trace does not hold every event (trace.enabled or a filter)")
    return "\n".join(lines)


def plot_goals(trace: Trace | Kernel | Iterable[TraceEvent], ns: str | None = None, *,
               source: str | None = None, ax: Axes | None = None, until: TimeLike | None = None,
               title: str | None = None) -> Figure:
    """Draw the goals of ``trace`` over simulated time; returns the Figure.

    ``trace`` is a world (its trace, up to ``world.now``), a trace, or any
    sequence of trace events.  One row per goal: bars for the server-side
    status (PENDING grey, ACTIVE blue, PREEMPTING yellow, RECALLING lilac);
    a diamond and a label for the terminal status (SUCCEEDED green, ABORTED
    red, PREEMPTED orange, ...); a rug of small ticks on the bar's lower
    edge for feedback (a band with the count and rate in the row's label
    when there are too many to tell apart); ``x`` above the bar for cancel
    requests received; ``^`` below it for preempt requests; black squares
    where the client marked the goal LOST.

    The x-axis runs from the first to the last event of the trace (to
    ``world.now`` for a world; to ``until``, seconds or a Time, if given),
    and the bars of unfinished goals run to that end.  ``ns`` keeps one
    action namespace: a namespace with no goals while others have some
    raises :class:`~ddes.errors.DdesValueError` naming them (a typo, most
    often); a trace with no goals at all gives a figure that says so in its
    middle.  Pass ``ax`` to draw into existing axes (that figure is returned).
    A new figure is a :class:`ddes.display.figure.DisplayFigure`: the last
    line of a notebook cell shows it.
    """
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch

    from ddes.display.figure import new_figure

    events, start, end, complete = _resolve(trace, until)
    timelines = goal_timelines(events, ns, source)
    if not timelines and ns is not None:
        others = _namespaces_with_goals(events)
        if others:
            near = difflib.get_close_matches(ns, others, n=1)
            hint = f"; did you mean {near[0]!r}?" if near else ""
            raise DdesValueError(
                f"plot_goals: no goals on action namespace {ns!r} in this trace{hint} "
                f"(goals were sent on: {', '.join(map(repr, others))}); "
                f"pass ns= one of them, or ns=None for all")
    if end <= start:
        end = start + 1_000_000_000
    x0, x1 = ns_to_sec(start), ns_to_sec(end)
    fs = FONT_SIZES
    if ax is None:
        fig: Figure = new_figure(figsize=(10.0, 1.7 + 0.6 * max(1, len(timelines))))
        ax = fig.add_subplot(1, 1, 1)
    else:
        fig = ax.figure  # type: ignore[assignment]
    ax.set_xlim(x0, x1)
    ax.set_xlabel("simulated time [s]", fontsize=fs["axis"])
    ax.tick_params(labelsize=fs["ticks"])
    ax.set_title(title if title is not None else f"goals of {ns}" if ns else "action goals",
                 fontsize=fs["title"])
    if not timelines:
        ax.set_yticks([])
        ax.set_ylim(0.0, 1.0)
        ax.text(0.5, 0.5, _no_goals_message(events, ns, source, complete),
                transform=ax.transAxes, ha="center", va="center", fontsize=fs["message"],
                color="#555555", gid="no-goals")
        if hasattr(fig, "tight_layout"):
            fig.tight_layout()
        return fig

    used: set[str] = set()
    marks: set[str] = set()
    labels: list[str] = []
    dense_x = DENSE_FEEDBACK * (x1 - x0)
    for row, tl in enumerate(timelines):
        y = len(timelines) - 1 - row
        label = tl.goal_id
        for seg_start, stop, status in tl.segments:
            stop_t = end if stop is None else min(stop, end)
            bar = (ns_to_sec(seg_start), ns_to_sec(max(stop_t - seg_start, 0)))
            ax.broken_barh([bar], (y - _BAR, 2 * _BAR), facecolors=STATUS_COLORS[status],
                           edgecolors="none", gid=f"status:{status}")
            used.add(status)
        if tl.terminal is not None:
            t, status = tl.terminal
            tx = ns_to_sec(t)
            ax.plot([tx], [y], marker="D", color=STATUS_COLORS[status], markersize=8,
                    markeredgecolor="white", linestyle="none", clip_on=False,
                    gid=f"terminal:{status}", zorder=3)
            near_end = tx > x0 + 0.8 * (x1 - x0)
            ax.annotate(status, (tx, y), xytext=(-7 if near_end else 7, 7),
                        textcoords="offset points", ha="right" if near_end else "left",
                        fontsize=fs["labels"])
            used.add(status)
        if tl.feedback:
            fx = [ns_to_sec(t) for t in tl.feedback]
            span = fx[-1] - fx[0]
            if len(fx) > 1 and span / (len(fx) - 1) < dense_x:
                ax.plot([fx[0], fx[-1]], [y - _BAR + 0.06] * 2, color=MARK_COLORS["feedback"],
                        linewidth=3, alpha=0.45, solid_capstyle="butt", gid="feedback-band")
                rate = (len(fx) - 1) / span if span > 0 else 0.0
                label += f"\n{len(fx)} feedback" + (f", {rate:.3g}/s" if rate else "")
            else:
                ax.plot(fx, [y - _BAR + 0.07] * len(fx), marker="|", markersize=8,
                        markeredgewidth=1.3, alpha=0.7, color=MARK_COLORS["feedback"],
                        linestyle="none", gid="feedback")
            marks.add("feedback")
        if tl.cancels:
            ax.plot([ns_to_sec(t) for t in tl.cancels], [y + _BAR + 0.12] * len(tl.cancels),
                    marker="x", markersize=7, color=MARK_COLORS["cancel"], linestyle="none",
                    clip_on=False, gid="cancel")
            marks.add("cancel")
        if tl.preempts:
            ax.plot([ns_to_sec(t) for t in tl.preempts], [y - _BAR - 0.12] * len(tl.preempts),
                    marker="^", markersize=7, color=MARK_COLORS["preempt"], linestyle="none",
                    clip_on=False, gid="preempt")
            marks.add("preempt")
        if tl.lost:
            ax.plot([ns_to_sec(t) for t in tl.lost], [y] * len(tl.lost), marker="s",
                    markersize=8, color=MARK_COLORS["LOST"], linestyle="none", clip_on=False,
                    gid="lost", zorder=3)
            marks.add("LOST")
        labels.append(label)
    ax.set_yticks(list(range(len(timelines))))
    ax.set_yticklabels(list(reversed(labels)), fontsize=fs["ticks"])
    ax.set_ylim(-0.6, len(timelines) - 0.4)
    ax.grid(axis="x", color="#e0e0e0", linewidth=0.8)
    ax.set_axisbelow(True)
    handles: list[Artist] = [Patch(color=STATUS_COLORS[s], label=s)
                             for s in STATUS_COLORS if s in used]
    if "feedback" in marks:
        handles.append(Line2D([], [], marker="|", color=MARK_COLORS["feedback"], alpha=0.7,
                              linestyle="none", markersize=8, markeredgewidth=1.3,
                              label="feedback"))
    if "cancel" in marks:
        handles.append(Line2D([], [], marker="x", color=MARK_COLORS["cancel"],
                              linestyle="none", label="cancel received"))
    if "preempt" in marks:
        handles.append(Line2D([], [], marker="^", color=MARK_COLORS["preempt"],
                              linestyle="none", label="preempt request"))
    if "LOST" in marks:
        handles.append(Line2D([], [], marker="s", color=MARK_COLORS["LOST"], linestyle="none",
                              label="LOST (client)"))
    ax.legend(handles=handles, loc="upper left", bbox_to_anchor=(1.01, 1.0),
              fontsize=fs["legend"], frameon=False)
    if hasattr(fig, "tight_layout"):
        fig.tight_layout()
    return fig
