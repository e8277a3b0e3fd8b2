"""``ddes demo``: the ROS concepts, the robot (simulator, P controller, top view) and a graded
submission (exercise 3's reference solution, public scenario) when a checkout is at hand."""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from ddes.cli import demo
from ddes.cli.main import main

REPO = Path(__file__).resolve().parents[2]


def test_ddes_demo_shows_the_concepts_the_robot_and_a_graded_submission(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch,
        capsys: pytest.CaptureFixture[str]) -> None:
    monkeypatch.chdir(REPO)  # where README's set-up command runs it
    pictures = tmp_path / "pictures"
    assert main(["demo", "--pictures", str(pictures)]) == 0
    out, err = capsys.readouterr()
    assert err == ""
    parts = re.split(r"\n(?=The robot \(seed 0\)|A graded submission)", out)
    assert len(parts) == 3, out
    concepts, robot, graded = parts
    # the first part is unchanged: its digest is run_demo's
    digests = re.findall(r"trace digest: ([0-9a-f]{64})", out)
    assert len(digests) == 2
    assert digests[0] == demo.run_demo(out=lambda s: None)
    assert "client: 10 + 5 = 15" in concepts and digests[0] in concepts
    # the robot: the pose each second, the collision when it happens, the picture, the digest
    assert [line[:10] for line in robot.splitlines() if "] robot: " in line] == [
        f"[{t:7.3f}]" + " " for t in range(6)]
    assert "[WARN] [4.380000]: collision with pillar at 1.000 m/s" in robot
    assert "collision: pillar at t=4.380 s, 1.000 m/s" in robot
    assert f"top view: {pictures / 'top_view.png'}" in robot
    assert (pictures / "top_view.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert digests[1] in robot
    assert "real-time factor" not in out  # wall-clock figures would make the output differ
    # the graded submission: the report of the reference solution, public scenario
    assert "`ddes grade ex3_pillar solutions/ex3_pillar --public`" in graded
    for cid, points in (("3.1", "20/20"), ("3.2", "30/30"), ("3.3", "20/20"), ("3.4", "30/30")):
        assert re.search(rf"^{re.escape(cid)} .* {points}$", graded, flags=re.M), graded
    assert graded.rstrip().endswith("total: 100/100 (100.0 %, public scenarios only)")


def test_the_robot_is_deterministic_and_draws_into_a_temporary_folder_by_default(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(tmp_path)
    lines: list[str] = []
    first = demo.run_robot(seed=4, out=lines.append)
    picture = Path(next(line for line in lines if line.startswith("top view: "))[10:])
    try:
        assert picture.is_file() and picture.name == "top_view.png"
        assert not picture.is_relative_to(tmp_path)
        assert list(tmp_path.iterdir()) == []  # nothing in the current directory
    finally:
        shutil.rmtree(picture.parent)
    again: list[str] = []
    assert demo.run_robot(seed=4, pictures=tmp_path / "p", out=again.append) == first
    assert [x for x in lines if not x.startswith("top view: ")] == [
        x for x in again if not x.startswith("top view: ")]
    assert demo.run_robot(seed=5, pictures=tmp_path / "p", out=lambda s: None) != first


def test_find_solutions_looks_next_to_the_package_then_in_the_current_directory(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    found = demo.find_solutions()
    assert found == REPO / "solutions" / "ex3_pillar"  # tests run from a checkout
    assert demo.find_solutions(roots=[tmp_path]) is None
    shutil.copytree(REPO / "solutions" / "ex3_pillar", tmp_path / "solutions" / "ex3_pillar")
    assert demo.find_solutions(roots=[tmp_path / "x", tmp_path]) == (
        tmp_path / "solutions" / "ex3_pillar")


def test_without_a_checkout_the_demo_says_where_the_exercises_are(
        monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(demo, "find_solutions", lambda exercise="": None)
    lines: list[str] = []
    assert demo.run_graded_submission(out=lines.append) is None
    assert len(lines) == 1
    assert "exercises/, solutions/" in lines[0] and "ddes grade ex3_pillar" in lines[0]


ROBOT = ("from ddes.cli.demo import build_robot\n"
         "world, sim = build_robot(seed=2, out=lambda s: None)\n"
         "world.run(until=5.0)\n"
         "print(world.digest())\n")


def test_the_robot_digest_is_independent_of_the_hash_seed() -> None:
    digests = {subprocess.run([sys.executable, "-c", ROBOT], capture_output=True, text=True,
                              check=True, timeout=120,
                              env=dict(os.environ, PYTHONHASHSEED=seed)).stdout.strip()
               for seed in ("0", "4242")}
    world, _ = demo.build_robot(seed=2, out=lambda s: None)
    world.run(until=5.0)
    assert digests == {world.digest()}
