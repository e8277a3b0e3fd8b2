"""ddes.compat.rospy and rospy scripts as nodes: plain rospy code on simulated time."""

from __future__ import annotations

import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

import ddes
from ddes.compat import rospy
from ddes.compat.scripts import run_script
from ddes.errors import BlockingOutsideNodeError, ROSException, ROSInitException
from ddes.graph.blocking import INIT_TEXT

SCRIPTS = Path(ddes.__file__).parent / "packages" / "rospy_tutorials" / "scripts"


def _world(lines: list[str]) -> ddes.World:
    world = ddes.World(seed=1)
    world.log_output = lambda line, _level: lines.append(line)
    return world


def _script(tmp_path: Path, body: str, name: str = "node.py") -> Path:
    path = tmp_path / name
    path.write_text(textwrap.dedent(body))
    return path


def test_the_tutorial_talker_and_listener_run_unchanged() -> None:
    lines: list[str] = []
    world = _world(lines)
    _, talker = run_script(world, SCRIPTS / "talker.py")
    _, listener = run_script(world, SCRIPTS / "listener.py")
    world.run(until=0.25)
    assert talker.node is not None and talker.node.name == "/talker_1"
    assert listener.node is not None and listener.node.name == "/listener_2"
    assert lines == [
        "[INFO] [0.000000]: hello world 0.0",
        "[INFO] [0.100000]: hello world 0.1",
        "[INFO] [0.100000]: /listener_2I heard hello world 0.1",
        "[INFO] [0.200000]: hello world 0.2",
        "[INFO] [0.200000]: /listener_2I heard hello world 0.2",
    ]


def test_the_add_two_ints_server_and_client_block_on_simulated_time() -> None:
    printed: list[str] = []
    world = ddes.World()

    def out(text: str, _stderr: bool) -> None:
        printed.append(f"{world.now} {text}")

    run_script(world, SCRIPTS / "add_two_ints_server.py", print_line=out)
    done, client = run_script(world, SCRIPTS / "add_two_ints_client.py", ["3", "4"],
                              print_line=out)
    world.run(until=1.0)
    assert done.value == 0 and client.node is not None and client.node.is_shutdown()
    assert printed == ["0 Ready to add two ints.", "0 Requesting 3+4",
                       "300000 Returning [3 + 4 = 7]", "400000 3 + 4 = 7"]


def test_a_usage_error_exits_before_init_node_with_its_code() -> None:
    printed: list[str] = []
    world = ddes.World()
    done, context = run_script(world, SCRIPTS / "add_two_ints_client.py",
                               print_line=lambda t, _e: printed.append(t))
    world.run()
    assert done.value == 1 and context.node is None
    assert printed == [f"{SCRIPTS / 'add_two_ints_client.py'} [x y]"]


def test_each_script_sees_its_own_node_argv_remappings_and_private_params(tmp_path: Path
                                                                           ) -> None:
    path = _script(tmp_path, """
        import sys
        import rospy
        from std_msgs.msg import Int32
        rospy.init_node("counter")
        out = rospy.Publisher("out", Int32, queue_size=1)
        rospy.loginfo("%s %s %s %s %s", rospy.get_name(), rospy.get_namespace(),
                      rospy.resolve_name("out"), rospy.get_param("~rate"), rospy.myargv())
        rospy.loginfo("argv %s", sys.argv[1:])
    """)
    lines: list[str] = []
    world = _world(lines)
    run_script(world, path, ["a", "out:=/x", "_rate:=5"])
    run_script(world, path, ["b", "__name:=other", "_rate:=7"], namespace="/ns")
    world.run()
    assert lines == [
        f"[INFO] [0.000000]: /counter / /x 5 ['{path}', 'a']",
        "[INFO] [0.000000]: argv ['a', 'out:=/x', '_rate:=5']",
        f"[INFO] [0.000000]: /ns/other /ns/ /ns/out 7 ['{path}', 'b']",
        "[INFO] [0.000000]: argv ['b', '__name:=other', '_rate:=7']",
    ]


def test_blocking_calls_timers_waits_and_shutdown_hooks(tmp_path: Path) -> None:
    path = _script(tmp_path, """
        import rospy
        from std_msgs.msg import String

        rospy.init_node("worker")
        pub = rospy.Publisher("ping", String, queue_size=10, latch=True)
        rospy.on_shutdown(lambda: rospy.loginfo("hook"))

        def tick(event):
            rospy.loginfo("tick %s", event.current_real.to_sec())
            rospy.sleep(0.05)  # a callback may block: only this timer waits
            rospy.loginfo("tock %s", rospy.Time.now().to_sec())

        rospy.Timer(rospy.Duration(0.5), tick)
        rospy.sleep(1.2)
        pub.publish("hi")
        msg = rospy.wait_for_message("pong", String, timeout=1.0)
        rospy.loginfo("got %s at %s", msg.data, rospy.get_time())
        try:
            rospy.wait_for_message("never", String, timeout=0.5)
        except rospy.ROSException as exc:
            rospy.logwarn("%s", exc)
        rospy.signal_shutdown("done")
        rospy.loginfo("shut down: %s", rospy.is_shutdown())
    """)
    echo = _script(tmp_path, """
        import rospy
        from std_msgs.msg import String
        rospy.init_node("echo")
        pub = rospy.Publisher("pong", String, queue_size=10)
        rospy.Subscriber("ping", String, lambda m: (rospy.sleep(0.1), pub.publish(m.data + "!")))
        rospy.spin()
    """, "echo.py")
    lines: list[str] = []
    world = _world(lines)
    run_script(world, echo)
    run_script(world, path)
    world.run(until=5.0)
    assert lines == [
        "[INFO] [0.500000]: tick 0.5",
        "[INFO] [0.550000]: tock 0.55",
        "[INFO] [1.000000]: tick 1.0",
        "[INFO] [1.050000]: tock 1.05",
        "[INFO] [1.300000]: got hi! at 1.299999999",  # rospy.sleep(1.2): genpy truncates
        "[INFO] [1.500000]: tick 1.5",
        "[INFO] [1.550000]: tock 1.55",
        "[WARN] [1.800000]: timeout exceeded while waiting for message on topic never",
        "[INFO] [1.800000]: hook",
        "[INFO] [1.800000]: shut down: True",
    ]


def test_throttle_and_once_count_per_call_site_in_the_script(tmp_path: Path) -> None:
    path = _script(tmp_path, """
        import rospy
        rospy.init_node("chatty")
        rate = rospy.Rate(10)
        for i in range(12):
            rospy.loginfo_throttle(0.5, "a %d" % i)
            rospy.logwarn_once("b %d" % i)
            rospy.loginfo_throttle(1.0, "c %d" % i)
            rate.sleep()
    """)
    lines: list[str] = []
    world = _world(lines)
    run_script(world, path)
    world.run()
    assert lines == ["[INFO] [0.000000]: a 0", "[WARN] [0.000000]: b 0",
                     "[INFO] [0.000000]: c 0", "[INFO] [0.500000]: a 5",
                     "[INFO] [1.000000]: a 10", "[INFO] [1.000000]: c 10"]


def test_a_second_init_node_with_other_arguments_raises_rospys_text(tmp_path: Path) -> None:
    path = _script(tmp_path, """
        import rospy
        rospy.init_node("one")
        rospy.init_node("one")  # the same arguments: nothing happens
        try:
            rospy.init_node("two")
        except rospy.ROSException as exc:
            rospy.logerr("%s", exc)
        try:
            rospy.init_node("a/b")
        except ValueError as exc:
            rospy.logerr("%s", exc)
    """)
    lines: list[str] = []
    world = _world(lines)
    run_script(world, path)
    world.run()
    assert lines == [
        "[ERROR] [0.000000]: rospy.init_node() has already been called with different "
        f"arguments: ('one', ['{path}'], False, None, False, False)",
        "[ERROR] [0.000000]: namespaces are not allowed in node names",
    ]


def test_init_node_rejects_a_namespace_in_the_name(tmp_path: Path) -> None:
    path = _script(tmp_path, """
        import rospy
        rospy.init_node("a/b")
    """)
    world = ddes.World(strict=False)
    done, _ = run_script(world, path, print_line=lambda t, e: None)
    world.run()
    assert done.triggered and not done.ok and str(done.value) == \
        "namespaces are not allowed in node names"


def test_rospy_calls_outside_any_node_raise_rospys_texts() -> None:
    with pytest.raises(ROSInitException, match="time is not initialized"):
        rospy.get_time()
    with pytest.raises(BlockingOutsideNodeError, match="rospy.sleep"):
        rospy.sleep(0.5)
    with pytest.raises(ROSInitException, match="outside any script node"):
        rospy.init_node("x")
    with pytest.raises(ROSInitException, match="time is not initialized"):
        rospy.Rate(10)
    with pytest.raises(ROSInitException, match=r"client code must call rospy.init_node\(\) first"):
        rospy.spin()
    assert rospy.get_name() == "/unnamed" and not rospy.is_shutdown()
    assert INIT_TEXT == "time is not initialized. Have you called init_node()?"


def test_blocking_before_init_node_in_a_script_says_so(tmp_path: Path) -> None:
    path = _script(tmp_path, """
        import rospy
        from std_msgs.msg import String
        pub = rospy.Publisher("early", String, queue_size=1)
        try:
            pub.publish("x")
        except rospy.ROSException as exc:
            print(exc)
        try:
            rospy.get_time()
        except rospy.ROSInitException as exc:
            print(type(exc).__name__, "time is not initialized" in str(exc))
        rospy.sleep(1.0)  # rospy sleeps on the wall clock before init_node: the kernel's here
        rospy.init_node("late")
        pub.publish("now fine")
        print(pub.resolved_name, rospy.get_time())
    """)
    printed: list[str] = []
    world = ddes.World()
    run_script(world, path, print_line=lambda t, _e: printed.append(t))
    world.run()
    assert printed == [
        "ROS node has not been initialized yet. Please call init_node() first",
        "ROSInitException True",
        "/early 1.0",
    ]


def test_the_import_hook_is_scoped_to_the_scripts_code(tmp_path: Path) -> None:
    path = _script(tmp_path, """
        import rospy
        import std_msgs.msg
        from rospy_tutorials.srv import AddTwoInts, AddTwoIntsRequest, AddTwoIntsResponse
        rospy.init_node("imports")
        print(std_msgs.msg.String._type, AddTwoInts._type, AddTwoIntsRequest._type,
              AddTwoIntsResponse(3).sum)
        try:
            from std_msgs.msg import NoSuchType
        except ImportError as exc:
            print("ImportError", "NoSuchType" in str(exc))
    """)
    printed: list[str] = []
    world = ddes.World()
    run_script(world, path, print_line=lambda t, _e: printed.append(t))
    world.run()
    assert printed == ["std_msgs/String rospy_tutorials/AddTwoInts "
                       "rospy_tutorials/AddTwoIntsRequest 3", "ImportError True"]
    assert "std_msgs" not in sys.modules and "std_msgs.msg" not in sys.modules
    assert sys.modules.get("rospy") is None
    import builtins
    assert builtins.__import__.__module__ == "builtins"


def test_rosrun_and_launch_find_scripts_next_to_node_types(tmp_path: Path) -> None:
    console = ddes.Console()
    out = console.run("rosrun rospy_tutorials add_two_ints_server.py &")
    assert "Ready to add two ints." in out
    out = console.run("rosrun rospy_tutorials add_two_ints_client.py 10 5")
    assert "10 + 5 = 15" in out
    launch = tmp_path / "chat.launch"
    launch.write_text('<launch><node pkg="rospy_tutorials" type="talker.py" name="t" '
                      'output="screen"><remap from="chatter" to="/talk"/></node></launch>')
    out = console.run(f"roslaunch {launch} &")
    assert "t (rospy_tutorials/talker.py)" in out
    assert "]: hello world 0.1" in console.run("sleep 0.15")
    assert "/t" in console.run("rosnode list").split()
    assert "/talk" in console.run("rostopic list")


def test_script_runs_are_identical_under_three_hash_seeds(tmp_path: Path) -> None:
    code = textwrap.dedent(f"""
        import ddes
        from ddes.compat.scripts import run_script
        world = ddes.World(seed=5)
        world.log_output = False
        for name in ("talker.py", "listener.py", "add_two_ints_server.py"):
            run_script(world, {str(SCRIPTS)!r} + "/" + name, print_line=lambda t, e: None)
        run_script(world, {str(SCRIPTS)!r} + "/add_two_ints_client.py", ["1", "2"],
                   print_line=lambda t, e: None)
        world.run(until=2.0)
        print(world.digest())
    """)
    digests = {subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                              env={"PYTHONHASHSEED": seed, "PATH": "/usr/bin"},
                              check=True).stdout for seed in ("0", "1", "12345")}
    assert len(digests) == 1 and len(digests.pop().strip()) == 64


def test_a_raising_script_crashes_only_its_node(tmp_path: Path) -> None:
    path = _script(tmp_path, """
        import rospy
        rospy.init_node("fragile")
        rospy.sleep(0.5)
        raise RuntimeError("boom")
    """)
    lines: list[str] = []
    world = _world(lines)
    world.strict = False
    _, context = run_script(world, path)
    _, talker = run_script(world, SCRIPTS / "talker.py")
    world.run(until=1.0)
    assert context.node is not None and context.node.is_shutdown()
    assert talker.node is not None and not talker.node.is_shutdown()
    assert any("process has died" in line and "RuntimeError: boom" in line for line in lines)


def test_rospy_exceptions_are_ddes_errors() -> None:
    assert issubclass(rospy.ROSInterruptException, rospy.ROSException)
    assert not issubclass(rospy.ServiceException, rospy.ROSException)
    with pytest.raises(ROSException):
        raise rospy.ROSInitException("x")


def test_ddes_run_runs_scripts_with_their_arguments() -> None:
    from ddes.cli.run import is_rospy_script, run_scripts
    from ddes.errors import ROSConsoleError

    lines: list[str] = []
    world = run_scripts([str(SCRIPTS / "add_two_ints_server.py"),
                         str(SCRIPTS / "add_two_ints_client.py"), "3", "4"],
                        until=1.0, out=lines.append)
    assert lines == ["Ready to add two ints.", "Requesting 3+4", "Returning [3 + 4 = 7]",
                     "3 + 4 = 7"]
    assert world.now == 1_000_000_000
    assert is_rospy_script(SCRIPTS / "talker.py")
    with pytest.raises(ROSConsoleError, match="before any script"):
        run_scripts(["3", str(SCRIPTS / "talker.py")], until=1.0)
    with pytest.raises(ROSConsoleError, match="script not found"):
        run_scripts(["nope.py"], until=1.0)


def test_the_rospy_example_prints_the_same_under_three_hash_seeds() -> None:
    example = Path(__file__).resolve().parents[2] / "examples" / "rospy_scripts.py"
    outs = {subprocess.run([sys.executable, str(example)], capture_output=True, text=True,
                           env={"PYTHONHASHSEED": seed, "PATH": "/usr/bin"}, check=True).stdout
            for seed in ("0", "1", "12345")}
    assert len(outs) == 1
    out = outs.pop()
    assert "[0.000400] (print) 3 + 4 = 7" in out and "watcher heard 199 messages" in out
    assert "(print) Result: 0, 1, 1, 2, 3, 5, 8" in out


def test_the_script_in_docs_rospy_md_runs_as_shown(tmp_path: Path) -> None:
    import re

    doc = (Path(__file__).resolve().parents[2] / "docs" / "rospy.md").read_text(encoding="utf-8")
    block = re.findall(r"```python\n(.*?)```", doc, re.S)[0]
    lines: list[str] = []
    world = _world(lines)
    run_script(world, _script(tmp_path, block, "talker.py"))
    world.run(until=0.15)
    assert lines == ["[INFO] [0.000000]: hello world 0.0", "[INFO] [0.100000]: hello world 0.1"]
