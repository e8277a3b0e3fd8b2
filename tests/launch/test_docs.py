"""Every ```python block of docs/launch.md runs."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from ..docsnippets import run_snippet

DOC = Path(__file__).resolve().parents[2] / "docs" / "launch.md"
BLOCKS = re.findall(r"```python\n(.*?)```", DOC.read_text(), flags=re.S)


def test_the_doc_has_snippets() -> None:
    assert len(BLOCKS) >= 2


@pytest.mark.parametrize("index", range(len(BLOCKS)),
                         ids=[f"block{i}" for i in range(len(BLOCKS))])
def test_snippet_runs(index: int) -> None:
    run_snippet(BLOCKS[index], DOC, index)  # asserts inside
