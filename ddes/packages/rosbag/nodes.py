"""Node types of ``rosbag``: ``record`` and ``play``, as launch files and ``rosrun`` start them.

``<node pkg="rosbag" type="record" name="rec" args="-a -O out.bag"/>`` and
``<node pkg="rosbag" type="play" name="player" args="--clock -r 0.5 $(find
pkg)/data/x.bag"/>`` run the C++ programs of ros_comm's ``tools/rosbag``
(``record.cpp``, ``play.cpp``); so do these, on :class:`~ddes.rosbag.Recorder`
and :class:`~ddes.rosbag.Player`:

* the command line is the programs' (:mod:`ddes.rosbag.options`, the same
  options as the console's ``rosbag record``/``play``); a bad one logs
  ``Error reading options: ...`` and exits 1;
* the node is named as roslaunch or rosrun name it (``name="rec"`` gives
  ``/rec``); without a name it is anonymous (``/record_<n>``), as
  ``ros::init_options::AnonymousName``;
* ``record`` runs until ``--duration``/``--limit`` end it or the node shuts
  down (the launch ending, Ctrl+C, ``rosnode kill``), and writes the bag then,
  as record.cpp does; ``play`` ends when the bag is done (so a
  ``required="true"`` player ends the launch), ``--loop`` plays it again and
  again, ``--keep-alive`` stays;
* what the programs print outside their logger (``Hit space to toggle
  paused``, ``Done.``, ``No topics specified.``) goes to the node's standard
  output or error (:func:`ddes.nodes.print_line`): on the screen with
  ``output="screen"`` or ``rosrun``, only the errors otherwise;
* relative bag names start at the directory the node was started in
  (:func:`ddes.nodes.node_cwd`); a default recording name takes its date
  from ``DDES_BAG_DATE`` (read when the recording starts) unless the world has
  one (:func:`ddes.rosbag.recorder.set_record_date`).
"""

from __future__ import annotations

import os
from typing import TYPE_CHECKING

from ddes.errors import DdesError, ROSBagException, ROSBagUnindexedException
from ddes.nodes import NodeType, node_cwd, print_line
from ddes.rosbag import Player, Recorder
from ddes.rosbag.options import BagOptionsError, parse_play_args, parse_record_args
from ddes.rosbag.player import NO_MESSAGES
from ddes.rosbag.recorder import default_record_date

if TYPE_CHECKING:
    from simpy.events import ProcessGenerator

    from ddes.graph.node import Node


def _unsupported(node: Node, what: list[str]) -> int:
    node.logerr("Error reading options: ddes does not model %s (see docs/bags.md)", ", ".join(what))
    return 1


def record(node: Node) -> ProcessGenerator:
    """``record [options] [TOPIC ...]``: rosbag record (record.cpp) on this node; exit code 0/1."""
    try:
        opts = parse_record_args(node.argv)
    except BagOptionsError as exc:
        node.logerr("Error reading options: %s", exc)
        return 1
    if isinstance(opts, str):  # -h
        for line in opts.splitlines():
            print_line(node, line)
        return 0
    if opts.unsupported:
        return _unsupported(node, opts.unsupported)
    if opts.node:
        print_line(node, f"Recording from: {opts.node}")
    if opts.exclude and not (opts.all or opts.regex):
        print_line(node, "Warning: Exclusion regex given, but no topics to subscribe to.",
                   stderr=True)
        print_line(node, "Adding implicit 'record all'.", stderr=True)
    if not opts.topics:
        if opts.limit > 0:
            print_line(node, "Specifying a count is not valid with automatic topic subscription.",
                       stderr=True)
            return 1
        if not opts.all and not opts.node and not opts.exclude:
            print_line(node, "No topics specified.", stderr=True)
            return 1
    world = node.world
    try:
        # The program reads its environment (DDES_BAG_DATE stands in for the machine's clock).
        rec = Recorder(world, opts.topics, on_node=node, cwd=node_cwd(node),
                       date=default_record_date(world, os.environ), **opts.recorder_kwargs())
    except ROSBagException as exc:
        node.logerr("%s", exc)  # record.cpp: "Error writing: ..."
        return 1
    except DdesError as exc:
        node.logerr("Error reading options: %s", exc)
        return 1
    yield rec.done
    return 0


def play(node: Node) -> ProcessGenerator:
    """``play [options] BAGFILE ...``: rosbag play (play.cpp) on this node; ends with the bag."""
    try:
        opts = parse_play_args(node.argv)
    except BagOptionsError as exc:
        node.logerr("Error reading options: %s", exc)
        return 1
    if isinstance(opts, str):  # -h
        for line in opts.splitlines():
            print_line(node, line)
        return 0
    if opts.unsupported:
        return _unsupported(node, opts.unsupported)
    try:
        player = Player(node.world, opts.bags, on_node=node, cwd=node_cwd(node),
                        out=lambda line: print_line(node, line), **opts.player_kwargs())
    except ROSBagUnindexedException as exc:
        print_line(node, str(exc), stderr=True)  # play.cpp returns from publish(): exit 0
        return 0
    except ROSBagException as exc:
        if str(exc) == NO_MESSAGES:
            print_line(node, NO_MESSAGES, stderr=True)  # play.cpp shuts down: exit 0
            return 0
        node.logfatal("%s", exc)  # play.cpp: ROS_FATAL of the bag's exception, exit 1
        return 1
    except DdesError as exc:
        node.logfatal("%s", exc)  # options_.check() in publish(): ROS_FATAL, exit 1
        return 1
    try:
        yield player.done
    except ROSBagException as exc:
        node.logfatal("%s", exc)
        return 1
    return 0


NODES: dict[str, NodeType] = {
    "record": NodeType(record, name="record", anonymous=True, log_style="roscpp",
                       doc=record.__doc__ or ""),
    "play": NodeType(play, name="play", anonymous=True, log_style="roscpp",
                     doc=play.__doc__ or ""),
}
