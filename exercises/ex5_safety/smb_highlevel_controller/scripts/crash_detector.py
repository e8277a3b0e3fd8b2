#!/usr/bin/env python3
"""Crash detector: calls the emergency stop (std_srvs/SetBool, data true) when the IMU's forward
acceleration shows an impact (larger in magnitude than ~threshold)."""

import os
import sys

import rospy
from sensor_msgs.msg import Imu
from std_srvs.srv import SetBool

# On a robot, catkin_python_setup() puts src/ on the path; from the source tree this line does.
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), os.pardir, "src"))
from smb_highlevel_controller.safety import is_crash  # noqa: E402


class CrashDetector:
    """Watches /imu/data and stops the robot after a crash."""

    def __init__(self):
        self.imu_topic = rospy.get_param("~imu_topic", "/imu/data")
        self.threshold = float(rospy.get_param("~threshold"))
        self.stop_service_name = rospy.get_param("~stop_service_name")
        self.crashed = False
        pass  # your code here: wait for the service, its ServiceProxy, the IMU subscriber
        rospy.loginfo("crash_detector started")

    def imu_callback(self, imu):
        """Stop once at the first sample of an impact."""
        raise NotImplementedError("your code here")


if __name__ == "__main__":
    rospy.init_node("crash_detector")
    node = CrashDetector()
    rospy.spin()
