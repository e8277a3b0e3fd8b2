#!/usr/bin/env python3
"""Serve add_two_ints (rospy_tutorials/AddTwoInts), printing each request it answers."""

import rospy
from rospy_tutorials.srv import AddTwoInts, AddTwoIntsResponse


def handle_add_two_ints(req):
    print(f"Returning [{req.a} + {req.b} = {req.a + req.b}]")
    return AddTwoIntsResponse(req.a + req.b)


def add_two_ints_server():
    rospy.init_node("add_two_ints_server")
    rospy.Service("add_two_ints", AddTwoInts, handle_add_two_ints)
    print("Ready to add two ints.")
    rospy.spin()


if __name__ == "__main__":
    add_two_ints_server()
