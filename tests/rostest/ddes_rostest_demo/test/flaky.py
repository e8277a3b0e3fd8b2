#!/usr/bin/env python3
"""Passes or fails by a draw of the world's random stream: a different seed, another draw."""
import random
import sys
import unittest

import rospy
import rostest


class Flaky(unittest.TestCase):

    def test_coin(self):
        draw = random.random()
        print(f"drew {draw:.6f}")
        self.assertLess(draw, 0.5)


if __name__ == "__main__":
    rospy.init_node("flaky")
    rostest.rosrun("ddes_rostest_demo", "flaky", Flaky, sys.argv)
