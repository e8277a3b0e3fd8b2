"""Jupyter display: figures that show themselves and small HTML tables.

A notebook shows the last value of a cell through the value's ``_repr_*_``
methods (IPython's display formatter asks for each format it knows).  This
room holds what the rooms above need for that:

* :mod:`ddes.display.tables` — escaped HTML tables for the ``_repr_html_``
  of ``World``, ``Bag`` and trace selections (no third-party import);
* :mod:`ddes.display.figure` — :class:`~ddes.display.figure.Figure`, a
  matplotlib ``Figure`` with an Agg canvas and ``_repr_png_``, made without
  pyplot, so a cell that returns one shows the picture with no
  ``%matplotlib inline``.  It imports matplotlib; nothing imports it until a
  plot is drawn, so ``import ddes`` does not load matplotlib.
"""

from ddes.display.tables import html_table, html_text, key_value_table

__all__ = ["html_table", "html_text", "key_value_table"]
