"""actionlib's Python modules in a script: every public name of each, importable, of its kind.

``NAMES`` is the public names of each module of Noetic's actionlib (``/usr/lib/python3/
dist-packages/actionlib``) with what each is (a class, a function, an int, a module, other),
frozen here; the test marked ``ros`` lists them again from the real package. A script run by
ddes imports each module (``import actionlib.X as m``, ``from actionlib import X``) and each
name (``from actionlib.X import name``) and prints what it got.
"""

from __future__ import annotations

import json
import textwrap
from collections.abc import Callable
from pathlib import Path
from typing import Any

import pytest

import ddes
from ddes.compat.scripts import run_script

C, F, I, M = "class", "function", "int", "module"  # noqa: E741 - the kinds, short

#: Noetic actionlib 1.14's modules (the package itself as ""): public name -> kind.
NAMES: dict[str, dict[str, str]] = {
    "": {"ActionClient": C, "ActionException": C, "ActionServer": C, "ClientGoalHandle": C,
         "CommState": C, "CommStateMachine": C, "GoalID": C, "GoalIDGenerator": C,
         "GoalManager": C, "GoalStatus": C, "GoalStatusArray": C, "HandleTrackerDeleter": C,
         "Header": C, "INVALID_TRANSITION": I, "NO_TRANSITION": I, "ServerGoalHandle": C,
         "SimpleActionClient": C, "SimpleActionServer": C, "SimpleGoalState": C,
         "StatusTracker": C, "TerminalState": C, "action_client": M, "action_server": M,
         "exceptions": M, "g_goal_id": I, "get_name_of_constant": F, "goal_id_generator": M,
         "handle_tracker_deleter": M, "nop_cb": F, "rospy": M, "server_goal_handle": M,
         "simple_action_client": M, "simple_action_server": M, "status_tracker": M,
         "threading": M, "time": M, "traceback": M, "weakref": M},
    "action_client": {"ActionClient": C, "ActionException": C, "ClientGoalHandle": C,
                      "CommState": C, "CommStateMachine": C, "GoalID": C, "GoalManager": C,
                      "GoalStatus": C, "GoalStatusArray": C, "Header": C,
                      "INVALID_TRANSITION": I, "NO_TRANSITION": I, "TerminalState": C,
                      "g_goal_id": I, "get_name_of_constant": F, "rospy": M, "threading": M,
                      "time": M, "weakref": M},
    "simple_action_client": {"ActionClient": C, "CommState": C, "GoalStatus": C,
                             "SimpleActionClient": C, "SimpleGoalState": C,
                             "get_name_of_constant": F, "rospy": M, "threading": M},
    "action_server": {"ActionException": C, "ActionServer": C, "GoalID": C,
                      "GoalIDGenerator": C, "GoalStatus": C, "GoalStatusArray": C,
                      "HandleTrackerDeleter": C, "ServerGoalHandle": C, "StatusTracker": C,
                      "nop_cb": F, "rospy": M, "threading": M},
    "simple_action_server": {"ActionServer": C, "GoalStatus": C, "ServerGoalHandle": C,
                             "SimpleActionServer": C, "nop_cb": F, "rospy": M, "threading": M,
                             "traceback": M},
    "server_goal_handle": {"ServerGoalHandle": C, "actionlib_msgs": M, "rospy": M},
    "goal_id_generator": {"GoalID": C, "GoalIDGenerator": C, "rospy": M, "s_goalcount": I,
                          "s_goalcount_lock": "other", "threading": M},
    "status_tracker": {"StatusTracker": C, "actionlib_msgs": M, "goal_id_generator": M,
                       "rospy": M},
    "handle_tracker_deleter": {"HandleTrackerDeleter": C, "rospy": M},
    "exceptions": {"ActionException": C},
}

#: A function, run in a script (ddes) or in Noetic's Python, naming what a value is.
KIND = textwrap.dedent("""
    import types

    def kind(v):
        if isinstance(v, types.ModuleType):
            return "module"
        if isinstance(v, type):
            return "class"
        if isinstance(v, types.FunctionType):
            return "function"
        if isinstance(v, int) and not isinstance(v, bool):
            return "int"
        return "other"
""")


def _import_script() -> str:
    """A script importing every module and name of ``NAMES`` one by one; prints JSON."""
    lines = ["import json", "import rospy", KIND, "got = {}"]
    for mod, names in NAMES.items():
        full = f"actionlib.{mod}" if mod else "actionlib"
        lines.append(f"import {full} as m" if mod else "import actionlib as m")
        if mod:
            lines.append(f"from actionlib import {mod} as m2")
            lines.append("assert m2 is m, (m2, m)")
        lines.append(f"got[{mod!r}] = {{}}")
        for name in names:
            lines.append(f"from {full} import {name} as v")
            lines.append(f"got[{mod!r}][{name!r}] = kind(v)")
        lines.append(f"assert sorted(m.__all__) == sorted(got[{mod!r}]), {mod!r}")
    lines.append("print(json.dumps(got))")
    return "\n".join(lines) + "\n"


def _run(tmp_path: Path, source: str, until: float = 1.0) -> list[str]:
    script = tmp_path / "script.py"
    script.write_text(source)
    printed: list[str] = []
    world = ddes.World()
    world.log_output = lambda line, _level: printed.append(line)
    done, _ = run_script(world, script, print_line=lambda text, _err: printed.append(text))
    world.run(until=until)
    assert done.triggered and done.ok, printed
    return printed


def test_every_public_name_of_every_actionlib_module_imports_in_a_script(tmp_path: Path) -> None:
    printed = _run(tmp_path, _import_script())
    assert json.loads(printed[-1]) == NAMES


def test_star_import_gives_actionlibs_names(tmp_path: Path) -> None:
    printed = _run(tmp_path, textwrap.dedent("""
        from actionlib import *
        from actionlib.action_client import *
        print(sorted(n for n in dir() if not n.startswith("_")))
    """))
    assert printed == [str(sorted(NAMES[""]))]


def test_the_names_are_ddes_classes_and_the_worlds_messages(tmp_path: Path) -> None:
    printed = _run(tmp_path, textwrap.dedent("""
        import actionlib
        import actionlib.simple_action_client as sac
        from actionlib.action_server import ActionServer, ServerGoalHandle
        from actionlib.exceptions import ActionException
        from actionlib_msgs.msg import GoalID, GoalStatus
        from std_msgs.msg import Header
        import ddes.actionlib
        import ddes.errors
        print(actionlib.GoalStatus is GoalStatus, actionlib.GoalID is GoalID,
              actionlib.Header is Header, sac.GoalStatus is GoalStatus)
        print(ActionServer is actionlib.ActionServer,
              issubclass(ActionServer, ddes.actionlib.ActionServer),
              issubclass(ServerGoalHandle, ddes.actionlib.ServerGoalHandle),
              actionlib.ClientGoalHandle is ddes.actionlib.ClientGoalHandle,
              ActionException is ddes.errors.ROSActionException)
        print(actionlib.simple_action_server.SimpleActionServer is actionlib.SimpleActionServer)
    """))
    assert printed == ["True True True True", "True True True True True", "True"]


def test_goal_ids_count_per_node_shared_with_its_servers(tmp_path: Path) -> None:
    printed = _run(tmp_path, textwrap.dedent("""
        import rospy
        import actionlib
        from actionlib import goal_id_generator
        from actionlib_tutorials.msg import FibonacciAction, FibonacciGoal
        from actionlib_msgs.msg import GoalID
        rospy.init_node("gen")
        rospy.sleep(1.5)
        a = goal_id_generator.GoalIDGenerator()
        b = goal_id_generator.GoalIDGenerator("/other")
        print(a.generate_ID().id, b.generate_ID().id, goal_id_generator.s_goalcount)
        g = a.generate_ID()
        print(type(g) is GoalID, g.stamp.to_sec(), actionlib.action_client.g_goal_id)
        server = actionlib.SimpleActionServer("fib", FibonacciAction, auto_start=False)
        server.start()
        pub = rospy.Publisher("fib/goal", actionlib.SimpleActionClient("fib", FibonacciAction)
                              .action_client.ActionGoal, queue_size=1)
        rospy.sleep(0.5)
        pub.publish(pub.data_class(goal=FibonacciGoal(order=1)))  # no id: the server makes one
        rospy.sleep(0.5)
        print([s.status.goal_id.id for s in server.action_server.status_list])
    """), until=5.0)
    assert printed[:2] == ["/gen-1-1.500000000 /other-2-1.500000000 2", "True 1.5 1"]
    assert printed[2] == "['/gen-4-2.0']"


def test_to_string_and_get_name_of_constant_answer_as_actionlibs(tmp_path: Path) -> None:
    printed = _run(tmp_path, textwrap.dedent(TO_STRING))
    assert printed == [json.dumps(TO_STRING_NOETIC)]


#: What a script prints of the to_string methods (the same in Noetic's Python: TO_STRING_NOETIC).
TO_STRING = """
    import json
    import actionlib
    from actionlib import CommState, SimpleGoalState, TerminalState, get_name_of_constant
    from actionlib_msgs.msg import GoalStatus
    out = [[GoalStatus.to_string(n) for n in range(11)],
           [CommState.to_string(n) for n in range(10)],
           [TerminalState.to_string(n) for n in range(11)],
           [SimpleGoalState.to_string(n) for n in range(4)],
           [get_name_of_constant(GoalStatus, 3), actionlib.NO_TRANSITION,
            actionlib.INVALID_TRANSITION, TerminalState.LOST, CommState.LOST]]
    print(json.dumps(out))
"""

TO_STRING_NOETIC = [
    ["_has_header", "ACTIVE", "PREEMPTED", "SUCCEEDED", "ABORTED", "REJECTED", "PREEMPTING",
     "RECALLING", "RECALLED", "LOST", "NO_SUCH_STATE_10"],
    ["WAITING_FOR_GOAL_ACK", "PENDING", "ACTIVE", "WAITING_FOR_RESULT", "WAITING_FOR_CANCEL_ACK",
     "RECALLING", "PREEMPTING", "DONE", "LOST", "NO_SUCH_STATE_9"],
    ["NO_SUCH_STATE_0", "NO_SUCH_STATE_1", "PREEMPTED", "SUCCEEDED", "ABORTED", "REJECTED",
     "NO_SUCH_STATE_6", "NO_SUCH_STATE_7", "RECALLED", "LOST", "NO_SUCH_STATE_10"],
    ["PENDING", "ACTIVE", "DONE", "NO_SUCH_STATE_3"],
    ["SUCCEEDED", -1, -2, 9, 8],
]


def test_a_server_goal_handle_without_a_server_logs_actionlibs_errors(tmp_path: Path) -> None:
    printed = _run(tmp_path, textwrap.dedent("""
        import rospy
        from actionlib.server_goal_handle import ServerGoalHandle
        from actionlib_tutorials.msg import FibonacciResult
        rospy.init_node("h")
        gh = ServerGoalHandle()
        print(gh.get_goal(), gh.goal, gh.status_tracker, gh.action_server, gh == gh)
        gh.set_succeeded(FibonacciResult())
        try:
            gh.set_aborted()
        except AttributeError as e:
            print("AttributeError:", e)
    """))
    assert printed == [
        "None None None None False",
        "[ERROR] [0.000000]: Attempt to get a goal id on an uninitialized ServerGoalHandle",
        "[ERROR] [0.000000]: Attempt to get a goal id on an uninitialized ServerGoalHandle",
        "[ERROR] [0.000000]: Attempt to set status on an uninitialized ServerGoalHandle",
        "AttributeError: 'NoneType' object has no attribute 'ActionResultType'",
    ]


# -- against Noetic's actionlib ------------------------------------------------------------

@pytest.mark.ros
def test_the_frozen_names_are_noetics(ros_python: Callable[..., Any]) -> None:
    real = ros_python(KIND + textwrap.dedent(f"""
        import importlib, json
        out = {{}}
        for mod in {list(NAMES)!r}:
            m = importlib.import_module("actionlib." + mod if mod else "actionlib")
            out[mod] = {{n: kind(getattr(m, n)) for n in dir(m) if not n.startswith("_")}}
        print(json.dumps(out))
    """), as_json=True)
    assert real == NAMES


@pytest.mark.ros
def test_to_string_is_noetics(ros_python: Callable[..., Any]) -> None:
    assert ros_python(textwrap.dedent(TO_STRING), as_json=True) == TO_STRING_NOETIC


@pytest.mark.ros
def test_a_server_goal_handle_without_a_server_fails_as_noetics(
        ros_python: Callable[..., Any]) -> None:
    out = ros_python(textwrap.dedent("""
        from actionlib.server_goal_handle import ServerGoalHandle
        gh = ServerGoalHandle()
        print(gh.get_goal(), gh.goal, gh.status_tracker, gh.action_server, gh == gh)
        try:
            gh.set_aborted()
        except AttributeError as e:
            print("AttributeError:", e)
    """))
    assert out.splitlines() == [
        "None None None None False",
        "AttributeError: 'NoneType' object has no attribute 'ActionResultType'"]
