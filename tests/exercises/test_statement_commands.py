"""Every ``ddes`` command a statement or the README prints is one the CLI takes as written, and
every console session a statement prints runs, from the exercise's folder, against the reference
solution (issue 42 item 1)."""

from __future__ import annotations

import re
import shlex
from pathlib import Path

import pytest

import ddes
from ddes.cli.main import build_parser
from ddes.console.shell import Console
from ddes.rospack import command_package_path

ROOT = Path(__file__).resolve().parents[2]
DOCUMENTS = [ROOT / "README.md", *sorted((ROOT / "exercises").glob("*/README.md"))]


def _commands(text: str) -> list[str]:
    """The ``ddes ...`` command lines of a document: in fenced blocks and in inline code."""
    lines: list[tuple[str, bool]] = []
    for block in re.findall(r"```[a-z]*\n(.*?)```", text, flags=re.S):
        lines += [(line, True) for line in block.splitlines()]
    # inline code naming a whole command (`ddes grade` alone is prose naming the tool)
    lines += [(span, False) for span in re.findall(r"`([^`\n]*ddes [^`\n]*)`", text)]
    found = []
    for line, fenced in lines:
        for part in line.split("|"):  # printf '...' | ddes console
            if not re.match(r"\s*([A-Z_]+=\S*\s+)*(\S*/)?ddes\s", part):
                continue
            words = shlex.split(part, comments=True)
            while words and re.fullmatch(r"[A-Z_]+=.*", words[0]):  # VAR=value ddes ...
                words.pop(0)
            if any(re.fullmatch(r"[A-Z][A-Z_]{2,}(:[A-Z]+)?", w) for w in words):
                continue  # a synopsis with placeholders (ddes console --until SECONDS)
            if words and words[0].split("/")[-1] == "ddes" and len(words) > (1 if fenced else 2):
                found.append(shlex.join(["ddes", *words[1:]]))
    return found


CASES = [(doc, cmd) for doc in DOCUMENTS for cmd in _commands(doc.read_text(encoding="utf-8"))]


def test_the_documents_hold_commands() -> None:
    names = {doc.parent.name for doc, _ in CASES}
    assert "ex4b_actions" in names and ROOT.name in names  # the README's too
    assert len(CASES) >= 20


@pytest.mark.parametrize(("doc", "command"), CASES,
                         ids=[f"{d.parent.name}:{c}" for d, c in CASES])
def test_every_printed_ddes_command_is_one_the_cli_takes(doc: Path, command: str) -> None:
    parser = build_parser()
    try:
        args = parser.parse_args(shlex.split(command)[1:])
    except SystemExit as e:  # argparse's usage error (0: a -h printed its help)
        if e.code == 0:
            return
        pytest.fail(f"{doc.relative_to(ROOT)} prints `{command}`, which ddes refuses ({e.code})")
    assert args.command


def test_a_command_that_does_not_exist_is_caught() -> None:
    assert _commands("```\nddes launch smb_follow_path smb_follow_path.launch\n```") == [
        "ddes launch smb_follow_path smb_follow_path.launch"]
    with pytest.raises(SystemExit):
        build_parser().parse_args(["launch", "smb_follow_path", "smb_follow_path.launch"])


SESSIONS = [(doc, block) for doc in DOCUMENTS[1:]
            for block in re.findall(r"<!-- console session -->\n```[a-z]*\n(.*?)```",
                                    doc.read_text(encoding="utf-8"), flags=re.S)]


def test_exercise_4b_prints_a_console_session() -> None:
    assert any(doc.parent.name == "ex4b_actions" for doc, _ in SESSIONS)


@pytest.mark.parametrize(("doc", "block"), SESSIONS, ids=[d.parent.name for d, _ in SESSIONS])
def test_a_statements_console_session_runs_against_the_reference(doc: Path, block: str) -> None:
    """As a student who has finished it types it: in the exercise's folder, the package found
    there (``ddes console`` started in it), on the reference solution."""
    folder = ROOT / "solutions" / doc.parent.name
    lines = [line[2:] for line in block.splitlines() if line.startswith("$ ")]
    assert lines
    world = ddes.World(package_path=command_package_path({}, folder))
    code, text = Console(world).transcript(lines)
    assert code == 0, text
    assert "Traceback" not in text and "ERROR" not in text, text
    if doc.parent.name == "ex4b_actions":
        assert "no result after 3.0 s: cancelling" in text
        assert "finished: state 2, success False" in text  # PREEMPTED


GRADES = [(doc, cmd) for doc, cmd in CASES
          if doc.parent.parent.name == "exercises" and cmd.startswith("ddes grade ")
          and " . " in f"{cmd} "]


def test_every_statement_prints_its_grade_command() -> None:
    graded = {doc.parent.name for doc, _ in GRADES}
    assert graded == {p.name for p in (ROOT / "exercises").iterdir() if (p / "README.md").is_file()}


@pytest.mark.parametrize(("doc", "command"), GRADES, ids=[c for _, c in GRADES])
def test_a_statements_grade_command_runs_as_written_in_the_finished_folder(
        doc: Path, command: str, tmp_path: Path) -> None:
    """``ddes grade EX . …`` typed in the exercise's folder once the student has finished it (a
    copy of the reference solution): it grades, or replays and draws, and exits 0."""
    import shutil
    import subprocess
    import sys

    folder = tmp_path / doc.parent.name
    shutil.copytree(ROOT / "solutions" / doc.parent.name, folder,
                    ignore=shutil.ignore_patterns("mutants"))
    done = subprocess.run([sys.executable, "-m", "ddes", *shlex.split(command)[1:]], cwd=folder,
                          capture_output=True, text=True, timeout=300, check=False)
    assert done.returncode == 0, done.stdout[-3000:] + done.stderr[-3000:]
    assert "Traceback" not in done.stderr
    if " replay " in command:
        picture = shlex.split(command)[shlex.split(command).index("--picture") + 1]
        assert (folder / picture).stat().st_size > 0
    else:
        assert "total: " in done.stdout and "(100.0 %" in done.stdout, done.stdout[-2000:]
