"""A3 equality spoofing: publish objects that compare equal to anything.

Only wire bytes cross into the grader, decoded there by its own classes: an object that is not a
std_msgs/String cannot be serialized, so nothing crosses.
"""
import rospy
from std_msgs.msg import String


class Always:
    _type = "std_msgs/String"
    _md5sum = String._md5sum

    def __eq__(self, other):
        return True

    def __ne__(self, other):
        return False

    __hash__ = object.__hash__


rospy.init_node("talker")
pub = rospy.Publisher("chatter", String, queue_size=10)
rate = rospy.Rate(10)
while not rospy.is_shutdown():
    for bad in (Always(), String(data=Always())):
        try:
            pub.publish(bad)
        except Exception as exc:
            print("refused:", type(exc).__name__)
    rate.sleep()
