"""Plain rospy scripts on simulated time, next to a yield-style node, in one world.

Run it with ``python examples/rospy_scripts.py``.  The scripts are the bundled tutorials'
(``ddes/packages/rospy_tutorials/scripts`` and ``ddes/packages/actionlib_tutorials/scripts``);
they run unchanged under real ROS 1 too (``rosrun rospy_tutorials talker.py`` in a catkin
workspace).  Here:

1. talker.py and listener.py chat at 10 Hz;
2. add_two_ints_server.py answers add_two_ints_client.py 3 4;
3. fibonacci_server.py computes a sequence for fibonacci_client.py, one number per second;
4. a yield-style ddes node listens to the talker too: both styles share the world.

The same run prints the same lines and digest on every machine and every PYTHONHASHSEED.
From a shell: ``ddes run talker.py listener.py --until 5`` in the scripts' folder.
"""

from __future__ import annotations

from pathlib import Path

import ddes
from ddes.compat.scripts import run_script

PACKAGES = Path(ddes.__file__).parent / "packages"
RP = PACKAGES / "rospy_tutorials" / "scripts"
AL = PACKAGES / "actionlib_tutorials" / "scripts"


def main() -> None:
    world = ddes.World(seed=0)
    world.log_output = lambda line, _level: print(line)

    def out(text: str, _stderr: bool) -> None:
        print(f"[{world.now / 1e9:.6f}] (print) {text}")

    run_script(world, RP / "talker.py", ["__name:=talker"], print_line=out)
    run_script(world, RP / "listener.py", ["__name:=listener"], print_line=out)
    run_script(world, RP / "add_two_ints_server.py", print_line=out)
    run_script(world, RP / "add_two_ints_client.py", ["3", "4"], print_line=out)
    run_script(world, AL / "fibonacci_server.py", print_line=out)
    run_script(world, AL / "fibonacci_client.py", print_line=out)

    watcher = world.create_node("watcher")  # the yield style, in the same world
    count = [0]
    ddes.Subscriber(watcher, "chatter", ddes.get_message_class("std_msgs/String"),
                    lambda msg: count.__setitem__(0, count[0] + 1))

    world.run(until=0.35)
    world.log_output = False  # quiet from here: the action takes 19 simulated seconds
    world.run(until=20.0)
    print(f"watcher heard {count[0]} messages; trace digest {world.digest()[:16]}")


if __name__ == "__main__":
    main()
