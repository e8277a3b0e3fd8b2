"""threading in a rospy script: locks, conditions, events and threads on greenlets."""

from __future__ import annotations

import textwrap
from pathlib import Path

import ddes
from ddes.compat.scripts import run_script


def _run(tmp_path: Path, body: str, until: float = 5.0) -> list[str]:
    path = tmp_path / "node.py"
    path.write_text(textwrap.dedent(body))
    printed: list[str] = []
    world = ddes.World(strict=False)
    world.log_output = lambda line, _level: printed.append(line.split("]: ", 1)[-1])
    run_script(world, path, print_line=lambda t, _e: printed.append(t))
    world.run(until=until)
    return printed


def test_a_lock_held_across_a_sleep_blocks_only_the_callback_that_waits(tmp_path: Path) -> None:
    printed = _run(tmp_path, """
        import threading
        import rospy
        rospy.init_node("locker")
        lock = threading.Lock()

        def tick(event):
            with lock:  # waits while the main holds it; the rest of the node runs on
                print("tick got the lock at %s" % rospy.get_time())

        rospy.Timer(rospy.Duration(0.5), tick, oneshot=True)
        with lock:
            rospy.sleep(1.0)
            print("main releases at %s" % rospy.get_time())
        rospy.sleep(0.1)
    """)
    assert printed == ["main releases at 1.0", "tick got the lock at 1.0"]


def test_threads_conditions_and_events(tmp_path: Path) -> None:
    printed = _run(tmp_path, """
        import threading
        import rospy
        rospy.init_node("worker")
        ready = threading.Event()
        cond = threading.Condition()
        items = []

        def producer():
            for i in range(3):
                rospy.sleep(0.1)
                with cond:
                    items.append(i)
                    cond.notify()
            ready.set()

        t = threading.Thread(target=producer)
        t.start()
        got = []
        while len(got) < 3:
            with cond:
                cond.wait_for(lambda: items)
                got.append((items.pop(0), rospy.get_time()))
        print(ready.wait(1.0), got)
        t.join()
        print("joined", t.is_alive(), threading.Event().wait(0.25), rospy.get_time())
    """)
    assert printed == ["True [(0, 0.1), (1, 0.2), (2, 0.3)]", "joined False False 0.55"]


def test_a_deadlock_names_the_nodes_instead_of_freezing(tmp_path: Path) -> None:
    printed = _run(tmp_path, """
        import threading
        import rospy
        rospy.init_node("philosopher")
        a, b = threading.Lock(), threading.Lock()

        def other():
            with b:
                rospy.sleep(0.1)
                with a:
                    pass

        threading.Thread(target=other).start()
        with a:
            rospy.sleep(0.2)
            try:
                b.acquire()
            except rospy.ROSException as exc:
                print(type(exc).__name__, str(exc).split(" waits")[0])
        again = threading.Lock()
        again.acquire()
        print(again.acquire(timeout=0.5), again.acquire(blocking=False))
    """)
    assert printed == ["DeadlockError deadlock: /philosopher -> /philosopher -> /philosopher",
                       "False False"]


def test_an_exception_ends_only_its_thread_as_in_python(tmp_path: Path,
                                                        capfd: object) -> None:
    """threading.excepthook's behaviour: "Exception in thread Thread-1 (boom):" and the
    traceback on standard error; the node and its other threads go on."""
    import subprocess
    import sys

    body = """
        import threading, time
        def boom():
            raise ValueError("only this thread")
        t = threading.Thread(target=boom)
        t.start()
        t.join()
        print("alive", t.is_alive(), t.name)
    """
    real = subprocess.run([sys.executable, "-c", textwrap.dedent(body)], capture_output=True,
                          text=True, check=True)
    printed = _run(tmp_path, """
        import threading
        import rospy
        rospy.init_node("threads")
        def boom():
            raise ValueError("only this thread")
        t = threading.Thread(target=boom)
        t.start()
        t.join()
        print("alive", t.is_alive(), t.name)
        rospy.sleep(0.5)
        print("the node goes on at", rospy.get_time())
    """)
    assert real.stdout.splitlines() == printed[:1] == ["alive False Thread-1 (boom)"]
    assert printed[1:] == ["the node goes on at 0.5"]
    err = capfd.readouterr().err  # type: ignore[attr-defined]
    assert real.stderr.startswith("Exception in thread Thread-1 (boom):\nTraceback")
    assert "Exception in thread Thread-1 (boom):\nTraceback" in err
    assert err.rstrip().endswith("ValueError: only this thread")
