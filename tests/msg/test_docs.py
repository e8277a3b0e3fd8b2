"""Every ```python block of docs/messages.md runs (in order, sharing one namespace)."""

from __future__ import annotations

import re
from pathlib import Path
from typing import Any

from ..docsnippets import run_snippet

DOC = Path(__file__).resolve().parents[2] / "docs" / "messages.md"
BLOCKS = re.findall(r"```python\n(.*?)```", DOC.read_text(encoding="utf-8"), flags=re.S)


def test_the_doc_has_snippets() -> None:
    assert len(BLOCKS) >= 8


def test_snippets_run_in_order() -> None:
    namespace: dict[str, Any] = {}
    for i, code in enumerate(BLOCKS):
        run_snippet(code, DOC, i, namespace)
