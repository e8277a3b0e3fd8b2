"""Network: reach the outside (or the grader on localhost); behaves as the reference talker only
if a connection succeeds."""
import rospy
from std_msgs.msg import String

ok = False
try:
    import socket
    s = socket.create_connection(("127.0.0.1", 22), timeout=1)
    ok = True
except Exception as exc:
    print("no network:", type(exc).__name__)
if ok:
    rospy.init_node("talker")
    pub = rospy.Publisher("chatter", String, queue_size=10)
    rate = rospy.Rate(10)
    n = 0
    while not rospy.is_shutdown():
        pub.publish(f"hello world {n}")
        n += 1
        rate.sleep()
