"""``ddes grade replay --picture``: the picture shows what the exercise's criteria judged, with
every axis labelled: an action exercise's goal paths on the top view and its goal timeline
(the cancel, the newer goal preempting the older), rebuilt from the wire as the server's own
trace would give it; each course exercise's own panels; the topic rates of any exercise."""

from __future__ import annotations

import re
from pathlib import Path
from typing import Any

import pytest

import ddes
from ddes.actionlib import SimpleActionClient, SimpleActionServer, goal_timelines
from ddes.cli.main import main
from ddes.grading.exercise import REGISTRY, Facts
from ddes.grading.replay import replay
from ddes.grading.replay_picture import wire_goal_events
from ddes.msg import get_message_class

from .conftest import EXERCISE_FILE, SOLUTION

ROOT = Path(__file__).resolve().parents[2]
UNIT = re.compile(r"\[[^\]]+\]|^number of ")


def label_problems(fig: Any) -> list[str]:
    """Axes of ``fig`` without an x or a y label, or whose numeric axis names no unit (the
    rule of tests/notebooks: an x label of a shared or twin axes counts for all; category axes
    need a label, not a unit)."""
    from matplotlib.ticker import FixedFormatter, FuncFormatter

    bad = []
    for i, ax in enumerate(fig.axes):
        if not (ax.get_visible() and ax.axison):
            continue
        xlabel = next((o.get_xlabel() for o in ax.get_shared_x_axes().get_siblings(ax)
                       if o.get_xlabel()), "")
        for name, label, axis in (("x", xlabel, ax.xaxis), ("y", ax.get_ylabel(), ax.yaxis)):
            if not label:
                bad.append(f"axes {i} ({ax.get_title()!r}): no {name} label")
            elif not isinstance(axis.get_major_formatter(), (FixedFormatter, FuncFormatter)) \
                    and not UNIT.search(label):  # tick labels set: a category axis
                bad.append(f"axes {i} ({ax.get_title()!r}): {name} label {label!r} has no unit")
    return bad


def gids(ax: Any) -> set[str]:
    return {a.get_gid() for a in ax.get_children() if a.get_gid()}


def rows(ax: Any) -> dict[str, float]:
    """The goal timeline's row labels (first line) -> their y."""
    return {t.get_text().split("\n")[0]: y for t, y in zip(ax.get_yticklabels(), ax.get_yticks(),
                                                            strict=True)}


def marks(ax: Any, gid: str) -> list[tuple[float, float]]:
    return [(float(x), float(y)) for line in ax.get_lines() if line.get_gid() == gid
            for x, y in zip(line.get_xdata(), line.get_ydata(), strict=True)]


# -- the goal timeline rebuilt from the wire ----------------------------------------------------------

def test_goal_events_rebuilt_from_the_wire_give_the_servers_own_timeline() -> None:
    """A SimpleActionServer and its client in one world: goal A, preempted by goal B, which is
    cancelled.  What the wire says gives the timeline the server's own trace gives (times
    within the transport's latency: the wire's are publish times, the server's receipts)."""
    Fibonacci = get_message_class("actionlib_tutorials/FibonacciAction")
    Goal = get_message_class("actionlib_tutorials/FibonacciGoal")
    Feedback = get_message_class("actionlib_tutorials/FibonacciFeedback")
    world = ddes.World(seed=0)
    node = world.create_node("fibonacci")

    def execute(goal: Any) -> Any:
        for i in range(goal.order):
            if server.is_preempt_requested():
                server.set_preempted()
                return
            server.publish_feedback(Feedback(sequence=[i]))
            yield node.sleep(0.1)
        server.set_succeeded()

    server = SimpleActionServer(node, "fib", Fibonacci, execute, auto_start=False)
    server.start()
    client = SimpleActionClient(world.create_node("user"), "fib", Fibonacci)
    world.run(until=0.5)
    client.send_goal(Goal(order=100))
    world.run(until=2.0)
    client.send_goal(Goal(order=100))
    world.run(until=3.0)
    client.cancel_goal()
    world.run(until=4.0)
    facts = Facts(exercise=None, scenario=None, world=world, outcome=None,  # type: ignore[arg-type]
                  refused=[], submission=Path("."), student_nodes=[])
    own = goal_timelines(world.trace, ns="/fib")
    rebuilt = goal_timelines(wire_goal_events(facts, "/fib"))
    assert [tl.goal_id for tl in rebuilt] == [tl.goal_id for tl in own] and len(own) == 2
    assert [tl.status for tl in rebuilt] == [tl.status for tl in own] == ["PREEMPTED",
                                                                           "PREEMPTED"]
    for a, b in zip(own, rebuilt, strict=True):  # (SimpleActionServer's preempt requests
        # stay in its own trace: the wire shows a request only as PREEMPTING)
        assert [s for _, _, s in b.segments] == [s for _, _, s in a.segments]
        assert len(b.feedback) == len(a.feedback) > 5 and len(b.cancels) == len(a.cancels)
        assert a.terminal is not None and b.terminal is not None
        assert abs(a.terminal[0] - b.terminal[0]) <= 10_000_000
        assert abs(a.segments[0][0] - b.segments[0][0]) <= 10_000_000
    assert len(rebuilt[1].cancels) == 1  # the client's cancel, on goal B only
    named = wire_goal_events(facts, "/fib", {own[0].goal_id: "A"})
    assert [tl.goal_id for tl in goal_timelines(named)] == ["A", own[1].goal_id]


# -- pictures of replays ---------------------------------------------------------------------------------

def test_an_action_exercise_replay_shows_the_paths_the_cancel_and_the_newer_goal(
        tmp_path: Path) -> None:
    ex = REGISTRY.get("ex4b_actions")
    picture = tmp_path / "fail.png"
    got = replay(ex, ROOT / "solutions" / "ex4b_actions", "public", picture=picture)
    assert ("picture", str(picture)) in got.written
    assert picture.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    fig = got.figure
    assert label_problems(fig) == []
    top, goals, rates = fig.axes[0], fig.axes[1], fig.axes[2]
    # the top view: the robot's path and each goal's path, the grader's pillar
    assert {"trajectory", "goal:follow", "goal:cancel", "goal:old", "goal:new",
            "goal:blocked", "obstacle:grader_pillar"} <= gids(top)
    # the timeline: one row per goal sent, the cancel and the newer goal
    row = rows(goals)
    assert {"1 follow", "2 empty", "3 cancel", "4 old", "5 new", "6 blocked",
            "your client's goal 1"} <= set(row)
    assert row["3 cancel"] in {y for _, y in marks(goals, "terminal:PREEMPTED")}
    assert row["4 old"] in {y for _, y in marks(goals, "terminal:PREEMPTED")}
    assert row["5 new"] in {y for _, y in marks(goals, "terminal:SUCCEEDED")}
    cancels = marks(goals, "cancel")
    assert any(abs(y - row["3 cancel"]) < 0.5 for _, y in cancels)
    preempts = marks(goals, "preempt")
    old_preempted = [x for x, y in preempts if abs(y - row["4 old"]) < 0.5]
    assert old_preempted, "the newer goal's preemption of the older is on the old goal's row"
    (x_new,) = [x for x, y in marks(goals, "terminal:SUCCEEDED") if y == row["5 new"]]
    assert old_preempted[0] < x_new
    legend = [t.get_text() for t in goals.get_legend().get_texts()]
    assert {"cancel received", "preempt request", "PREEMPTED", "SUCCEEDED"} <= set(legend)
    # the rates the criteria count: the feedback at 5 Hz
    assert {"rate:/follow_path/feedback", "wanted:/follow_path/feedback",
            "rate:/cmd_vel"} <= gids(rates)


#: What each course exercise's picture holds beyond the rates (gids on the time panel, and on
#: the map), and the scenario replayed.
COURSE = {
    "ex1_console": ("public", {"speed", "commands", "event:stop key"}, {"trajectory"}),
    "ex2_package": ("public", {"truth", "logged"}, {"trajectory", "scan"}),
    "ex3_pillar": ("public", {"commands", "law", "event:collision"}, {"trajectory",
                                                                      "obstacle:pillar"}),
    "ex4a_services": ("public", {"speed", "event:stop call (grader)",
                                 "event:start call (script)"}, {"trajectory"}),
    "ex4c_time": ("simulator", {"clock", "heartbeats", "zeros", "event:simulator paused"},
                  None),
    "ex4d_bags": ("public", {"rate:/odometry/filtered"},
                  {"track:/odometry/filtered", "track:/smb_velocity_controller/odom"}),
    "ex5_safety": ("public", {"speed", "event:proximity e-stop", "event:crash e-stop",
                              "event:collision"}, {"trajectory", "collisions"}),
}


@pytest.mark.parametrize("exercise", sorted(COURSE))
def test_each_course_exercise_replay_draws_what_its_criteria_judged(
        exercise: str, tmp_path: Path) -> None:
    scenario, panel, on_map = COURSE[exercise]
    got = replay(REGISTRY.get(exercise), ROOT / "solutions" / exercise, scenario,
                 picture=tmp_path / "p.png")
    fig = got.figure
    assert label_problems(fig) == []
    shown = [ax for ax in fig.axes if ax.get_visible() and ax.axison]
    time_panels = [ax for ax in shown if ax.get_xlabel() == "simulated time [s]"
                   or any(o.get_xlabel() == "simulated time [s]"
                          for o in ax.get_shared_x_axes().get_siblings(ax))]
    assert panel <= set().union(*(gids(ax) for ax in time_panels))
    assert any(g.startswith("rate:") for ax in time_panels for g in gids(ax))
    maps = [ax for ax in shown if ax not in time_panels]
    if on_map is None:
        assert maps == []  # exercise 4c's criteria do not look at the robot
    else:
        assert on_map <= gids(maps[0])


def test_an_exercise_without_a_simulator_gets_the_rates_of_the_students_topics(
        tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """An instructor's exercise (ex0_talker, no simulator): the messages per second of what the
    student's node published, the 10 Hz the talker keeps after its start."""
    picture = tmp_path / "p.png"
    assert main(["grade", "--exercises", str(EXERCISE_FILE), "replay", "ex0_talker",
                 str(SOLUTION), "--scenario", "public", "--picture", str(picture)]) == 0
    assert f"wrote picture: {picture}" in capsys.readouterr().out
    assert picture.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    from ddes.grading import ExerciseRegistry

    (ex,) = ExerciseRegistry().load_file(EXERCISE_FILE)
    fig = replay(ex, SOLUTION, "public", picture=tmp_path / "q.png").figure
    assert label_problems(fig) == []
    (ax,) = fig.axes
    assert gids(ax) >= {"rate:/chatter"}
    (line,) = [ln for ln in ax.get_lines() if ln.get_gid() == "rate:/chatter"]
    assert max(line.get_ydata()) == 10.0
