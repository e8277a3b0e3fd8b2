"""Every Python snippet in README.md runs (the README must stay true)."""

from __future__ import annotations

import contextlib
import io
import json
import re
from pathlib import Path

import pytest

from .docsnippets import run_snippet

README = Path(__file__).resolve().parent.parent / "README.md"
BLOCKS = re.findall(r"```python\n(.*?)```", README.read_text(encoding="utf-8"), flags=re.S)


def test_readme_has_snippets() -> None:
    assert len(BLOCKS) >= 2


@pytest.mark.parametrize("index", range(len(BLOCKS)))
def test_readme_snippet_runs(index: int) -> None:
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        run_snippet(BLOCKS[index], README, index)
    assert out.getvalue()  # every snippet prints something


TRANSCRIPTS = re.findall(r"<!-- transcript -->\n```text\n(.*?)```",
                         README.read_text(encoding="utf-8"), flags=re.S)


@pytest.mark.parametrize("index", range(len(TRANSCRIPTS)))
def test_readme_transcript_is_what_the_console_prints(index: int) -> None:
    from ddes.console.shell import Console

    block = TRANSCRIPTS[index]
    script: list[str] = []
    for line in block.splitlines():
        if line.startswith("$ "):
            script.append(line[2:])
        elif line.startswith("> "):  # a quoted argument continued on the next line
            script.append(line[2:])
    code, text = Console(seed=0).transcript(script)
    assert code == 0
    assert text == block


def test_readme_has_a_transcript() -> None:
    assert TRANSCRIPTS


def _ddes_command(bin_dir: Path) -> Path:
    """``bin_dir/ddes``: the ddes of the Python running the tests, as an installed command."""
    import sys

    bin_dir.mkdir(parents=True)
    (bin_dir / "ddes").write_text(f"#!/bin/sh\nexec {sys.executable} -m ddes \"$@\"\n")
    (bin_dir / "ddes").chmod(0o755)
    return bin_dir


def test_readme_console_commands_run_as_written(tmp_path: Path) -> None:
    """The README's console block, run by a shell in the checkout (``.venv/bin/ddes`` being the
    ddes of the Python running the tests)."""
    import os
    import subprocess

    text = README.read_text(encoding="utf-8")
    block = next(b for b in re.findall(r"```sh\n(.*?)```", text, flags=re.S)
                 if "ddes console" in b and "printf" in b)
    bin_dir = _ddes_command(tmp_path / ".venv" / "bin")
    root = README.parent
    lines = [line.replace(".venv/bin/ddes", str(bin_dir / "ddes")) for line in block.splitlines()]
    done = subprocess.run(["bash", "-e", "-c", "\n".join(lines)], cwd=root, capture_output=True,
                          text=True, timeout=300, check=False,
                          env={**os.environ, "PYTHONPATH": str(root)})
    assert done.returncode == 0, done.stdout[-2000:] + done.stderr[-2000:]
    assert done.stdout.count('data: "hello world') == 2  # rostopic echo -n 2 /chatter
    assert "/listenerI heard hello world 0.1" in done.stdout  # the launch file's listener


def test_readme_student_loop_runs_as_written(tmp_path: Path) -> None:
    """The student's loop: copy the starter to ~/ex3, grade it (the untouched starter earns
    little, and says why), replay and draw the public scenario."""
    import os
    import subprocess

    text = README.read_text(encoding="utf-8")
    block = next(b for b in re.findall(r"```sh\n(.*?)```", text, flags=re.S)
                 if b.startswith("cp -r exercises/"))
    bin_dir = _ddes_command(tmp_path / "bin")
    home = tmp_path / "home"
    home.mkdir()
    root = README.parent
    done = subprocess.run(["bash", "-e", "-c", block], cwd=root, capture_output=True, text=True,
                          timeout=300, check=False,
                          env={**os.environ, "HOME": str(home), "PYTHONPATH": str(root),
                               "PATH": f"{bin_dir}:{os.environ['PATH']}"})
    assert done.returncode == 0, done.stdout[-2000:] + done.stderr[-2000:]
    assert "total: " in done.stdout and "public scenarios only" in done.stdout
    assert "replay: ddes grade replay ex3_pillar . --scenario public --seed 0" in done.stdout
    assert (home / "ex3" / "fail.png").stat().st_size > 0


@pytest.mark.slow
@pytest.mark.ci
def test_readme_instructor_loop_runs_as_written(tmp_path: Path) -> None:
    """The instructor's block, in a folder holding ``submissions/`` (two copies of the reference)
    and ``solutions/`` as the checkout's, SUBMISSION one of them: every line exits 0, the
    operator sweep with the verdict its comment names (its sample of exercise 3 holds the one
    documented survivor, docs/grading.md)."""
    import os
    import shutil
    import subprocess

    text = README.read_text(encoding="utf-8")
    block = next(b for b in re.findall(r"```sh\n(.*?)```", text, flags=re.S)
                 if "ddes grade batch" in b)
    root = README.parent
    work = tmp_path / "work"
    for name in ("a", "b"):
        shutil.copytree(root / "solutions" / "ex3_pillar", work / "submissions" / name,
                        ignore=shutil.ignore_patterns("mutants"))
    shutil.copytree(root / "solutions", work / "solutions")
    shutil.copytree(root / "exercises", work / "exercises")
    bin_dir = _ddes_command(tmp_path / "bin")
    env = {**os.environ, "PYTHONPATH": str(root), "PATH": f"{bin_dir}:{os.environ['PATH']}"}
    for line in block.splitlines():
        command = line.split("  #")[0].replace("SUBMISSION", "submissions/a").strip()
        if "--workers" in command:
            pytest.importorskip("distributed")
        done = subprocess.run(["bash", "-e", "-c", command], cwd=work, capture_output=True,
                              text=True, timeout=900, check=False, env=env)
        if " operators " in command:  # its verdict: exit 1 when the sample's kill rate < 95 %
            assert "(exit 1 under 95 %)" in line
            rate = float(re.findall(r"kill rate ([0-9.]+) %", done.stdout)[-1])
            assert done.returncode == (0 if rate >= 95 else 1), done.stdout[-2000:]
            continue
        assert done.returncode == 0, (command, done.stdout[-2000:], done.stderr[-2000:])
    assert json.loads((work / "results.json").read_text())["score"] > 0
    assert (work / "graded" / "summary.csv").read_text().count("\n") >= 3
