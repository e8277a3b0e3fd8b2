# ddes-digest: 0672a31971b7ecce30c42ca9cdfae1e86b497c1169560cd7d61bbb01bd91ee5d
# %% [markdown]
# # Lecture 4b: actions
#
# An **action** is a long task with a goal, feedback while it runs, and a result; the client
# can cancel it, and a new goal can **preempt** the running one. actionlib builds it from five
# topics (`goal`, `cancel`, `status`, `feedback`, `result`) and a state machine per goal:
# PENDING → ACTIVE → SUCCEEDED, ABORTED or PREEMPTED.
#
# The lecture's example is `FollowPath`: the goal a `nav_msgs/Path`, the feedback the remaining
# distance, the result a success flag. Here a small server drives the simulated robot along the
# path; a client sends a path, replaces it by a second one halfway, then cancels that one.

# %%
import math

import ddes
from ddes.actionlib import GoalStatus, SimpleActionClient, SimpleActionServer, plot_goals
from ddes.display.figure import new_figure
from ddes.msg import get_message_class
from ddes.rqt import rqt_plot
from ddes.sim import Simulator, WorldSpec
from ddes.transformations import atan2

FollowPath = get_message_class("lecture4_actions/FollowPathAction")
Goal = get_message_class("lecture4_actions/FollowPathGoal")
Feedback = get_message_class("lecture4_actions/FollowPathFeedback")
Result = get_message_class("lecture4_actions/FollowPathResult")
Path = get_message_class("nav_msgs/Path")
PoseStamped = get_message_class("geometry_msgs/PoseStamped")
Pose = get_message_class("geometry_msgs/Pose")
Point = get_message_class("geometry_msgs/Point")
Odometry = get_message_class("nav_msgs/Odometry")
Twist = get_message_class("geometry_msgs/Twist")
Vector3 = get_message_class("geometry_msgs/Vector3")

world = ddes.World(seed=0)
sim = Simulator(world, WorldSpec.load("empty"), noise=False)

# %% [markdown]
# The server: an execute callback on simulated time. Every 0.1 s it checks for preemption,
# steers to the next waypoint (turn towards it, drive when roughly facing it) and publishes the
# remaining distance as feedback.

# %%
node = world.create_node("follow_path")
cmd = ddes.Publisher(node, "/cmd_vel", Twist, queue_size=1)
pose = [0.0, 0.0, 0.0]


def on_odom(msg):
    p, q = msg.pose.pose.position, msg.pose.pose.orientation
    pose[:] = [p.x, p.y, 2.0 * atan2(q.z, q.w)]


ddes.Subscriber(node, "/odom", Odometry, on_odom, queue_size=1)


def remaining(points, k):
    d = math.dist(pose[:2], points[k])
    return d + sum(math.dist(a, b) for a, b in zip(points[k:], points[k + 1:]))


def execute(goal):
    points = [(p.pose.position.x, p.pose.position.y) for p in goal.path.poses]
    if not points:
        server.set_aborted(Result(success=False))
        return
    initial, k = remaining(points, 0), 0
    while k < len(points):
        if server.is_preempt_requested():
            cmd.publish(Twist())
            server.set_preempted(Result(success=False))
            return
        (x, y), (gx, gy) = pose[:2], points[k]
        if math.dist((x, y), (gx, gy)) < 0.3:
            k += 1
            continue
        error = atan2(gy - y, gx - x) - pose[2]
        error = (error + math.pi) % (2 * math.pi) - math.pi
        forward = 0.8 if abs(error) < 0.5 else 0.0
        cmd.publish(Twist(linear=Vector3(x=forward), angular=Vector3(z=2.0 * error)))
        server.publish_feedback(Feedback(remaining_distance=remaining(points, k),
                                         initial_distance=initial))
        yield node.sleep(0.1)
    cmd.publish(Twist())
    server.set_succeeded(Result(success=True))


server = SimpleActionServer(node, "follow_path", FollowPath, execute, auto_start=False)
server.start()

# %% [markdown]
# The client: path A (a square's corner), replaced after 6 s by path B, which is cancelled
# after 14 s. A SimpleActionServer accepts the new goal and preempts the old one.


# %%
def path(points):
    return Path(poses=[PoseStamped(pose=Pose(position=Point(x=x, y=y))) for x, y in points])


client = SimpleActionClient(world.create_node("user"), "follow_path", FollowPath)
path_a = [(3.0, 0.0), (3.0, 3.0), (0.0, 3.0)]
path_b = [(5.0, 1.0), (5.0, -3.0), (1.0, -3.0)]
world.run(until=0.5)
client.send_goal(Goal(path=path(path_a)))
world.run(until=6.0)
client.send_goal(Goal(path=path(path_b)))
world.run(until=14.0)
client.cancel_goal()
world.run(until=16.0)
print("last goal:", GoalStatus(client.get_state()).name)

# %% [markdown]
# The goals over time (`plot_goals`): each goal's row shows its states, the feedback ticks, the
# preempt request and the terminal state.

# %% tags=["plot"]
timeline = plot_goals(world, ns="/follow_path")
timeline.axes[0].set_ylabel("goal (id)")
timeline

# %% [markdown]
# The paths against the track the robot drove:

# %% tags=["plot"]
h = sim.history()
fig = new_figure(figsize=(6, 5))
ax = fig.add_subplot(1, 1, 1)
ax.plot(h.x, h.y, color="black", label="driven (truth)")
for name, pts, style in (("path A", path_a, "o--"), ("path B", path_b, "s--")):
    ax.plot([x for x, _ in pts], [y for _, y in pts], style, label=name)
ax.plot([0.0], [0.0], "k^", label="start")
ax.set_aspect("equal")
ax.set_xlabel("x [m]")
ax.set_ylabel("y [m]")
ax.legend(fontsize=8)
ax.set_title("goals and the track")
fig

# %% [markdown]
# The feedback: the remaining distance falls while a goal runs and restarts with the new goal.

# %% tags=["plot"]
rqt_plot(world, "/follow_path/feedback/feedback/remaining_distance",
         "/follow_path/feedback/feedback/initial_distance", ylabel="distance [m]")

# %% tags=["digest"]
print(world.digest())

# %% [markdown]
# ## Try this
#
# Exercise 4b (`exercises/ex4b_actions/README.md`) builds this server as a rospy package, with
# the empty path, preemption and cancellation handled as actionlib expects. Here, send path B
# only after path A succeeded (`client.wait_for_result()`), or an empty path, and compare the
# goal timelines.
