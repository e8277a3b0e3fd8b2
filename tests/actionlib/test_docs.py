"""docs/actionlib.md, "Servers and clients on topics": every ```python block runs, in order,
sharing one namespace."""

from __future__ import annotations

from pathlib import Path

import matplotlib

from ..docsnippets import run_snippet

matplotlib.use("Agg")

DOC = Path(__file__).resolve().parents[2] / "docs" / "actionlib.md"


def test_servers_and_clients_section_runs() -> None:
    text = DOC.read_text(encoding="utf-8")
    section = text.split("## Servers and clients on topics", 1)[1].split("\n## ", 1)[0]
    blocks = [b.split("```", 1)[0] for b in section.split("```python\n")[1:]]
    assert len(blocks) >= 4
    namespace: dict[str, object] = {}
    for i, block in enumerate(blocks):
        run_snippet(block, DOC, f"'Servers and clients on topics' block {i}", namespace)
