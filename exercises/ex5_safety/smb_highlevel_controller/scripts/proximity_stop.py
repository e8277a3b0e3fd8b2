#!/usr/bin/env python3
"""Proximity stop: calls the emergency stop (std_srvs/SetBool, data true) once per approach when
an obstacle in front of the robot comes closer than ~min_distance."""

import os
import sys

import rospy
from sensor_msgs.msg import LaserScan
from std_srvs.srv import SetBool

# On a robot, catkin_python_setup() puts src/ on the path; from the source tree this line does.
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), os.pardir, "src"))
from smb_highlevel_controller.safety import closest_in_sector, too_close  # noqa: E402


class ProximityStop:
    """Watches the laser's front sector and stops the robot before it touches an obstacle."""

    def __init__(self):
        self.scan_topic = rospy.get_param("~scan_topic", "/scan")
        self.min_distance = float(rospy.get_param("~min_distance"))
        self.sector_half_angle = float(rospy.get_param("~sector_half_angle"))
        self.stop_service_name = rospy.get_param("~stop_service_name")
        self.triggered = False
        pass  # your code here: wait for the service, its ServiceProxy, the scan subscriber
        rospy.loginfo("proximity_stop started")

    def scan_callback(self, scan):
        """Stop once when the closest obstacle in front is too close; arm again when it is
        clearly away (20 % farther than the threshold)."""
        raise NotImplementedError("your code here")


if __name__ == "__main__":
    rospy.init_node("proximity_stop")
    node = ProximityStop()
    rospy.spin()
