"""turtle_tf2's official Python broadcaster and listener (ros/geometry_tutorials) on ddes and ROS.

Issue 39: "turtle_tf2's official Python broadcaster never moves the second turtle".  Its
``handle_turtle_pose`` makes a new ``tf2_ros.TransformBroadcaster()`` (a new ``/tf``
Publisher) for every pose, and rospy delivers what it sends at once, because the node's
connections on ``/tf`` are per topic, not per Publisher (docs/rospy.md).  ddes bundles neither
turtlesim nor turtle_tf2 and ../shared/upstream has no geometry_tutorials, so the scripts are
here (tests/upstream/turtle/turtle_tf2/nodes/*.py.upstream: the official files, unchanged) with
the demo launch file (less its keyboard node) and a windowless turtlesim stand-in
(turtle/turtlesim: its Pose and Spawn definitions and a ``turtlesim_node`` moving the turtles
as turtlesim does).  The listener spawns turtle2 at (4, 2) and steers it to turtle1, which
stays in the middle: turtle2 must get there, on ddes and under real roslaunch.
"""

from __future__ import annotations

import json
import math
from collections.abc import Callable
from pathlib import Path
from typing import Any

import pytest

import ddes
from ddes.compat.scripts import run_script
from ddes.msg import get_message_class

from .harness import checkout, master_script, parts, run_on_ddes, run_real

HERE = Path(__file__).resolve().parent
TURTLE = HERE / "turtle"
POSES = HERE / "probes" / "turtle_poses.py"
MIDDLE = round(11.088889 / 2, 4)


def _workspace(root: Path) -> Path:
    return checkout([TURTLE / "turtlesim", TURTLE / "turtle_tf2"], root)


def _distances(samples: list[list[float]]) -> list[float]:
    return [math.hypot(x1 - x2, y1 - y2) for x1, y1, x2, y2, _theta in samples]


def _check_follows(samples: list[list[float]]) -> None:
    """turtle1 stays in the middle; turtle2 leaves (4, 2) and closes in on it all the way."""
    assert len(samples) >= 8, samples
    assert all(s[:2] == [MIDDLE, MIDDLE] for s in samples)
    start = math.hypot(MIDDLE - 4, MIDDLE - 2)
    distances = _distances(samples)
    assert distances[0] < start
    assert all(b < a for a, b in zip(distances, distances[1:])), distances
    assert distances[-1] < 0.25 * start
    x1, y1, x2, y2, theta = samples[-1]  # turtle2 has turned to face turtle1
    assert abs(theta - math.atan2(y1 - y2, x1 - x2)) < 0.05


def test_the_second_turtle_follows_the_first_on_ddes(tmp_path: Path) -> None:
    src = _workspace(tmp_path)
    run = run_on_ddes(["turtle_tf2", "turtle_tf2_demo.launch"], 6.0, path=[src],
                      probes=[(0.0, POSES)])
    got = parts(run.out)
    assert got.started == ["master", "rosout-1", "sim-2", "turtle1_tf2_broadcaster-3",
                           "turtle2_tf2_broadcaster-4", "turtle_pointer-5"]
    assert got.nodes == [
        "[INFO] [0.000000]: Starting turtlesim with node name /sim",
        "[INFO] [0.000000]: Spawning turtle [turtle1] at x=[5.544444], y=[5.544444], "
        "theta=[0.000000]",
        "[INFO] [0.000300]: Spawning turtle [turtle2] at x=[4.000000], y=[2.000000], "
        "theta=[0.000000]",
    ]
    samples = [json.loads(line) for line in run.probes["turtle_poses.py"]]
    _check_follows(samples)
    assert samples[0] == [MIDDLE, MIDDLE, 4.542, 2.4433, 1.0668]  # at 0.5 s, every run
    again = run_on_ddes(["turtle_tf2", "turtle_tf2_demo.launch"], 6.0, path=[src],
                        probes=[(0.0, POSES)])
    assert again.probes == run.probes and again.world.digest() == run.world.digest()


def test_a_broadcaster_per_pose_loses_no_transform(tmp_path: Path) -> None:
    """Every pose the official broadcaster hears goes out on /tf, each from its own new
    TransformBroadcaster, and arrives with the pose's values: all but the first, sent as the
    node's first /tf Publisher is made, before any subscriber is connected to it (as in
    rospy, whose later Publishers of the topic share that first one's connections)."""
    src = _workspace(tmp_path)
    world = ddes.World(package_path=[str(src)])
    run_script(world, src / "turtle_tf2" / "nodes" / "turtle_tf2_broadcaster.py",
               ["_turtle:=turtle1"])
    pose_type = get_message_class("turtlesim/Pose", registry=world.messages)
    heard: list[Any] = []
    watcher = world.create_node("watcher")
    ddes.Subscriber(watcher, "/tf", get_message_class("tf2_msgs/TFMessage"),
                    lambda msg: heard.extend(msg.transforms))
    driver = world.create_node("driver")
    pub = ddes.Publisher(driver, "/turtle1/pose", pose_type, queue_size=10)
    sent: list[float] = []

    def drive() -> Any:
        yield driver.sleep(0.5)  # the broadcaster's subscription is connected by then
        for i in range(20):
            sent.append(0.1 * i)
            pub.publish(pose_type(x=1.0 + 0.1 * i, y=2.0, theta=0.5))
            yield driver.sleep(0.05)

    driver.process(drive())
    world.run(until=2.0)
    assert len(sent) == 20 and len(heard) == 19
    assert [round(t.transform.translation.x, 5) for t in heard] == \
        [round(1.0 + 0.1 * i, 5) for i in range(1, 20)]
    assert {(t.header.frame_id, t.child_frame_id) for t in heard} == {("world", "turtle1")}
    assert math.isclose(heard[0].transform.rotation.z, math.sin(0.25), rel_tol=1e-6)


@pytest.mark.ros
def test_the_second_turtle_follows_the_first_under_roslaunch(ros_python: Callable[..., Any],
                                                             tmp_path: Path) -> None:
    src = _workspace(tmp_path / "real")
    theirs = run_real(ros_python, tmp_path / "work", src, ["turtle_tf2", "turtle_tf2_demo.launch"],
                      until=[(r"Spawning turtle \[turtle2\]", 1)], probes=[POSES],
                      generate=["turtlesim"], limit=14.0)
    assert theirs["met"], "\n".join(theirs["lines"])
    samples = [json.loads(line) for line in theirs["probes"]["turtle_poses.py"]]
    _check_follows(samples)
    ours = parts(run_on_ddes(["turtle_tf2", "turtle_tf2_demo.launch"], 1.0,
                             path=[_workspace(tmp_path / "ddes")]).out)
    real = parts(theirs["lines"])
    assert ours.summary == real.summary and ours.started == real.started


REAL_BROADCASTS = r'''
import json, os, signal, subprocess, tempfile
from genpy.generator import MsgGenerator
gen = tempfile.mkdtemp(prefix="ddes-gen-")
out = os.path.join(gen, "turtlesim", "msg")
os.makedirs(out)
MsgGenerator().generate_messages("turtlesim", [MSG + "/Pose.msg"], out, {"turtlesim": [MSG]})
with open(os.path.join(out, "__init__.py"), "w") as f:
    f.write("from ._Pose import *\n")
open(os.path.join(gen, "turtlesim", "__init__.py"), "w").close()
os.environ["PYTHONPATH"] = gen
broadcaster = start_process([sys.executable, "-u", BROADCASTER, "_turtle:=turtle1"])
driver = subprocess.run([sys.executable, "-u", "-c", DRIVER], capture_output=True, text=True,
                        env=dict(os.environ), timeout=60)
broadcaster.send_signal(signal.SIGINT)
broadcaster.communicate(timeout=30)
print(json.dumps({"heard": driver.stdout.split(), "err": driver.stderr}))
'''

DRIVER = r'''
import rospy, time
from tf2_msgs.msg import TFMessage
from turtlesim.msg import Pose
heard = []
rospy.init_node("driver")
rospy.Subscriber("/tf", TFMessage, lambda m: heard.extend(t.transform.translation.x
                                                          for t in m.transforms))
pub = rospy.Publisher("/turtle1/pose", Pose, queue_size=10)
while pub.get_num_connections() < 1:
    time.sleep(0.05)
time.sleep(0.5)
for i in range(20):
    pub.publish(Pose(x=1.0 + 0.1 * i, y=2.0, theta=0.5))
    time.sleep(0.05)
time.sleep(1.0)
print(" ".join("%.3f" % x for x in heard))
'''


@pytest.mark.ros
def test_a_broadcaster_per_pose_loses_only_the_first_transforms_in_rospy(
        ros_python: Callable[..., Any], tmp_path: Path) -> None:
    """In rospy too only the transforms sent before the driver is connected to the node's
    first /tf Publisher are lost (a few, on the wall clock); every later one arrives."""
    src = _workspace(tmp_path)
    head = "".join(f"{k} = {v!r}\n" for k, v in {
        "MSG": str(src / "turtlesim" / "msg"), "DRIVER": DRIVER,
        "BROADCASTER": str(src / "turtle_tf2" / "nodes" / "turtle_tf2_broadcaster.py")}.items())
    theirs = ros_python(master_script() + head + REAL_BROADCASTS, as_json=True, timeout=120)
    sent = [f"{1.0 + 0.1 * i:.3f}" for i in range(20)]
    heard = theirs["heard"]
    assert 10 <= len(heard) < 20, theirs
    assert heard == sent[20 - len(heard):]  # the first ones lost, then every one
