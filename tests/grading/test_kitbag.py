"""The localisation exercise's kit bag (``ddes course make-bag``): the course bag's four topics
and types plus /scan, stamped from 1612345678 s, the same bytes on every run; the EKF of a
bag-playing launch (use_sim_time, --clock, robot_frames) follows the simulator's truth."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import pytest

import ddes
from ddes.cli.main import main
from ddes.grading.kitbag import STAMP_OFFSET, TOPICS, drive_script, make_bag, plot_localization
from ddes.msg import get_message_class
from ddes.rosbag import Bag
from ddes.tf2_ros import Buffer, TransformListener
from ddes.time import Time

from ..docsnippets import python_blocks, run_snippet


@pytest.fixture(scope="module")
def kit(tmp_path_factory: pytest.TempPathFactory) -> Any:
    return make_bag(tmp_path_factory.mktemp("kit") / "smb_navigation.bag")


def test_topics_types_and_stamps(kit: Any) -> None:
    with Bag(str(kit.path)) as bag:
        info = bag.get_type_and_topic_info()
        assert {t: i.msg_type for t, i in info.topics.items()} == TOPICS
        assert bag.get_start_time() >= STAMP_OFFSET
        assert bag.get_end_time() <= STAMP_OFFSET + 38.0
        for _topic, raw, t in bag.read_messages(topics=["/smb_velocity_controller/odom"]):
            msg: Any = raw
            assert msg.header.stamp == t and msg.child_frame_id == "base_link"
    assert kit.counts == {"/imu/data": 760, "/joint_states": 380, "/rslidar_points": 380,
                          "/scan": 380, "/smb_velocity_controller/odom": 380}
    assert sum(seconds for seconds, _v, _w in drive_script(2021)) == pytest.approx(38.0)


def test_same_seed_same_bytes_other_seed_other_drive(kit: Any, tmp_path: Path) -> None:
    assert main(["course", "make-bag", str(tmp_path / "again.bag")]) == 0
    assert (tmp_path / "again.bag").read_bytes() == kit.path.read_bytes()
    other = make_bag(tmp_path / "other.bag", seed=7)
    assert other.truth[-1] != kit.truth[-1]


def test_ekf_on_the_bag_follows_the_truth(kit: Any, tmp_path: Path) -> None:
    launch = tmp_path / "ekf_bag.launch"
    launch.write_text(
        '<launch>\n  <param name="use_sim_time" value="true"/>\n'
        '  <node pkg="robot_localization" type="ekf_localization_node" name="ekf_localization">\n'
        '    <rosparam command="load" file="$(find ddes_sim)/config/localization.yaml"/>\n'
        '  </node>\n  <node pkg="ddes_sim" type="robot_frames" name="robot_state_publisher"/>\n'
        f'  <node pkg="rosbag" type="play" name="player" args="--clock {kit.path}"/>\n'
        '</launch>\n')
    console = ddes.Console(seed=0)
    console.run(f"roslaunch {launch} &")
    out: list[Any] = []
    probe = console.world.create_node("probe", use_sim_time=True)
    probe.subscribe("/odometry/filtered", get_message_class("nav_msgs/Odometry"), out.append)
    buffer = Buffer(node=probe)
    TransformListener(probe, buffer)
    console.world.run(until=40.0)
    last = out[-1]
    _t, x, y, _yaw = kit.truth[-1]
    assert last.header.stamp.to_sec() == pytest.approx(STAMP_OFFSET + 38.0)
    assert math.hypot(last.pose.pose.position.x - x, last.pose.pose.position.y - y) < 0.3
    # the chain odom → base_link (EKF) → imu_link (robot_frames) exists
    imu = buffer.lookup_transform("odom", "imu_link", Time())
    assert imu.transform.translation.x == pytest.approx(last.pose.pose.position.x, abs=0.3)


def test_the_docs_figure_and_snippet(kit: Any, tmp_path: Path,
                                     capsys: pytest.CaptureFixture[str]) -> None:
    """docs/localization.md: the figure's command gives the errors the page states, and its
    Python block runs."""
    png = tmp_path / "ekf.png"
    errors = plot_localization(kit, png)
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert (round(errors.ekf_final, 3), round(errors.odom_final, 3)) == (0.161, 0.909)
    assert errors.ekf_max < 0.2 < errors.odom_max
    doc = Path(__file__).resolve().parents[2] / "docs" / "localization.md"
    text = doc.read_text(encoding="utf-8")
    assert "final 0.161 m, max 0.166 m; wheel odometry final 0.909 m" in text
    (block,) = python_blocks(text)
    run_snippet(block, doc, 0, {})
    assert "final error 0.16 m" in capsys.readouterr().out
