#!/usr/bin/env python3
"""Passes against the talker: hears it, at its rate, and reads its own <param>."""
import sys
import unittest

import rospy
import rostest
from std_msgs.msg import String


class HearsTalker(unittest.TestCase):

    def test_hears_hello(self):
        msg = rospy.wait_for_message("chatter", String, timeout=5.0)
        print(f"heard {msg.data}")
        self.assertTrue(msg.data.startswith(rospy.get_param("~expected")))

    def test_rate_on_simulated_time(self):
        stamps = []
        sub = rospy.Subscriber("chatter", String, lambda m: stamps.append(rospy.get_time()))
        while len(stamps) < 5:
            rospy.sleep(0.05)
        sub.unregister()
        gaps = [round(b - a, 6) for a, b in zip(stamps, stamps[1:])]
        self.assertEqual(gaps, [0.1] * 4)

    def test_master_knows_the_talker(self):
        self.assertTrue(rostest.is_publisher("/chatter", "/talker"))
        self.assertFalse(rostest.is_subscriber("/chatter", "/talker"))


if __name__ == "__main__":
    rospy.init_node("hears_talker")
    rostest.rosrun("ddes_rostest_demo", "hears_talker", HearsTalker, sys.argv)
