"""docs/tf.md: every transcript is what the console prints; every Python block runs."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from ddes.console.shell import Console

from ..docsnippets import run_snippet

DOC = Path(__file__).resolve().parents[2] / "docs" / "tf.md"
TEXT = DOC.read_text()
TRANSCRIPTS = re.findall(r"<!-- transcript -->\n```text\n(.*?)```", TEXT, flags=re.S)
PYTHON = re.findall(r"```python\n(.*?)```", TEXT, flags=re.S)


def test_the_doc_has_transcripts_and_snippets() -> None:
    assert len(TRANSCRIPTS) >= 1 and len(PYTHON) >= 2


@pytest.mark.parametrize("block", TRANSCRIPTS, ids=[f"transcript{i}" for i in range(len(TRANSCRIPTS))])
def test_transcript_is_what_the_console_prints(block: str) -> None:
    commands = [line[2:] for line in block.splitlines() if line.startswith("$ ")]
    code, text = Console(seed=0).transcript(commands)
    assert code == 0
    assert text == block


@pytest.mark.parametrize("index", range(len(PYTHON)),
                         ids=[f"python{i}" for i in range(len(PYTHON))])
def test_snippet_runs(index: int) -> None:
    run_snippet(PYTHON[index], DOC, index)  # asserts inside
