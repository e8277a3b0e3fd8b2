"""docs/grading.md: every ```python block runs, in order, sharing one namespace, and prints the
text the document shows after it."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from ..docsnippets import python_blocks, run_snippet

DOC = Path(__file__).resolve().parents[2] / "docs" / "grading.md"


def test_snippets_run_in_order_and_print_what_the_doc_shows(
        capsys: pytest.CaptureFixture[str]) -> None:
    text = DOC.read_text()
    blocks = python_blocks(text)
    assert len(blocks) == 6
    shown = re.findall(r"```python\n.*?```\n\n(?:prints `([^`]*)`|```text\n(.*?)```|prints\n\n"
                       r"```text\n(.*?)```)", text, flags=re.S)
    scope: dict[str, object] = {}
    for i, code in enumerate(blocks):
        run_snippet(code, DOC, i, scope)
        out = capsys.readouterr().out
        expected = next(x for x in shown[i] if x)
        assert out.strip() == expected.strip(), (i, out)
