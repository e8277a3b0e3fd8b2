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
        ### BEGIN SOLUTION stub: pass  # your code here: wait for the service, its ServiceProxy, the IMU subscriber
        rospy.wait_for_service(self.stop_service_name)
        self.stop = rospy.ServiceProxy(self.stop_service_name, SetBool)
        self.subscriber = rospy.Subscriber(self.imu_topic, Imu, self.imu_callback, queue_size=10)
        ### END SOLUTION
        rospy.loginfo("crash_detector started")

    def imu_callback(self, imu):
        """Stop once at the first sample of an impact."""
        ### BEGIN SOLUTION
        ax = imu.linear_acceleration.x
        if self.crashed or not is_crash(ax, self.threshold):
            return
        self.crashed = True
        try:
            response = self.stop(True)
            rospy.logwarn("crash (a_x = %.1f m/s^2): emergency stop (%s)", ax, response.message)
        except rospy.ServiceException as exc:
            rospy.logerr("emergency stop failed: %s", exc)
        ### END SOLUTION


if __name__ == "__main__":
    rospy.init_node("crash_detector")
    node = CrashDetector()
    rospy.spin()
