"""Exercise 4d: the reference earns everything, the starter at most 20 %; the hidden bags come
from the seed; the grader's reference EKF agrees with a bag-playing launch; without
robot_frames the IMU is dropped and the track ends elsewhere; one grading's wall time is
printed."""

from __future__ import annotations

import shutil
import time
from pathlib import Path

from ddes.grading import REGISTRY, grade
from ddes.grading.exercises.ex4d_bags import reference_final, scenarios

ROOT = Path(__file__).resolve().parents[2]
SOLUTION = ROOT / "solutions" / "ex4d_bags"
STARTER = ROOT / "exercises" / "ex4d_bags"
LAUNCH = "smb_highlevel_controller/launch/ekf_bag.launch"
EX = REGISTRY.get("ex4d_bags")


def points(report):  # type: ignore[no-untyped-def]
    return {c.id: c.points for c in report.criteria}


def test_reference_earns_everything_and_one_grading_is_timed() -> None:
    start = time.perf_counter()
    report = grade(EX, SOLUTION, seed=0)
    wall = time.perf_counter() - start
    print(f"ex4d_bags: one grading (3 bag scenarios and the simulator run) took {wall:.2f} s wall")
    assert report.score == report.max_score == 110, [c.evidence for c in report.criteria]
    assert report.percent == 100


def test_starter_earns_at_most_20_percent() -> None:
    assert grade(EX, STARTER, seed=0).percent <= 20


def test_without_robot_frames_the_imu_is_dropped(tmp_path: Path) -> None:
    sub = tmp_path / "sub"
    shutil.copytree(SOLUTION, sub)
    launch = sub / LAUNCH
    text = launch.read_text()
    line = '  <node pkg="ddes_sim" type="robot_frames" name="robot_state_publisher"/>\n'
    assert line in text
    launch.write_text(text.replace(line, ""))
    got = points(grade(EX, sub, seed=0))
    # the track still covers the bag, but ends away from the grader's EKF (odometry only)
    assert got["4d.4"] == 15 and got["4d.7"] == 10 and got["4d.1"] == 10


def test_hidden_bags_come_from_the_seed() -> None:
    a, b = scenarios(5, False), scenarios(5, False)
    assert a == b and a[0].params["drive_seed"] == 2021
    assert a[1].params != scenarios(6, False)[1].params and a[1].params != a[2].params
    assert reference_final(2021) == reference_final(2021)


def test_the_simulator_run_starts_no_code_of_the_submission(tmp_path: Path) -> None:
    """ekf_sim.launch is run in the grader's process: a node of any package the submission holds
    is left out (its nodes.py or scripts never execute there), the bundled ones still run."""
    from ddes.grading.exercises.ex4d_bags import _sim_run

    sub = tmp_path / "sub"
    shutil.copytree(SOLUTION, sub, ignore=shutil.ignore_patterns("mutants"))
    marker = tmp_path / "ran"
    pkg = sub / "evil_pkg"
    pkg.mkdir()
    (pkg / "package.xml").write_text("<package format=\"2\"><name>evil_pkg</name></package>\n")
    (pkg / "nodes.py").write_text(f"open({str(marker)!r}, 'w').write('ran')\nNODES = {{}}\n")
    launch = sub / "smb_highlevel_controller" / "launch" / "ekf_sim.launch"
    launch.write_text(launch.read_text().replace(
        "</launch>", '  <node pkg="evil_pkg" type="x" name="x"/>\n</launch>'))
    run = _sim_run(sub, 0)
    assert not marker.exists()
    assert run.rate_ok and run.one_authority, run.why
