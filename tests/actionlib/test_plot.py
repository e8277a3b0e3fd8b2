"""The goal timeline: goal_timelines from the trace, plot_goals' artists (Agg backend)."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")

from collections.abc import Generator  # noqa: E402
from pathlib import Path  # noqa: E402
from typing import Any  # noqa: E402

import pytest  # noqa: E402
from matplotlib.collections import PolyCollection  # noqa: E402
from matplotlib.figure import Figure  # noqa: E402

import ddes  # noqa: E402
from ddes.actionlib import SimpleActionClient, goal_timelines, plot_goals  # noqa: E402
from ddes.errors import DdesTypeError  # noqa: E402

from .servers import RequestAction, RequestGoal, SimpleTester  # noqa: E402


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


def test_goal_timelines_follow_the_server(world: ddes.World) -> None:
    scenario(world)
    a, b, c = goal_timelines(world.trace, ns="/test_request_action")
    assert [tl.status for tl in (a, b, c)] == ["SUCCEEDED", "PREEMPTED", "PREEMPTED"]
    assert [s[2] for s in a.segments] == ["PENDING", "ACTIVE"]
    assert a.terminal is not None and a.terminal[0] == a.segments[-1][1]
    assert b.preempts and not b.cancels  # preempted by the newer goal, not cancelled
    assert c.cancels and [s[2] for s in c.segments][-1] == "PREEMPTING"
    assert goal_timelines(world.trace, ns="/elsewhere") == []
    assert goal_timelines(world.trace, source="/nobody") == []


def test_plot_goals_draws_bars_markers_and_legend(world: ddes.World) -> None:
    scenario(world)
    timelines = goal_timelines(world.trace, ns="/test_request_action")
    fig = plot_goals(world.trace, ns="/test_request_action")
    assert isinstance(fig, Figure)
    (ax,) = fig.axes
    bars = [c for c in ax.collections if isinstance(c, PolyCollection)]
    assert len(bars) == sum(len(tl.segments) for tl in timelines)
    markers = [line.get_marker() for line in ax.lines]
    assert markers.count("D") == 3  # one terminal marker per goal
    assert "x" in markers and "^" in markers
    labels = [t.get_text() for t in ax.get_yticklabels()]
    assert labels == [tl.goal_id for tl in reversed(timelines)]
    legend = [t.get_text() for t in ax.get_legend().get_texts()]
    assert {"ACTIVE", "SUCCEEDED", "PREEMPTED", "feedback", "cancel received"} <= set(legend)
    assert ax.get_title() == "goals of /test_request_action"
    assert ax.get_xlabel() == "simulated time [s]"


def test_plot_goals_into_given_axes_and_to_png(world: ddes.World, tmp_path: Path) -> None:
    scenario(world)
    fig = Figure()
    ax = fig.add_subplot(2, 1, 2)
    out = plot_goals(world.trace, ax=ax, until=ddes.Time(6), title="mine")
    assert out is fig and ax.get_title() == "mine"
    assert ax.get_xlim()[1] > 6.0
    fig.savefig(tmp_path / "goals.png")
    assert (tmp_path / "goals.png").read_bytes()[:4] == b"\x89PNG"


def test_plot_of_an_empty_trace_and_bad_until(world: ddes.World) -> None:
    fig = plot_goals(world.trace)
    assert fig.axes[0].get_yticklabels() == []
    with pytest.raises(DdesTypeError):
        plot_goals(world.trace, until="later")


def test_lost_goals_are_marked(world: ddes.World) -> None:
    SimpleTester(world.create_node("server"))
    client = SimpleActionClient(world.create_node("client"), "test_request_action",
                                RequestAction)
    world.run(until=0.5)
    client.send_goal(RequestGoal(terminate_status=RequestGoal.TERMINATE_LOSE))
    world.run(until=1.0)
    (tl,) = goal_timelines(world.trace)
    assert len(tl.lost) == 1
    fig = plot_goals(world.trace)
    assert "s" in [line.get_marker() for line in fig.axes[0].lines]
