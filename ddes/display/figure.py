"""A matplotlib Figure that a notebook shows as it is, made without pyplot.

``DisplayFigure`` is a :class:`matplotlib.figure.Figure` with an Agg canvas
and ``_repr_png_``: IPython's display formatter (what Jupyter calls on the
last value of a cell) finds the method and shows the picture, with no
``%matplotlib inline`` and whatever the backend.  The figure is not in
pyplot's list of figures, so no GUI window opens, nothing leaks between
cells, and the inline backend does not show it a second time.

One picture per output: the PNG by default (drawn at twice its CSS size, so
it is sharp on high-density screens); ``fig.display_format = "svg"`` makes
the notebook show an SVG instead (``_repr_png_`` then returns None, and
IPython leaves PNG out of the output).
"""

from __future__ import annotations

import io
import struct
from typing import Any

from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure

from ddes.errors import DdesValueError

__all__ = ["DISPLAY_FORMATS", "DisplayFigure", "new_figure"]

#: What ``DisplayFigure.display_format`` may be.
DISPLAY_FORMATS = ("png", "svg")


class DisplayFigure(Figure):
    """A Figure that displays itself in Jupyter (``_repr_png_`` / ``_repr_svg_``)."""

    #: CSS pixels per inch of the picture in a notebook.
    display_dpi: float = 100.0
    #: The PNG is drawn at this many device pixels per CSS pixel.
    display_scale: float = 2.0

    _display_format: str = "png"

    @property
    def display_format(self) -> str:
        """``"png"`` (default) or ``"svg"``: the one picture a notebook shows."""
        return self._display_format

    @display_format.setter
    def display_format(self, value: str) -> None:
        if value not in DISPLAY_FORMATS:
            raise DdesValueError(f"display_format must be one of {DISPLAY_FORMATS}, got {value!r}")
        self._display_format = value

    def _render(self, fmt: str, dpi: float) -> bytes:
        buf = io.BytesIO()
        self.savefig(buf, format=fmt, dpi=dpi, bbox_inches="tight", facecolor="white")
        return buf.getvalue()

    def to_png(self) -> bytes:
        """The PNG a notebook shows (``display_dpi * display_scale`` pixels per inch)."""
        return self._render("png", self.display_dpi * self.display_scale)

    def to_svg(self) -> str:
        """The figure as SVG text."""
        return self._render("svg", self.display_dpi).decode("utf-8")

    def _repr_png_(self) -> tuple[bytes, dict[str, int]] | None:
        if self._display_format != "png":
            return None
        data = self.to_png()
        width, height = struct.unpack(">II", data[16:24])  # the IHDR chunk
        return data, {"width": round(width / self.display_scale),
                      "height": round(height / self.display_scale)}

    def _repr_svg_(self) -> str | None:
        if self._display_format != "svg":
            return None
        return self.to_svg()


def new_figure(**kwargs: Any) -> DisplayFigure:
    """A :class:`DisplayFigure` on an Agg canvas (keyword arguments as for ``Figure``)."""
    fig = DisplayFigure(**kwargs)
    FigureCanvasAgg(fig)
    return fig
