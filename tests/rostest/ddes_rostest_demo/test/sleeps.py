#!/usr/bin/env python3
"""Sleeps 100 simulated seconds: past any small time-limit."""
import sys
import unittest

import rospy
import rostest


class Sleeps(unittest.TestCase):

    def test_sleeps(self):
        rospy.sleep(100.0)


if __name__ == "__main__":
    rospy.init_node("sleeps")
    rostest.rosrun("ddes_rostest_demo", "sleeps", Sleeps, sys.argv)
