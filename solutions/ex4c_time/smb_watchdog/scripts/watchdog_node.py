#!/usr/bin/env python3
"""The SMB watchdog (lecture 4, ROS time): a heartbeat on /heartbeat at ~rate in ROS time, a
watchdog that stops the robot when /odom has been silent for ~timeout seconds of ROS time, and a
status line every second of wall time."""

import threading
import time

import rospy
from geometry_msgs.msg import Twist
from nav_msgs.msg import Odometry
from std_msgs.msg import Header


class Watchdog:
    """The node's ROS interface: parameters, the heartbeat and command publishers, the odometry
    subscriber, the watchdog timer and the status thread."""

    def __init__(self):
        self.rate = float(rospy.get_param("~rate"))
        self.timeout = float(rospy.get_param("~timeout"))
        self.heartbeat_publisher = rospy.Publisher("/heartbeat", Header, queue_size=10)
        self.cmd_publisher = rospy.Publisher("/cmd_vel", Twist, queue_size=1)
        self.last_odom = None
        self.odom_subscriber = rospy.Subscriber("/odom", Odometry, self.odom_callback,
                                                queue_size=10)
        self.watchdog_timer = rospy.Timer(rospy.Duration(0.1), self.watchdog_tick)
        self.status_thread = threading.Thread(target=self.status_loop)
        self.status_thread.start()

    def heartbeat_loop(self):
        """Publish a Header stamped with the ROS time now, ~rate times per second of ROS time,
        until shutdown. Nothing before the first /clock; survive /clock jumping back."""
        ### BEGIN SOLUTION
        rate = rospy.Rate(self.rate, reset=True)
        while not rospy.is_shutdown():
            rate.sleep()
            header = Header()
            header.stamp = rospy.Time.now()
            header.frame_id = "watchdog"
            self.heartbeat_publisher.publish(header)
        ### END SOLUTION

    def odom_callback(self, odom):
        """Remember when (in ROS time) odometry last arrived."""
        ### BEGIN SOLUTION
        self.last_odom = rospy.Time.now()
        ### END SOLUTION

    def watchdog_tick(self, event):
        """Every 0.1 s of ROS time: when /odom has been silent for longer than ~timeout, publish
        a zero Twist on /cmd_vel and warn (once)."""
        ### BEGIN SOLUTION
        now = rospy.Time.now()
        if self.last_odom is None:
            self.last_odom = now  # the silence counts from the first tick
        if now - self.last_odom > rospy.Duration(self.timeout):
            self.cmd_publisher.publish(Twist())
            rospy.logwarn_once("no odometry for %.1f s of ROS time: stopping the robot",
                               self.timeout)
        ### END SOLUTION

    def status_loop(self):
        """Every second of wall time, log 'wall=%.1f ros=%.1f' (wall time, ROS time)."""
        ### BEGIN SOLUTION
        while not rospy.is_shutdown():
            rospy.loginfo("wall=%.1f ros=%.1f", time.time(), rospy.get_time())
            time.sleep(1.0)
        ### END SOLUTION


if __name__ == "__main__":
    rospy.init_node("watchdog")
    watchdog = Watchdog()
    watchdog.heartbeat_loop()
