"""docs/services.md: every transcript is what the console prints; every Python block runs."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from ddes.console.shell import Console

from ..docsnippets import run_snippet

DOC = Path(__file__).resolve().parents[2] / "docs" / "services.md"
TEXT = DOC.read_text()
TRANSCRIPTS = re.findall(r"<!-- transcript( keep-going)? -->\n```text\n(.*?)```", TEXT, flags=re.S)
PYTHON = re.findall(r"```python\n(.*?)```", TEXT, flags=re.S)


def test_the_doc_has_transcripts_and_snippets() -> None:
    assert len(TRANSCRIPTS) >= 3 and len(PYTHON) >= 3


@pytest.mark.parametrize(("keep_going", "block"), TRANSCRIPTS,
                         ids=[f"transcript{i}" for i in range(len(TRANSCRIPTS))])
def test_transcript_is_what_the_console_prints(keep_going: str, block: str) -> None:
    # "$ " starts a command; "> " continues one inside an open quote, as the console echoes it
    commands = [line[2:] for line in block.splitlines() if line.startswith(("$ ", "> "))]
    code, text = Console(seed=0).transcript(commands, keep_going=bool(keep_going))
    assert code == (1 if keep_going else 0)
    assert text == block


@pytest.mark.parametrize("index", range(len(PYTHON)),
                         ids=[f"python{i}" for i in range(len(PYTHON))])
def test_snippet_runs(index: int) -> None:
    run_snippet(PYTHON[index], DOC, index)  # asserts inside
