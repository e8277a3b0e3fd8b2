"""actionlib's own Python tests (../shared/upstream/actionlib/actionlib/test), run unchanged.

Each rostest launch file of actionlib's Python tests starts its server nodes and its test node;
here each server script runs as a script node of one world (``run_script``) and the test file
runs in a node of its own whose script loads it, as rostest loads it, and runs its TestCase with
unittest. actionlib's 18 Python test methods must all pass. rostest and rosnode are not what
this tests: where ddes provides no module of that name to scripts, the test node's ``import
rostest`` finds a stand-in here (its ``rosrun`` / ``run`` are only called under ``__main__``),
and the deadlock test's ``rosnode.get_node_names`` / ``kill_nodes`` one that reads and shuts
down the world's nodes.
"""

from __future__ import annotations

import sys
import textwrap
import types
from pathlib import Path

import pytest

import ddes
from ddes.compat.scripts import run_script
from ddes.graph.blocking import current_task

UPSTREAM = Path(__file__).resolve().parents[3] / "shared" / "upstream"
TESTS = UPSTREAM / "actionlib" / "actionlib" / "test"

pytestmark = pytest.mark.skipif(not TESTS.is_dir(), reason="no ../shared/upstream here")

#: (launch file, test file, its TestCase, the test node's name, server scripts and node names,
#:  the methods, simulated seconds to run)
CASES = {
    "test_imports": ("test_imports.py", "TestImports", "test_imports", [],
                     ["test_imports"], 5),
    "test_python_server_components": (
        "test_server_components.py", "TestGoalIDGenerator", "test_goal_id_generator", [],
        ["test_generator", "test_status_tracker", "test_threaded_generation"], 5),
    "test_python_exercise_simple_client": (
        "exercise_simple_client.py", "SimpleExerciser", "exercise_simple_server",
        [("mock_simple_server.py", "mock_simple_server")],
        ["test_drop", "test_exception", "test_ignore_cancel_and_succeed", "test_just_abort",
         "test_just_preempt", "test_just_succeed", "test_lose"], 120),
    "test_python_server2": (
        "simple_python_client_test.py", "TestSimpleActionClient", "simple_python_client_test",
        [("ref_server.py", "ref_server")], ["testsimple"], 60),
    "test_python_server3": (
        "test_ref_action_server.py", "TestRefSimpleActionServer", "test_ref_action_server",
        [("ref_server.py", "ref_server")],
        ["test_abort", "test_feedback", "test_result", "testsimple"], 60),
    "test_python_simple_server": (
        "test_ref_simple_action_server.py", "TestRefSimpleActionServer",
        "test_simple_python_server", [("ref_simple_server.py", "ref_simple_server")],
        ["test_one"], 60),
    "test_simple_action_server_deadlock_python": (
        "test_simple_action_server_deadlock.py", "DeadlockTest",
        "test_simple_action_server_deadlock",
        [("simple_action_server_deadlock_companion.py", f"deadlock_companion_{i}")
         for i in range(1, 6)], ["test_deadlock"], 50),
}

#: Seconds of latency per message, by launch file (default: ddes's instant delivery).  With
#: instant delivery the deadlock test's five companions and its server trade goals at one
#: instant for ever (a result makes a companion send its next goal at once, which preempts
#: another companion's, whose result...): a zero-time livelock that the latency of real ROS
#: breaks.  50 ms a message keeps the status arrays small and the run a few seconds.
LATENCY = {"test_simple_action_server_deadlock_python": 0.05}

RUNNER = textwrap.dedent("""
    import unittest
    import rospy

    rospy.init_node({node!r})
    path = {path!r}
    scope = {{"__name__": "upstream_test", "__file__": path, "__builtins__": __builtins__}}
    with open(path) as f:
        exec(compile(f.read(), path, "exec"), scope)
    suite = unittest.defaultTestLoader.loadTestsFromTestCase(scope[{case!r}])
    names = [test.id().rsplit(".", 1)[1] for test in suite]
    result = unittest.TestResult()
    suite.run(result)
    for test, trace in result.failures + result.errors:
        print("FAILED", test.id().rsplit(".", 1)[1], trace)
    print("RAN", result.testsRun, *names)
""")


def _rostest() -> types.ModuleType:
    mod = types.ModuleType("rostest")

    def rosrun(*_args: object, **_kwargs: object) -> None:
        raise AssertionError("rostest.rosrun is only called under __main__")

    mod.rosrun = mod.run = rosrun  # type: ignore[attr-defined]
    return mod


def _rosnode() -> types.ModuleType:
    mod = types.ModuleType("rosnode")

    def world() -> ddes.World:
        task = current_task()
        assert task is not None
        return task.world

    def get_node_names(namespace: str | None = None) -> list[str]:
        return sorted(world().nodes)

    def kill_nodes(names: object) -> tuple[list[str], list[str]]:
        killed = []
        for name in names:  # type: ignore[attr-defined]
            node = world().lookup_node(name)
            if node is not None:
                node.shutdown("killed by rosnode")
                killed.append(name)
        return killed, []

    mod.get_node_names = get_node_names  # type: ignore[attr-defined]
    mod.kill_nodes = kill_nodes  # type: ignore[attr-defined]
    return mod


@pytest.mark.parametrize("launch", list(CASES))
def test_actionlib_python_tests_pass(launch: str, tmp_path: Path,
                                     monkeypatch: pytest.MonkeyPatch) -> None:
    test_file, case, node, servers, methods, seconds = CASES[launch]
    assert (TESTS / f"{launch}.launch").is_file()
    monkeypatch.setitem(sys.modules, "rostest", _rostest())
    monkeypatch.setitem(sys.modules, "rosnode", _rosnode())
    world = ddes.World(seed=3, strict=False)
    world.log_output = False
    world.set_link(latency=LATENCY.get(launch, 0.0))
    for script, name in servers:
        run_script(world, TESTS / script, [f"__name:={name}"])
    runner = tmp_path / "runner.py"
    runner.write_text(RUNNER.format(node=node, path=str(TESTS / test_file), case=case))
    printed: list[str] = []
    done, _ = run_script(world, runner, print_line=lambda text, _err: printed.append(text))
    world.run(until=float(seconds))
    assert done.triggered and done.ok, printed
    failed = [line for line in printed if line.startswith("FAILED")]
    assert failed == [], "\n".join(failed)
    assert printed[-1] == " ".join(["RAN", str(len(methods)), *methods])
