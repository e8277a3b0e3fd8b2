"""tf2's warnings and errors (TF_OLD_DATA, TF_REPEATED_DATA, TF_SELF_TRANSFORM...) from a Buffer
that belongs to a node go to that node's log: /rosout at the simulated instant and its console
line; a Buffer without a node writes them to standard error as tf2_ros does (console_bridge's
words, tests/tf2_ros/test_standalone_buffer.py), a BufferCore logs them to the ``ddes.tf2``
logger."""

from __future__ import annotations

import logging
from typing import Any

import pytest

import ddes
from ddes.msg import get_message_class
from ddes.tf2 import BufferCore
from ddes.tf2_ros import Buffer, TransformBroadcaster, TransformListener
from ddes.time.rostime import Time

TransformStamped = get_message_class("geometry_msgs/TransformStamped")
Log = get_message_class("rosgraph_msgs/Log")

OLD = ("TF_OLD_DATA ignoring data from the past (Possible reasons are listed at "
       "http://wiki.ros.org/tf/Errors%20explained) for frame base_link at time 1.000000 "
       "according to authority /robot")


def stamped(parent: str, child: str, stamp: Any, w: float = 1.0) -> Any:
    ts = TransformStamped()
    ts.header.stamp = stamp
    ts.header.frame_id = parent
    ts.child_frame_id = child
    ts.transform.rotation.w = w
    return ts


def _world(style: str = "rospy") -> tuple[Any, list[Any]]:
    world = ddes.World()
    robot = world.create_node("robot")
    listener = world.create_node("listener", log_style=style)
    buf = Buffer()
    TransformListener(listener, buf)
    br = TransformBroadcaster(robot)
    seen: list[Any] = []
    watcher = world.create_node("watcher")
    ddes.Subscriber(watcher, "/rosout", Log, seen.append)

    def send() -> Any:
        yield robot.sleep(1.0)
        br.sendTransform(stamped("odom", "base_link", Time(12)))   # new data at 1 s
        yield robot.sleep(1.0)
        br.sendTransform(stamped("odom", "base_link", Time(1)))    # 11 s older: TF_OLD_DATA
        yield robot.sleep(0.5)
        br.sendTransform(stamped("odom", "base_link", Time(12)))   # TF_REPEATED_DATA
        br.sendTransform(stamped("odom", "odom", Time(13)))        # TF_SELF_TRANSFORM
        br.sendTransform(stamped("odom", "base_link", Time(13), 2.0))  # denormalised

    robot.process(send())
    return world, seen


def test_a_listener_logs_old_data_on_rosout_at_the_instant_it_arrives(
        capsys: pytest.CaptureFixture[str]) -> None:
    world, seen = _world()
    world.run(until=3)
    lines = [(m.header.stamp, m.name, m.level, m.msg) for m in seen if m.name == "/listener"]
    assert lines == [
        (Time(2), "/listener", Log.WARN, OLD),
        (Time(2, 500_000_000), "/listener", Log.WARN,
         "TF_REPEATED_DATA ignoring data with redundant timestamp for frame base_link at time "
         "12.000000 according to authority /robot"),
        (Time(2, 500_000_000), "/listener", Log.ERROR,
         'TF_SELF_TRANSFORM: Ignoring transform from authority "/robot" with frame_id and '
         'child_frame_id  "odom" because they are the same'),
        (Time(2, 500_000_000), "/listener", Log.ERROR,
         'TF_DENORMALIZED_QUATERNION: Ignoring transform for child_frame_id "base_link" from '
         'authority "/robot" because of an invalid quaternion in the transform '
         "(0.000000 0.000000 0.000000 2.000000)"),
    ]
    first = next(m for m in seen if m.msg == OLD)
    assert first.file == "buffer_core.py"        # the line tf2 logs it from, as buffer_core.cpp
    assert first.function == "_set_transform"
    err = capsys.readouterr().err
    assert f"[WARN] [2.000000]: {OLD}" in err   # rospy's console line


def test_a_roscpp_listener_prints_rosconsoles_line() -> None:
    world, _seen = _world("roscpp")
    printed: list[tuple[str, int]] = []
    world.log_output = lambda line, level: printed.append((line, level))
    world.run(until=2.1)
    assert printed == [(f"[ WARN] [2.000000000]: {OLD}", 4)]


def test_a_buffer_core_logs_to_ddes_tf2(caplog: pytest.LogCaptureFixture) -> None:
    buf = BufferCore()
    with caplog.at_level(logging.WARNING, logger="ddes.tf2"):
        buf.set_transform(stamped("odom", "base_link", Time(12)), "/robot")
        buf.set_transform(stamped("odom", "base_link", Time(1)), "/robot")
    assert caplog.messages == [OLD]
    assert caplog.records[0].name == "ddes.tf2"


def test_a_buffer_without_a_node_writes_console_bridges_lines_to_stderr(
        caplog: pytest.LogCaptureFixture, capsys: pytest.CaptureFixture[str]) -> None:
    buf = Buffer()
    with caplog.at_level(logging.WARNING, logger="ddes.tf2"):
        buf.set_transform(stamped("odom", "base_link", Time(12)), "/robot")
        buf.set_transform(stamped("odom", "base_link", Time(1)), "/robot")
    assert caplog.messages == []
    assert capsys.readouterr().err == (
        f"Warning: {OLD}\n         at line 278 in ./tf2/src/buffer_core.cpp\n")


def test_the_log_hook_can_be_overridden() -> None:
    class Collecting(BufferCore):
        def __init__(self) -> None:
            super().__init__()
            self.lines: list[tuple[int, str]] = []

        def _log(self, level: int, text: str) -> None:
            self.lines.append((level, text))

    core = Collecting()
    core.set_transform(stamped("a", "a", Time(1)), "me")
    assert core.can_transform_core("", "a", Time(0)) == (False, "")
    assert core.lines == [
        (logging.ERROR, 'TF_SELF_TRANSFORM: Ignoring transform from authority "me" with '
                        'frame_id and child_frame_id  "a" because they are the same'),
        (logging.WARNING, "Invalid argument passed to canTransform argument target_frame in tf2 "
                          "frame_ids cannot be empty"),
    ]
