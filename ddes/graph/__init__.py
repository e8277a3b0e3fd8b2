"""The ROS graph: nodes (and, as they land, master, names, parameters, topics)."""

from ddes.graph.node import Node

__all__ = ["Node"]
