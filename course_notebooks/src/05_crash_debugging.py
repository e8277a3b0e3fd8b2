# ddes-digest: 33594f4d52b6700f81571b7a78e2ef34ba7be98100d5d0ddd44fd803cd50c946
# %% [markdown]
# # Lecture 5: debugging a crash
#
# A robot that hits something leaves evidence in three places: the **IMU** feels the impact as
# a short, sharp pulse of deceleration (far stronger than any braking); the **simulator** knows
# the exact instant, obstacle and speed of the contact; and the **trace** of the run holds every
# message. Because ddes is deterministic, the same seed replays the same run bit for bit: the
# same digest, the same crash at the same nanosecond. So a crash seen once can be studied again
# and again, with more plots each time, and a fix can be checked against exactly that run.

# %%
import hashlib
import math

import ddes
from ddes.display.figure import new_figure
from ddes.msg import get_message_class
from ddes.rqt import field_series, rqt_plot
from ddes.sim import Simulator, WorldSpec
from ddes.sim.view import top_view

Twist = get_message_class("geometry_msgs/Twist")
Vector3 = get_message_class("geometry_msgs/Vector3")
LaserScan = get_message_class("sensor_msgs/LaserScan")


def reckless_controller(world, gain=1.0, speed=1.0):
    """Steers to the nearest laser return and never brakes: it will hit the pillar."""
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


def run(seed):
    world = ddes.World(seed=seed)
    sim = Simulator(world, WorldSpec.load("single_pillar"), x=0.0, y=-2.0, yaw=-0.5)
    reckless_controller(world)
    world.run(until=25.0)
    return world, sim

# %% [markdown]
# ## The crash
#
# The controller drives at 1 m/s towards the pillar at (20, 5) and never slows down. The
# simulator records each contact as a `Collision`: when (kernel time and the stamp of the
# sensor data), with what, at what speed, along which normal, at which pose.

# %%
world, sim = run(seed=5)
crash = sim.collisions[0]
print(crash)
print(f"hit the {crash.obstacle} at {crash.stamp_ns / 1e9:.2f} s, at {crash.speed:.2f} m/s")

# %% [markdown]
# ## The IMU's crash pulse
#
# The forward acceleration `/imu/data/linear_acceleration/x` (rqt_plot reads it from the run's
# trace): noise around 0 while cruising, then at impact a half-sine of 0.1 s, about
# −(π/2)·v/0.1 ≈ −16 m/s² at 1 m/s, and a short ringing. Braking at the robot's limit would
# show only −2 m/s². The odometry's speed is in m/s, another unit: it is drawn against the
# y-axis on the right (dashed), where it drops to 0 at the impact.

# %% tags=["plot"]
rqt_plot(world, "/imu/data/linear_acceleration/x", ylabel="IMU a_x [m/s²]",
         right=["/odom/twist/twist/linear/x"], right_ylabel="odometry speed [m/s]",
         title="the crash pulse: IMU a_x and odometry speed")

# %% [markdown]
# Zoomed in around the collision, with the instant the simulator recorded and a detection
# threshold of −8 m/s² (a crash detector could watch for it):

# %% tags=["plot"]
ax_series = field_series(world, "/imu/data/linear_acceleration/x")
t0 = crash.stamp_ns / 1e9
window = [(t, a) for t, a in zip(ax_series.t, ax_series.y) if t0 - 0.5 <= t <= t0 + 0.6]
detected = next(t for t, a in window if a < -8.0)
fig = new_figure(figsize=(7, 3.5))
ax = fig.add_subplot(1, 1, 1)
ax.plot([t for t, _ in window], [a for _, a in window], ".-", markersize=3, label="IMU a_x")
ax.axvline(t0, color="red", label=f"collision {t0:.2f} s")
ax.axhline(-8.0, color="grey", linestyle=":", label="threshold −8 m/s²")
ax.set_xlabel("time [s]")
ax.set_ylabel("a_x [m/s²]")
ax.legend(fontsize=8)
ax.set_title(f"first sample below the threshold: {detected:.2f} s")
fig

# %% [markdown]
# ## Where it happened
#
# The top view marks the collision with a red cross on the trajectory, and shows the robot
# where it stopped, against the pillar:

# %% tags=["plot"]
top_view(sim, title="the crash, from above")

# %% [markdown]
# The trace says who was to blame: what the controller commanded in the last half second
# before the contact (`/cmd_vel` has no header, so its time is the publish time).

# %%
commands = field_series(world, "/cmd_vel/linear/x")
for t, v in zip(commands.t, commands.y):
    if t0 - 0.5 <= t <= t0:
        print(f"{t:6.2f} s  /cmd_vel linear.x = {v}")

# %% [markdown]
# ## Replay the same seed
#
# Running the same code with the same seed gives the same trace, bit for bit: the same digest,
# and the crash at the same nanosecond. A different seed changes the sensor noise and so,
# slightly, the path and the crash instant.

# %%
again_world, again = run(seed=5)
other_world, other = run(seed=6)
print("seed 5, first run: ", world.digest()[:16], crash.stamp_ns)
print("seed 5, replayed:  ", again_world.digest()[:16], again.collisions[0].stamp_ns)
print("seed 6:            ", other_world.digest()[:16], other.collisions[0].stamp_ns)
assert again_world.digest() == world.digest() and again.collisions[0] == crash

# %% tags=["digest"]
print(hashlib.sha256(" ".join([world.digest(), again_world.digest(),
                               other_world.digest()]).encode()).hexdigest())

# %% [markdown]
# ## Try this
#
# Exercise 5 (`exercises/ex5_safety/`, coming) adds a crash detector that stops the robot when
# the IMU pulse passes a threshold. Here, try thresholds from −2 to −15 m/s² over a few seeds:
# which catch the crash, and which would also fire while the robot only brakes?
