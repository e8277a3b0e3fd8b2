"""rqt's pictures, drawn with matplotlib (no pyplot): ``rqt_plot`` and ``rqt_graph``.

* :func:`ddes.rqt.plot.rqt_plot` — time series of numeric message fields
  (``rqt_plot(world, "/odom/twist/twist/linear/x")``), read from the world's
  trace (every ``topic.publish`` event holds the message's bytes) or from a bag;
* :func:`ddes.rqt.graph.rqt_graph` — the node/topic graph of a running world
  (nodes as ellipses, topics as boxes, a layered left-to-right layout of its own).

Each returns a :class:`ddes.display.figure.DisplayFigure`: a notebook shows it as it
is, ``fig.savefig("x.png")`` writes it.  matplotlib is imported only when a picture is
drawn.  See docs/sim.md, "Pictures".
"""

from ddes.rqt.graph import GraphData, graph_data, layered_layout, rqt_graph
from ddes.rqt.plot import Series, field_series, rqt_plot

__all__ = ["GraphData", "Series", "field_series", "graph_data", "layered_layout", "rqt_graph",
           "rqt_plot"]
