"""ddes.compat.actionlib: actionlib scripts with blocking waits and blocking execute callbacks."""

from __future__ import annotations

import textwrap
from pathlib import Path

import ddes
from ddes.compat.scripts import run_script

SCRIPTS = Path(ddes.__file__).parent / "packages" / "actionlib_tutorials" / "scripts"


def test_the_fibonacci_tutorial_scripts_run_unchanged() -> None:
    lines: list[str] = []
    printed: list[tuple[int, str]] = []
    world = ddes.World()
    world.log_output = lambda line, _level: lines.append(line)
    run_script(world, SCRIPTS / "fibonacci_server.py")
    done, _ = run_script(world, SCRIPTS / "fibonacci_client.py",
                         print_line=lambda t, _e: printed.append((world.now, t)))
    world.run(until=30.0)
    assert done.value == 0
    assert lines == ["[INFO] [0.001000]: /fibonacci: Executing, creating fibonacci sequence of "
                     "order 20 with seeds 0, 1", "[INFO] [19.001000]: /fibonacci: Succeeded"]
    assert printed == [(19_001_000_000, "Result: 0, 1, 1, 2, 3, 5, 8, 13, 21, 34, 55, 89, 144, "
                                        "233, 377, 610, 987, 1597, 2584, 4181, 6765")]


def test_send_goal_and_wait_preempts_and_waits_time_out(tmp_path: Path) -> None:
    client = tmp_path / "client.py"
    client.write_text(textwrap.dedent("""
        import actionlib
        import rospy
        from actionlib_msgs.msg import GoalStatus
        from actionlib_tutorials.msg import FibonacciAction, FibonacciGoal
        rospy.init_node("impatient")
        c = actionlib.SimpleActionClient("fibonacci", FibonacciAction)
        print("nobody yet:", c.wait_for_server(rospy.Duration(0.5)), rospy.get_time())
        c.wait_for_server()
        state = c.send_goal_and_wait(FibonacciGoal(order=20), rospy.Duration(3.0),
                                     rospy.Duration(2.0))
        print(GoalStatus.PREEMPTED == state, rospy.get_time(), len(c.get_result().sequence))
    """))
    printed: list[str] = []
    world = ddes.World()
    world.log_output = False
    run_script(world, client, print_line=lambda t, _e: printed.append(t))
    world.call_at(1_000_000_000, lambda: run_script(world, SCRIPTS / "fibonacci_server.py"))
    world.run(until=30.0)
    assert printed[0] == "nobody yet: False 0.5"
    # cancelled 3 s after the goal (t = 4.001), preempted at the server's next 1 Hz check
    assert printed[1:] == ["True 5.001 0"]


def test_a_raising_execute_callback_aborts_the_goal(tmp_path: Path) -> None:
    script = tmp_path / "both.py"
    script.write_text(textwrap.dedent("""
        import actionlib
        import rospy
        from actionlib_tutorials.msg import FibonacciAction, FibonacciGoal
        rospy.init_node("both")

        def execute(goal):
            rospy.sleep(0.5)
            raise ValueError("bad order %d" % goal.order)

        actionlib.SimpleActionServer("fib", FibonacciAction, execute, auto_start=False).start()
        c = actionlib.SimpleActionClient("fib", FibonacciAction)
        c.wait_for_server()
        c.send_goal(FibonacciGoal(order=3))
        print(c.wait_for_result(), c.get_state(), c.get_goal_status_text(), rospy.get_time())
    """))
    printed: list[str] = []
    world = ddes.World()
    world.log_output = False
    run_script(world, script, print_line=lambda t, _e: printed.append(t))
    world.run(until=5.0)
    assert printed == ["True 4 Exception in execute callback: bad order 3 0.501"]
