"""actionlib_tutorials' Python nodes (../shared/upstream/common_tutorials, unchanged) on ddes and
under real rospy.

The upstream package's ``scripts/`` are fibonacci_server.py, fibonacci_client.py and
gen_numbers.py (its averaging server and client are C++, ``src/averaging_*.cpp``: ddes runs
them as the bundled package's node types, started here beside the upstream gen_numbers.py).
The scripts are started as ``rosrun actionlib_tutorials SCRIPT`` finds them with issue 39's
package path (the upstream package shadows the bundled one).  The ``ros`` tests run the same
files as processes of a private rosmaster (Debian's ROS lacks actionlib_tutorials' Python
messages: genpy generates them from the definitions ddes reads from the upstream ``.action``).
"""

from __future__ import annotations

import json
import math
import re
import struct
from collections.abc import Callable
from pathlib import Path
from typing import Any

import pytest

import ddes
from ddes.compat.scripts import run_script
from ddes.msg import MessageRegistry, get_message_class
from ddes.nodes import start_node
from ddes.rospack import RosPack

from .harness import ACTIONLIB_TUTORIALS, PATH, master_script, shape

pytestmark = pytest.mark.skipif(not ACTIONLIB_TUTORIALS.is_dir(),
                                reason="no ../shared/upstream here")

SCRIPTS = ACTIONLIB_TUTORIALS / "scripts"
PROBES = Path(__file__).resolve().parent / "probes"
SERVER_STARTS = ("[INFO] [0.001000]: /fibonacci: Executing, creating fibonacci sequence of "
                 "order 20 with seeds 0, 1")
FIBONACCI = ("Result: 0, 1, 1, 2, 3, 5, 8, 13, 21, 34, 55, 89, 144, 233, 377, 610, 987, 1597, "
             "2584, 4181, 6765")
#: What rospy warns (warnings.warn, SyntaxWarning) for gen_numbers.py's Publisher without
#: queue_size; Python prints the file, the line and the code line.
QUEUE_SIZE_WARNING = [
    f"{SCRIPTS / 'gen_numbers.py'}:14: SyntaxWarning: The publisher should be created with an "
    "explicit keyword argument 'queue_size'. Please see "
    "http://wiki.ros.org/rospy/Overview/Publishers%20and%20Subscribers for more information.",
    "  pub = rospy.Publisher('random_number', Float32)"]
#: Messages a subscriber made at 0 s hears from gen_numbers.py in 2 simulated seconds: those
#: of 0.05 s ... 1.95 s (the one of 0 s goes before it is connected).
NUMBERS_IN_2S = 39


def _world(seed: int = 0) -> tuple[ddes.World, list[str]]:
    """A world on issue 39's package path, and the lines its nodes log and print, in order."""
    world = ddes.World(seed=seed, package_path=[str(p) for p in PATH])
    lines: list[str] = []
    world.log_output = lambda line, _level: lines.append(line)
    return world, lines


def _rosrun(world: ddes.World, *scripts: str) -> None:
    """``rosrun actionlib_tutorials SCRIPT`` for each script: the upstream file, found on the
    package path (the upstream package shadows the bundled one)."""
    for script in scripts:
        start_node(world, "actionlib_tutorials", script, rospack=RosPack(PATH))


def test_the_upstream_scripts_are_what_rosrun_finds() -> None:
    from ddes.nodes import find_script

    rospack = RosPack(PATH)
    folder = Path(rospack.get_path("actionlib_tutorials"))
    assert folder == ACTIONLIB_TUTORIALS
    for script in ("fibonacci_server.py", "fibonacci_client.py", "gen_numbers.py"):
        assert find_script(folder, script, "actionlib_tutorials") == SCRIPTS / script


# -- fibonacci --------------------------------------------------------------------------------------

def test_fibonacci_server_and_client_on_ddes() -> None:
    world, lines = _world()
    _rosrun(world, "fibonacci_server.py", "fibonacci_client.py")
    world.run(until=25.0)
    assert lines == [SERVER_STARTS, "[INFO] [19.001000]: /fibonacci: Succeeded", FIBONACCI]
    assert [e.details["code"] for e in world.trace.filter(kind="node.exit")] == [0]
    assert len(world.trace.filter(kind="action.server.feedback")) == 19  # rospy.Rate(1)


#: Generate actionlib_tutorials' messages (MSGS: the .msg files written from ddes's registry,
#: DEPS: the definitions they use) with genpy, then run BODY.
GENERATE = r'''
import json, signal, subprocess
from genpy.generator import MsgGenerator
_gen = tempfile.mkdtemp(prefix="ddes-gen-")
_msg_out = os.path.join(_gen, "actionlib_tutorials", "msg")
os.makedirs(_msg_out)
_files = sorted(os.path.join(MSGS, f) for f in os.listdir(MSGS))
MsgGenerator().generate_messages("actionlib_tutorials", _files, _msg_out,
                                 {"actionlib_tutorials": [MSGS],
                                  "actionlib_msgs": [DEPS + "/actionlib_msgs"],
                                  "std_msgs": [DEPS + "/std_msgs"]})
open(os.path.join(_gen, "actionlib_tutorials", "__init__.py"), "w").close()
with open(os.path.join(_msg_out, "__init__.py"), "w") as f:
    for name in sorted(os.listdir(MSGS)):
        f.write("from ._%s import *\n" % name[:-4])
os.environ["PYTHONPATH"] = _gen

def stop(p):
    p.send_signal(signal.SIGINT)
    out, err = p.communicate(timeout=30)
    return out.splitlines(), err.splitlines(), p.returncode
'''

REAL_FIBONACCI = r'''
server = start_process([sys.executable, "-u", SCRIPTS + "/fibonacci_server.py"])
client = subprocess.run([sys.executable, "-u", SCRIPTS + "/fibonacci_client.py"],
                        capture_output=True, text=True, timeout=90, env=dict(os.environ))
out, err, code = stop(server)
print(json.dumps({"server": out, "client": client.stdout.splitlines(),
                  "client_err": client.stderr.splitlines(), "code": client.returncode}))
'''

REAL_GEN_NUMBERS = r'''
gen = start_process([sys.executable, "-u", SCRIPTS + "/gen_numbers.py"])
probe = subprocess.run([sys.executable, "-u", PROBE], capture_output=True, text=True,
                       timeout=60, env=dict(os.environ))
out, err, code = stop(gen)
print(json.dumps({"out": out, "err": err, "code": code, "probe": probe.stdout.splitlines(),
                  "probe_err": probe.stderr}))
'''


def _reference(ros_python: Callable[..., Any], tmp_path: Path, body: str, **names: str) -> Any:
    registry = MessageRegistry([str(p) for p in PATH])
    msgs = tmp_path / "msg"
    msgs.mkdir()
    for full in registry.list_types("actionlib_tutorials", "msg"):
        (msgs / (full.split("/")[1] + ".msg")).write_text(registry.get_msg_spec(full).text)
    deps = tmp_path / "deps"
    for full in ("actionlib_msgs/GoalID", "actionlib_msgs/GoalStatus", "std_msgs/Header"):
        package, name = full.split("/")
        (deps / package).mkdir(parents=True, exist_ok=True)
        (deps / package / f"{name}.msg").write_text(registry.get_msg_spec(full).text)
    head = "".join(f"{k} = {v!r}\n" for k, v in
                   {"SCRIPTS": str(SCRIPTS), "MSGS": str(msgs), "DEPS": str(deps), **names}.items())
    return ros_python(master_script() + head + GENERATE + body, as_json=True, timeout=150)


@pytest.mark.ros
@pytest.mark.slow  # the server computes at 1 Hz: about 20 wall seconds in ROS
def test_fibonacci_server_and_client_match_rospy(ros_python: Callable[..., Any],
                                                 tmp_path: Path) -> None:
    theirs = _reference(ros_python, tmp_path, REAL_FIBONACCI)
    world, lines = _world()
    _rosrun(world, "fibonacci_server.py", "fibonacci_client.py")
    world.run(until=25.0)
    assert theirs["code"] == 0, theirs
    assert theirs["client"] == [FIBONACCI] == lines[-1:]
    assert [shape(line) for line in theirs["server"]] == [shape(line) for line in lines[:-1]]


# -- gen_numbers and the averaging action ---------------------------------------------------------

def _numbers(seed: int, until: float) -> tuple[list[str], list[float]]:
    world, lines = _world(seed=seed)
    _rosrun(world, "gen_numbers.py")
    numbers: list[float] = []
    listener = world.create_node("numbers")
    ddes.Subscriber(listener, "random_number", get_message_class("std_msgs/Float32"),
                    lambda msg: numbers.append(msg.data))
    world.run(until=until)
    return lines, numbers


def test_gen_numbers_on_ddes() -> None:
    lines, numbers = _numbers(1, 2.0)
    # the Publisher, made after init_node, warns (on standard error) before the log line
    assert lines == ["\n".join(QUEUE_SIZE_WARNING), "[INFO] [0.000000]: Generating random numbers"]
    assert len(numbers) == NUMBERS_IN_2S  # rospy.Rate(20)
    assert abs(sum(numbers) / len(numbers) - 5) < 0.6  # random.normalvariate(5, 1)
    assert all(n == struct.unpack("f", struct.pack("f", n))[0] for n in numbers)  # Float32
    assert _numbers(1, 2.0)[1] == numbers != _numbers(2, 2.0)[1]  # the world's seed


def test_gen_numbers_feeds_the_averaging_action() -> None:
    """gen_numbers.py (upstream) with the averaging server and client of the C++ tutorial
    (ddes's bundled node types of actionlib_tutorials)."""
    world, lines = _world(seed=1)
    _rosrun(world, "gen_numbers.py")
    bundled = RosPack([])
    start_node(world, "actionlib_tutorials", "averaging_server", rospack=bundled)
    start_node(world, "actionlib_tutorials", "averaging_client", rospack=bundled)
    world.run(until=6.0)
    assert lines[:4] == ["\n".join(QUEUE_SIZE_WARNING),
                         "[INFO] [0.000000]: Generating random numbers",
                         "[ INFO] [0.000000000]: Waiting for action server to start.",
                         "[ INFO] [0.001000000]: Action server started, sending goal."]
    end = re.fullmatch(r"\[ INFO\] \[(5\.\d+)\]: /averaging: (Succeeded|Aborted)", lines[4])
    assert end is not None, lines
    state = "SUCCEEDED" if end.group(2) == "Succeeded" else "ABORTED"
    assert lines[5:] == [f"[ INFO] [{end.group(1)}]: Action finished: {state}"]


@pytest.mark.ros
def test_gen_numbers_matches_rospy(ros_python: Callable[..., Any], tmp_path: Path) -> None:
    probe = PROBES / "sample_numbers.py"
    theirs = _reference(ros_python, tmp_path, REAL_GEN_NUMBERS, PROBE=str(probe))
    world, lines = _world(seed=1)
    _rosrun(world, "gen_numbers.py")
    ours: list[str] = []
    run_script(world, probe, print_line=lambda text, _err: ours.append(text))
    world.run(until=4.0)
    assert theirs["err"] == QUEUE_SIZE_WARNING
    assert [shape(line) for line in theirs["out"]] == ["[INFO] [N]: Generating random numbers"]
    assert [shape(line) for line in lines] == [shape("\n".join(QUEUE_SIZE_WARNING)),
                                               *(shape(line) for line in theirs["out"])]
    for got in (theirs["probe"], ours):
        (line,) = got
        sample = json.loads(line)
        assert sample["count"] == 40 and sample["float32"]
        assert abs(sample["mean"] - 5) < 1.0 and 0.4 < sample["std"] < 1.8
        assert math.isclose(sample["mean"], sum(sample["values"]) / 40)
