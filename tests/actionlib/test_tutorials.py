"""The actionlib tutorials' nodes, the lecture's FollowPath package and the examples."""

from __future__ import annotations

import importlib.util
from pathlib import Path
from types import ModuleType

import pytest
from hypothesis import strategies as st

import ddes
from ddes.actionlib import GoalStatus
from ddes.console.tooling import run_command
from ddes.msg import get_message_class
from ddes.nodes import start_node
from ddes.testing.actions import run_protocol_machine

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


def logs(world: ddes.World, node: str) -> list[tuple[float, str]]:
    return [(round(e.t / 1e9, 3), e.details["msg"]) for e in world.trace.filter(kind="log")
            if e.source == node]


def load_example(name: str) -> ModuleType:
    spec = importlib.util.spec_from_file_location(name, EXAMPLES / f"{name}.py")
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_fibonacci_server_and_client(world: ddes.World) -> None:
    start_node(world, "actionlib_tutorials", "fibonacci_server")
    start_node(world, "actionlib_tutorials", "fibonacci_client")
    world.run(until=25.0)
    assert logs(world, "/fibonacci") == [
        (0.001, "/fibonacci: Executing, creating fibonacci sequence of order 20 with seeds 0, 1"),
        (19.001, "/fibonacci: Succeeded"),
    ]
    assert logs(world, "/fibonacci_client_py") == [
        (19.001, "Result: 0, 1, 1, 2, 3, 5, 8, 13, 21, 34, 55, 89, 144, 233, 377, 610, 987, "
                 "1597, 2584, 4181, 6765")]
    assert [e.details["code"] for e in world.trace.filter(kind="node.exit")] == [0]
    feedback = world.trace.filter(kind="action.server.feedback")
    assert len(feedback) == 19  # one per second, as rospy.Rate(1)


def test_averaging_server_and_client(world: ddes.World) -> None:
    start_node(world, "actionlib_tutorials", "gen_numbers")
    start_node(world, "actionlib_tutorials", "averaging_server")
    start_node(world, "actionlib_tutorials", "averaging_client")
    world.run(until=10.0)
    client = logs(world, "/test_averaging")
    assert client[:2] == [(0.0, "Waiting for action server to start."),
                          (0.001, "Action server started, sending goal.")]
    (t_end, final), = client[2:]
    server = logs(world, "/averaging")
    assert len(server) == 1 and server[0][0] == t_end
    state = final.removeprefix("Action finished: ")
    assert state in ("SUCCEEDED", "ABORTED")
    assert server[0][1] == f"/averaging: {'Succeeded' if state == 'SUCCEEDED' else 'Aborted'}"
    # 101 samples at 20 Hz: the 101st arrives 5 s after the first
    assert 5.0 < t_end < 5.1
    assert len(world.trace.filter(kind="action.server.feedback")) == 101


def test_averaging_client_times_out_without_numbers(world: ddes.World) -> None:
    start_node(world, "actionlib_tutorials", "averaging_server")
    start_node(world, "actionlib_tutorials", "averaging_client")
    world.run(until=40.0)
    assert logs(world, "/test_averaging")[-1] == (30.001, "Action did not finish before the time out.")


def test_averaging_runs_are_deterministic() -> None:
    digests = []
    for _ in range(2):
        world = ddes.World(seed=7)
        for node in ("gen_numbers", "averaging_server", "averaging_client"):
            start_node(world, "actionlib_tutorials", node)
        world.run(until=6.0)
        digests.append(world.digest())
    assert digests[0] == digests[1]


def test_follow_path_action_definition() -> None:
    goal = get_message_class("lecture4_actions/FollowPathGoal")
    feedback = get_message_class("lecture4_actions/FollowPathFeedback")
    result = get_message_class("lecture4_actions/FollowPathResult")
    assert goal._slot_types == ["nav_msgs/Path"]
    assert (list(feedback.__slots__), feedback._slot_types) == (
        ["remaining_distance", "initial_distance"], ["float32", "float32"])
    assert (list(result.__slots__), result._slot_types) == (["success"], ["bool"])


def test_follow_path_succeeds_and_can_be_cancelled(world: ddes.World) -> None:
    start_node(world, "lecture4_actions", "follow_path_server", argv=["_speed:=1.0"])
    start_node(world, "lecture4_actions", "follow_path_client")
    world.run(until=12.0)
    assert logs(world, "/follow_path_client")[-1] == (8.001, "Finished: SUCCEEDED, success=True")
    start_node(world, "lecture4_actions", "follow_path_client", name="quitter",
               argv=["_cancel_after:=2.0"])
    world.run(until=20.0)
    quitter = [entry for entry in logs(world, "/quitter") if "remaining" not in entry[1]]
    assert quitter[-2:] == [(14.001, "No result after 2.0 s: cancelling"),
                            (14.101, "Finished: PREEMPTED, success=False")]
    assert logs(world, "/follow_path_server")[-1] == (
        14.101, "follow_path: preempted with 5.90 m to go")


def test_follow_path_rejects_an_empty_path(world: ddes.World) -> None:
    from ddes.actionlib import SimpleActionClient

    start_node(world, "lecture4_actions", "follow_path_server")
    client = SimpleActionClient(world.create_node("c"), "follow_path",
                                "lecture4_actions/FollowPathAction")
    world.run(until=0.5)
    client.send_goal(get_message_class("lecture4_actions/FollowPathGoal")())
    world.run(until=1.0)
    assert client.get_state() == GoalStatus.ABORTED
    assert client.get_goal_status_text() == "empty path"


def test_rosrun_starts_the_tutorial_nodes(world: ddes.World) -> None:
    run_command(world, "rosrun actionlib_tutorials fibonacci_server &")
    world.run(until=0.5)
    assert "/fibonacci/goal" in run_command(world, "rostopic list").split()


def test_tutorial_server_passes_the_protocol_machine() -> None:
    example = load_example("actions_protocol_check")
    run_protocol_machine(example.tutorial_server, action=example.Fibonacci, ns="/action_server",
                         goals=st.integers(0, 3).map(lambda n: {"order": n}), max_examples=10,
                         derandomize=True, database=None)


@pytest.mark.parametrize("name", ["actions_fibonacci", "actions_follow_path"])
def test_examples_run(name: str, tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    load_example(name).main(["--plot", str(tmp_path / "goals.png")])
    out = capsys.readouterr().out
    assert (tmp_path / "goals.png").stat().st_size > 0
    assert "trace digest:" in out
    if name == "actions_fibonacci":
        assert "/fibonacci/status" in out and "my goal ended PREEMPTED" in out
    else:
        assert "SUCCEEDED" in out and "PREEMPTED" in out


@pytest.mark.slow
def test_protocol_check_example_reports_the_student_bug(capsys: pytest.CaptureFixture[str]) -> None:
    load_example("actions_protocol_check").main()
    out = capsys.readouterr().out
    assert "tutorial server: no violation" in out
    assert "set_succeeded on goal" in out and "replay: world seed" in out
