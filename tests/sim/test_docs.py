"""docs/sim.md: every ```python block runs, in order, sharing one namespace."""

from __future__ import annotations

from pathlib import Path

from ..docsnippets import python_blocks, run_snippet

DOC = Path(__file__).resolve().parents[2] / "docs" / "sim.md"


def test_the_doc_has_snippets() -> None:
    assert len(python_blocks(DOC.read_text())) >= 4


def test_snippets_run_in_order(capsys) -> None:  # type: ignore[no-untyped-def]
    scope: dict[str, object] = {}
    for i, code in enumerate(python_blocks(DOC.read_text())):
        run_snippet(code, DOC, i, scope)
    out = capsys.readouterr().out
    assert "pillar " in out and "Truth(x=1.0, y=0.0" in out
    assert "missing field 'radius'" in out


def test_the_yaml_example_is_a_valid_world() -> None:
    from ddes.sim import WorldSpec

    text = DOC.read_text()
    block = text.split("```yaml\n", 1)[1].split("```", 1)[0]
    assert [ob.name for ob in WorldSpec.from_yaml(block)] == ["pillar", "wall", "crate"]
