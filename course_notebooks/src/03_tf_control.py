# ddes-digest: b54bf04ceda14bd8d301ca2ac7043dce20d0b41107c912a147c000852626c735
# %% [markdown]
# # Lecture 3: TF and a P controller
#
# A robot has many coordinate **frames**: `odom` (where it started), `base_link` (the robot),
# `base_laser` (the laser). **TF** keeps the transforms between them as a tree, each stamped in
# time, so a node can ask "where was this laser point in `odom` when the scan was taken?"
# (`lookup_transform(target, source, time)`; time 0 means "the latest available").
#
# The control idea of exercise 3: find the pillar as the nearest laser return, and steer with a
# **P controller**: angular speed = gain × bearing of the pillar. The robot turns towards the
# pillar and drives into it.

# %%
import hashlib
import math

from matplotlib.patches import Circle

import ddes
from ddes.display.figure import new_figure
from ddes.msg import get_message_class
from ddes.rqt import rqt_plot
from ddes.sim import Simulator, WorldSpec
from ddes.sim.view import top_view
from ddes.tf2_ros import Buffer, TransformListener
from ddes.tf2_ros.plot import plot_frames

Twist = get_message_class("geometry_msgs/Twist")
Vector3 = get_message_class("geometry_msgs/Vector3")
LaserScan = get_message_class("sensor_msgs/LaserScan")


def pillar_controller(world, gain, speed=1.0):
    """A node steering to the nearest laser return: w = gain * bearing."""
    node = world.create_node("pillar_controller")
    cmd = ddes.Publisher(node, "/cmd_vel", Twist, queue_size=1)

    def on_scan(scan):
        best, index = math.inf, -1
        for i, r in enumerate(scan.ranges):
            if scan.range_min <= r < best:
                best, index = r, i
        if index < 0:
            return
        bearing = scan.angle_min + index * scan.angle_increment
        cmd.publish(Twist(linear=Vector3(x=speed), angular=Vector3(z=gain * bearing)))

    ddes.Subscriber(node, "/scan", LaserScan, on_scan, queue_size=1)
    return node

# %% [markdown]
# ## One run, in the console's world
#
# The simulator starts at the origin, facing along x; the pillar stands at (20, 5). The robot
# hits it after about twenty seconds of simulated time.

# %%
console = ddes.Console(seed=1)
sh = lambda command: print(console.run(command), end="")  # noqa: E731 - a shell prompt
sh("rosrun ddes_sim simulator _world:=single_pillar _y:=-2 _yaw:=-0.5 &")
pillar_controller(console.world, gain=1.0)
buffer = Buffer()
TransformListener(console.world.create_node("tf_listener"), buffer)
sh("sleep 20")
from ddes.console.viz import find_simulator  # noqa: E402 - the Simulator behind rosrun

sim = find_simulator(console.world)
print(sim.collisions)

# %% tags=["plot"]
top_view(sim)

# %% [markdown]
# ## The TF tree
#
# `/tf_static` carries the fixed mounts (laser and IMU on the robot), `/tf` the moving
# `odom → base_link` from odometry. `plot_frames` draws what `view_frames` draws:

# %% tags=["plot"]
plot_frames(buffer)

# %% [markdown]
# Looking a transform up: at time 0 (the latest), at a stamp inside the buffer (interpolated
# between two odometry updates), for a frame that does not exist, and for a stamp older than
# the buffer keeps (10 s): tf2's own error texts.

# %%
latest = buffer.lookup_transform("odom", "base_laser", ddes.Time(0))
print("latest:", latest.header.stamp.to_sec(), latest.transform.translation)
earlier = buffer.lookup_transform("odom", "base_laser", ddes.Time(15.005))
print("at 15.005 s:", earlier.transform.translation)
for frame, stamp in (("camera", 0), ("base_laser", 5.0)):
    try:
        buffer.lookup_transform("odom", frame, ddes.Time(stamp))
    except Exception as err:  # tf2's LookupException, ExtrapolationException
        print(f"{type(err).__name__}: {err}")

# %% [markdown]
# `tf_echo` in the console prints the same at 1 Hz:

# %%
sh("rosrun tf tf_echo odom base_laser &")
sh("sleep 1.5")
sh("kill %2")

# %% [markdown]
# ## The gain matters
#
# The same start, facing 30° away from the pillar, four gains. With a small gain the robot
# turns slowly and may pass the pillar; a larger gain turns it towards the pillar early.

# %% tags=["plot"]
fig = new_figure(figsize=(8, 4))
ax = fig.add_subplot(1, 1, 1)
digests = []
for gain in (0.05, 0.2, 1.0, 3.0):
    world = ddes.World(seed=1)
    run = Simulator(world, WorldSpec.load("single_pillar"), x=0.0, y=-2.0, yaw=-0.5)
    pillar_controller(world, gain)
    world.run(until=30.0)
    h = run.history()
    hit = f", hit at {run.collisions[0].stamp_ns / 1e9:.1f} s" if run.collisions else ""
    ax.plot(h.x, h.y, label=f"gain {gain}{hit}")
    digests.append(world.digest())
ax.add_patch(Circle((20, 5), 1.0, color="grey"))
ax.set_aspect("equal")
ax.set_xlabel("x [m]")
ax.set_ylabel("y [m]")
ax.legend(fontsize=8)
ax.set_title("P controller: trajectories for four gains")
fig

# %% [markdown]
# The commanded turn rate over time (rqt_plot of `/cmd_vel/angular/z`) in the console's run:

# %% tags=["plot"]
rqt_plot(console.world, "/cmd_vel/angular/z", "/odom/twist/twist/angular/z",
         ylabel="turn rate [rad/s]")

# %% [markdown]
# One digest for all five runs: the console's world and the four of the gain sweep.

# %% tags=["digest"]
print(hashlib.sha256(" ".join([console.world.digest(), *digests]).encode()).hexdigest())

# %% [markdown]
# ## Try this
#
# Exercise 3 (`exercises/ex3_pillar/README.md`) builds this controller as a rospy package, with
# the gain as a parameter, and publishes an RViz marker at the pillar, transformed from the
# laser frame to `odom` with TF. Here, try a negative gain, or a start facing away
# (`_yaw:=3.1`), and look at the top view.
