#!/usr/bin/env python3
"""Send the fibonacci server a goal of order 20, wait for the result and print it."""

import actionlib
import rospy
from actionlib_tutorials.msg import FibonacciAction, FibonacciGoal


def fibonacci_client():
    client = actionlib.SimpleActionClient("fibonacci", FibonacciAction)
    client.wait_for_server()
    goal = FibonacciGoal(order=20)
    client.send_goal(goal)
    client.wait_for_result()
    return client.get_result()


if __name__ == "__main__":
    try:
        rospy.init_node("fibonacci_client_py")
        result = fibonacci_client()
        print("Result:", ", ".join([str(n) for n in result.sequence]))
    except rospy.ROSInterruptException:
        print("program interrupted before completion")
