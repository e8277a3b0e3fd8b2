"""course_notebooks/: every notebook runs cleanly from any folder, draws its pictures with
labelled axes, and prints its digest.

Each notebook is executed as Jupyter runs it (nbclient, kernel python3, MPLBACKEND=Agg), with
the kernel started in a temporary folder rather than course_notebooks/ (a notebook must not
depend on the folder it runs in): no cell may raise, every cell tagged ``plot`` must show an
image, and the cell tagged ``digest`` must print the trace digest stored in the notebook's
``metadata["ddes"]["digest"]`` (after a deliberate change of behaviour:
``python course_notebooks/make.py --record-digests NAME``).  Two cells the test adds around the
notebook's own record every matplotlib figure the kernel made and report its axes: each shown
axes needs an x and a y label (an x label of a twin or shared axes counts for all), and a
numeric axis a unit in brackets (``time [s]``) or a count (``number of seeds``); category axes
(tick labels, such as a kill matrix's rows) need a label, not a unit.  The committed files carry
no outputs and are exactly what ``course_notebooks/make.py`` writes from
``course_notebooks/src/``.
"""

from __future__ import annotations

import importlib.util
import json
import os
import re
import shlex
import shutil
import subprocess
import sys
from pathlib import Path
from types import ModuleType
from typing import Any

import nbformat
import pytest
import tomllib

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


#: Run before the notebook's cells: every matplotlib Figure made from then on is kept.
PROBE = """\
import matplotlib.figure as _probe_mpl
_probe_figures = []
_probe_init = _probe_mpl.Figure.__init__
def _probe_record(self, *args, **kwargs):
    _probe_init(self, *args, **kwargs)
    _probe_figures.append(self)
_probe_mpl.Figure.__init__ = _probe_record
"""

#: Run after them: what each kept figure's axes show, as one JSON line.
REPORT = """\
import json as _probe_json
from matplotlib.ticker import FixedFormatter as _probe_fixed, FuncFormatter as _probe_func
def _probe_axes(fig):
    axes = list(fig.axes)
    out = []
    for ax in axes:
        legend = ax.get_legend()
        out.append({
            "shown": bool(ax.get_visible() and ax.axison),
            "title": ax.get_title() or (fig.texts[0].get_text() if fig.texts else ""),
            "x": ax.get_xlabel(), "y": ax.get_ylabel(),
            "x_shared": [axes.index(o) for o in ax.get_shared_x_axes().get_siblings(ax)
                         if o in axes],
            "x_categories": isinstance(ax.xaxis.get_major_formatter(), (_probe_fixed, _probe_func)),
            "y_categories": isinstance(ax.yaxis.get_major_formatter(), (_probe_fixed, _probe_func)),
            "y_ticks": [t.get_text() for t in ax.get_yticklabels()],
            "legend": None if legend is None else [t.get_text() for t in legend.get_texts()],
            "colorbar": hasattr(ax, "_colorbar"),
        })
    return out
print("FIGURES " + _probe_json.dumps([_probe_axes(f) for f in _probe_figures]))
"""

#: A numeric axis's label names its unit: ``time [s]``, ``a_x [m/s²]``, or counts something.
UNIT = re.compile(r"\[[^\]]+\]|^number of ")


def unlabelled(figures: list[list[dict[str, Any]]]) -> list[str]:
    """What is missing on the figures the report cell described, one line each."""
    bad = []
    for f, axes in enumerate(figures):
        for a, ax in enumerate(axes):
            if not ax["shown"] or ax["colorbar"]:
                continue
            where = f"figure {f + 1} ({ax['title']!r}), axes {a + 1}"
            xlabels = [axes[i]["x"] for i in ax["x_shared"]] + [ax["x"]]
            xlabel = next((x for x in xlabels if x), "")
            for name, label, categories in (("x", xlabel, ax["x_categories"]),
                                            ("y", ax["y"], ax["y_categories"])):
                if not label:
                    bad.append(f"{where}: no {name} label")
                elif not categories and not UNIT.search(label):
                    bad.append(f"{where}: the {name} label {label!r} names no unit "
                               "('[unit]', or 'number of ...')")
    return bad


def test_unlabelled_axes_are_found() -> None:
    ok = {"shown": True, "title": "t", "x": "time [s]", "y": "speed [m/s]", "x_shared": [0],
          "x_categories": False, "y_categories": False, "y_ticks": [], "legend": None,
          "colorbar": False}
    twin = {**ok, "x": "", "y": "", "x_shared": [0, 1]}
    assert unlabelled([[ok, {**twin, "y": "turn rate [rad/s]"}]]) == []
    assert unlabelled([[ok, twin]]) == ["figure 1 ('t'), axes 2: no y label"]
    assert unlabelled([[{**ok, "y": "speed"}]]) == [
        "figure 1 ('t'), axes 1: the y label 'speed' names no unit ('[unit]', or "
        "'number of ...')"]
    assert unlabelled([[{**ok, "y": "mutant", "y_categories": True},
                        {**ok, "shown": False, "x": ""}]]) == []


def _run(path: Path, cwd: Path) -> tuple[Any, float, list[list[dict[str, Any]]]]:
    """Execute the notebook with the probe and report cells around it, kernel in ``cwd``."""
    make = _make()
    nb = nbformat.read(path, as_version=4)
    nb.cells = [nbformat.v4.new_code_cell(PROBE), *nb.cells, nbformat.v4.new_code_cell(REPORT)]
    nb, seconds = make.execute(nb, timeout=120, cwd=cwd)
    printed = "".join(o.get("text", "") for o in nb.cells[-1].outputs
                      if o.output_type == "stream")
    reports = [line[len("FIGURES "):] for line in printed.splitlines()
               if line.startswith("FIGURES ")]
    assert len(reports) == 1, f"the report cell printed {printed!r}; outputs: " \
        f"{nb.cells[-1].outputs}"
    nb.cells = nb.cells[1:-1]
    return nb, seconds, json.loads(reports[0])


@pytest.mark.parametrize("path", NOTEBOOKS, ids=[p.stem for p in NOTEBOOKS])
def test_notebook_runs_from_any_folder_draws_labelled_figures_and_keeps_its_digest(
        path: Path, tmp_path: Path) -> None:
    make = _make()
    nb, seconds, figures = _run(path, tmp_path)
    print(f"{path.stem}: {seconds:.1f} s, {len(figures)} figure(s)")
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
    assert figures, "the notebook made no matplotlib figure"
    assert unlabelled(figures) == []
    if path.stem == "00_grading":  # the kill matrix: a label per row, a legend for its marks
        (matrix,) = [axes[0] for axes in figures if "kill matrix" in axes[0]["title"]]
        assert matrix["y_ticks"] and all(matrix["y_ticks"])
        assert len(set(matrix["y_ticks"])) == len(matrix["y_ticks"])
        assert matrix["legend"] is not None and len(matrix["legend"]) >= 3
        assert any("must lose" in text for text in matrix["legend"])
    if path.stem in TWO_UNITS:  # two units, two y-axes (twinx), each named with its unit
        left, right = TWO_UNITS[path.stem]
        assert any(len(axes) == 2 and left in axes[0]["y"] and right in axes[1]["y"]
                   and 1 in axes[0]["x_shared"] for axes in figures), figures
    assert seconds < BUDGET_S


#: Notebooks with an overlay of two units: (the left axis's unit, the right one's).
TWO_UNITS = {"01_graph_console": ("[m/s]", "[rad/s]"),
             "05_crash_debugging": ("[m/s²]", "[m/s]")}


def _readme_notebook_commands() -> list[str]:
    text = (ROOT / "README.md").read_text(encoding="utf-8")
    start = text.index("\n## Notebooks")
    section = text[start:text.index("\n## ", start + 1)]
    return [line for block in re.findall(r"```sh\n(.*?)```", section, flags=re.S)
            for line in block.splitlines() if line.strip()]


def test_the_readmes_install_runs_the_notebooks(tmp_path: Path) -> None:
    """README's notebook commands: the extra they install brings what runs them (Jupyter's
    metapackage has nbconvert; nbclient and ipykernel are named), and the nbconvert command
    executes every notebook into a folder of its own, never over the committed files.  Where
    nbconvert is installed (the notebooks extra) it runs that command on one notebook, from
    another folder."""
    commands = _readme_notebook_commands()
    install = next(c for c in commands if "pip install" in c)
    assert '".[notebooks]"' in install and "jupyter lab course_notebooks/" in install
    extra = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"][
        "optional-dependencies"]["notebooks"]
    assert {re.split(r"[<>=]", r)[0] for r in extra} >= {"jupyter", "nbclient", "ipykernel"}
    (run,) = [c for c in commands if "nbconvert" in c]
    words = shlex.split(run)
    assert words[:4] == [".venv/bin/jupyter", "nbconvert", "--to", "notebook"]
    assert "--execute" in words and words[-1] == "course_notebooks/*.ipynb"
    assert "--inplace" not in words and "--output-dir" in words
    nbconvert = Path(sys.executable).parent / "jupyter-nbconvert"
    if not nbconvert.exists() and shutil.which("jupyter-nbconvert") is None:
        pytest.skip("nbconvert is not installed (pip install \".[notebooks]\")")
    where = words.index("--output-dir") + 1
    cmd = [str(Path(sys.executable).parent / "jupyter"), *words[1:where], str(tmp_path / "out"),
           str(FOLDER / "04a_services.ipynb")]
    done = subprocess.run(cmd, cwd=tmp_path, capture_output=True, text=True, timeout=300,
                          env={**os.environ, "MPLBACKEND": "Agg"})
    assert done.returncode == 0, done.stderr[-3000:]
    executed = nbformat.read(tmp_path / "out" / "04a_services.ipynb", as_version=4)
    assert _make().printed_digest(executed) == executed.metadata["ddes"]["digest"]
