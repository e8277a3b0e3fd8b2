"""Issue 38's attack classes on the sandbox, each closed: nothing a submission starts outlives its
grade, no host socket is reachable, a grade has a wall budget, the child cannot tell hidden from
public nor import the grader's exercises, the grader's memory and the disk are bounded, a zero-
time livelock gets a verdict, and an honest node keeps its score whatever a thread beside it
tries.  Each submission is the demo talker plus the attack (docs/grading.md, "Attacks")."""

from __future__ import annotations

import os
import re
import socket
import textwrap
import time
from pathlib import Path

import pytest

from ddes.grading import grade
from ddes.grading.sandbox import UID_BASE, Limits, Sandbox, claim_uid, seccomp_available

HERE = Path(__file__).resolve().parent
TALKER = (HERE / "fixtures" / "ex0_solution" / "talker.py").read_text()

needs_seccomp = pytest.mark.skipif(not seccomp_available(), reason="the kernel has no seccomp")


def _submission(tmp_path: Path, attack: str, *, before_main: bool = True) -> Path:
    """The reference talker with ``attack`` run before its main (in a thread when it says so)."""
    sub = tmp_path / "sub"
    sub.mkdir()
    head, sep, tail = TALKER.partition('if __name__ == "__main__":')
    body = textwrap.dedent(attack)
    text = head + body + "\n\n" + sep + tail if before_main else TALKER + "\n" + body
    (sub / "talker.py").write_text(text)
    return sub


def _leftovers(marker: str) -> list[int]:
    pids = []
    for entry in os.listdir("/proc"):
        if not entry.isdigit():
            continue
        try:
            with open(f"/proc/{entry}/cmdline", "rb") as f:
                if marker.encode() in f.read():
                    pids.append(int(entry))
        except OSError:
            pass
    return pids


def test_processes_started_without_an_audit_event_do_not_outlive_the_grade(
        ex0, tmp_path: Path) -> None:  # type: ignore[no-untyped-def]
    marker = "3141.59"
    sub = _submission(tmp_path, f"""
        import _posixsubprocess, os, sys
        def _escape():
            # subprocess.Popen's own path, below its audit event: fork, setsid, exec
            r, w = os.pipe()
            try:
                _posixsubprocess.fork_exec(
                    [sys.executable, "-c", "import os, time; os.setsid(); time.sleep({marker})"],
                    [sys.executable.encode()], True, (w,), None, None, -1, -1, -1, -1, -1, -1, r, w, True,
                    True, -1, None, None, None, -1, None, False)
            except OSError as exc:
                print("refused:", exc)
        _escape()
    """)
    report = grade(ex0, sub)
    assert report.score == 10  # the talker itself is honest
    assert _leftovers(marker) == []
    if seccomp_available():
        assert any("seccomp" in e for e in report.enforced)


def test_a_leftover_process_is_killed_and_named(tmp_path: Path) -> None:
    """Below the seccomp filter (switched off here) a process that escapes the group kill is
    still found, killed, and named in the outcome."""
    marker = "2718.28"
    script = tmp_path / "sub"
    script.mkdir()
    (script / "node.py").write_text(textwrap.dedent(f"""
        import _posixsubprocess, os, sys
        r, w = os.pipe()
        _posixsubprocess.fork_exec(
            [sys.executable, "-c", "import os, time; os.setsid(); time.sleep({marker})"],
            [sys.executable.encode()], True, (w,), None,
            None, -1, -1, -1, -1, -1, -1, r, w, True, True, -1, None, None, None, -1, None, False)
        open("forked", "w").close()
        import rospy
        rospy.init_node("node")
        rospy.spin()
    """))
    box = Sandbox(script, [("node.py", [])], limits=Limits(step_wall_s=5.0), seccomp=False)
    box.start()
    t = 0
    deadline = time.monotonic() + 30.0  # the script's thread forks while the steps go on
    while not (box.workdir / "forked").exists() and time.monotonic() < deadline:
        box.step(t, [])
        t += 10_000_000
    assert (box.workdir / "forked").exists()
    outcome = box.close()
    assert _leftovers(marker) == []
    assert outcome.leftovers and marker in outcome.leftovers[0], outcome.output_tail


@needs_seccomp
def test_host_unix_sockets_are_out_of_reach(ex0, tmp_path: Path) -> None:  # type: ignore[no-untyped-def]
    path = str(tmp_path / "host.sock")
    server = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
    server.bind(path)
    server.listen(4)
    server.settimeout(0.0)
    os.chmod(path, 0o777)
    accepted: list[object] = []
    sub = _submission(tmp_path, f"""
        import _socket
        for attempt in ("_socket", "socket"):
            try:
                mod = __import__(attempt)
                s = mod.socket(1, 1)
                s.connect({path!r})
                s.send(b"escaped")
            except OSError as exc:
                print(attempt, "refused:", exc)
    """)
    report = grade(ex0, sub)
    try:
        accepted.append(server.accept())
    except (BlockingIOError, OSError):
        pass
    server.close()
    assert accepted == []
    assert report.score == 10


def test_a_grade_has_a_wall_budget_and_the_verdict_names_it(ex0, tmp_path: Path) -> None:  # type: ignore[no-untyped-def]
    sub = _submission(tmp_path, """
        def _slow(event):
            for _ in range(5_000_000):  # about 0.15 s: under the per-step budget, every step
                pass
    """)
    text = (sub / "talker.py").read_text().replace(
        "    rate = rospy.Rate(10)\n", "    rate = rospy.Rate(10)\n    rospy.Timer(rospy.Duration(0.01), _slow)\n")
    (sub / "talker.py").write_text(text)
    report = grade(ex0, sub, limits=Limits(step_wall_s=2.0, grade_wall_s=3.0))
    assert any("wall budget of 3 s" in p for p in report.problems), report.problems
    assert report.score < 10


def test_the_child_cannot_import_the_graders_exercises_nor_learn_its_seed(tmp_path: Path) -> None:
    from ddes.grading import ExerciseRegistry
    from ddes.grading.grader import run_scenario
    from ddes.grading.scenarios import select_scenarios
    from ddes.grading.submission import prepare

    (hidden,) = ExerciseRegistry().load_file(HERE / "fixtures" / "ex0_hidden.py")
    sub = _submission(tmp_path, """
        import random, sys
        def _probe():
            seen = []
            for name in ("ddes.grading.exercises.ex5_safety", "ddes.grading.course",
                         "ddes.grading.grader", "ddes.grading.scenarios"):
                try:
                    __import__(name)
                    seen.append(name)
                except ImportError:
                    pass
            try:
                import ddes.grading.exercises as where
                open(where.__file__).read()
                seen.append("read")
            except (ImportError, OSError):
                pass
            return seen
        _SEEN = _probe()
        _ARGV = list(sys.argv)
        _DRAW = random.random()
    """)
    text = (sub / "talker.py").read_text().replace(
        'pub.publish(f"hello world {n}")',
        'pub.publish(f"{_SEEN} {_ARGV} {_DRAW} "\n'
        '            f"{sorted(m for m in sys.modules if m.startswith(\'ddes.grading\'))}")')
    (sub / "talker.py").write_text(text)
    prepared = tmp_path / "prep"
    prepare(sub, prepared)
    said = []
    for scenario in select_scenarios(hidden, 1234, False, None):
        _world, facts = run_scenario(hidden, scenario, prepared, None)
        text = [m.data for _t, who, m in facts.messages("/chatter")
                if who in facts.student_nodes][0]
        # each child's copy of the submission has a folder of its own (a temporary name)
        said.append(re.sub(r"ddes-grade-[^/]+", "ddes-grade-*", text))
    first = said[0]
    assert first.startswith("[] "), first  # nothing of the grader importable or readable
    assert "ddes.grading.grader" not in first and "ddes.grading.exercise'" not in first
    assert "1234" not in first
    assert len(said) == 3 and len(set(said)) == 1  # public and hidden look the same inside


def test_messages_beyond_the_budget_end_the_node_with_a_verdict(ex0, tmp_path: Path) -> None:  # type: ignore[no-untyped-def]
    sub = _submission(tmp_path, "")
    text = (sub / "talker.py").read_text().replace(
        'pub.publish(f"hello world {n}")', 'pub.publish("x" * (4 << 20))')
    (sub / "talker.py").write_text(text)
    report = grade(ex0, sub, limits=Limits(message_bytes=32 << 20))
    assert any("32 MiB" in p and "messages" in p for p in report.problems), report.problems


def test_files_beyond_the_disk_budget_end_the_node_with_a_verdict(ex0, tmp_path: Path) -> None:  # type: ignore[no-untyped-def]
    sub = _submission(tmp_path, """
        def _fill():
            for i in range(64):
                with open(f"junk{i}", "wb") as f:
                    f.write(b"x" * (1 << 20))
        _fill()
    """)
    report = grade(ex0, sub, limits=Limits(disk_bytes=8 << 20))
    assert any("8 MiB" in p and "files" in p for p in report.problems), report.problems


def test_a_zero_time_livelock_gets_a_verdict_naming_it(ex0, tmp_path: Path) -> None:  # type: ignore[no-untyped-def]
    sub = _submission(tmp_path, "")
    text = (sub / "talker.py").read_text().replace("    rate = rospy.Rate(10)\n", """\
    echo = rospy.Publisher("echo", String, queue_size=10)
    rospy.Subscriber("echo", String, lambda m: echo.publish(m))
    rospy.sleep(0.5)
    echo.publish("again")
    rate = rospy.Rate(10)
""")
    (sub / "talker.py").write_text(text)
    report = grade(ex0, sub, limits=Limits(step_wall_s=30.0))
    assert any("at one instant" in p for p in report.problems), report.problems


def _in_main(sub: Path, code: str) -> None:
    """Put ``code`` into the talker's main, right after init_node."""
    node = sub / "talker.py"
    lines = textwrap.indent(textwrap.dedent(code), "    ")
    node.write_text(node.read_text().replace('    rospy.init_node("talker")\n',
                                             '    rospy.init_node("talker")\n' + lines, 1))


def test_a_forging_thread_beside_an_honest_node_costs_nothing(ex0, tmp_path: Path) -> None:  # type: ignore[no-untyped-def]
    sub = _submission(tmp_path, """
        import json, os, threading, time
        def _forge():
            while True:
                for where in ("/tmp/results.json", "../results.json", "/autograder/results",
                              "results.json"):
                    try:
                        with open(where, "w") as f:
                            json.dump({"score": 100, "tests": []}, f)
                    except OSError:
                        pass
                try:
                    os.write(1, b"DG\\x01\\x00\\x00\\x00\\x00")
                    os.write(3, b"DG\\x06\\x00\\x00\\x00\\x00")
                except OSError:
                    pass
                time.sleep(0.05)
    """)
    _in_main(sub, "threading.Thread(target=_forge, daemon=True).start()\n")
    report = grade(ex0, sub)
    assert report.score == 10, report.problems


def test_threads_still_work_under_the_filter(ex0, tmp_path: Path) -> None:  # type: ignore[no-untyped-def]
    sub = _submission(tmp_path, "import threading\n")
    _in_main(sub, """
        box = []
        worker = threading.Thread(target=lambda: box.append(sum(range(10))))
        worker.start()
        worker.join()
        assert box == [45]
    """)
    report = grade(ex0, sub)
    assert report.score == 10, report.problems


def test_a_thread_whose_forgery_raises_ends_only_that_thread(ex0, tmp_path: Path) -> None:  # type: ignore[no-untyped-def]
    """As in Python: an uncaught exception ends its thread ("Exception in thread …" on
    standard error), not the node (a node used to die of it, and lose everything)."""
    sub = _submission(tmp_path, """
        import json, threading
        def _forge():
            with open("/tmp/results.json", "w") as f:  # refused: a PermissionError
                json.dump({"score": 100}, f)
    """)
    _in_main(sub, "threading.Thread(target=_forge).start()\n")
    report = grade(ex0, sub)
    assert report.score == 10, report.problems


def test_a_run_starts_a_bounded_number_of_children(tmp_path: Path,
                                                   monkeypatch: pytest.MonkeyPatch) -> None:
    from ddes.grading import Criterion, Exercise
    from ddes.grading import grader as grader_module

    monkeypatch.setattr(grader_module, "MAX_CHILDREN", 1)
    sub = tmp_path / "sub"
    sub.mkdir()
    for name in ("a.py", "b.py"):
        (sub / name).write_text(f"import rospy\nrospy.init_node('n_{name[0]}')\nrospy.spin()\n")
    ex = Exercise(id="two", title="Two nodes", duration=0.2,
                  build=lambda world, scenario: None,
                  scripts=(("a.py", ()), ("b.py", ())),
                  criteria=(Criterion("1", "nothing", 1, lambda facts: (1.0, [])),))
    report = grade(ex, sub)
    assert any("1 more student node(s) than the 1 a grade runs were not started (b.py" in p
               for p in report.problems), report.problems


def test_each_sandbox_has_a_user_of_its_own(tmp_path: Path) -> None:
    """The processes rlimit counts per user: two grades at once (a batch's workers) must not
    share one, or the threads of one would make the other's fail."""
    locks = tmp_path / "locks"
    if os.geteuid() != 0:
        with pytest.raises(OSError):  # only root can hand out users; the locks still work
            os.setuid(claim_uid(locks)[0])
        return
    first, fd1 = claim_uid(locks)
    second, fd2 = claim_uid(locks)
    assert first == UID_BASE and second == UID_BASE + 1
    os.close(fd1)
    again, fd3 = claim_uid(locks)
    assert again == first  # the lowest free one: sequential grades run as one user
    os.close(fd2)
    os.close(fd3)


def test_threads_of_one_sandbox_do_not_count_against_another(tmp_path: Path) -> None:
    script = tmp_path / "sub"
    script.mkdir()
    (script / "node.py").write_text(textwrap.dedent("""
        import threading, rospy
        rospy.init_node("node")
        gate = threading.Event()
        threads = [threading.Thread(target=gate.wait) for _ in range(10)]
        for t in threads:
            t.start()
        rospy.loginfo("ten threads started")
        rospy.spin()
    """))
    boxes = [Sandbox(script, [("node.py", [])], limits=Limits(step_wall_s=5.0)) for _ in range(2)]
    for box in boxes:
        box.start()
    for t in range(0, 100_000_000, 10_000_000):
        for box in boxes:
            box.step(t, [])
    outcomes = [box.close() for box in boxes]
    for o in outcomes:
        assert "ten threads started" in o.output_tail, o.output_tail
    if os.geteuid() == 0 and boxes[0].uid is not None:
        assert boxes[0].uid != boxes[1].uid
