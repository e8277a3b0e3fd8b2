"""Probe: 40 of gen_numbers.py's /random_number (std_msgs/Float32), summarised as JSON."""

import json
import math
import struct

import rospy
from std_msgs.msg import Float32

values = []


def keep(msg):
    if len(values) < 40:
        values.append(msg.data)


rospy.init_node("numbers_probe", anonymous=True)
rospy.Subscriber("random_number", Float32, keep)
while len(values) < 40 and not rospy.is_shutdown():
    rospy.sleep(0.1)
mean = sum(values) / len(values)
print(json.dumps({
    "count": len(values), "mean": mean, "values": values,
    "std": math.sqrt(sum((v - mean) ** 2 for v in values) / (len(values) - 1)),
    "float32": all(v == struct.unpack("f", struct.pack("f", v))[0] for v in values),
}))
