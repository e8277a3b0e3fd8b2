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
        ### BEGIN SOLUTION stub: pass  # your code here: wait for the service, its ServiceProxy, the scan subscriber
        rospy.wait_for_service(self.stop_service_name)
        self.stop = rospy.ServiceProxy(self.stop_service_name, SetBool)
        self.subscriber = rospy.Subscriber(self.scan_topic, LaserScan, self.scan_callback,
                                           queue_size=1)
        ### END SOLUTION
        rospy.loginfo("proximity_stop started")

    def scan_callback(self, scan):
        """Stop once when the closest obstacle in front is too close; arm again when it is
        clearly away (20 % farther than the threshold)."""
        ### BEGIN SOLUTION
        distance = closest_in_sector(scan.ranges, scan.angle_min, scan.angle_increment,
                                     scan.range_min, scan.range_max, self.sector_half_angle)
        if too_close(distance, self.min_distance):
            if not self.triggered:
                self.triggered = True
                try:
                    response = self.stop(True)
                    rospy.logwarn("obstacle at %.2f m: emergency stop (%s)", distance,
                                  response.message)
                except rospy.ServiceException as exc:
                    rospy.logerr("emergency stop failed: %s", exc)
        elif distance > 1.2 * self.min_distance:
            self.triggered = False
        ### END SOLUTION


if __name__ == "__main__":
    rospy.init_node("proximity_stop")
    node = ProximityStop()
    rospy.spin()
