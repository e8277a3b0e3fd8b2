"""Every ```python block of docs/bags.md runs, in order, sharing one namespace."""

from __future__ import annotations

import re
from pathlib import Path

DOC = Path(__file__).resolve().parents[2] / "docs" / "bags.md"
BLOCKS = re.findall(r"```python\n(.*?)```", DOC.read_text(), flags=re.S)


def test_the_doc_has_snippets() -> None:
    assert len(BLOCKS) >= 4


def test_snippets_run_in_order(utc: None) -> None:
    scope: dict[str, object] = {}
    for code in BLOCKS:
        exec(compile(code, str(DOC), "exec"), scope)  # noqa: S102 - our own documentation
