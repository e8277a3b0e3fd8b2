"""Probe: two messages of advanced_publish.py's /color (std_msgs/ColorRGBA), one per line."""

import rospy
from std_msgs.msg import ColorRGBA

rospy.init_node("color_probe", anonymous=True)
seen = []
while len(seen) < 2 and not rospy.is_shutdown():
    msg = rospy.wait_for_message("/color", ColorRGBA)
    seen.append(f"r={msg.r:g} g={msg.g:g} b={msg.b:g} a={msg.a:g}")
for line in sorted(seen):
    print(line)
