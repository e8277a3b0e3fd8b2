"""DisplayFigure: what IPython's display formatter (Jupyter's) makes of ddes figures."""

from __future__ import annotations

import subprocess
import sys

import pytest
from IPython.core.formatters import DisplayFormatter
from matplotlib.backends.backend_agg import FigureCanvasAgg

from ddes.display.figure import DisplayFigure, new_figure
from ddes.errors import DdesValueError


def figure() -> DisplayFigure:
    fig = new_figure(figsize=(4.0, 2.0))
    fig.add_subplot(1, 1, 1).plot([0, 1], [1, 0])
    return fig


def test_a_notebook_shows_one_png_with_its_size() -> None:
    data, metadata = DisplayFormatter().format(figure())
    assert sorted(data) == ["image/png", "text/plain"]  # one picture, no svg twin
    assert data["image/png"][:8] == b"\x89PNG\r\n\x1a\n"
    assert data["text/plain"].startswith("<DisplayFigure size 400x200")
    size = metadata["image/png"]
    assert 300 < size["width"] <= 400 and 100 < size["height"] <= 200
    png = figure().to_png()  # drawn at twice the CSS size
    assert int.from_bytes(png[16:20], "big") == pytest.approx(2 * size["width"], abs=2)


def test_svg_instead_of_png() -> None:
    fig = figure()
    fig.display_format = "svg"
    data, _ = DisplayFormatter().format(fig)
    assert sorted(data) == ["image/svg+xml", "text/plain"]
    assert "<svg" in data["image/svg+xml"]
    with pytest.raises(DdesValueError, match="display_format must be one of"):
        fig.display_format = "jpeg"


def test_made_without_pyplot() -> None:
    fig = figure()
    assert isinstance(fig.canvas, FigureCanvasAgg)
    assert "matplotlib.pyplot" not in sys.modules or fig not in [
        m.canvas.figure for m in sys.modules["matplotlib._pylab_helpers"].Gcf.get_all_fig_managers()]


def test_import_ddes_loads_no_matplotlib() -> None:
    code = ("import sys, ddes, ddes.actionlib, ddes.rosbag, ddes.display\n"
            "print(sorted(m for m in sys.modules if m.split('.')[0] == 'matplotlib'))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "[]"
