"""course_notebooks/: every notebook runs cleanly, draws its pictures, and prints its digest.

Each notebook is executed as Jupyter runs it (nbclient, kernel python3, MPLBACKEND=Agg, the
working directory course_notebooks/): no cell may raise, every cell tagged ``plot`` must show an
image, and the cell tagged ``digest`` must print the trace digest stored in the notebook's
``metadata["ddes"]["digest"]`` (after a deliberate change of behaviour:
``python course_notebooks/make.py --record-digests NAME``).  The committed files carry no
outputs and are exactly what ``course_notebooks/make.py`` writes from ``course_notebooks/src/``.
"""

from __future__ import annotations

import importlib.util
from pathlib import Path
from types import ModuleType

import nbformat
import pytest

ROOT = Path(__file__).resolve().parents[2]
FOLDER = ROOT / "course_notebooks"
NOTEBOOKS = sorted(FOLDER.glob("*.ipynb"))
BUDGET_S = 60.0  # per notebook; all of them together stay within 6 minutes of CI


def _make() -> ModuleType:
    spec = importlib.util.spec_from_file_location("course_notebooks_make", FOLDER / "make.py")
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_there_are_notebooks_and_they_are_up_to_date() -> None:
    assert NOTEBOOKS, "no course_notebooks/*.ipynb"
    assert _make().stale() == []  # python course_notebooks/make.py rewrites them


@pytest.mark.parametrize("path", NOTEBOOKS, ids=[p.stem for p in NOTEBOOKS])
def test_committed_without_outputs(path: Path) -> None:
    nb = nbformat.read(path, as_version=4)
    for i, cell in enumerate(nb.cells):
        if cell.cell_type == "code":
            assert cell.outputs == [] and cell.execution_count is None, f"cell {i} has outputs"
    tags = [t for cell in nb.cells for t in cell.metadata.get("tags", [])]
    assert tags.count("digest") == 1 and "plot" in tags
    assert len(nb.metadata["ddes"]["digest"]) == 64


@pytest.mark.parametrize("path", NOTEBOOKS, ids=[p.stem for p in NOTEBOOKS])
def test_notebook_runs_draws_and_keeps_its_digest(path: Path) -> None:
    make = _make()
    nb, seconds = make.execute(path, timeout=120)
    print(f"{path.stem}: {seconds:.1f} s")
    for i, cell in enumerate(nb.cells):
        if cell.cell_type != "code":
            continue
        errors = [o for o in cell.outputs if o.output_type == "error"]
        assert not errors, f"cell {i}: {errors[0].ename}: {errors[0].evalue}"
        if "plot" in cell.metadata.get("tags", []):
            images = [o for o in cell.outputs
                      if {"image/png", "image/svg+xml"} & set(o.get("data", {}))]
            assert images, f"cell {i} is tagged plot but shows no image:\n{cell.source}"
    assert make.printed_digest(nb) == nb.metadata["ddes"]["digest"], (
        "the trace changed; if that was deliberate: "
        f"python course_notebooks/make.py --record-digests {path.stem}")
    assert seconds < BUDGET_S
