"""docs/testing.md: every example of the protocol machines and the explorer runs, and prints
exactly what the page shows (the shrunk failure and its replay call)."""

from __future__ import annotations

import contextlib
import io
import re
import sys
from pathlib import Path

import hypothesis
import matplotlib
import pytest

from ..docsnippets import run_snippet

matplotlib.use("Agg")

DOC = Path(__file__).resolve().parents[2] / "docs" / "testing.md"
_BLOCK = re.compile(r"<!-- testing (example|output): ([\w-]+) -->\n```(?:python|text)\n(.*?)```",
                    re.S)


def blocks() -> dict[tuple[str, str], str]:
    return {(kind, name): body for kind, name, body in _BLOCK.findall(DOC.read_text("utf-8"))}


#: The hypothesis version and the Pythons whose searches gave the page's outputs (checked: the
#: same draws on 3.11 and 3.12; 3.13 draws others).  Elsewhere (``.ci/min-versions`` runs the
#: oldest hypothesis allowed) the same bug may shrink to another minimal schedule: there the
#: example must still find its bug and print a problem and a replay call.
SHRUNK_WITH = "6.170.15"
SHRUNK_ON = ((3, 11), (3, 12))

EXAMPLES = sorted({name.split("-")[0] for kind, name in blocks() if kind == "example"})


def test_every_machine_has_a_runnable_example() -> None:
    assert EXAMPLES == ["actions", "explore", "rostime", "services"]
    for name in EXAMPLES:
        assert ("output", name) in blocks()


@pytest.mark.parametrize("name", EXAMPLES)
def test_the_example_finds_and_shrinks_its_planted_bug(name: str, tmp_path: Path,
                                                       monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(tmp_path)
    found = blocks()
    namespace: dict[str, object] = {"__name__": f"docs_testing_{name}"}
    parts = sorted(n for kind, n in found if kind == "example" and n.split("-")[0] == name)
    for part in parts:  # "explore", then "explore-ties" in the same namespace
        out = io.StringIO()
        with contextlib.redirect_stdout(out):
            run_snippet(found[("example", part)], DOC, part, namespace)
        expected = found[("output", part)]
        if hypothesis.__version__ == SHRUNK_WITH and sys.version_info[:2] in SHRUNK_ON:
            assert out.getvalue() == expected, part
        else:
            got = out.getvalue().splitlines()
            assert len(got) == len(expected.splitlines()), (part, got)
            assert got[-1].split("(")[0] == expected.splitlines()[-1].split("(")[0], (part, got)
    if name == "actions":
        assert (tmp_path / "deaf_server.png").stat().st_size > 0
