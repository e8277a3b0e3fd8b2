"""tf_echo and static_transform_publisher: ddes prints what the real programs print.

The real side runs Debian's ``/usr/lib/tf2_ros/static_transform_publisher`` (both argument
forms) and ``/usr/lib/tf/tf_echo`` on a real rosmaster; ddes runs the same command lines in its
console.  The blocks tf_echo prints for the same static transforms are identical (failure blocks
too, but for the wall-clock time of ``Failure at``), and the transforms both forms of tf2_ros's
program and tf1's periodic one publish are the same bits.
"""

from __future__ import annotations

import importlib.util
import os
from collections.abc import Callable
from pathlib import Path
from typing import Any

import pytest

import ddes
from ddes.console.shell import Console
from ddes.msg import get_message_class
from ddes.nodes import start_node

pytestmark = pytest.mark.ros

STATIC = [
    "1 2 3 0.5 0.2 -0.1 base laser",                      # yaw pitch roll
    "0.1 -0.2 0.3 0 0 0.70710678 -0.70710678 laser cam",   # qx qy qz qw, w < 0
    "0 0 0.5 3.0 -1.4 2.5 cam tool",                        # large angles
    "-1 0 0 0 1.5707963 0 base up",                          # pitch near pi/2
]
ECHO = [("base", "laser"), ("laser", "base"), ("base", "cam"), ("tool", "base"),
        ("up", "tool"), ("base", "nope")]

REAL = r'''
import time
pubs = [start_process(["/usr/lib/tf2_ros/static_transform_publisher"] + a.split())
        for a in ARGS]
time.sleep(1.5)
out = {}
for src, tgt in ECHO:
    p = start_process(["/usr/lib/tf/tf_echo", src, tgt])
    time.sleep(1.6)
    p.send_signal(2)
    o, e = p.communicate(timeout=20)
    out[src + " " + tgt] = o.splitlines()
usage = subprocess.run(["/usr/lib/tf2_ros/static_transform_publisher"], capture_output=True,
                       text=True, env=dict(os.environ), timeout=20)
out["usage"] = usage.stdout.splitlines() + [str(usage.returncode)]
print(json.dumps(out))
'''


def _master_script() -> str:
    path = Path(__file__).resolve().parents[1] / "graph" / "rosmaster_script.py"
    spec = importlib.util.spec_from_file_location("_ddes_rosmaster_script_tf", path)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return str(module.MASTER)


def _first_block(lines: list[str]) -> list[str]:
    """The first block tf_echo printed: 5 lines, or a failure's lines without its time, the
    frames sorted (tf2 lists them in the order they arrived, which the real run does not fix)."""
    if lines and lines[0].startswith("Failure at "):
        end = lines.index("", 1)
        return lines[1:3] + sorted(lines[3:end])
    return lines[:5]


def test_tf_echo_prints_what_the_real_one_prints(ros_python: Callable[..., Any]) -> None:
    if not (os.path.exists("/usr/lib/tf/tf_echo")
            and os.path.exists("/usr/lib/tf2_ros/static_transform_publisher")):
        pytest.skip("real tf/tf2_ros programs are not installed (bash .ci/install-ros)")
    body = f"ARGS = {STATIC!r}\nECHO = {ECHO!r}\nimport json\n" + REAL
    theirs = ros_python(_master_script() + body, as_json=True, timeout=180)
    console = Console(seed=0)
    for i, args in enumerate(STATIC):
        console.run(f"rosrun tf2_ros static_transform_publisher {args} &")
        assert f"[{i + 1}]" in console.run("jobs")
    console.run("sleep 0.1")
    job = len(STATIC)
    for src, tgt in ECHO:
        job += 1
        console.run(f"rosrun tf tf_echo {src} {tgt} &")
        ours = console.run("sleep 1.2").splitlines()
        console.run(f"kill %{job}")
        assert _first_block(ours) == _first_block(theirs[f"{src} {tgt}"]), (src, tgt)
        assert _first_block(ours), (src, tgt)
    usage = console.execute("rosrun tf2_ros static_transform_publisher")
    ours_usage = [x for x in usage.out.splitlines() if not x.startswith("[ERROR]")]
    assert ours_usage == theirs["usage"][:-1]
    assert usage.code == int(theirs["usage"][-1]) == 255



PUBLISHED = r'''
import time
import rospy
from tf2_msgs.msg import TFMessage
pubs = [start_process(["/usr/lib/tf2_ros/static_transform_publisher"] + a.split()) for a in ARGS]
tf1 = start_process(["/usr/lib/tf/static_transform_publisher"] + TF1.split())
rospy.init_node("probe")
got = {}
def keep(msg):
    for t in msg.transforms:
        r, v = t.transform.rotation, t.transform.translation
        got[t.child_frame_id] = [t.header.frame_id, v.x, v.y, v.z, r.x, r.y, r.z, r.w]
static = rospy.Subscriber("/tf_static", TFMessage, keep)
m = rospy.wait_for_message("/tf", TFMessage, timeout=30)
now = rospy.Time.now()
keep(m)
future = (m.transforms[0].header.stamp - now).to_sec()
deadline = time.time() + 30
while len(got) < len(ARGS) + 1 and time.time() < deadline:
    time.sleep(0.05)
print(json.dumps({"got": got, "future": future}))
'''
TF1 = "0.5 -1 2 -2.5 0.7 3.1 odom base 100"


def test_static_transform_publishers_send_the_same_bits(ros_python: Callable[..., Any]) -> None:
    """Both tf2_ros forms and tf1's: the same frames, translation and quaternion, bit for bit."""
    if not (os.path.exists("/usr/lib/tf/static_transform_publisher")
            and os.path.exists("/usr/lib/tf2_ros/static_transform_publisher")):
        pytest.skip("real tf/tf2_ros programs are not installed (bash .ci/install-ros)")
    body = f"ARGS = {STATIC!r}\nTF1 = {TF1!r}\nimport json\n" + PUBLISHED
    theirs = ros_python(_master_script() + body, as_json=True, timeout=180)
    world = ddes.World()
    got: dict[str, list[Any]] = {}

    def keep(msg: Any) -> None:
        for t in msg.transforms:
            r, v = t.transform.rotation, t.transform.translation
            got[t.child_frame_id] = [t.header.frame_id, v.x, v.y, v.z, r.x, r.y, r.z, r.w]

    probe = world.create_node("probe")
    tf_message = get_message_class("tf2_msgs/TFMessage")
    ddes.Subscriber(probe, "/tf_static", tf_message, keep)
    ddes.Subscriber(probe, "/tf", tf_message, keep)
    world.run(until=0.01)
    for args in STATIC:
        start_node(world, "tf2_ros", "static_transform_publisher", argv=args.split())
    start_node(world, "tf", "static_transform_publisher", argv=TF1.split())
    world.run(until=0.5)
    assert got == theirs["got"]
    assert abs(theirs["future"] - 0.1) < 0.05  # stamped a period ahead there too
