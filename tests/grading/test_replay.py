"""``ddes grade replay``: the grade's replay line, run as it is, reproduces the scenario (same
digest) and writes its trace, bag and top view."""

from __future__ import annotations

import json
import shlex
from pathlib import Path

import pytest

from ddes.cli.main import main
from ddes.grading import ExerciseRegistry
from ddes.grading.replay import replay
from ddes.rosbag import Bag

from .conftest import EXERCISE_FILE, FIXTURES, SOLUTION

HIDDEN_FILE = FIXTURES / "ex0_hidden.py"


def _five_hz(tmp_path: Path) -> Path:
    sub = tmp_path / "bob"
    sub.mkdir()
    (sub / "talker.py").write_text((SOLUTION / "talker.py").read_text().replace(
        "rospy.Rate(10)", "rospy.Rate(5)"))
    return sub


def test_the_reports_replay_line_reproduces_the_scenario(
        tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    sub = _five_hz(tmp_path)
    results = tmp_path / "results.json"
    assert main(["grade", "--exercises", str(EXERCISE_FILE), "ex0_talker", str(sub),
                 "--results", str(results)]) == 0
    out = capsys.readouterr().out
    lines = [x.strip()[len("replay: "):] for x in out.splitlines()
             if x.strip().startswith("replay: ")]
    assert lines == [shlex.join(["ddes", "grade", "replay", "ex0_talker", str(sub), "--scenario",
                                 "public", "--seed", "0", "--exercises", str(EXERCISE_FILE)])]
    data = json.loads(results.read_text())
    digest = data["extra_data"]["digests"]["public"]
    assert len(digest) == 64
    assert f"replay: {lines[0]}" in data["tests"][1]["output"]

    trace, bag = tmp_path / "out" / "run.jsonl", tmp_path / "out" / "run.bag"
    words = shlex.split(lines[0])
    assert words[:2] == ["ddes", "grade"]
    assert main([*words[1:], "--trace", str(trace), "--bag", str(bag)]) == 0
    out = capsys.readouterr().out
    assert f"digest: {digest}" in out
    assert "0.2 10 Hz within 5 % " in out and " 0/4" in out
    assert "public (seed 0): 9 message(s) on /chatter" in out
    events = [json.loads(x) for x in trace.read_text().splitlines()]
    assert events[0] == [0, "node.start", "/grader_listener", {"use_sim_time": False}]
    published = [e for e in events if e[1] == "topic.publish" and e[3]["topic"] == "/chatter"]
    assert len(published) == 9
    with Bag(str(bag)) as b:
        got = [(topic, getattr(msg, "data", None), t.to_nsec())
               for topic, msg, t in b.read_messages()]
    assert [t for _, _, t in got] == [e[0] for e in published]
    assert [text for _, text, _ in got] == [f"hello world {n}" for n in range(1, 10)]  # 0 before the connection


def test_hidden_scenario_replay_with_the_secret_and_the_top_view(
        tmp_path: Path, capsys: pytest.CaptureFixture[str],
        monkeypatch: pytest.MonkeyPatch) -> None:
    (ex,) = ExerciseRegistry().load_file(HIDDEN_FILE)
    sub = tmp_path / "carol"
    sub.mkdir()
    (sub / "talker.py").write_text("import rospy\nrospy.init_node('talker')\nrospy.spin()\n")
    monkeypatch.setenv("DDES_GRADE_SECRET", "course-secret-2024")
    assert main(["grade", "--exercises", str(HIDDEN_FILE), "ex0_hidden", str(sub),
                 "--attempt", "3", "--results", str(tmp_path / "r.json")]) == 0
    out = capsys.readouterr().out
    digests = json.loads((tmp_path / "r.json").read_text())["extra_data"]["digests"]
    replay_line = next(x.strip()[8:] for x in out.splitlines() if "replay:" in x)
    assert replay_line == shlex.join(["ddes", "grade", "replay", "ex0_hidden", str(sub),
                                      "--scenario", "public", "--seed", "0", "--exercises",
                                      str(HIDDEN_FILE)])
    # the instructor replays hidden-1 of carol's attempt 3 with the secret
    picture = tmp_path / "top.png"
    assert main(["grade", "replay", "ex0_hidden", str(sub), "--scenario", "hidden-1",
                 "--student", "carol", "--attempt", "3", "--exercises", str(HIDDEN_FILE),
                 "--picture", str(picture)]) == 0
    out = capsys.readouterr().out
    assert f"digest: {digests['hidden-1']}" in out
    assert "ex0_hidden — scenario hidden-1 (hidden)" in out
    assert picture.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    # the API gives the same, and without the secret hidden-1 is another scenario
    from ddes.grading.scenarios import HiddenKey

    same = replay(ex, sub, "hidden-1", key=HiddenKey(b"course-secret-2024", "carol", 3))
    assert same.digest == digests["hidden-1"]
    monkeypatch.delenv("DDES_GRADE_SECRET")
    assert replay(ex, sub, "hidden-1").digest != digests["hidden-1"]


@pytest.mark.parametrize("words, text", [
    (["replay", "ex0_talker", "x"], "usage: ddes grade replay"),
    (["replay", "ex0_talker", str(SOLUTION), "--scenario", "nope"],
     "exercise ex0_talker has no scenario 'nope' for seed 0 (its scenarios: public)"),
])
def test_replay_usage_errors_exit_2(words: list[str], text: str, tmp_path: Path,
                                    capsys: pytest.CaptureFixture[str],
                                    monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(tmp_path)
    assert main(["grade", "--exercises", str(EXERCISE_FILE), *words]) == 2
    assert text in capsys.readouterr().err
