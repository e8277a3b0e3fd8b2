"""ddes/testing/_draws.py: derandomized draws do not depend on which local modules are loaded."""

from __future__ import annotations

import importlib
import sys
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from ddes.testing._draws import same_draws_everywhere


def draws() -> list[int]:
    seen: list[int] = []

    @settings(max_examples=300, derandomize=True, database=None)
    @given(st.integers(0, 10**6))
    def record(value: int) -> None:
        seen.append(value)

    record()
    return seen


def test_a_newly_imported_local_module_changes_no_draw(tmp_path: Path,
                                                      monkeypatch: pytest.MonkeyPatch) -> None:
    with same_draws_everywhere():
        before = draws()
    # A module outside site-packages (a "local" one to hypothesis) full of constants in range.
    (tmp_path / "ddes_draws_constants.py").write_text(
        "".join(f"C{i} = {777_000 + i}\n" for i in range(50)), encoding="utf-8")
    monkeypatch.syspath_prepend(str(tmp_path))
    importlib.import_module("ddes_draws_constants")
    try:
        with same_draws_everywhere():
            after = draws()
        plain = draws()
    finally:
        sys.modules.pop("ddes_draws_constants", None)
    assert after == before
    assert not any(777_000 <= v < 777_050 for v in after)
    try:
        from hypothesis.internal.conjecture import providers
    except ImportError:  # older hypothesis: no providers module, no pool
        return
    if hasattr(providers, "_get_local_constants"):  # hypothesis >= 6.131 has the pool
        # without the guard, the module's constants reach the draws
        assert any(777_000 <= v < 777_050 for v in plain)
