#!/usr/bin/env python3
"""Publishes "hello N" on chatter at ~rate Hz (default 10), N counting from 0."""
import rospy
from std_msgs.msg import String

rospy.init_node("talker")
pub = rospy.Publisher("chatter", String, queue_size=10)
rate = rospy.Rate(rospy.get_param("~rate", 10))
count = 0
while not rospy.is_shutdown():
    pub.publish(String(data=f"hello {count}"))
    count += 1
    rate.sleep()
