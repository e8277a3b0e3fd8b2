# ddes-digest: f4a357801d081841e5a8c589391dbb799065fd1cffaf60d754add0fc29a8ee71
# %% [markdown]
# # Lecture 1: the ROS graph and the console
#
# A ROS system is a graph: **nodes** (processes) exchange **messages** over named **topics**.
# A node that publishes on a topic does not know who listens; the master only introduces
# publishers to subscribers. The command-line tools (`rosnode`, `rostopic`) ask the graph what
# is there and let you listen (`echo`), measure (`hz`) and talk (`pub`) yourself.
#
# Here the graph lives in one simulated world, and `ddes.Console` is a shell with the ROS tools
# in it: what they print is what ROS prints. Time only advances while a command needs it, so the
# same commands give the same output on every run.

# %%
import ddes
from ddes.console.viz import find_simulator  # the Simulator behind `rosrun ddes_sim`
from ddes.rqt import rqt_graph, rqt_plot
from ddes.sim.view import top_view

console = ddes.Console(seed=0)
sh = lambda command: print(console.run(command), end="")  # noqa: E731 - a shell prompt

sh("rosrun ddes_sim simulator _world:=single_pillar _noise:=false &")
sh("rosrun --quiet roscpp_tutorials talker &")

# %% [markdown]
# ## What is running: `rosnode` and `rostopic`
#
# The simulator node stands in for Gazebo and the robot's drivers: it subscribes to `/cmd_vel`
# and publishes the laser, odometry, IMU, TF and the clock. The talker publishes on `/chatter`.

# %%
sh("rosnode list")
sh("rostopic list")
sh("rostopic info /cmd_vel")

# %% [markdown]
# `rostopic echo` subscribes and prints what arrives; `rostopic hz` measures the publishing rate.
# Both need time to pass, so each runs the world until it has its answer.

# %%
sh("rostopic echo -n 2 /chatter")
sh("rostopic hz --duration 1 /odom")

# %% [markdown]
# ## The node/topic graph (rqt_graph)
#
# Ellipses are nodes, boxes are topics; arrows go publisher → topic → subscriber.

# %% tags=["plot"]
rqt_graph(console.world)

# %% [markdown]
# ## Talking to the robot: `rostopic pub`
#
# The robot's controller drops a velocity command that is older than 0.25 s (`cmd_vel_timeout`),
# a safety rule of real robots. So `pub -1` (one message) moves the robot only a few
# centimetres, while `pub -r 10` (ten a second) keeps it going until the publisher stops.

# %%
sh("rostopic pub -1 /cmd_vel geometry_msgs/Twist '{linear: {x: 0.5}}'")
sh("sleep 2")
sh("rostopic pub -r 10 --duration 4 /cmd_vel geometry_msgs/Twist "
   "'{linear: {x: 0.8}, angular: {z: 0.3}}'")
sh("sleep 2")
sh("rostopic echo -n 1 /odom/pose/pose/position")

# %% [markdown]
# The speed over time, as rqt_plot draws it: a short bump for `pub -1`, then a plateau while
# `pub -r 10` runs, and the drop 0.25 s after its last message. The turn rate has another unit
# (rad/s), so it gets its own y-axis on the right (dashed).

# %% tags=["plot"]
rqt_plot(console.world, "/odom/twist/twist/linear/x", ylabel="speed [m/s]",
         right=["/odom/twist/twist/angular/z"], right_ylabel="turn rate [rad/s]")

# %% [markdown]
# The robot seen from above (what RViz would show): the world, the robot's footprint, the last
# laser scan, its frames and the path it drove.

# %% tags=["plot"]
top_view(find_simulator(console.world))

# %% [markdown]
# ## Determinism
#
# The world's trace digest is a hash of everything that happened. Run the notebook again and it
# is the same; a change in ddes that changes the behaviour changes it.

# %% tags=["digest"]
print(console.world.digest())

# %% [markdown]
# ## Try this
#
# Exercise 1 (`exercises/ex1_console/README.md`) does this in the `ddes console` shell: start
# the simulator in another world, drive it with `teleop_twist_keyboard`, and answer questions
# with `rosnode`, `rostopic` and `rosmsg`. Try `rostopic hz /scan` here, or `rosnode info
# /simulator`, and compare with what the graph picture shows.
