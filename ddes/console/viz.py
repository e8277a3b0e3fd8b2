"""``rviz``, ``rqt_plot`` and ``rqt_graph`` in the console: they write PNG files.

ROS's tools open windows; these draw the same pictures with matplotlib (no pyplot, no
display needed) into a PNG in the console's current directory (``roscd``/``cd`` move it) and
print its path.  They never open the file (a deviation: there may be no display):

* ``rviz [-o FILE] [--markers TOPIC] [--no-scan] [--odometry] [--simulator NODE]``: the
  simulator's top view now (:func:`ddes.sim.view.top_view`), ``rviz.png``;
* ``rqt_plot [-o FILE] [--bag BAG] FIELD [FIELD ...]``: fields over time from the world's
  trace or a bag (:func:`ddes.rqt.plot.rqt_plot`), ``rqt_plot.png``;
* ``rqt_graph [-o FILE] [--debug]``: the node/topic graph now
  (:func:`ddes.rqt.graph.rqt_graph`), ``rqt_graph.png``.

``ddes rqt_plot --bag run.bag FIELD ...`` does the same on a bag file from the shell.
"""

from __future__ import annotations

import argparse
import os
import sys
from collections.abc import Callable, Sequence
from typing import TYPE_CHECKING, Any, NoReturn

from ddes.errors import ROSConsoleError

if TYPE_CHECKING:
    from ddes.console.tooling import ToolContext

__all__ = ["TOOLS", "find_simulator", "register", "rqt_graph_tool", "rqt_plot_main",
           "rqt_plot_tool", "rviz_tool"]


class _Exit(Exception):
    def __init__(self, code: int) -> None:
        super().__init__(code)
        self.code = code


class _Parser(argparse.ArgumentParser):
    """argparse writing through the tool's sinks, never calling sys.exit."""

    def __init__(self, out: Callable[[str], None], err: Callable[[str], None], **kw: Any) -> None:
        super().__init__(**kw)
        self._out, self._err = out, err

    def error(self, message: str) -> NoReturn:
        self._err(self.format_usage().rstrip())
        self._err(f"{self.prog}: error: {message}")
        raise _Exit(2)

    def exit(self, status: int = 0, message: str | None = None) -> NoReturn:
        if message:
            self._err(message.rstrip())
        raise _Exit(status)

    def print_help(self, file: Any = None) -> None:
        self._out(self.format_help().rstrip())


def _parse(parser: _Parser, argv: Sequence[str]) -> argparse.Namespace | int:
    try:
        return parser.parse_args(list(argv))
    except _Exit as done:
        return done.code


def _write(ctx: ToolContext, fig: Any, path: str) -> int:
    target = ctx.resolve_path(path)
    try:
        fig.savefig(target, format="png", dpi=120, facecolor="white")
    except OSError as exc:
        raise ROSConsoleError(f"cannot write {target}: {exc.strerror or exc}") from None
    ctx.print(f"wrote {os.path.abspath(target)}")
    return 0


def find_simulator(world: Any, name: str | None = None) -> Any:
    """The world's Simulator (the one on node ``name`` when given)."""
    from ddes.sim.simulator import Simulator

    found = [(n, e) for n in sorted(world.nodes) for e in world.nodes[n].entities
             if isinstance(e, Simulator)]
    if name is not None:
        found = [(n, e) for n, e in found if n == name or n == "/" + name.lstrip("/")]
    if not found:
        raise ROSConsoleError("rviz: no simulator " + (f"on node {name} " if name else "")
                              + "is running (start one: rosrun ddes_sim simulator)")
    return found[0][1]


def rviz_tool(ctx: ToolContext, argv: list[str]) -> int:
    """``rviz``: the simulator's top view as a PNG."""
    p = _Parser(ctx.print, ctx.eprint, prog="rviz", description="write the simulator's top view "
                "(world, robot, scan, frames, trajectory) as a PNG")
    p.add_argument("-o", "--output", default="rviz.png", help="file (default rviz.png)")
    p.add_argument("--markers", metavar="TOPIC", help="draw visualization_msgs/Marker of TOPIC")
    p.add_argument("--no-scan", action="store_true", help="leave out the laser scan")
    p.add_argument("--odometry", action="store_true", help="add the odometry's footprint")
    p.add_argument("--simulator", metavar="NODE", help="the simulator's node (default: the first)")
    args = _parse(p, argv)
    if isinstance(args, int):
        return args
    from ddes.sim.view import top_view

    sim = find_simulator(ctx.world, args.simulator)
    fig = top_view(sim, scan=None if args.no_scan else "latest", markers=args.markers,
                   odometry=args.odometry)
    return _write(ctx, fig, args.output)


def _plot_parser(out: Callable[[str], None], err: Callable[[str], None]) -> _Parser:
    p = _Parser(out, err, prog="rqt_plot", description="plot numeric message fields over time "
                "into a PNG (e.g. /odom/twist/twist/linear/x, /scan/ranges[180], /pose/x:y)")
    p.add_argument("fields", nargs="+", metavar="FIELD")
    p.add_argument("-o", "--output", default="rqt_plot.png", help="file (default rqt_plot.png)")
    p.add_argument("--bag", help="read the messages from this bag instead of the world")
    p.add_argument("--time", choices=("auto", "header", "publish"), default="auto",
                   help="x axis: header stamps when there are (auto), or publish times")
    return p


def rqt_plot_tool(ctx: ToolContext, argv: list[str]) -> int:
    """``rqt_plot``: fields over time as a PNG."""
    args = _parse(_plot_parser(ctx.print, ctx.eprint), argv)
    if isinstance(args, int):
        return args
    from ddes.rqt.plot import rqt_plot

    source = ctx.resolve_path(args.bag) if args.bag else ctx.world
    return _write(ctx, rqt_plot(source, *args.fields, time=args.time), args.output)


def rqt_graph_tool(ctx: ToolContext, argv: list[str]) -> int:
    """``rqt_graph``: the node/topic graph as a PNG."""
    p = _Parser(ctx.print, ctx.eprint, prog="rqt_graph",
                description="draw the nodes and topics of the world into a PNG")
    p.add_argument("-o", "--output", default="rqt_graph.png", help="file (default rqt_graph.png)")
    p.add_argument("--debug", action="store_true", help="show /rosout and /rosout_agg too")
    p.add_argument("--hide-tf", action="store_true", help="leave out /tf and /tf_static")
    p.add_argument("--hide-leaf-topics", action="store_true",
                   help="leave out topics nobody subscribes to")
    args = _parse(p, argv)
    if isinstance(args, int):
        return args
    from ddes.rqt.graph import rqt_graph

    fig = rqt_graph(ctx.world, hide_debug=not args.debug, hide_tf=args.hide_tf,
                    hide_leaf_topics=args.hide_leaf_topics)
    return _write(ctx, fig, args.output)


TOOLS = {"rviz": rviz_tool, "rqt_plot": rqt_plot_tool, "rqt_graph": rqt_graph_tool}


def rqt_plot_main(args: argparse.Namespace) -> int:
    """``ddes rqt_plot --bag run.bag FIELD ...``: a PNG from a bag file."""
    from ddes.rqt.plot import rqt_plot

    if not args.bag:
        print("ddes rqt_plot: give --bag FILE (a running world's fields: rqt_plot in "
              "'ddes console')", file=sys.stderr)
        return 2
    fig = rqt_plot(args.bag, *args.fields, time=args.time)
    fig.savefig(args.output, format="png", dpi=120, facecolor="white")
    print(f"wrote {os.path.abspath(args.output)}")
    return 0


def register(subparsers: argparse._SubParsersAction[argparse.ArgumentParser]) -> None:
    """Add ``ddes rqt_plot`` (fields of a bag file over time, as a PNG)."""
    tool = subparsers.add_parser(
        "rqt_plot", help="plot numeric fields of a bag's messages over time into a PNG",
        description="plot numeric message fields of a bag over time into a PNG "
                    "(e.g. ddes rqt_plot --bag run.bag /odom/twist/twist/linear/x)")
    tool.add_argument("fields", nargs="+", metavar="FIELD")
    tool.add_argument("--bag", help="the bag file to read (required)")
    tool.add_argument("-o", "--output", default="rqt_plot.png", help="file (default rqt_plot.png)")
    tool.add_argument("--time", choices=("auto", "header", "publish"), default="auto",
                      help="x axis: header stamps when there are (auto), or record times")
    tool.set_defaults(func=rqt_plot_main)
