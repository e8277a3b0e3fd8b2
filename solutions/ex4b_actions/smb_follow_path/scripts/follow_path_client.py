#!/usr/bin/env python3
"""The lecture's cancel demo: send a square path to the FollowPath server, log the feedback, and
cancel the goal after ~cancel_after seconds (0: never).

    rosrun smb_follow_path follow_path_client.py _side:=2.0 _cancel_after:=3.0
"""

import actionlib
import rospy
from geometry_msgs.msg import PoseStamped
from lecture4_actions.msg import FollowPathAction, FollowPathGoal
from nav_msgs.msg import Path


class FollowPathClient:
    """Sends one square path and waits for its end (cancelling it after a while)."""

    def __init__(self):
        self.action_name = rospy.get_param("~action_name", "follow_path")
        self.side = float(rospy.get_param("~side", 2.0))
        self.cancel_after = float(rospy.get_param("~cancel_after", 0.0))
        self.client = actionlib.SimpleActionClient(self.action_name, FollowPathAction)

    def square(self):
        path = Path()
        path.header.frame_id = "odom"
        for x, y in ((self.side, 0.0), (self.side, self.side), (0.0, self.side), (0.0, 0.0)):
            pose = PoseStamped()
            pose.header.frame_id = "odom"
            pose.pose.position.x = x
            pose.pose.position.y = y
            pose.pose.orientation.w = 1.0
            path.poses.append(pose)
        return path

    def feedback_callback(self, feedback):
        rospy.loginfo_throttle(1.0, "remaining %.2f of %.2f m", feedback.remaining_distance,
                               feedback.initial_distance)

    def run(self):
        rospy.loginfo("waiting for the %s server", self.action_name)
        self.client.wait_for_server()
        ### BEGIN SOLUTION
        self.client.send_goal(FollowPathGoal(path=self.square()),
                              feedback_cb=self.feedback_callback)
        timeout = rospy.Duration(self.cancel_after)  # zero: wait for ever
        if not self.client.wait_for_result(timeout):
            rospy.loginfo("no result after %.1f s: cancelling", self.cancel_after)
            self.client.cancel_goal()
            self.client.wait_for_result()
        ### END SOLUTION
        result = self.client.get_result()
        rospy.loginfo("finished: state %d, success %s", self.client.get_state(),
                      None if result is None else result.success)


if __name__ == "__main__":
    rospy.init_node("follow_path_client")
    FollowPathClient().run()
