#!/usr/bin/env python3
"""One method passes, one fails an assertion, one raises."""
import sys
import unittest

import rospy
import rostest


class Fails(unittest.TestCase):

    def test_a_passes(self):
        rospy.sleep(1.0)
        self.assertEqual(rospy.get_time(), 1.0)

    def test_b_fails(self):
        self.assertEqual(1 + 1, 3, "arithmetic is off")

    def test_c_errors(self):
        raise RuntimeError("boom")


if __name__ == "__main__":
    rospy.init_node("fails")
    rostest.rosrun("ddes_rostest_demo", "fails", Fails, sys.argv)
