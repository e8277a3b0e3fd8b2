"""docs/bags.md: every ```python block runs, in order, sharing one namespace; every transcript is
what the console prints."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from ddes.console.shell import Console

from ..docsnippets import run_snippet

DOC = Path(__file__).resolve().parents[2] / "docs" / "bags.md"
TEXT = DOC.read_text()
BLOCKS = re.findall(r"```python\n(.*?)```", TEXT, flags=re.S)
TRANSCRIPTS = re.findall(r"<!-- transcript -->\n```text\n(.*?)```", TEXT, flags=re.S)


def test_the_doc_has_snippets() -> None:
    assert len(BLOCKS) >= 4 and len(TRANSCRIPTS) >= 1


def test_snippets_run_in_order(utc: None) -> None:
    scope: dict[str, object] = {}
    for i, code in enumerate(BLOCKS):
        run_snippet(code, DOC, i, scope)


@pytest.mark.parametrize("block", TRANSCRIPTS,
                         ids=[f"transcript{i}" for i in range(len(TRANSCRIPTS))])
def test_transcript_is_what_the_console_prints(block: str, tmp_path: Path,
                                               monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(tmp_path)  # the bags the session writes
    monkeypatch.setenv("DDES_BAG_DATE", "2024-03-01-12-00-00")  # as the text says
    commands = [line[2:] for line in block.splitlines() if line.startswith("$ ")]
    code, text = Console(seed=0).transcript(commands, keep_going=True)
    assert text == block
    assert code == 1  # `record -a -l 3` fails, as it does in ROS
