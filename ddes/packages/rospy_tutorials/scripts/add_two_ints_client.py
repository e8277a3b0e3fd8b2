#!/usr/bin/env python3
"""add_two_ints_client.py x y: wait for add_two_ints, call it, print 'x + y = sum'."""

import sys

import rospy
from rospy_tutorials.srv import AddTwoInts


def add_two_ints_client(x, y):
    rospy.wait_for_service("add_two_ints")
    try:
        add_two_ints = rospy.ServiceProxy("add_two_ints", AddTwoInts)
        resp1 = add_two_ints(x, y)
        return resp1.sum
    except rospy.ServiceException as e:
        print(f"Service call failed: {e}")


def usage():
    return f"{sys.argv[0]} [x y]"


if __name__ == "__main__":
    argv = rospy.myargv(argv=sys.argv)
    if len(argv) == 3:
        x = int(argv[1])
        y = int(argv[2])
    else:
        print(usage())
        sys.exit(1)
    rospy.init_node("add_two_ints_client", anonymous=True)
    print(f"Requesting {x}+{y}")
    print(f"{x} + {y} = {add_two_ints_client(x, y)}")
