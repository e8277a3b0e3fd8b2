"""ddes's pytest plugin (ddes/testing/pytest_plugin.py), run on small test files with pytester.

The inner runs load the plugin as any project does: through its ``pytest11`` entry point.
"""

from __future__ import annotations

import re
import shlex
import xml.etree.ElementTree as ET
from importlib.metadata import entry_points
from pathlib import Path

import pytest

pytest_plugins = ["pytester"]

DOC = Path(__file__).resolve().parents[2] / "docs" / "testing.md"


def _section() -> str:
    text = DOC.read_text(encoding="utf-8")
    return text[text.index("## The pytest plugin"):]


def _doc_block(marker: str) -> str:
    """The fenced block that follows ``<!-- marker -->`` in the plugin's section of the doc."""
    match = re.search(rf"<!-- {re.escape(marker)} -->\n```\w+\n(.*?)```", _section(), flags=re.S)
    assert match, f"docs/testing.md has no block after <!-- {marker} -->"
    return match.group(1)


def _ddes_section(output: str) -> list[str]:
    """The lines of the ``ddes`` report sections in pytest's output."""
    lines = output.splitlines()
    found = []
    for i, line in enumerate(lines):
        if re.fullmatch(r"-+ ddes -+", line):
            found += lines[i:i + 3]
    return found


def test_the_entry_point_names_the_plugin() -> None:
    (ep,) = [ep for ep in entry_points(group="pytest11") if ep.name == "ddes"]
    assert ep.value == "ddes.testing.pytest_plugin"


FIXTURES = """
import ddes

def test_fixtures(ddes_seed, world, console):
    assert type(world) is ddes.World and isinstance(console, ddes.Console)
    assert world.seed == ddes_seed == {seed}
    assert console.world is world and world.strict is False  # a console's world: rospy's rule
    assert "/rosout" in console.run("rosnode list").split()

def test_the_world_is_strict_and_fresh(world):
    assert world.strict and world.now == 0 and not world.nodes
    node = world.create_node("n")
    node.create_timer(0.1, lambda _e: 1 / 0, oneshot=True)
    try:
        world.run(until=1)
    except ZeroDivisionError:
        return
    raise AssertionError("a strict world raises the callback's exception")
"""


def test_the_fixtures_default_to_seed_0(pytester: pytest.Pytester) -> None:
    pytester.makepyfile(FIXTURES.format(seed=0))
    result = pytester.runpytest("-p", "no:cacheprovider")
    result.assert_outcomes(passed=2)
    assert "--ddes-seed" not in result.stdout.str()  # no header line on the default seed


def test_ddes_seed_sets_the_seed_of_the_fixtures(pytester: pytest.Pytester) -> None:
    pytester.makepyfile(FIXTURES.format(seed=5))
    result = pytester.runpytest("-p", "no:cacheprovider", "--ddes-seed", "5")
    result.assert_outcomes(passed=2)
    result.stdout.fnmatch_lines(["ddes *: --ddes-seed 5"])


def test_the_option_is_in_pytest_help(pytester: pytest.Pytester) -> None:
    result = pytester.runpytest("--help")
    result.stdout.fnmatch_lines(["ddes: deterministic ROS worlds:", "*--ddes-seed=N*"])


def test_no_ddes_turns_the_plugin_off(pytester: pytest.Pytester) -> None:
    pytester.makepyfile("def test_x(world):\n    pass\n")
    result = pytester.runpytest("-p", "no:cacheprovider", "-p", "no:ddes")
    result.assert_outcomes(errors=1)
    result.stdout.fnmatch_lines(["*fixture 'world' not found*"])


FAILING = """
import pytest

def test_fails_on_its_world(world):
    world.create_node("n")
    world.run(until=1.5)
    assert world.seed == 0

def test_passes(world):
    pass

def test_fails_without_a_world():
    assert False

@pytest.mark.parametrize("ddes_seed", [1, 2])
def test_fails_on_seed_2(ddes_seed):
    assert ddes_seed != 2
"""


def test_a_failure_prints_the_seed_and_the_replay_command(pytester: pytest.Pytester) -> None:
    pytester.makepyfile(test_robot=FAILING)
    result = pytester.runpytest("-p", "no:cacheprovider", "--ddes-seed", "3")
    result.assert_outcomes(passed=2, failed=3)
    assert _ddes_section(result.stdout.str()) == [
        "-" * 37 + " ddes " + "-" * 37,
        "seed: 3",
        "replay: pytest test_robot.py::test_fails_on_its_world --ddes-seed 3",
        "-" * 37 + " ddes " + "-" * 37,
        "seed: 2",
        "replay: pytest 'test_robot.py::test_fails_on_seed_2[2]'",
    ]  # and none for the test without a world


def test_the_replay_command_replays_the_failure(pytester: pytest.Pytester) -> None:
    pytester.makepyfile(test_robot=FAILING)
    result = pytester.runpytest("-p", "no:cacheprovider", "--ddes-seed", "3")
    commands = [line.split("replay: ", 1)[1] for line in _ddes_section(result.stdout.str())
                if line.startswith("replay: ")]
    assert len(commands) == 2
    for command in commands:
        argv = shlex.split(command)
        assert argv[0] == "pytest"
        again = pytester.runpytest("-p", "no:cacheprovider", *argv[1:])
        again.assert_outcomes(failed=1)
        assert _ddes_section(again.stdout.str())[2] == f"replay: {command}"


def test_the_replay_command_starts_where_pytest_started(pytester: pytest.Pytester) -> None:
    (pytester.path / "robot").mkdir()
    (pytester.path / "robot" / "test_arm.py").write_text("def test_arm(world):\n    assert 0\n")
    top = pytester.runpytest("-p", "no:cacheprovider", "robot")
    assert _ddes_section(top.stdout.str())[2] == (
        "replay: pytest robot/test_arm.py::test_arm --ddes-seed 0")
    with pytest.MonkeyPatch.context() as mp:
        mp.chdir(pytester.path / "robot")
        below = pytester.runpytest("-p", "no:cacheprovider", "--rootdir", str(pytester.path),
                                   ".")
    assert _ddes_section(below.stdout.str())[2] == (
        "replay: pytest test_arm.py::test_arm --ddes-seed 0")
    (pytester.path / "elsewhere").mkdir()
    with pytest.MonkeyPatch.context() as mp:
        mp.chdir(pytester.path / "elsewhere")
        beside = pytester.runpytest("-p", "no:cacheprovider", "--rootdir", str(pytester.path),
                                    "../robot")
    assert _ddes_section(beside.stdout.str())[2] == (
        "replay: pytest ../robot/test_arm.py::test_arm --ddes-seed 0")


def test_a_setup_error_in_a_fixture_on_the_world_prints_it_too(
        pytester: pytest.Pytester) -> None:
    pytester.makeconftest("""
import pytest

@pytest.fixture
def robot(world):
    raise RuntimeError("no robot")
""")
    pytester.makepyfile("def test_x(robot):\n    pass\n")
    result = pytester.runpytest("-p", "no:cacheprovider", "--ddes-seed", "7")
    result.assert_outcomes(errors=1)
    assert _ddes_section(result.stdout.str())[1:] == [
        "seed: 7", "replay: pytest test_a_setup_error_in_a_fixture_on_the_world_prints_it_too.py"
                   "::test_x --ddes-seed 7"]


def test_junitxml_has_the_seed_and_the_command(pytester: pytest.Pytester) -> None:
    pytester.makepyfile(test_robot=FAILING)
    pytester.runpytest("-p", "no:cacheprovider", "--ddes-seed", "3", "--junitxml=out.xml")
    cases = {case.get("name"): case for case in ET.parse(pytester.path / "out.xml").iter("testcase")}
    props = {p.get("name"): p.get("value")
             for p in cases["test_fails_on_its_world"].iter("property")}
    assert props == {"ddes_seed": "3",
                     "ddes_replay": "pytest test_robot.py::test_fails_on_its_world --ddes-seed 3"}
    assert not list(cases["test_passes"].iter("property"))


def test_a_conftest_world_wins_over_the_plugins(pytester: pytest.Pytester) -> None:
    pytester.makeconftest("""
import pytest

@pytest.fixture
def world():
    return "mine"
""")
    pytester.makepyfile("def test_x(world):\n    assert world == 'yours'\n")
    result = pytester.runpytest("-p", "no:cacheprovider", "--ddes-seed", "3")
    result.assert_outcomes(failed=1)
    assert _ddes_section(result.stdout.str()) == []  # that world has no ddes seed


def test_the_console_fixture_prints_between_commands(pytester: pytest.Pytester) -> None:
    pytester.makepyfile("""
def test_talker(console):
    console.run("rosrun rospy_tutorials talker &")
    console.world.run(until=0.35)
    assert False
""")
    result = pytester.runpytest("-p", "no:cacheprovider")
    result.assert_outcomes(failed=1)
    result.stdout.fnmatch_lines(["*- Captured stdout call -*", "*hello world*"])


PROFILE = """
from hypothesis import HealthCheck, settings, strategies as st
from hypothesis.stateful import RuleBasedStateMachine, rule, run_state_machine_as_test

class Machine(RuleBasedStateMachine):
    drawn = []

    @rule(x=st.integers(0, 10**9))
    def step(self, x):
        Machine.drawn.append(x)

def draws(**kw):
    Machine.drawn = []
    run_state_machine_as_test(Machine, settings=settings(  # as a protocol machine builds its own
        max_examples=5, stateful_step_count=5, suppress_health_check=[HealthCheck.too_slow], **kw))
    return Machine.drawn

def test_the_profile_is_loaded():
    current = settings(max_examples=3)
    assert current.derandomize and current.deadline is None and current.print_blob
    assert current.database is None
    assert HealthCheck.too_slow in current.suppress_health_check

def test_a_machine_draws_the_same_steps_on_every_run():
    first = draws()
    assert first and draws() == first
    assert draws(derandomize=False) != first  # what the profile changes
"""


def test_the_protocol_profile(pytester: pytest.Pytester) -> None:
    pytester.makepyfile(PROFILE)
    # a subprocess: loading a profile changes hypothesis's default settings for the process
    result = pytester.runpytest_subprocess("-p", "no:cacheprovider",
                                           "--hypothesis-profile", "ddes-protocols")
    result.assert_outcomes(passed=2)


# -- the example of docs/testing.md, "The pytest plugin" --------------------------------------------

def test_the_docs_example_passes_on_seed_0(pytester: pytest.Pytester) -> None:
    pytester.makepyfile(test_chatter=_doc_block("pytest file: test_chatter.py"))
    result = pytester.runpytest("-p", "no:cacheprovider")
    result.assert_outcomes(passed=13)
    assert "13 tests" in _section()


def test_the_docs_example_fails_on_seed_3_as_the_doc_shows(pytester: pytest.Pytester) -> None:
    pytester.makepyfile(test_chatter=_doc_block("pytest file: test_chatter.py"))
    result = pytester.runpytest("-p", "no:cacheprovider", "--ddes-seed", "3")
    result.assert_outcomes(passed=12, failed=1)
    result.stdout.fnmatch_lines(["E   * assert 4 <= 3"])
    shown = _doc_block("the ddes section of: pytest test_chatter.py --ddes-seed 3")
    assert _ddes_section(result.stdout.str()) == shown.splitlines()
