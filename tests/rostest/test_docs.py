"""docs/rostest.md's example is what ``ddes rostest`` prints for the demo's pass.test."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from ddes.cli.main import main

ROOT = Path(__file__).resolve().parents[2]
DOC = (ROOT / "docs" / "rostest.md").read_text(encoding="utf-8")
PASS = Path(__file__).resolve().parent / "ddes_rostest_demo" / "test" / "pass.test"


def test_the_example_is_the_commands_output(tmp_path: Path,
                                            capsys: pytest.CaptureFixture[str]) -> None:
    block = DOC[DOC.index("```text\n[ROSUNIT]") + len("```text\n"):]
    block = block[:block.index("```")]
    assert main(["rostest", "--results-dir", str(tmp_path), str(PASS)]) == 0
    out = capsys.readouterr().out.replace(str(tmp_path), "RESULTS")
    digest = re.compile(r"^trace digest: [0-9a-f]{64}$", re.M)
    assert digest.search(out) and digest.search(block)
    assert digest.sub("trace digest: D", out) == digest.sub("trace digest: D", block)


def test_every_option_is_documented() -> None:
    from ddes.console.rostest import _USAGE

    for option in re.findall(r"--[a-z-]+", _USAGE):
        assert f"`{option}" in DOC, option
