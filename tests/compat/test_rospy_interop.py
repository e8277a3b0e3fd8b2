"""The bundled rospy scripts under real rospy (Debian ROS, system Python) and under ddes agree.

The same files, ``ddes/packages/rospy_tutorials/scripts/*.py`` (and actionlib_tutorials'), run as
real ROS processes on a real rosmaster and as ddes nodes, both directly and as the pairs of
``examples/rospy_scripts.py``.  add_two_ints is deterministic in ROS too, so its printed lines
must be identical; talker/listener lines carry wall-clock times and pids in ROS, so they are
compared with every number replaced by ``N``.
"""

from __future__ import annotations

import importlib.util
import re
from collections.abc import Callable
from pathlib import Path
from typing import Any

import pytest

import ddes
from ddes.compat.scripts import run_script

SCRIPTS = Path(ddes.__file__).parent / "packages" / "rospy_tutorials" / "scripts"
PACKAGE = SCRIPTS.parent

def _example_pair(pair: str) -> dict[str, list[str]]:
    """What examples/rospy_scripts.py's ``pair`` prints and logs under ddes, by script file."""
    path = Path(__file__).resolve().parents[2] / "examples" / "rospy_scripts.py"
    spec = importlib.util.spec_from_file_location("_ddes_rospy_scripts_example", path)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    out: dict[str, list[str]] = {}
    module.run_pair(pair, lambda script, kind, text: out.setdefault(f"{script} {kind}", [])
                    .append(text))
    return out


def _master_script() -> str:
    """tests/graph/rosmaster_script.py's MASTER (a file of another test folder)."""
    path = Path(__file__).resolve().parents[1] / "graph" / "rosmaster_script.py"
    spec = importlib.util.spec_from_file_location("_ddes_rosmaster_script", path)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return str(module.MASTER)


#: rospy_tutorials' Python messages are not in Debian's ROS: generate them with genpy.
GENERATE = r'''
import json, signal, subprocess
from genpy.generator import SrvGenerator
_gen = tempfile.mkdtemp(prefix="ddes-gen-")
_out = os.path.join(_gen, "rospy_tutorials", "srv")
os.makedirs(_out)
SrvGenerator().generate_messages("rospy_tutorials", [PACKAGE + "/srv/AddTwoInts.srv"], _out,
                                 {"rospy_tutorials": [PACKAGE + "/msg"],
                                  "std_msgs": ["/usr/share/std_msgs/msg"]})
open(os.path.join(_gen, "rospy_tutorials", "__init__.py"), "w").close()
with open(os.path.join(_out, "__init__.py"), "w") as f:
    f.write("from ._AddTwoInts import *\n")
os.environ["PYTHONPATH"] = _gen

def stop(p):
    p.send_signal(signal.SIGINT)
    out, err = p.communicate(timeout=30)
    return out.splitlines()
'''

ADD_TWO_INTS = r'''
server = start_process([sys.executable, "-u", SCRIPTS + "/add_two_ints_server.py"])
client = subprocess.run([sys.executable, "-u", SCRIPTS + "/add_two_ints_client.py", "3", "4"],
                        capture_output=True, text=True, timeout=60, env=dict(os.environ))
print(json.dumps({"server": stop(server), "client": client.stdout.splitlines(),
                  "code": client.returncode}))
'''

CHATTER = r'''
import threading

def follow(p):
    """Read p's output as it comes (the shared CI machine may start a process slowly)."""
    lines = []
    def read(stream, into):
        for line in stream:
            into.append(line.rstrip("\n"))
    p.readers = [threading.Thread(target=read, args=(stream, into), daemon=True)
                 for stream, into in ((p.stdout, lines), (p.stderr, []))]
    for reader in p.readers:
        reader.start()
    return lines

def stop_followed(p, lines):
    p.send_signal(signal.SIGINT)
    p.wait(timeout=30)
    for reader in p.readers:  # each ends at its stream's end
        reader.join(timeout=30)
    return list(lines)

listener = start_process([sys.executable, "-u", SCRIPTS + "/listener.py"])
heard = follow(listener)
time.sleep(1.0)
talker = start_process([sys.executable, "-u", SCRIPTS + "/talker.py"])
said = follow(talker)
deadline = time.monotonic() + 60
while sum("I heard" in line for line in heard) < 6 and time.monotonic() < deadline:
    time.sleep(0.1)
t = stop_followed(talker, said)
print(json.dumps({"talker": t, "listener": stop_followed(listener, heard)}))
'''


def _reference(ros_python: Callable[..., Any], body: str) -> Any:
    head = f"SCRIPTS = {str(SCRIPTS)!r}\nPACKAGE = {str(PACKAGE)!r}\n"
    return ros_python(_master_script() + head + GENERATE + body, as_json=True, timeout=120)


def _shape(line: str) -> str:
    """A log line with its numbers (times, pids, anonymous suffixes) replaced by N."""
    return re.sub(r"N(_N)+", "N", re.sub(r"\d+(\.\d+)?", "N", line))


def test_add_two_ints_prints_the_same_lines(ros_python: Callable[..., Any]) -> None:
    theirs = _reference(ros_python, ADD_TWO_INTS)
    printed: dict[str, list[str]] = {"server": [], "client": []}
    world = ddes.World()
    run_script(world, SCRIPTS / "add_two_ints_server.py",
               print_line=lambda t, _e: printed["server"].append(t))
    done, _ = run_script(world, SCRIPTS / "add_two_ints_client.py", ["3", "4"],
                         print_line=lambda t, _e: printed["client"].append(t))
    world.run(until=1.0)
    assert theirs["code"] == done.value == 0
    assert theirs["client"] == printed["client"] == ["Requesting 3+4", "3 + 4 = 7"]
    assert theirs["server"] == printed["server"] == ["Ready to add two ints.",
                                                     "Returning [3 + 4 = 7]"]
    example = _example_pair("add_two_ints")  # examples/rospy_scripts.py add_two_ints
    assert example == {"add_two_ints_server.py print": theirs["server"],
                       "add_two_ints_client.py print": theirs["client"]}


def test_talker_and_listener_print_lines_of_the_same_shape(ros_python: Callable[..., Any]
                                                           ) -> None:
    theirs = _reference(ros_python, CHATTER)
    lines: dict[str, list[str]] = {"talker": [], "listener": []}
    world = ddes.World()
    world.log_output = lambda line, _level: lines[
        "listener" if "I heard" in line else "talker"].append(line)
    run_script(world, SCRIPTS / "listener.py")
    run_script(world, SCRIPTS / "talker.py")
    world.run(until=2.0)
    for who in ("talker", "listener"):
        assert len(theirs[who]) >= 5, theirs
        assert {_shape(line) for line in theirs[who]} == {_shape(line) for line in lines[who]}
    # the listener hears what the talker said, in both
    for said, heard in ((theirs["talker"], theirs["listener"]),
                        (lines["talker"], lines["listener"])):
        texts = {line.split("]: ", 1)[1] for line in said}
        assert all(line.split("I heard ", 1)[1] in texts for line in heard)
    example = _example_pair("chatter")  # examples/rospy_scripts.py chatter
    assert set(example) == {"talker.py log", "listener.py log"}
    for who in ("talker", "listener"):  # the example names its nodes (__name:=): no suffix
        assert {_shape(line).replace("/listener_N", "/listener") for line in theirs[who]} == \
            {_shape(line) for line in example[f"{who}.py log"]}


FIBONACCI = r'''
from genpy.generator import MsgGenerator
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
server = start_process([sys.executable, "-u", AL + "/fibonacci_server.py"])
client = subprocess.run([sys.executable, "-u", AL + "/fibonacci_client.py"],
                        capture_output=True, text=True, timeout=90, env=dict(os.environ))
print(json.dumps({"server": stop(server), "client": client.stdout.splitlines(),
                  "code": client.returncode}))
'''


@pytest.mark.slow
def test_the_fibonacci_action_scripts_agree(ros_python: Callable[..., Any],
                                            tmp_path: Path) -> None:
    from ddes.msg import default_registry

    registry = default_registry()
    msgs = tmp_path / "msg"
    msgs.mkdir()
    for full in registry.list_types("actionlib_tutorials", "msg"):
        if full.split("/")[1].startswith("Fibonacci"):
            (msgs / (full.split("/")[1] + ".msg")).write_text(registry.get_msg_spec(full).text)
    # genpy reads the definitions the action messages depend on from these folders, written
    # from ddes's registry (the same text and md5 as upstream's): Debian's definition files
    # (ros-actionlib-msgs, ros-std-msgs) need not be installed, only their Python modules.
    deps = tmp_path / "deps"
    for full in ("actionlib_msgs/GoalID", "actionlib_msgs/GoalStatus", "std_msgs/Header"):
        package, name = full.split("/")
        (deps / package).mkdir(parents=True, exist_ok=True)
        (deps / package / f"{name}.msg").write_text(registry.get_msg_spec(full).text)
    al = SCRIPTS.parents[1] / "actionlib_tutorials" / "scripts"
    head = f"AL = {str(al)!r}\nMSGS = {str(msgs)!r}\nDEPS = {str(deps)!r}\n"
    theirs = _reference(ros_python, head + FIBONACCI)

    lines: list[str] = []
    printed: list[str] = []
    world = ddes.World()
    world.log_output = lambda line, _level: lines.append(line)
    run_script(world, al / "fibonacci_server.py")
    done, _ = run_script(world, al / "fibonacci_client.py",
                         print_line=lambda t, _e: printed.append(t))
    world.run(until=30.0)
    assert theirs["code"] == done.value == 0
    assert theirs["client"] == printed
    assert printed[0].startswith("Result: 0, 1, 1, 2, 3, 5") and printed[0].endswith("6765")
    assert [line.split("]: ", 1)[1] for line in theirs["server"]] == \
        [line.split("]: ", 1)[1] for line in lines]
    example = _example_pair("fibonacci")  # examples/rospy_scripts.py fibonacci
    assert example["fibonacci_client.py print"] == theirs["client"]
    assert [line.split("]: ", 1)[1] for line in example["fibonacci_server.py log"]] == \
        [line.split("]: ", 1)[1] for line in theirs["server"]]


HEADER_SERVER = '''
import json, rospy
from rospy_tutorials.srv import AddTwoInts, AddTwoIntsResponse
def handle(req):
    print(json.dumps(sorted(req._connection_header.items())), flush=True)
    return AddTwoIntsResponse(req.a + req.b)
rospy.init_node("header_server")
rospy.Service("add_two_ints", AddTwoInts, handle)
print("ready", flush=True)
rospy.spin()
'''

HEADER_CLIENT = '''
import json, rospy
from rospy_tutorials.srv import AddTwoInts
rospy.wait_for_service("add_two_ints")
early = rospy.ServiceProxy("add_two_ints", AddTwoInts, headers={"cookies": "peanut butter"})
resp = early(1, 2)  # before init_node: rospy calls as /unnamed
print(resp.sum, json.dumps(sorted(resp._connection_header.items())), flush=True)
rospy.init_node("header_client")
print(early.call(3, 4).sum, flush=True)
'''

HEADERS = r'''
with open(os.path.join(_gen, "server.py"), "w") as f:
    f.write(SERVER)
with open(os.path.join(_gen, "client.py"), "w") as f:
    f.write(CLIENT)
server = start_process([sys.executable, "-u", os.path.join(_gen, "server.py")])
while server.stdout.readline().strip() != "ready":
    pass
client = subprocess.run([sys.executable, "-u", os.path.join(_gen, "client.py")],
                        capture_output=True, text=True, timeout=60, env=dict(os.environ))
print(json.dumps({"server": stop(server), "client": client.stdout.splitlines(),
                  "code": client.returncode, "err": client.stderr}))
'''


def test_service_connection_headers_and_calls_before_init_node_are_rospys(
        ros_python: Callable[..., Any], tmp_path: Path) -> None:
    """A call before init_node goes out as /unnamed; the server's request carries the client's
    header (custom fields included) and the client's response the server's header."""
    body = f"SERVER = {HEADER_SERVER!r}\nCLIENT = {HEADER_CLIENT!r}\n" + HEADERS
    theirs = _reference(ros_python, body)
    assert theirs["code"] == 0, theirs
    (tmp_path / "server.py").write_text(HEADER_SERVER)
    (tmp_path / "client.py").write_text(HEADER_CLIENT)
    printed: dict[str, list[str]] = {"server": [], "client": []}
    world = ddes.World()
    run_script(world, tmp_path / "server.py", print_line=lambda t, _e: printed["server"].append(t))
    done, _ = run_script(world, tmp_path / "client.py",
                         print_line=lambda t, _e: printed["client"].append(t))
    world.run(until=2.0)
    assert done.value == 0
    assert printed["client"] == theirs["client"]
    assert printed["server"][0] == "ready"  # the reference read this line to know the server is up
    assert printed["server"][1:] == theirs["server"]
    assert '["callerid", "/unnamed"]' in theirs["server"][0] and "cookies" in theirs["server"][0]
    assert '["callerid", "/header_client"]' in theirs["server"][1]
