"""Plain rospy scripts on simulated time, next to a yield-style node, in one world.

Run it with ``python examples/rospy_scripts.py``.  The scripts are the bundled tutorials'
(``ddes/packages/rospy_tutorials/scripts`` and ``ddes/packages/actionlib_tutorials/scripts``);
they run unchanged under real ROS 1 too (``rosrun rospy_tutorials talker.py`` in a catkin
workspace).  Here:

1. talker.py and listener.py chat at 10 Hz;
2. add_two_ints_server.py answers add_two_ints_client.py 3 4;
3. fibonacci_server.py computes a sequence for fibonacci_client.py, one number per second;
4. a yield-style ddes node listens to the talker too: both styles share the world.

``python examples/rospy_scripts.py chatter add_two_ints fibonacci`` runs each named pair alone
instead, in a world of its own, and prints every line its scripts print or log (each tagged
with its script) and the world's trace digest.

The same run prints the same lines and digest on every machine and every PYTHONHASHSEED
(tests/compat/test_examples_hashseed.py); tests/compat/test_rospy_interop.py runs the same
pairs under real rospy and compares what they print.
From a shell: ``ddes run talker.py listener.py --until 5`` in the scripts' folder.
"""

from __future__ import annotations

import sys
from collections.abc import Callable
from pathlib import Path

import ddes
from ddes.compat.scripts import ScriptContext, run_script
from ddes.graph.blocking import current_task

PACKAGES = Path(ddes.__file__).parent / "packages"
RP = PACKAGES / "rospy_tutorials" / "scripts"
AL = PACKAGES / "actionlib_tutorials" / "scripts"

#: Each pair: its scripts with their arguments, and how long (simulated seconds) it runs.
PAIRS: dict[str, tuple[list[tuple[Path, list[str]]], float]] = {
    "chatter": ([(RP / "talker.py", ["__name:=talker"]),
                 (RP / "listener.py", ["__name:=listener"])], 0.35),
    "add_two_ints": ([(RP / "add_two_ints_server.py", []),
                      (RP / "add_two_ints_client.py", ["3", "4"])], 1.0),
    "fibonacci": ([(AL / "fibonacci_server.py", []), (AL / "fibonacci_client.py", [])], 20.0),
}


def run_pair(name: str, out: Callable[[str, str, str], None]) -> ddes.World:
    """Run the pair ``name`` alone; ``out(script, kind, text)`` gets each line, in order.

    ``kind`` is ``"print"`` for what a script prints and ``"log"`` for a log line;
    ``script`` is the file name of the script that printed or logged it.  Returns the world.
    """
    scripts, until = PAIRS[name]
    world = ddes.World(seed=0)
    contexts: list[ScriptContext] = []

    def log(line: str, _level: int) -> None:
        # rospy.loginfo runs on the greenlet of the script's main (its context) or of one of
        # its node's callbacks
        task = current_task()
        context = task.context if task is not None else None
        if context is None and task is not None:
            context = next((c for c in contexts if c.node is task.node), None)
        out(context.path.name if isinstance(context, ScriptContext) else "-", "log", line)

    def printer(script: str) -> Callable[[str, bool], None]:
        return lambda text, _stderr: out(script, "print", text)

    world.log_output = log
    for path, args in scripts:
        contexts.append(run_script(world, path, args, print_line=printer(path.name))[1])
    world.run(until=until)
    return world


def main(argv: list[str]) -> None:
    if argv:
        for name in argv:
            world = run_pair(name, lambda who, kind, text: print(f"{who} ({kind}) {text}"))
            print(f"{name}: trace digest {world.digest()[:16]}")
        return
    world = ddes.World(seed=0)
    world.log_output = lambda line, _level: print(line)

    def out(text: str, _stderr: bool) -> None:
        print(f"[{world.now / 1e9:.6f}] (print) {text}")

    for scripts, _until in PAIRS.values():
        for path, args in scripts:
            run_script(world, path, args, print_line=out)

    watcher = world.create_node("watcher")  # the yield style, in the same world
    count = [0]
    ddes.Subscriber(watcher, "chatter", ddes.get_message_class("std_msgs/String"),
                    lambda msg: count.__setitem__(0, count[0] + 1))

    world.run(until=0.35)
    world.log_output = False  # quiet from here: the action takes 19 simulated seconds
    world.run(until=20.0)
    print(f"watcher heard {count[0]} messages; trace digest {world.digest()[:16]}")


if __name__ == "__main__":
    main(sys.argv[1:])
