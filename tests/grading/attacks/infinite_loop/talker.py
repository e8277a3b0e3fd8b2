"""A8 infinite loop: never block, never answer the grader (the step's wall budget ends it)."""
import rospy

rospy.init_node("talker")
while True:
    pass
