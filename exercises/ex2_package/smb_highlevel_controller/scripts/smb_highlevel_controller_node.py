#!/usr/bin/env python3
"""The SMB high-level controller: prints the smallest distance of every laser scan."""

import os
import sys

import rospy
from sensor_msgs.msg import LaserScan

# On a robot, catkin_python_setup() puts src/ on the path; from the source tree this line does.
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), os.pardir, "src"))
from smb_highlevel_controller.algorithm import smallest_range  # noqa: E402


class SmbHighlevelController:
    """The node's ROS interface: parameters, the scan subscriber."""

    def __init__(self):
        self.read_parameters()
        raise NotImplementedError("your code here")
        rospy.loginfo("smb_highlevel_controller started")

    def read_parameters(self):
        """Read the topic name and the queue size from the private parameters."""
        raise NotImplementedError("your code here")

    def scan_callback(self, scan):
        """Log the smallest distance of one scan."""
        raise NotImplementedError("your code here")


if __name__ == "__main__":
    rospy.init_node("smb_highlevel_controller")
    controller = SmbHighlevelController()
    rospy.spin()
