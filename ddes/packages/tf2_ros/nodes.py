"""Node types of ``tf2_ros``: ``static_transform_publisher`` (docs/tf.md).

``static_transform_publisher x y z yaw pitch roll frame_id child_frame_id``, ``... x y z qx qy
qz qw frame_id child_frame_id`` or ``/param_name`` is
``tf2_ros/src/static_transform_broadcaster_program.cpp``: an anonymous roscpp node that sends
the transform once, stamped now, with a StaticTransformBroadcaster (latched ``/tf_static``),
logs ``Spinning until killed publishing FRAME to CHILD`` and spins; its usage text, its errors
and exit codes are the program's.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from ddes.nodes import NodeType, print_line
from ddes.tf2_ros import StaticTransformBroadcaster
from ddes.tf2_ros.linmath import tf_set_rpy
from ddes.tf2_ros.tools import atof

if TYPE_CHECKING:
    from simpy.events import ProcessGenerator

    from ddes.graph.node import Node

_USAGE = [
    "A command line utility for manually sending a transform.",
    "Usage: static_transform_publisher x y z qx qy qz qw frame_id child_frame_id ",
    "OR ",
    "Usage: static_transform_publisher x y z yaw pitch roll frame_id child_frame_id ",
    "OR ",
    "Usage: static_transform_publisher /param_name ",
    "",
    "This transform is the transform of the coordinate frame from frame_id into the "
    "coordinate frame ",
    "of the child_frame_id.  ",
]


def _valid(tf_data: Any) -> bool:
    """validateXmlRpcTf: the fields a TransformStamped needs are there."""
    def has(d: Any, *keys: str) -> bool:
        for k in keys:
            if not isinstance(d, dict) or k not in d:
                return False
            d = d[k]
        return True

    return (has(tf_data, "child_frame_id") and has(tf_data, "header", "frame_id")
            and all(has(tf_data, "transform", "translation", k) for k in "xyz")
            and all(has(tf_data, "transform", "rotation", k) for k in "xyzw"))


def static_transform_publisher(node: Node) -> ProcessGenerator:
    """Send one static transform on latched /tf_static, then spin until killed."""
    argv = node.argv
    msg = node.world.messages.get_message_class("geometry_msgs/TransformStamped")()
    tr, rot = msg.transform.translation, msg.transform.rotation
    if len(argv) >= 9:
        tr.x, tr.y, tr.z = atof(argv[0]), atof(argv[1]), atof(argv[2])
        rot.x, rot.y, rot.z, rot.w = atof(argv[3]), atof(argv[4]), atof(argv[5]), atof(argv[6])
        msg.header.frame_id, msg.child_frame_id = argv[7], argv[8]
    elif len(argv) == 8:
        tr.x, tr.y, tr.z = atof(argv[0]), atof(argv[1]), atof(argv[2])
        rot.x, rot.y, rot.z, rot.w = tf_set_rpy(atof(argv[5]), atof(argv[4]), atof(argv[3]))
        msg.header.frame_id, msg.child_frame_id = argv[6], argv[7]
    elif len(argv) == 1:
        name = argv[0]
        node.loginfo("Looking for TF in parameter: %s", name)
        if not node.has_param(name):
            node.logfatal("Could not read TF from parameter server: %s", name)
            return 255
        tf_data = node.get_param(name)
        if not _valid(tf_data):
            node.logfatal("Could not validate XmlRpcC for TF data: %s", tf_data)
            return 255
        t, r = tf_data["transform"]["translation"], tf_data["transform"]["rotation"]
        tr.x, tr.y, tr.z = float(t["x"]), float(t["y"]), float(t["z"])
        rot.x, rot.y, rot.z, rot.w = float(r["x"]), float(r["y"]), float(r["z"]), float(r["w"])
        msg.header.frame_id = str(tf_data["header"]["frame_id"])
        msg.child_frame_id = str(tf_data["child_frame_id"])
    else:
        for line in _USAGE:
            print_line(node, line)
        node.logerr("static_transform_publisher exited due to not having the right number of "
                    "arguments")
        return 255
    msg.header.stamp = node.get_rostime()
    if msg.header.frame_id == msg.child_frame_id:
        node.logfatal("target_frame and source frame are the same (%s, %s) this cannot work",
                      msg.header.frame_id, msg.child_frame_id)
        return 1
    StaticTransformBroadcaster(node).sendTransform(msg)
    node.loginfo("Spinning until killed publishing %s to %s", msg.header.frame_id,
                 msg.child_frame_id)
    yield node.spin()
    return 0


NODES: dict[str, NodeType] = {
    "static_transform_publisher": NodeType(
        static_transform_publisher, name="static_transform_publisher", anonymous=True,
        log_style="roscpp", doc=static_transform_publisher.__doc__ or ""),
}
