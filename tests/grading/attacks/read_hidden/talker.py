"""A5 reading hidden data: the grader's files, its environment, its command line.

If any of it can be read, the script behaves as the reference talker (so a leak would show as
points); when every read is refused it does nothing and earns nothing.
"""
import os

import rospy
from std_msgs.msg import String

leaked = []
for path in [f"/proc/{os.getppid()}/environ", f"/proc/{os.getppid()}/cmdline",
             "/work/main/tests/grading/fixtures/ex0_talker.py", "/etc/shadow", "/root/.bashrc",
             "../../ex0_talker.py"]:
    try:
        with open(path, "rb") as f:
            leaked.append(f.read(100))
    except OSError:
        pass
for key in ("DDES_TEST_SECRET", "DDES_COURSE_SECRET", "HOME_SECRET"):
    if key in os.environ:
        leaked.append(os.environ[key])
print("leaked", len(leaked))
if leaked:
    rospy.init_node("talker")
    pub = rospy.Publisher("chatter", String, queue_size=10)
    rate = rospy.Rate(10)
    n = 0
    while not rospy.is_shutdown():
        pub.publish(f"hello world {n}")
        n += 1
        rate.sleep()
