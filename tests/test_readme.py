"""Every Python snippet in README.md runs (the README must stay true)."""

from __future__ import annotations

import contextlib
import io
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
