"""Hidden scenarios from a keyed hash: scenario_seed and the --secret-file/env plumbing."""

from __future__ import annotations

import hashlib
import hmac
from pathlib import Path

import pytest

from ddes.cli.main import main
from ddes.errors import GradingError
from ddes.grading import ExerciseRegistry
from ddes.grading.scenarios import HiddenKey, read_secret, scenario_seed, select_scenarios

from .conftest import FIXTURES

HIDDEN_FILE = FIXTURES / "ex0_hidden.py"
SECRET = b"course-secret-2024"


@pytest.fixture(scope="module")
def ex():  # type: ignore[no-untyped-def]
    (exercise,) = ExerciseRegistry().load_file(HIDDEN_FILE)
    return exercise


def test_scenario_seed_is_the_documented_hmac() -> None:
    mac = hmac.new(SECRET, b"ex3_pillar/alice/2/1", hashlib.sha256).digest()
    assert scenario_seed(SECRET, "ex3_pillar", "alice", 2, 1) == int.from_bytes(mac[:8], "big") >> 1
    assert scenario_seed(SECRET.decode(), "ex3_pillar", "alice", 2, 1) == \
        scenario_seed(SECRET, "ex3_pillar", "alice", 2, 1)
    seeds = {scenario_seed(SECRET, ex, st, at, i) for ex in ("ex1", "ex3") for st in ("a", "b")
             for at in (0, 1) for i in range(3)}
    assert len(seeds) == 24 and all(0 <= s < 2**63 for s in seeds)
    assert scenario_seed(b"another", "ex3_pillar", "alice", 2, 1) != \
        scenario_seed(SECRET, "ex3_pillar", "alice", 2, 1)


@pytest.mark.parametrize("args, text", [
    ((b"", "ex", "a", 0, 0), "the course secret is empty"),
    ((SECRET, "ex", "a/b", 0, 0), "student 'a/b' must be a string without '/'"),
    ((SECRET, "ex", "a", -1, 0), "attempt -1"),
    ((SECRET, "ex", "a", 0, True), "index True"),
])
def test_scenario_seed_refuses_bad_fields(args: tuple, text: str) -> None:  # type: ignore[type-arg]
    with pytest.raises(GradingError, match=text):
        scenario_seed(*args)


def test_students_differ_and_an_attempt_repeats(ex) -> None:  # type: ignore[no-untyped-def]
    def hidden(student: str, attempt: int) -> list[dict]:  # type: ignore[type-arg]
        got = select_scenarios(ex, 0, False, HiddenKey(SECRET, student, attempt))
        assert [s.name for s in got] == ["public", "hidden-0", "hidden-1"]
        assert got[0].params == {"word": "public", "x": 0.0}
        return [s.params for s in got if s.hidden]

    alice = hidden("alice", 1)
    assert hidden("alice", 1) == alice
    assert hidden("bob", 1) != alice and hidden("alice", 2) != alice
    assert alice[0] != alice[1]
    assert [s.params for s in select_scenarios(ex, 0, False) if s.hidden] != alice  # open default
    assert [s.name for s in select_scenarios(ex, 0, True, HiddenKey(SECRET, "alice", 1))] == [
        "public"]


def test_read_secret(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.delenv("DDES_GRADE_SECRET", raising=False)
    assert read_secret(None) is None
    monkeypatch.setenv("DDES_GRADE_SECRET", " from-env \n")
    assert read_secret(None) == b"from-env"
    (tmp_path / "s").write_bytes(b"from-file\n")
    assert read_secret(str(tmp_path / "s")) == b"from-file"
    (tmp_path / "e").write_bytes(b"\n")
    with pytest.raises(GradingError, match="is empty"):
        read_secret(str(tmp_path / "e"))
    with pytest.raises(GradingError, match="no such file"):
        read_secret(str(tmp_path / "nope"))
    assert "from-file" not in repr(HiddenKey(b"from-file", "a", 0))


def test_the_command_line_grades_each_student_on_their_own_hidden_scenarios(
        tmp_path: Path, capsys: pytest.CaptureFixture[str],
        monkeypatch: pytest.MonkeyPatch) -> None:
    import json

    monkeypatch.delenv("DDES_GRADE_SECRET", raising=False)
    secret = tmp_path / "secret"
    secret.write_bytes(SECRET)
    subs = tmp_path / "subs"
    for name in ("alice", "bob"):
        (subs / name).mkdir(parents=True)
        (subs / name / "talker.py").write_text((FIXTURES / "ex0_solution" / "talker.py")
                                               .read_text())
    out = tmp_path / "out"
    assert main(["grade", "--exercises", str(HIDDEN_FILE), "batch", "ex0_hidden", str(subs),
                 "--out", str(out), "--secret-file", str(secret), "--attempt", "1"]) == 0
    digests = {n: json.loads((out / n / "results.json").read_text())["extra_data"]["digests"]
               for n in ("alice", "bob")}
    assert digests["alice"]["public"] == digests["bob"]["public"]
    assert digests["alice"]["hidden-0"] != digests["bob"]["hidden-0"]
    # one grade of alice's attempt 1 with --student repeats the batch's hidden scenarios
    assert main(["grade", "--exercises", str(HIDDEN_FILE), "ex0_hidden", str(subs / "alice"),
                 "--secret-file", str(secret), "--student", "alice", "--attempt", "1",
                 "--results", str(tmp_path / "a.json")]) == 0
    again = json.loads((tmp_path / "a.json").read_text())["extra_data"]["digests"]
    assert again == digests["alice"]
    capsys.readouterr()
    for words, text in (
            (["--student", "alice"], "give --secret-file FILE or set $DDES_GRADE_SECRET"),
            (["--secret-file", str(tmp_path / "nope")], "no such file")):
        assert main(["grade", "--exercises", str(HIDDEN_FILE), "ex0_hidden",
                     str(subs / "alice"), *words]) == 2
        assert text in capsys.readouterr().err
    assert main(["grade", "--exercises", str(HIDDEN_FILE), "batch", "ex0_hidden", str(subs),
                 "--out", str(out), "--secret-file", str(secret), "--student", "x"]) == 2
    assert "leave out --student" in capsys.readouterr().err
