"""Node types of ``tf2_tools``: ``view_frames.py`` (docs/tf.md).

``rosrun tf2_tools view_frames.py`` is ``tf2_tools/scripts/view_frames.py``: a rospy node
``/view_frames`` listens to TF for 5 s of ROS time (a Buffer with ``~tf2_frames``, a
TransformListener), then writes ``frames.gv`` (the script's own dot text, from the buffer's
``all_frames_as_yaml``) in the directory it was started in.  Where the script runs graphviz
(``dot -Tpdf frames.gv -o frames.pdf``), ddes draws ``frames.pdf`` with matplotlib
(:func:`ddes.tf2_ros.plot_frames`): ddes needs no graphviz.
"""

from __future__ import annotations

import os
from typing import TYPE_CHECKING

from ddes.nodes import NodeType, node_cwd
from ddes.tf2_ros import Buffer, TransformListener
from ddes.tf2_ros.tools import frames_data, generate_dot

if TYPE_CHECKING:
    from simpy.events import ProcessGenerator

    from ddes.graph.node import Node


def view_frames(node: Node) -> ProcessGenerator:
    """Listen to TF for 5 s, then write frames.gv (and frames.pdf, drawn by matplotlib)."""
    node.loginfo("Listening to tf data during 5 seconds...")
    yield node.sleep(0.00001)
    buffer = Buffer(debug=True, node=node)
    TransformListener(node, buffer)
    yield node.sleep(5.0)
    node.loginfo("Generating graph in frames.pdf file...")
    data = frames_data(buffer)
    folder = node_cwd(node) or os.getcwd()
    with open(os.path.join(folder, "frames.gv"), "w", encoding="utf-8") as f:
        f.write(generate_dot(data, node.get_rostime().to_sec()))
    from ddes.tf2_ros.plot import plot_frames

    fig = plot_frames(data, title="view_frames Result")
    fig.savefig(os.path.join(folder, "frames.pdf"), format="pdf",
                metadata={"CreationDate": None, "ModDate": None})
    return 0


NODES: dict[str, NodeType] = {
    "view_frames.py": NodeType(view_frames, name="view_frames", doc=view_frames.__doc__ or ""),
}
