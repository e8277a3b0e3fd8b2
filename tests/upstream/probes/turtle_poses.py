"""Probe: turtle1's and turtle2's poses, printed twice a second for five seconds.

Each line is ``[turtle1 x, turtle1 y, turtle2 x, turtle2 y, turtle2 theta]`` (rounded), from
the first sample after turtle2 has a pose.  A rospy script: it runs unchanged on ddes and ROS.
"""

import json

import rospy
from turtlesim.msg import Pose

poses = {}


def keep(msg, name):
    poses[name] = msg


rospy.init_node("pose_probe", anonymous=True)
for name in ("turtle1", "turtle2"):
    rospy.Subscriber(f"/{name}/pose", Pose, keep, name)
rate = rospy.Rate(2)
samples = 0
while samples < 10 and not rospy.is_shutdown():
    rate.sleep()
    if "turtle1" in poses and "turtle2" in poses:
        one, two = poses["turtle1"], poses["turtle2"]
        print(json.dumps([round(v, 4) for v in (one.x, one.y, two.x, two.y, two.theta)]))
        samples += 1
