"""Node types of ``tf``: ``tf_echo`` and tf1's ``static_transform_publisher`` (docs/tf.md).

* ``tf_echo SOURCE TARGET [rate]`` is ``tf/src/tf_echo.cpp``: an anonymous roscpp node
  (``/tf_echo_<n>``) with a TransformListener; it waits up to 1 s of ROS time for the first
  transform, then at ``rate`` Hz (``~rate``, default 1; a roscpp ``ros::Rate``) prints the
  transform that takes data from TARGET into SOURCE at the latest common time
  (``lookupTransform(SOURCE, TARGET, Time(0))``) as tf_echo prints it, or ``Failure at <now>``,
  ``Exception thrown:<tf2's text>``, ``The current list of frames is:`` and the frames.
* ``static_transform_publisher x y z yaw pitch roll frame child period_ms`` (or ``x y z qx qy qz
  qw frame child period_ms``) is tf1's ``static_transform_publisher.cpp``: every period it
  publishes the transform on ``/tf`` stamped *now + period* (its "future dating"), the rotation
  passed through tf's LinearMath matrix as tf1 does.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from ddes.nodes import NodeType, print_line
from ddes.tf2 import TransformException
from ddes.tf2_ros import Buffer, TimeoutException, TransformListener
from ddes.tf2_ros.linmath import tf_matrix_to_quat, tf_quat_to_matrix, tf_set_rpy
from ddes.tf2_ros.tools import atof, echo_failure_lines, echo_lines
from ddes.time.rostime import Duration, Time

if TYPE_CHECKING:
    from simpy.events import ProcessGenerator

    from ddes.graph.node import Node

_ECHO_USAGE = [
    "Usage: tf_echo source_frame target_frame [echo_rate]",
    "",
    "This will echo the transform from the coordinate frame of the source_frame",
    "to the coordinate frame of the target_frame. ",
    "Note: This is the transform to get data from target_frame into the source_frame.",
    "Default echo rate is 1 if echo_rate is not given.",
]


def _strip(frame: str) -> str:
    """tf1's strip_slash: a leading ``/`` goes."""
    return frame[1:] if frame.startswith("/") else frame


def tf_echo(node: Node) -> ProcessGenerator:
    """``tf_echo source_frame target_frame [echo_rate]``: print the transform at a rate."""
    argv = node.argv
    if len(argv) < 2 or len(argv) > 3:
        for line in _ECHO_USAGE:
            print_line(node, line)
        return 255
    rate_hz = atof(argv[2]) if len(argv) == 3 else float(node.get_param("~rate", 1.0))
    if rate_hz <= 0.0:
        print_line(node, "Echo rate must be > 0.0", stderr=True)
        return 255
    rate = node.create_roscpp_rate(rate_hz)
    buffer = Buffer(node=node)
    TransformListener(node, buffer)
    source, target = _strip(argv[0]), _strip(argv[1])
    try:
        yield buffer.wait_for_transform(source, target, Time(), 1.0)
    except TimeoutException:
        pass  # waitForTransform returns false; the loop prints the failure
    while not node.is_shutdown():
        try:
            t = buffer.lookup_transform_core(source, target, Time())
            lines = echo_lines(t)
        except TransformException as exc:
            lines = echo_failure_lines(node.get_rostime(), exc, buffer.all_frames_as_string())
        for line in lines:
            print_line(node, line)
        yield rate.sleep()
    return 0


_STP_USAGE = [
    "A command line utility for manually sending a transform.",
    "It will periodicaly republish the given transform. ",
    "Usage: static_transform_publisher x y z yaw pitch roll frame_id child_frame_id  "
    "period(milliseconds) ",
    "OR ",
    "Usage: static_transform_publisher x y z qx qy qz qw frame_id child_frame_id  "
    "period(milliseconds) ",
    "",
    "This transform is the transform of the coordinate frame from frame_id into the "
    "coordinate frame ",
    "of the child_frame_id.  ",
]


def static_transform_publisher(node: Node) -> ProcessGenerator:
    """tf1's ``static_transform_publisher ... period_ms``: /tf every period, future-dated."""
    argv = node.argv
    if len(argv) not in (9, 10):
        for line in _STP_USAGE:
            print_line(node, line)
        node.logerr("static_transform_publisher exited due to not having the right number of "
                    "arguments")
        return 255
    nums = [atof(a) for a in argv[:len(argv) - 3]]
    frame, child, period = argv[-3], argv[-2], atof(argv[-1]) / 1000.0
    if frame == child:
        node.logfatal("target_frame and source frame are the same (%s, %s) this cannot work",
                      frame, child)
    if not period > 0.0:
        node.logfatal("static_transform_publisher: a period of %s ms would publish without end "
                      "in one instant of simulated time (give a period > 0)", argv[-1])
        return 1
    if len(nums) == 6:
        quat = tf_set_rpy(nums[5], nums[4], nums[3])  # q.setRPY(roll, pitch, yaw)
    else:
        quat = (nums[3], nums[4], nums[5], nums[6])
    qx, qy, qz, qw = tf_matrix_to_quat(tf_quat_to_matrix(*quat))  # tf::Transform's basis
    from ddes.tf2_ros import TransformBroadcaster

    broadcaster = TransformBroadcaster(node)
    stamped = node.world.messages.get_message_class("geometry_msgs/TransformStamped")
    sleeper = Duration.from_sec(period)
    while not node.is_shutdown():
        t = stamped()
        t.header.stamp = node.get_rostime() + sleeper
        t.header.frame_id = frame
        t.child_frame_id = child
        t.transform.translation.x, t.transform.translation.y, t.transform.translation.z = \
            nums[0], nums[1], nums[2]
        (t.transform.rotation.x, t.transform.rotation.y, t.transform.rotation.z,
         t.transform.rotation.w) = qx, qy, qz, qw
        broadcaster.sendTransform(t)
        yield node.duration_sleep(sleeper)
    return 0


NODES: dict[str, NodeType] = {
    "tf_echo": NodeType(tf_echo, name="tf_echo", anonymous=True, log_style="roscpp",
                        doc=tf_echo.__doc__ or ""),
    "static_transform_publisher": NodeType(
        static_transform_publisher, name="static_transform_publisher", anonymous=True,
        log_style="roscpp", doc=static_transform_publisher.__doc__ or ""),
}
