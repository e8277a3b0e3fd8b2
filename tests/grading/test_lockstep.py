"""The sandbox and the lockstep bridge: same messages as an in-process run, what is enforced on
the child, and budgets that end a child without ending the grade."""

from __future__ import annotations

import os
import textwrap
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from ddes.compat.scripts import run_script
from ddes.grading import Limits, Lockstep, Sandbox, protocol
from ddes.graph.world import World

SOLUTION = Path(__file__).resolve().parent / "fixtures" / "ex0_solution"


def listener_world() -> tuple[World, list[tuple[int, str, str]]]:
    world = World(0, wall_budget=None)
    got: list[tuple[int, str, str]] = []
    string = world.messages.get_message_class("std_msgs/String")
    node = world.create_node("/listener")
    node.subscribe("/chatter", string,
                   lambda m: got.append((world.now, m._connection_header["callerid"], m.data)))
    return world, got


def test_a_sandboxed_talker_delivers_what_an_in_process_one_delivers() -> None:
    world, inproc = listener_world()
    run_script(world, SOLUTION / "talker.py", print_line=lambda line, err: None)
    world.run(until=2.0)

    world2, sandboxed = listener_world()
    lock = Lockstep(world2, Sandbox(SOLUTION, [("talker.py", [])]))
    outcome = lock.run(2_000_000_000)
    assert outcome.state == "finished", outcome
    assert lock.problems == []
    assert sandboxed == inproc
    assert len(sandboxed) == 19 and sandboxed[0] == (100_000_000, "/talker", "hello world 1")
    # the proxy mirrors the student's graph on the grader's master
    assert world2.master.topics["/chatter"].publisher_nodes() == ["/talker"]


def test_a_run_ends_early_once_done_and_the_world_stops_there() -> None:
    world, got = listener_world()
    lock = Lockstep(world, Sandbox(SOLUTION, [("talker.py", [])]))
    lock.run(10_000_000_000, done=lambda: len(got) >= 5)
    # the fifth message arrives at 0.5 s: the world stops at that instant, not at 10 s
    assert [t for t, _, _ in got] == [100_000_000 * i for i in range(1, 6)]
    assert world.now == 500_000_000


def test_messages_cross_both_ways_at_the_same_instant(tmp_path: Path) -> None:
    (tmp_path / "echo.py").write_text(textwrap.dedent("""\
        import rospy
        from std_msgs.msg import String
        rospy.init_node("echo")
        pub = rospy.Publisher("/out", String, queue_size=10)
        rospy.Subscriber("/in", String, lambda m: pub.publish("echo " + m.data))
        rospy.spin()
    """))
    world = World(0, wall_budget=None)
    string = world.messages.get_message_class("std_msgs/String")
    node = world.create_node("/driver")
    got: list[tuple[int, str]] = []
    node.subscribe("/out", string, lambda m: got.append((world.now, m.data)))
    pub = node.advertise("/in", string, queue_size=10)

    def drive():  # type: ignore[no-untyped-def]
        yield node.sleep(0.5)
        for i in range(3):
            pub.publish(f"ping {i}")
            yield node.sleep(0.25)

    node.process(drive())
    lock = Lockstep(world, Sandbox(tmp_path, [("echo.py", [])]))
    lock.run(2_000_000_000)
    assert got == [(500_000_000, "echo ping 0"), (750_000_000, "echo ping 1"),
                   (1_000_000_000, "echo ping 2")]
    assert world.master.topics["/in"].subscriber_nodes() == ["/echo"]


PROBE = textwrap.dedent("""\
    import os, sys
    def probe(name, fn):
        try:
            fn()
            print(f"PROBE {name}: open", flush=True)
        except BaseException as exc:
            print(f"PROBE {name}: blocked {type(exc).__name__}", flush=True)
    def sock():
        import socket
        socket.socket()
    def fork():
        pid = os.fork()
        if pid == 0:
            os._exit(0)
    def sub():
        import subprocess
        subprocess.run(["/bin/true"])
    def ctypes_import():
        try:
            import ctypes  # noqa: F401
        except ImportError as exc:  # as on a Python without ctypes: what numpy expects
            raise PermissionError(str(exc)) from None
    def ctypes_lowlevel():
        import _ctypes  # noqa: F401
    def ctypes_via_numpy():  # numpy's own reference to ctypes is None, as without ctypes
        import numpy.ctypeslib
        numpy.ctypeslib.ctypes.memmove
    def numpy_():
        import numpy
        assert float(numpy.dot(numpy.arange(3.0), numpy.arange(3.0))) == 5.0
    def secret():
        if "DDES_TEST_SECRET" in os.environ:
            raise AssertionError
        raise PermissionError("no secret")
    probe("socket", sock)
    probe("read-grader-file", lambda: open(sys.argv[1]).read())
    probe("write-outside", lambda: open(sys.argv[2], "w").write("x"))
    probe("write-inside", lambda: open("note.txt", "w").write("x"))
    probe("fork", fork)
    probe("subprocess", sub)
    probe("numpy", numpy_)
    probe("ctypes-import", ctypes_import)
    probe("ctypes-lowlevel", ctypes_lowlevel)
    probe("ctypes-via-numpy", ctypes_via_numpy)
    probe("kill-parent", lambda: os.kill(os.getppid(), 0))
    probe("env-secret", secret)
""")


def test_what_the_sandbox_enforces(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("DDES_TEST_SECRET", "s3cret")
    sub = tmp_path / "sub"
    sub.mkdir()
    (sub / "probe.py").write_text(PROBE)
    outside = tmp_path / "outside.txt"
    grader_file = Path(__file__)
    box = Sandbox(sub, [("probe.py", [str(grader_file), str(outside)])])
    outcome = Lockstep(World(0, wall_budget=None), box).run(10_000_000)
    lines = dict(line.split(": ", 1) for line in outcome.output_tail.splitlines()
                 if line.startswith("PROBE "))
    assert lines["PROBE write-inside"] == "open"
    assert lines["PROBE numpy"] == "open", outcome.output_tail  # numpy works without ctypes
    for name in ("socket", "read-grader-file", "write-outside", "fork", "subprocess",
                 "ctypes-import", "ctypes-lowlevel", "ctypes-via-numpy", "kill-parent",
                 "env-secret"):
        assert lines[f"PROBE {name}"].startswith("blocked"), (name, outcome.output_tail)
    assert not outside.exists()
    assert any("network namespace (no network)" in e for e in outcome.enforced)


def test_a_hung_child_is_ended_by_the_step_budget_and_the_world_goes_on(tmp_path: Path) -> None:
    (tmp_path / "hang.py").write_text("import rospy\nrospy.init_node('hang')\nwhile True:\n    pass\n")
    world = World(0, wall_budget=None)
    box = Sandbox(tmp_path, [("hang.py", [])], limits=Limits(step_wall_s=1.0))
    outcome = Lockstep(world, box).run(1_000_000_000)
    assert outcome.state == "killed" and "wall budget" in outcome.reason
    assert world.now == 1_000_000_000


def test_an_exiting_child_ends_its_proxies(tmp_path: Path) -> None:
    (tmp_path / "bye.py").write_text(textwrap.dedent("""\
        import os, rospy
        from std_msgs.msg import String
        rospy.init_node("bye")
        pub = rospy.Publisher("/chatter", String, queue_size=1)
        rospy.sleep(0.5)
        os._exit(3)
    """))
    world = World(0, wall_budget=None)
    lock = Lockstep(world, Sandbox(tmp_path, [("bye.py", [])]))
    outcome = lock.run(1_000_000_000)
    assert outcome.state == "exited" and "exit code 3" in outcome.reason
    assert lock.proxies["/bye"].is_shutdown()


def test_a_student_node_cannot_take_a_grader_nodes_name(tmp_path: Path) -> None:
    (tmp_path / "evil.py").write_text(textwrap.dedent("""\
        import rospy
        from std_msgs.msg import String
        rospy.init_node("grader")
        pub = rospy.Publisher("/chatter", String, queue_size=1)
        rospy.spin()
    """))
    world = World(0, wall_budget=None)
    grader = world.create_node("/grader")
    lock = Lockstep(world, Sandbox(tmp_path, [("evil.py", [])]))
    lock.run(100_000_000)
    assert not grader.is_shutdown()
    assert any("taken by the grader" in text for _, text in lock.problems)


def test_the_child_runs_as_another_user_or_says_why() -> None:
    box = Sandbox(SOLUTION, [])
    box.start()
    try:
        text = " ".join(box.enforced)
        if os.geteuid() == 0:
            assert "of its own" in text or "NOT a separate user" in text
    finally:
        box.close()


def test_a_run_is_deterministic() -> None:
    digests = []
    for _ in range(2):
        world, _got = listener_world()
        Lockstep(world, Sandbox(SOLUTION, [("talker.py", [])])).run(1_000_000_000)
        digests.append(world.digest())
    assert digests[0] == digests[1]


texts = st.text(alphabet=st.sampled_from("/abc_~. 0\x00é"), max_size=12)
frames = st.one_of(
    st.builds(protocol.Adv, texts, texts, st.sampled_from(["std_msgs/String", "x/Y", "", "../a"]),
              st.sampled_from([String_md5 := "992ce8a1687cec8c8bd883ec73ca41d1", "0" * 32]),
              st.booleans()),
    st.builds(protocol.Sub, texts, texts, st.sampled_from(["std_msgs/String", "nope/Nope"]),
              st.sampled_from([String_md5, ""]), st.integers(-5, 5)),
    st.builds(protocol.Msg, texts, texts, st.integers(-1, 2), st.binary(max_size=12)),
    st.builds(protocol.Gone, texts),
)


@settings(max_examples=200)
@given(st.lists(frames, max_size=12))
def test_any_frames_from_the_child_are_validated_never_raised(fs: list[object]) -> None:
    world = World(0, wall_budget=None)
    world.create_node("/grader")
    lock = Lockstep(world, Sandbox.__new__(Sandbox))
    lock._apply(fs, 0)
    world.run(until=0.01)
    for name, node in lock.proxies.items():
        assert name.startswith("/") and name != "/grader" and node.name == name
