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
        pass  # your code here: the two publishers, the TF buffer and listener
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
        pass  # your code here: ~p_gain and ~speed
        pass  # your code here: ~stop_service_name

    def stop_callback(self, request):
        """The emergency stop: data true stops the robot at once (a zero Twist) and keeps it
        stopped; data false lets the controller drive again."""
        raise NotImplementedError("your code here")

    def scan_callback(self, scan):
        """Find the pillar in one scan, steer towards it, mark it."""
        raise NotImplementedError("your code here")

    def publish_marker(self, header, distance, angle):
        """A sphere at the pillar, transformed from the laser's frame into odom with TF at the
        scan's stamp."""
        raise NotImplementedError("your code here")


if __name__ == "__main__":
    rospy.init_node("smb_highlevel_controller")
    controller = SmbHighlevelController()
    rospy.spin()
