"""rospy behaviour that real code relies on, in ddes as in real rospy (issue 39, item 3).

The scenarios of ``rospy_behaviour_scripts.py`` (sharing one topic's connections among a
node's Publishers and Subscribers, publishing from a shutdown hook, SubscribeListener, custom
connection headers, topic statistics, rospy's texts and reprs, what works before
``init_node``, a script's own modules, ``from pkg.msg import *``, rosgraph) print
:data:`EXPECTED`: what they print under real rospy on a real rosmaster (the test marked
``ros`` checks that), and in ddes as script nodes of one world (the plain test).
"""

from __future__ import annotations

import importlib.util
import json
from collections.abc import Callable
from pathlib import Path
from typing import Any

import pytest

import ddes
from ddes.compat.scripts import run_script

_HERE = Path(__file__).resolve().parent


def _load(path: Path, name: str) -> Any:
    spec = importlib.util.spec_from_file_location(name, path)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


SCENARIOS: dict[str, tuple[dict[str, object], dict[str, str]]] = _load(
    _HERE / "rospy_behaviour_scripts.py", "_ddes_rospy_behaviour_scripts").SCENARIOS


def _started(files: dict[str, str]) -> list[str]:
    """The files a scenario starts (``*_mod.py`` are modules its scripts import)."""
    return [f for f in files if not f.endswith("_mod.py")]


def _shown(out: list[str], err: list[str], folder: str) -> list[str]:
    """What a script printed that both sides print alike: its own lines (not log lines, which
    carry wall-clock times in ROS) and rospy's SyntaxWarning with its source line."""
    lines = [line for line in out if not line.startswith("[")]
    for i, line in enumerate(err):
        if "SyntaxWarning" in line:
            lines.append("stderr: " + line.replace(folder, "DIR"))
            if i + 1 < len(err) and err[i + 1].startswith("  "):
                lines.append("stderr: " + err[i + 1])
    return lines


def run_in_ddes(name: str, folder: Path) -> dict[str, list[str]]:
    params, files = SCENARIOS[name]
    for file, source in files.items():
        (folder / file).write_text(source)
    world = ddes.World(seed=0)
    world.log_output = False
    for key, value in params.items():
        world.params.set_param(key, value)
    printed: dict[str, tuple[list[str], list[str]]] = {}
    for file in _started(files):
        out: list[str] = []
        err: list[str] = []
        printed[file] = (out, err)

        def line(text: str, to_err: bool, _out: list[str] = out, _err: list[str] = err) -> None:
            (_err if to_err else _out).extend(text.split("\n"))

        run_script(world, folder / file, print_line=line)
    world.run(until=60.0)
    return {file: _shown(out, err, str(folder)) for file, (out, err) in printed.items()}


ROS_RUNNER = r'''
import json, shutil
scenarios = json.loads(sys.stdin.read())
master = xmlrpc.client.ServerProxy(MASTER_URI)
results = {}
for name, (params, files, started) in scenarios.items():
    folder = tempfile.mkdtemp(prefix="ddes-behaviour-")
    for file, source in files.items():
        with open(os.path.join(folder, file), "w") as f:
            f.write(source)
    for key, value in params.items():
        master.setParam("/harness", key, value)
    procs = []
    for file in started:
        procs.append((file, start_process([sys.executable, "-u", os.path.join(folder, file)],
                                          cwd=folder)))
        time.sleep(0.3)
    out = {}
    for file, p in procs:
        try:
            o, e = p.communicate(timeout=90)
        except subprocess.TimeoutExpired:
            p.kill()
            o, e = p.communicate()
        out[file] = [o.splitlines(), e.splitlines(), p.returncode, folder]
    for key in params:
        master.deleteParam("/harness", key)
    results[name] = out
print(json.dumps(results))
'''


def run_in_ros(ros_python: Callable[..., Any]) -> dict[str, dict[str, list[str]]]:
    """Every scenario under real rospy: its scripts as processes on one real rosmaster."""
    master = _load(_HERE.parent / "graph" / "rosmaster_script.py", "_ddes_rosmaster_script")
    payload = {name: [params, files, _started(files)]
               for name, (params, files) in SCENARIOS.items()}
    got = ros_python(master.MASTER + ROS_RUNNER, as_json=True, stdin=json.dumps(payload),
                     timeout=900)
    return {name: {file: _shown(out, err, folder) for file, (out, err, _code, folder)
                   in per.items()} for name, per in got.items()}


EXPECTED: dict[str, dict[str, list[str]]] = {
    'shared_publisher': {
        'share_listener.py': [
            'heard 20 of 20',
        ],
        'share_talker.py': [
            'connections of each new publisher [1]',
        ],
    },
    'shared_subscriber': {
        'latch_talker.py': [],
        'latch_listener.py': [
            "second subscriber ['L'] connections 1",
            'wait_for_message L',
            "live ['after'] ['after']",
        ],
    },
    'shutdown_hook': {
        'hook_listener.py': [
            'heard ["I\'m dead now"]',
        ],
        'hook_talker.py': [
            'in the hook: is_shutdown False is_shutdown_requested True',
            'after signal_shutdown: is_shutdown True',
        ],
    },
    'subscribe_listener': {
        'sl_talker.py': [
            'peer_subscribe /announce',
            'peer_unsubscribe /announce 0',
        ],
        'sl_listener.py': [
            "heard ['hello peer', 'hello all']",
        ],
    },
    'connection_headers': {
        'hdr_talker.py': [],
        'hdr_listener.py': [
            "header keys ['callerid', 'cookies', 'latching', 'md5sum', 'message_definition', "
            "'topic', 'type']",
            'cookies yum callerid /cookie_jar latching 1',
        ],
    },
    'statistics': {
        'stats_listener.py': [
            'b report /measured /measurer delivered 1 dropped 0 traffic 1146 window True',
            'b report /measured /measurer delivered 1 dropped 0 traffic 47 window False',
            "a reports True [('/measured', '/measurer')] traffic per message [11]",
        ],
        'stats_talker.py': [],
    },
    'texts': {
        'texts.py': [
            'has_param missing -> False',
            "get_param missing raises KeyError  '~missing'",
            "get_param missing global raises KeyError  '/missing'",
            'delete_param -> None',
            "delete_param again raises KeyError  '~x'",
            'handler error raises ServiceException ServiceException service [/boom] responded with '
            "an error: b'error processing request: boom happened'",
            'handler None raises ServiceException ServiceException service [/none] responded with '
            "an error: b'service cannot process request: service handler returned None'",
            'bad response is a ServiceException: True',
            'bad request is a ServiceException: False',
            'unavailable raises ServiceException ServiceException service [/nosuch] unavailable',
            'repr rospy.Time[1000000005] rospy.Duration[2000000003] rospy.Time[0] '
            'rospy.Duration[-999999995] 1000000005',
            'repr arithmetic genpy.Duration[2000000000] rospy.Time[4000000000] '
            'rospy.Duration[2000000000] rospy.Duration[1500000000] rospy.Time[2500000000]',
            'now Time rospy.Time[',
            'wait_for_message raises ROSException  timeout exceeded while waiting for message on '
            'topic chatter',
            'wait_for_message private raises ROSException  timeout exceeded while waiting for '
            'message on topic ~chat',
            'rosout from a method function Talker.go file texts.py',
            'rosout from a static method function static file texts.py',
            'rosout from a function function func file texts.py',
            'rosout from the module function <module> file texts.py',
            'stderr: DIR/texts.py:7: SyntaxWarning: The publisher should be created with an '
            "explicit keyword argument 'queue_size'. Please see "
            'http://wiki.ros.org/rospy/Overview/Publishers%20and%20Subscribers for more '
            'information.',
            'stderr:   pub0 = rospy.Publisher("early", String)',
        ],
    },
    'before_init': {
        'before_init.py': [
            'name before init_node /unnamed /',
            'get_param 5 default',
            'has_param True False',
            "KeyError '/nothing_here'",
            'wait_for_service: timeout exceeded while waiting for service /no_such_service',
            'get_time: True',
            'calls 1 name /late_starter',
            'hook from before init_node',
        ],
    },
    'modules': {
        'helper_user.py': [
            'script folder first on sys.path True',
            'helper the helper runs in /module_user',
            "star std_msgs ['Bool', 'Byte', 'ByteMultiArray', 'Char', 'ColorRGBA', 'Duration', "
            "'Float32', 'Float32MultiArray', 'Float64', 'Float64MultiArray', 'Header', 'Int16', "
            "'Int16MultiArray', 'Int32', 'Int32MultiArray', 'Int64', 'Int64MultiArray', 'Int8', "
            "'Int8MultiArray', 'MultiArrayDimension', 'MultiArrayLayout', 'String', 'Time', "
            "'UInt16', 'UInt16MultiArray', 'UInt32', 'UInt32MultiArray', 'UInt64', "
            "'UInt64MultiArray', 'UInt8', 'UInt8MultiArray']",
            "star std_srvs ['Empty', 'EmptyRequest', 'EmptyResponse', 'SetBool', 'SetBoolRequest', "
            "'SetBoolResponse', 'Trigger', 'TriggerRequest', 'TriggerResponse']",
            "system state [['/modules_topic', ['/module_user']]]",
            "topic types [['/modules_topic', 'std_msgs/String']]",
            'lookupNode: unknown node [/no_such_node]',
            'getParam: Parameter [/no_such_param] is not set',
            'names /a/b a/b /a/b /module_user',
        ],
    },
}


@pytest.mark.parametrize("name", list(SCENARIOS))
def test_the_scenario_prints_what_rospy_prints(name: str, tmp_path: Path) -> None:
    assert run_in_ddes(name, tmp_path) == EXPECTED[name]


@pytest.mark.ros
def test_real_rospy_prints_the_same(ros_python: Callable[..., Any]) -> None:
    assert run_in_ros(ros_python) == EXPECTED
