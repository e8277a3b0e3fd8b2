"""Every row of docs/reliability.md names a test that exists (so each row is a test)."""

from __future__ import annotations

import re
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
DOC = REPO / "docs" / "reliability.md"


def rows() -> list[list[str]]:
    out = []
    for line in DOC.read_text(encoding="utf-8").splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if len(cells) == 5 and cells[4].startswith("`tests/"):
            out.append(cells)
    return out


def test_the_table_has_rows() -> None:
    assert len(rows()) >= 20


def test_every_row_names_an_existing_test() -> None:
    missing = []
    for cells in rows():
        node = cells[4].strip("`")
        path, _, name = node.partition("::")
        name = name.split("[")[0]
        file = REPO / path
        if not file.is_file() or not re.search(rf"^\s*def {re.escape(name)}\(",
                                               file.read_text(encoding="utf-8"), re.M):
            missing.append(node)
    assert not missing, f"rows of docs/reliability.md name tests that do not exist: {missing}"


def test_every_row_says_what_ddes_and_ros_do() -> None:
    for subsystem, tried, ddes_does, ros_does, _test in rows():
        assert subsystem and tried and ddes_does and ros_does
