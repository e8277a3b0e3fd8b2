#!/usr/bin/env python3
"""An offline test through rosunit.unitrun (no ROS graph needed)."""
import sys
import unittest

import rosunit


class Unit(unittest.TestCase):

    def test_sum(self):
        self.assertEqual(sum([1, 2, 3]), 6)


if __name__ == "__main__":
    rosunit.unitrun("ddes_rostest_demo", "unit", Unit, sys.argv)
