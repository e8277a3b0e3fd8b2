#!/usr/bin/env python3
"""A preemptable FollowPath action server on the SMB (lecture 4, "ROS Actions (actionlib)").

The goal is a nav_msgs/Path in the odom frame.  The server drives through its poses in order
with a pursuit controller on /odom -> /cmd_vel, publishes feedback (remaining and initial
distance) at ~feedback_rate Hz, and ends the goal:

* SUCCEEDED (success: true) at the last pose;
* ABORTED (success: false) for an empty path, or when the robot makes no progress for
  ~stall_timeout seconds (a waypoint it cannot reach);
* PREEMPTED on a cancel or a newer goal: it stops the robot (a zero Twist) first.
"""

import math

import actionlib
import rospy
from geometry_msgs.msg import Twist
from lecture4_actions.msg import FollowPathAction, FollowPathFeedback, FollowPathResult
from nav_msgs.msg import Odometry

MAX_TURN = 1.0  # rad/s, under the SMB's 1.1 rad/s limit
TURN_GAIN = 2.0


def yaw_of(q):
    """The yaw of a quaternion (x, y, z, w)."""
    return math.atan2(2.0 * (q.w * q.z + q.x * q.y), 1.0 - 2.0 * (q.y * q.y + q.z * q.z))


def wrap(angle):
    return math.atan2(math.sin(angle), math.cos(angle))


def path_length(points):
    """The length of the polyline through ``points`` [(x, y), ...]."""
    total = 0.0
    for a, b in zip(points, points[1:]):
        total += math.hypot(b[0] - a[0], b[1] - a[1])
    return total


class FollowPathServer:
    """The action server, its odometry subscriber and its command publisher."""

    def __init__(self):
        self.action_name = rospy.get_param("~action_name", "follow_path")
        self.speed = float(rospy.get_param("~speed", 0.6))
        self.feedback_rate = float(rospy.get_param("~feedback_rate", 10.0))
        self.tolerance = float(rospy.get_param("~waypoint_tolerance", 0.1))
        self.stall_timeout = float(rospy.get_param("~stall_timeout", 4.0))
        self.pose = None
        self.cmd_publisher = rospy.Publisher("/cmd_vel", Twist, queue_size=1)
        self.odom_subscriber = rospy.Subscriber("/odom", Odometry, self.odom_callback,
                                                queue_size=1)
        self.server = actionlib.SimpleActionServer(self.action_name, FollowPathAction,
                                                   execute_cb=self.execute, auto_start=False)
        self.server.start()
        rospy.loginfo("%s: ready", self.action_name)

    def odom_callback(self, odom):
        p = odom.pose.pose
        self.pose = (p.position.x, p.position.y, yaw_of(p.orientation))

    def stop(self):
        self.cmd_publisher.publish(Twist())

    def remaining(self, points, index):
        """Distance left: to waypoint ``index``, then along the path to its end."""
        x, y, _ = self.pose
        wx, wy = points[index]
        return math.hypot(wx - x, wy - y) + path_length(points[index:])

    def execute(self, goal):
        points = [(p.pose.position.x, p.pose.position.y) for p in goal.path.poses]
        ### BEGIN SOLUTION
        if not points or self.pose is None:
            rospy.logwarn("%s: empty path (or no odometry yet): aborted", self.action_name)
            self.server.set_aborted(FollowPathResult(success=False), "empty path")
            return
        rate = rospy.Rate(self.feedback_rate)
        index = 0
        initial = self.remaining(points, 0)
        best = initial
        last_progress = rospy.Time.now()
        rospy.loginfo("%s: following %d poses, %.2f m", self.action_name, len(points), initial)
        while not rospy.is_shutdown():
            if self.server.is_preempt_requested():
                self.stop()
                rospy.loginfo("%s: preempted", self.action_name)
                self.server.set_preempted(FollowPathResult(success=False))
                return
            x, y, yaw = self.pose
            while index < len(points) and math.hypot(points[index][0] - x,
                                                     points[index][1] - y) < self.tolerance:
                index += 1
            if index == len(points):
                self.stop()
                self.server.publish_feedback(FollowPathFeedback(remaining_distance=0.0,
                                                                initial_distance=initial))
                rospy.loginfo("%s: reached the end of the path", self.action_name)
                self.server.set_succeeded(FollowPathResult(success=True))
                return
            left = self.remaining(points, index)
            if left < best - 0.05:
                best, last_progress = left, rospy.Time.now()
            elif (rospy.Time.now() - last_progress).to_sec() > self.stall_timeout:
                self.stop()
                rospy.logwarn("%s: no progress for %.1f s: waypoint %d unreachable",
                              self.action_name, self.stall_timeout, index)
                self.server.set_aborted(FollowPathResult(success=False), "waypoint unreachable")
                return
            self.server.publish_feedback(FollowPathFeedback(remaining_distance=left,
                                                            initial_distance=initial))
            wx, wy = points[index]
            error = wrap(math.atan2(wy - y, wx - x) - yaw)
            twist = Twist()
            twist.angular.z = max(-MAX_TURN, min(MAX_TURN, TURN_GAIN * error))
            twist.linear.x = self.speed * max(0.0, math.cos(error)) ** 2
            self.cmd_publisher.publish(twist)
            rate.sleep()
        ### END SOLUTION


if __name__ == "__main__":
    rospy.init_node("follow_path_server")
    server = FollowPathServer()
    rospy.spin()
