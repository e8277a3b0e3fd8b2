#!/usr/bin/env python3
"""Exits after ~after seconds (default 1): a node whose end ends a launch when required."""
import rospy

rospy.init_node("quitter")
rospy.sleep(rospy.get_param("~after", 1.0))
