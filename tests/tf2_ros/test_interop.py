"""tf_echo and static_transform_publisher: ddes prints what the real programs print.

The real side runs Debian's ``/usr/lib/tf2_ros/static_transform_publisher`` (both argument
forms) and ``/usr/lib/tf/tf_echo`` on a real rosmaster; ddes runs the same command lines in its
console.  The blocks tf_echo prints for the same static transforms are identical (failure blocks
too, but for the wall-clock time of ``Failure at``).
"""

from __future__ import annotations

import importlib.util
import os
from collections.abc import Callable
from pathlib import Path
from typing import Any

import pytest

from ddes.console.shell import Console

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

