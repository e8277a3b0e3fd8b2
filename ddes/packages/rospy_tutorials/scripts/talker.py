#!/usr/bin/env python3
"""Publish 'hello world <time>' on chatter at 10 Hz (rospy_tutorials' talker, as plain rospy).

Runs unchanged under real rospy and under ddes (rosrun rospy_tutorials talker.py).
"""

import rospy
from std_msgs.msg import String


def talker():
    pub = rospy.Publisher("chatter", String, queue_size=10)
    rospy.init_node("talker", anonymous=True)
    rate = rospy.Rate(10)
    while not rospy.is_shutdown():
        hello_str = f"hello world {rospy.get_time()}"
        rospy.loginfo(hello_str)
        pub.publish(hello_str)
        rate.sleep()


if __name__ == "__main__":
    try:
        talker()
    except rospy.ROSInterruptException:
        pass
