"""A tf2_ros.Buffer of its own (no node): ``set_transform`` returns None and tf2's warnings
reach standard error in console_bridge's words, as with Noetic's tf2_ros (tf2_py 0.7.6), whose
process registers no console_bridge handler.

``STEPS`` runs the same insertions and queries on ddes's Buffer (yield style, and tf2_ros's in a
rospy script) and, in the test marked ``ros``, on the real one; ``NOETIC`` is what the real one
wrote to stderr, frozen.
"""

from __future__ import annotations

import json
import textwrap
from collections.abc import Callable
from pathlib import Path
from typing import Any

import pytest

import ddes
from ddes.compat.scripts import run_script
from ddes.msg import get_message_class
from ddes.tf2_ros import Buffer
from ddes.time.rostime import Time

#: Python run on either Buffer: ``b``, ``T`` (TransformStamped), ``Time`` and ``mark`` given.
STEPS = """
def t(parent="map", child="base", secs=1.0, q=(0, 0, 0, 1), x=0.0):
    m = T()
    m.header.frame_id = parent
    m.header.stamp = Time.from_sec(secs)
    m.child_frame_id = child
    m.transform.translation.x = x
    r = m.transform.rotation
    r.x, r.y, r.z, r.w = q
    return m

got = []
for name, call in [
        ("ok", lambda: b.set_transform(t(), "auth")),
        ("repeated", lambda: b.set_transform(t(), "auth")),
        ("newer", lambda: b.set_transform(t(secs=100.0), "a2")),
        ("old", lambda: b.set_transform(t(secs=1.0), "a3")),
        ("self", lambda: b.set_transform(t(parent="base", child="base"), "auth")),
        ("no child", lambda: b.set_transform(t(child=""), "auth")),
        ("no frame", lambda: b.set_transform(t(parent=""), "auth")),
        ("nan", lambda: b.set_transform(t(x=float("nan"), secs=200), "auth")),
        ("quaternion", lambda: b.set_transform(t(q=(0, 0, 0, 2), secs=201), "auth")),
        ("static", lambda: b.set_transform_static(t(child="laser"), "auth")),
        ("static zero", lambda: b.set_transform_static(t(child="laser", q=(0, 0, 0, 0)), "s")),
        ("slashes", lambda: b.set_transform(t(parent="/map", child="/odom", secs=300), "auth")),
        ("can slash", lambda: bool(b.can_transform("/map", "base", Time(0)))),
        ("can empty", lambda: bool(b.can_transform("map", "", Time(0)))),
        ("can full", lambda: bool(b.can_transform_full("map", Time(0), "/b", Time(0), ""))),
]:
    mark(name)
    got.append([name, call()])
"""

NOETIC = """\
=== ok
=== repeated
Warning: TF_REPEATED_DATA ignoring data with redundant timestamp for frame base at time 1.000000 according to authority auth
         at line 278 in ./tf2/src/buffer_core.cpp
=== newer
=== old
Warning: TF_OLD_DATA ignoring data from the past (Possible reasons are listed at http://wiki.ros.org/tf/Errors%20explained) for frame base at time 1.000000 according to authority a3
         at line 278 in ./tf2/src/buffer_core.cpp
=== self
Error:   TF_SELF_TRANSFORM: Ignoring transform from authority "auth" with frame_id and child_frame_id  "base" because they are the same
         at line 221 in ./tf2/src/buffer_core.cpp
=== no child
Error:   TF_NO_CHILD_FRAME_ID: Ignoring transform from authority "auth" because child_frame_id not set 
         at line 227 in ./tf2/src/buffer_core.cpp
=== no frame
Error:   TF_NO_FRAME_ID: Ignoring transform with child_frame_id "base"  from authority "auth" because frame_id not set
         at line 233 in ./tf2/src/buffer_core.cpp
=== nan
Error:   TF_NAN_INPUT: Ignoring transform for child_frame_id "base" from authority "auth" because of a nan value in the transform (nan 0.000000 0.000000) (0.000000 0.000000 0.000000 1.000000)
         at line 240 in ./tf2/src/buffer_core.cpp
=== quaternion
Error:   TF_DENORMALIZED_QUATERNION: Ignoring transform for child_frame_id "base" from authority "auth" because of an invalid quaternion in the transform (0.000000 0.000000 0.000000 2.000000)
         at line 255 in ./tf2/src/buffer_core.cpp
=== static
=== static zero
Error:   TF_DENORMALIZED_QUATERNION: Ignoring transform for child_frame_id "laser" from authority "s" because of an invalid quaternion in the transform (0.000000 0.000000 0.000000 0.000000)
         at line 255 in ./tf2/src/buffer_core.cpp
=== slashes
=== can slash
Warning: Invalid argument "/map" passed to canTransform argument target_frame in tf2 frame_ids cannot start with a '/' like: 
         at line 134 in ./tf2/src/buffer_core.cpp
=== can empty
Warning: Invalid argument passed to canTransform argument source_frame in tf2 frame_ids cannot be empty
         at line 126 in ./tf2/src/buffer_core.cpp
=== can full
Warning: Invalid argument "/b" passed to canTransform argument source_frame in tf2 frame_ids cannot start with a '/' like: 
         at line 134 in ./tf2/src/buffer_core.cpp
"""  # noqa: E501, W291 - tf2's lines as they are (one ends in a space)

#: What each step returns: set_transform None, as tf2_ros's; the queries False.
RESULTS = [[name, None] for name in (
    "ok", "repeated", "newer", "old", "self", "no child", "no frame", "nan", "quaternion",
    "static", "static zero", "slashes")] + [["can slash", False], ["can empty", False],
                                           ["can full", False]]


def test_a_buffer_without_a_node_writes_what_tf2_ros_writes(
        capsys: pytest.CaptureFixture[str]) -> None:
    import sys

    scope: dict[str, Any] = {
        "b": Buffer(), "T": get_message_class("geometry_msgs/TransformStamped"), "Time": Time,
        "mark": lambda name: sys.stderr.write(f"=== {name}\n")}
    exec(STEPS, scope)  # noqa: S102 - the steps above
    assert capsys.readouterr().err == NOETIC
    assert scope["got"] == RESULTS


def test_tf2_ros_buffer_in_a_script_before_init_node(tmp_path: Path) -> None:
    script = tmp_path / "standalone.py"
    script.write_text(textwrap.dedent("""
        import json
        import sys
        import rospy
        import tf2_ros
        from geometry_msgs.msg import TransformStamped as T
        from rospy import Time
        b = tf2_ros.Buffer(debug=False)

        def mark(name):
            print("=== " + name, file=sys.stderr)
    """) + STEPS + "\nprint(json.dumps(got))\n")
    out: list[str] = []
    err: list[str] = []
    world = ddes.World()
    run_script(world, script, print_line=lambda text, to_err: (err if to_err else out).append(text))
    world.run(until=1.0)
    assert "\n".join(err) + "\n" == NOETIC
    assert json.loads(out[-1]) == RESULTS


@pytest.mark.ros
def test_noetics_tf2_ros_writes_these_lines(ros_python: Callable[..., Any]) -> None:
    real = ros_python(textwrap.dedent("""
        import ctypes, json, os, sys, tempfile
        import rospy, tf2_ros
        from geometry_msgs.msg import TransformStamped as T
        from rospy import Time
        libc = ctypes.CDLL(None)
        log = tempfile.TemporaryFile()
        saved = os.dup(2)
        os.dup2(log.fileno(), 2)  # console_bridge writes to the C stderr

        def mark(name):
            libc.fflush(None)
            os.write(2, ("=== %s\\n" % name).encode())

        b = tf2_ros.Buffer(debug=False)
    """) + STEPS + textwrap.dedent("""
        libc.fflush(None)
        os.dup2(saved, 2)
        log.seek(0)
        print(json.dumps({"stderr": log.read().decode(), "got": got}))
    """), as_json=True)
    assert real["stderr"] == NOETIC
    assert [[n, bool(v) if n.startswith("can") else v] for n, v in real["got"]] == RESULTS
