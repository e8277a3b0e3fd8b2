"""The goal timeline: goal_timelines from the trace, plot_goals' artists (no pixels compared)."""

from __future__ import annotations

import itertools
import math
from collections.abc import Generator
from pathlib import Path
from typing import Any

import pytest
from matplotlib.collections import PolyCollection
from matplotlib.colors import to_hex, to_rgb
from matplotlib.figure import Figure
from matplotlib.lines import Line2D
from matplotlib.text import Text

import ddes
from ddes.actionlib import SimpleActionClient, goal_timelines, plot_goals
from ddes.actionlib.plot import FONT_SIZES, STATUS_COLORS
from ddes.display.figure import DisplayFigure
from ddes.errors import DdesTypeError, DdesValueError
from ddes.kernel.trace import TraceEvent

from .servers import RequestAction, RequestGoal, SimpleTester

NS = "/test_request_action"
S = 1_000_000_000


def scenario(world: ddes.World) -> SimpleActionClient:
    """Goal A runs 1 s and succeeds; B is preempted by C; C is cancelled."""
    SimpleTester(world.create_node("server"))
    client = SimpleActionClient(world.create_node("client"), "test_request_action",
                                RequestAction)

    def main() -> Generator[Any, Any, None]:
        yield client.wait_for_server()
        client.send_goal(RequestGoal(delay_terminate=ddes.Duration(1)))
        yield client.wait_for_result()
        client.send_goal(RequestGoal(delay_terminate=ddes.Duration(10)))
        yield client.node.sleep(1.0)
        client.send_goal(RequestGoal(delay_terminate=ddes.Duration(10)))
        yield client.node.sleep(1.0)
        client.cancel_goal()
        yield client.wait_for_result()

    client.node.process(main())
    world.run(until=5.0)
    return client


def goal(gid: str, t: float, *, feedback: list[float] = (), end: tuple[float, str] | None = None,
         lost: float | None = None, ns: str = "/fib") -> list[TraceEvent]:
    """Trace events of one goal: accepted at t, feedback, then an end (server) or LOST (client)."""
    d = {"ns": ns, "id": gid}
    evs = [TraceEvent(int(t * S), "action.server.goal", "/server", {**d, "arrival": "new"}),
           TraceEvent(int(t * S), "action.server.transition", "/server",
                      {**d, "before": "PENDING", "after": "ACTIVE"})]
    evs += [TraceEvent(int(f * S), "action.server.feedback", "/server", {**d, "status": 1})
            for f in feedback]
    if end is not None:
        evs.append(TraceEvent(int(end[0] * S), "action.server.transition", "/server",
                              {**d, "before": "ACTIVE", "after": end[1]}))
    if lost is not None:
        evs.append(TraceEvent(int(lost * S), "action.client.lost", "/client",
                              {**d, "state": "ACTIVE"}))
    return sorted(evs, key=lambda ev: ev.t)


def by_gid(fig: Figure, gid: str) -> list[Any]:
    """The artists whose gid is ``gid``, or starts with it when it ends in ':'."""
    (ax, *_) = fig.axes
    return [a for a in (*ax.lines, *ax.collections) if (a.get_gid() or "") == gid
            or gid.endswith(":") and (a.get_gid() or "").startswith(gid)]


def legend_labels(fig: Figure) -> list[str]:
    return [t.get_text() for t in fig.axes[0].get_legend().get_texts()]


def test_goal_timelines_follow_the_server(world: ddes.World) -> None:
    scenario(world)
    a, b, c = goal_timelines(world.trace, ns=NS)
    assert [tl.status for tl in (a, b, c)] == ["SUCCEEDED", "PREEMPTED", "PREEMPTED"]
    assert [s[2] for s in a.segments] == ["PENDING", "ACTIVE"]
    assert a.terminal is not None and a.terminal[0] == a.segments[-1][1]
    assert b.preempts and not b.cancels  # preempted by the newer goal, not cancelled
    assert c.cancels and [s[2] for s in c.segments][-1] == "PREEMPTING"
    assert goal_timelines(world.trace, ns="/elsewhere") == []
    assert goal_timelines(world.trace, source="/nobody") == []


def test_plot_goals_draws_bars_markers_and_legend(world: ddes.World) -> None:
    scenario(world)
    timelines = goal_timelines(world.trace, ns=NS)
    fig = plot_goals(world.trace, ns=NS)
    assert isinstance(fig, DisplayFigure)
    (ax,) = fig.axes
    bars = [c for c in ax.collections if isinstance(c, PolyCollection)]
    assert len(bars) == sum(len(tl.segments) for tl in timelines)
    assert [a.get_gid() for a in by_gid(fig, "terminal:")] == [
        "terminal:SUCCEEDED", "terminal:PREEMPTED", "terminal:PREEMPTED"]
    assert by_gid(fig, "cancel") and by_gid(fig, "preempt")
    labels = [t.get_text() for t in ax.get_yticklabels()]
    assert labels == [tl.goal_id for tl in reversed(timelines)]
    assert {"PENDING", "ACTIVE", "PREEMPTING", "SUCCEEDED", "PREEMPTED", "cancel received",
            "preempt request"} <= set(legend_labels(fig))
    assert "LOST (client)" not in legend_labels(fig)  # only what the plot shows
    assert ax.get_title() == "goals of /test_request_action"
    assert ax.get_xlabel() == "simulated time [s]"


def test_the_x_axis_spans_the_trace_not_the_goals(world: ddes.World) -> None:
    scenario(world)
    world.run(until=9.0)  # nothing happens to the goals after ~3 s
    last_goal_event = max(ev.t for ev in world.trace if ev.kind.startswith("action."))
    (ax,) = plot_goals(world.trace, ns=NS).axes
    assert ax.get_xlim() == (world.trace[0].t / S, world.trace[-1].t / S)
    assert ax.get_xlim()[1] > last_goal_event / S
    (ax,) = plot_goals(world, ns=NS).axes  # a world: up to its time
    assert ax.get_xlim() == (0.0, 9.0)
    (ax,) = plot_goals(world, ns=NS, until=12).axes
    assert ax.get_xlim()[1] == 12.0


def test_unfinished_goals_run_to_the_end() -> None:
    events = goal("/g", 1.0) + [TraceEvent(7 * S, "timer.fire", "/n", {})]
    fig = plot_goals(events)
    (bar,) = by_gid(fig, "status:ACTIVE")
    (x, _), (x_end, _) = bar.get_paths()[0].get_extents().get_points()
    assert (x, x_end) == (1.0, 7.0)
    assert fig.axes[0].get_xlim() == (1.0, 7.0)


def test_preempting_and_preempted_have_distinct_colours(world: ddes.World) -> None:
    scenario(world)
    fig = plot_goals(world.trace, ns=NS)
    preempting = {to_hex(c) for b in by_gid(fig, "status:PREEMPTING") for c in b.get_facecolor()}
    preempted = {to_hex(line.get_color()) for line in by_gid(fig, "terminal:PREEMPTED")}
    assert preempting == {STATUS_COLORS["PREEMPTING"]}
    assert preempted == {STATUS_COLORS["PREEMPTED"]}
    assert math.dist(to_rgb(STATUS_COLORS["PREEMPTING"]), to_rgb(STATUS_COLORS["PREEMPTED"])) > 0.4
    for (a, ca), (b, cb) in itertools.combinations(STATUS_COLORS.items(), 2):
        assert math.dist(to_rgb(ca), to_rgb(cb)) > 0.15, (a, b)


def test_lost_goals_are_marked_and_in_the_legend(world: ddes.World) -> None:
    SimpleTester(world.create_node("server"))
    client = SimpleActionClient(world.create_node("client"), "test_request_action",
                                RequestAction)
    world.run(until=0.5)
    client.send_goal(RequestGoal(terminate_status=RequestGoal.TERMINATE_LOSE))
    world.run(until=1.0)
    (tl,) = goal_timelines(world.trace)
    assert len(tl.lost) == 1
    fig = plot_goals(world)
    (lost,) = by_gid(fig, "lost")
    assert lost.get_marker() == "s" and len(lost.get_xdata()) == 1
    assert "LOST (client)" in legend_labels(fig)
    handle = fig.axes[0].get_legend().legend_handles[legend_labels(fig).index("LOST (client)")]
    assert handle.get_marker() == "s"


def test_fonts_are_readable(world: ddes.World) -> None:
    scenario(world)
    fig = plot_goals(world.trace, ns=NS)
    texts = [t for t in fig.findobj(Text) if t.get_text().strip()]
    assert len(texts) > 10
    assert min(t.get_fontsize() for t in texts) >= 9
    assert min(FONT_SIZES.values()) >= 9
    width, height = fig.get_size_inches()
    assert width >= 9 and height >= 0.6 * 3


def test_sparse_feedback_is_a_rug_of_small_ticks() -> None:
    fig = plot_goals(goal("/g", 0.0, feedback=[1, 2, 3, 4], end=(4.5, "SUCCEEDED")))
    (rug,) = by_gid(fig, "feedback")
    assert list(rug.get_xdata()) == [1.0, 2.0, 3.0, 4.0]
    assert rug.get_marker() == "|" and rug.get_markersize() <= 8 and rug.get_alpha() < 1
    assert set(rug.get_ydata()) == {rug.get_ydata()[0]} and rug.get_ydata()[0] < 0  # below y=0
    assert "feedback" in legend_labels(fig)
    assert [t.get_text() for t in fig.axes[0].get_yticklabels()] == ["/g"]


def test_dense_feedback_is_one_band_with_count_and_rate() -> None:
    fb = [0.1 * i for i in range(1, 161)]  # 10 Hz for 16 s
    fig = plot_goals(goal("/g", 0.0, feedback=fb, end=(16.5, "SUCCEEDED")))
    assert by_gid(fig, "feedback") == []
    (band,) = by_gid(fig, "feedback-band")
    assert isinstance(band, Line2D) and len(band.get_xdata()) == 2
    assert band.get_xdata()[0] == pytest.approx(0.1) and band.get_xdata()[1] == pytest.approx(16.0)
    assert band.get_alpha() < 1 and band.get_marker() in ("None", "none", None, "")
    (label,) = [t.get_text() for t in fig.axes[0].get_yticklabels()]
    assert label == "/g\n160 feedback, 10/s"


def test_a_namespace_with_no_goals_names_the_ones_that_have_some(world: ddes.World) -> None:
    scenario(world)
    with pytest.raises(DdesValueError) as err:
        plot_goals(world.trace, ns="/test_request_actoin")
    text = str(err.value)
    assert "'/test_request_actoin'" in text and "did you mean '/test_request_action'?" in text
    events = world.trace.events + goal("/h", 5.0, ns="/other")
    with pytest.raises(DdesValueError, match="goals were sent on: '/other', '/test_request_action'"):
        plot_goals(events, ns="/nowhere")


def test_no_goals_at_all_gives_a_figure_that_says_why(world: ddes.World) -> None:
    fig = plot_goals(world.trace)
    assert isinstance(fig, DisplayFigure)
    (msg,) = [t for t in fig.axes[0].texts if t.get_gid() == "no-goals"]
    assert msg.get_text().startswith("no action goals in this trace")
    assert "the trace is empty" in msg.get_text()
    assert msg.get_position() == (0.5, 0.5) and msg.get_ha() == "center"
    assert fig.axes[0].get_yticklabels() == []

    SimpleTester(world.create_node("server"))
    world.run(until=2.0)
    fig = plot_goals(world, ns=NS)
    (msg,) = [t for t in fig.axes[0].texts if t.get_gid() == "no-goals"]
    assert msg.get_text().splitlines() == [
        "no action goals on /test_request_action in this trace",
        "(the action server on /test_request_action started at 0 s and received no goal)"]
    assert fig.axes[0].get_xlim() == (0.0, 2.0)
    assert fig._repr_png_()[0][:4] == b"\x89PNG"


def test_plot_goals_into_given_axes_and_to_png(world: ddes.World, tmp_path: Path) -> None:
    scenario(world)
    fig = Figure()
    ax = fig.add_subplot(2, 1, 2)
    out = plot_goals(world.trace, ax=ax, until=ddes.Time(6), title="mine")
    assert out is fig and ax.get_title() == "mine"
    assert ax.get_xlim()[1] == 6.0
    fig.savefig(tmp_path / "goals.png")
    assert (tmp_path / "goals.png").read_bytes()[:4] == b"\x89PNG"


def test_the_figure_renders_png_bytes(world: ddes.World) -> None:
    scenario(world)
    fig = plot_goals(world, ns=NS)
    data, meta = fig._repr_png_()
    assert data[:8] == b"\x89PNG\r\n\x1a\n"
    assert 900 <= meta["width"] <= 1100 and meta["height"] > 150


def test_bad_until() -> None:
    with pytest.raises(DdesTypeError):
        plot_goals([], until="later")
