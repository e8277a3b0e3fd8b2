#!/usr/bin/env python3
"""The SMB high-level controller: drives the robot into the pillar its laser sees (a P controller
on the pillar's bearing), marks the pillar in RViz, in the odom frame, and serves an emergency
stop (std_srvs/SetBool: data true stops the robot, data false lets it drive again)."""

import os
import sys

import rospy
import tf2_ros
from geometry_msgs.msg import Twist
from sensor_msgs.msg import LaserScan
from std_srvs.srv import SetBool, SetBoolResponse
from visualization_msgs.msg import Marker

# On a robot, catkin_python_setup() puts src/ on the path; from the source tree this line does.
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), os.pardir, "src"))
from smb_highlevel_controller.algorithm import (  # noqa: E402
    find_pillar,
    p_control,
    polar_to_point,
    transform_point,
)


class SmbHighlevelController:
    """The node's ROS interface: parameters, the scan subscriber, the command and marker
    publishers, the TF listener."""

    def __init__(self):
        self.read_parameters()
        self.cmd_publisher = rospy.Publisher("/cmd_vel", Twist, queue_size=1)
        self.marker_publisher = rospy.Publisher("visualization_marker", Marker, queue_size=1)
        self.tf_buffer = tf2_ros.Buffer()
        self.tf_listener = tf2_ros.TransformListener(self.tf_buffer)
        self.subscriber = rospy.Subscriber(self.scan_topic, LaserScan, self.scan_callback,
                                           queue_size=self.queue_size)
        self.stopped = False
        pass  # your code here: the SetBool server named by ~stop_service_name
        rospy.loginfo("smb_highlevel_controller started")

    def read_parameters(self):
        """Read the topic name, the queue size, the controller's gain and the forward speed
        from the private parameters."""
        self.scan_topic = rospy.get_param("~scan_topic")
        self.queue_size = int(rospy.get_param("~queue_size"))
        self.p_gain = float(rospy.get_param("~p_gain"))
        self.speed = float(rospy.get_param("~speed"))
        pass  # your code here: ~stop_service_name

    def stop_callback(self, request):
        """The emergency stop: data true stops the robot at once (a zero Twist) and keeps it
        stopped; data false lets the controller drive again."""
        raise NotImplementedError("your code here")

    def scan_callback(self, scan):
        """Find the pillar in one scan, steer towards it, mark it."""
        pillar = find_pillar(scan.ranges, scan.angle_min, scan.angle_increment,
                             scan.range_min, scan.range_max)
        if pillar is None:
            return
        distance, angle = pillar
        self.publish_marker(scan.header, distance, angle)
        pass  # your code here: no driving command while stopped
        twist = Twist()
        twist.linear.x = self.speed
        twist.angular.z = p_control(self.p_gain, angle)
        self.cmd_publisher.publish(twist)

    def publish_marker(self, header, distance, angle):
        """A sphere at the pillar, transformed from the laser's frame into odom with TF at the
        scan's stamp."""
        try:
            laser_to_odom = self.tf_buffer.lookup_transform("odom", header.frame_id,
                                                            header.stamp, rospy.Duration(0.1))
        except tf2_ros.TransformException as exc:
            rospy.logwarn("no transform from %s to odom: %s", header.frame_id, exc)
            return
        t = laser_to_odom.transform
        x, y, z = transform_point((t.translation.x, t.translation.y, t.translation.z),
                                  (t.rotation.x, t.rotation.y, t.rotation.z, t.rotation.w),
                                  polar_to_point(distance, angle))
        marker = Marker()
        marker.header.frame_id = "odom"
        marker.header.stamp = header.stamp
        marker.ns = "pillar"
        marker.id = 0
        marker.type = Marker.SPHERE
        marker.action = Marker.ADD
        marker.pose.position.x = x
        marker.pose.position.y = y
        marker.pose.position.z = z
        marker.pose.orientation.w = 1.0
        marker.scale.x = marker.scale.y = marker.scale.z = 0.3
        marker.color.r = 1.0
        marker.color.a = 1.0
        self.marker_publisher.publish(marker)


if __name__ == "__main__":
    rospy.init_node("smb_highlevel_controller")
    controller = SmbHighlevelController()
    rospy.spin()
