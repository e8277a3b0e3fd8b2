"""A scenario with no student node to run starts no child and no lockstep (grader.run_scenario):
the same run, instant by instant, as the lockstep with an empty child, and nothing of the
submission executes."""

from __future__ import annotations

from pathlib import Path

from ddes.grading import Lockstep, Sandbox
from ddes.grading.exercise import Criterion, Exercise, Facts, Scenario
from ddes.grading.grader import run_scenario
from ddes.graph.world import World


def _build(world: World, _scenario: Scenario) -> None:
    string = world.messages.get_message_class("std_msgs/String")
    node = world.create_node("/talker")
    pub = node.advertise("/chatter", string, queue_size=10)
    node.create_timer(0.1, lambda _ev: pub.publish(string(data=f"at {world.now}")))
    world.create_node("/listener").subscribe("/chatter", string, lambda _m: None)


def _finished(world: World) -> bool:
    return len(world.trace.select(kind="topic.publish", topic="/chatter")) >= 7


def _exercise(finished: bool) -> Exercise:
    return Exercise(id="no_nodes", title="no student node", scripts=(), duration=5.0,
                    build=_build, finished=_finished if finished else None,
                    criteria=(Criterion("c", "ran", 1, lambda f: (1.0, [])),))


def _lockstep_run(exercise: Exercise, submission: Path) -> World:
    """What run_scenario did before: the lockstep with a child that runs no script."""
    world = World(0, wall_budget=None)
    world.log_output = None
    assert exercise.build is not None
    exercise.build(world, Scenario("public", 0))
    finished = exercise.finished
    Lockstep(world, Sandbox(submission, [])).run(
        5_000_000_000, done=None if finished is None else lambda: finished(world))
    return world


def test_no_student_node_starts_no_child_and_runs_as_the_lockstep(tmp_path: Path) -> None:
    # a script the exercise does not name: it must not run anywhere
    (tmp_path / "evil.py").write_text("raise SystemExit('ran')\n")
    for early in (True, False):
        ex = _exercise(early)
        world, facts = run_scenario(ex, Scenario("public", 0), tmp_path, None)
        assert isinstance(facts, Facts)
        assert facts.outcome.state == "not started"
        assert facts.outcome.reason.startswith("no student node to run")
        assert facts.outcome.enforced == [] and facts.student_nodes == []
        reference = _lockstep_run(ex, tmp_path)
        assert world.now == reference.now == (700_000_000 if early else 5_000_000_000)
        assert world.digest() == reference.digest()
