# ddes-digest: 7989189c6a027e43f778ff8df4c5f9b06ab00232f6aeceff4ea33ddc916c8a80
# %% [markdown]
# # Lecture 4d: rosbag
#
# A **bag** is a recording of messages: for each one its topic, its bytes and the time it was
# recorded. `rosbag record` subscribes to topics and writes what it hears; `rosbag info` says
# what a bag holds; `rosbag play` publishes the messages again with their original spacing, so
# a node cannot tell a replay from the robot. With `--clock` the player also publishes the
# bag's time on `/clock`: a node with `use_sim_time` then lives in the recorded time, and its
# stamps, timers and TF lookups match the data.
#
# Here the simulated robot drives a curve while a `Recorder` writes `/odom`, `/scan`, `/tf` and
# `/imu/data`; we save the bag, read it back, compare the wheel odometry in it with the
# simulator's ground truth, and play it back into a sim-time listener.

# %%
import hashlib
import os
import tempfile

import ddes
from ddes.console.tooling import run_command
from ddes.display.figure import new_figure
from ddes.msg import get_message_class
from ddes.rosbag import Bag, Player, Recorder
from ddes.rqt import field_series, rqt_plot
from ddes.sim import Simulator, WorldSpec

Twist = get_message_class("geometry_msgs/Twist")
Vector3 = get_message_class("geometry_msgs/Vector3")
Odometry = get_message_class("nav_msgs/Odometry")
digests = []

# %% [markdown]
# ## Record a drive
#
# A scripted `cmd_vel`: straight for 4 s, then a left curve for 8 s, at 10 Hz. The simulator's
# odometry has noise (a per-run scale error and wheel slip), so what the robot believes and
# where it really is drift apart.

# %%
world = ddes.World(seed=3)
sim = Simulator(world, WorldSpec.load("empty"), x=0.0, y=0.0, yaw=0.0, noise=True)
driver = world.create_node("driver")
cmd = ddes.Publisher(driver, "/cmd_vel", Twist, queue_size=1)


def drive():
    rate = driver.create_rate(10)
    while driver.get_time() < 12.0:
        turn = 0.0 if driver.get_time() < 4.0 else 0.35
        cmd.publish(Twist(linear=Vector3(x=1.0), angular=Vector3(z=turn)))
        yield rate.sleep()


driver.process(drive())
recorder = Recorder(world, ["/odom", "/scan", "/tf", "/imu/data"], in_memory=True)
world.run(until=12.0)
recorder.stop()
digests.append(world.digest())

folder = tempfile.mkdtemp()
path = os.path.join(folder, "drive.bag")
recorder.bag.save(path)
print(f"saved {recorder.bag.get_message_count()} messages, {os.path.getsize(path)} bytes")

# %% [markdown]
# ## Read it back
#
# `Bag(path)` opens the file; `rosbag info` prints what it holds (times in the local time zone,
# as the real tool does):

# %%
bag = Bag(path)
print(run_command(world, f"rosbag info {path}").replace(folder + os.sep, ""), end="")
first = next(bag.read_messages(topics=["/odom"]))
print(first.topic, first.timestamp.to_sec(), first.message.pose.pose.position)

# %% [markdown]
# The odometry's x/y from the bag (rqt_plot reads a bag as it reads a live world):

# %% tags=["plot"]
rqt_plot(bag, "/odom/pose/pose/position/x:y", title="rqt_plot --bag drive.bag",
         ylabel="position in odom [m]")

# %% [markdown]
# The same x/y as a path, against the ground truth the simulator kept (`sim.history()`). The
# bag holds what the robot *believed*; the gap is the odometry's drift.

# %% tags=["plot"]
xs = field_series(bag, "/odom/pose/pose/position/x")
ys = field_series(bag, "/odom/pose/pose/position/y")
truth = sim.history()
fig = new_figure(figsize=(6, 5))
ax = fig.add_subplot(1, 1, 1)
ax.plot(truth.x, truth.y, "k-", label="ground truth (simulator)")
ax.plot(xs.y, ys.y, "--", color="tab:blue", label="/odom from the bag")
ax.set_aspect("equal")
ax.set_xlabel("x [m]")
ax.set_ylabel("y [m]")
ax.legend()
ax.set_title("wheel odometry against ground truth")
fig

# %% [markdown]
# ## Play it back with `--clock`
#
# A fresh world with `/use_sim_time` set and no simulator: a listener on `/odom` prints its
# ROS time and the message's stamp (`rosbag play --clock drive.bag`, run in the bag's folder). The player publishes the bag's time on `/clock` (just
# before each message), so the listener's clock reads the recorded times.

# %%
replay = ddes.World(seed=3)
replay.use_sim_time = True
listener = replay.create_node("listener")
heard = []


def on_odom(msg):
    heard.append((listener.get_time(), msg.header.stamp.to_sec()))


listener.subscribe("/odom", Odometry, on_odom)
player = Player(replay, "drive.bag", cwd=folder, clock=True, topics=["/odom"], quiet=True)
replay.run(player.done)
digests.append(replay.digest())
for now, stamp in heard[:3] + heard[-2:]:
    print(f"ROS time {now:8.3f} s   stamp {stamp:8.3f} s")
print(f"{len(heard)} messages heard; ROS time equals the recorded stamp for "
      f"{sum(abs(a - b) < 1e-9 for a, b in heard)} of them; "
      f"the playback took {listener.get_walltime().to_sec():.2f} s of wall time")

# %% [markdown]
# The listener's ROS time at each message against the stamp recorded in the bag: one line.

# %% tags=["plot"]
fig = new_figure(figsize=(5, 4))
ax = fig.add_subplot(1, 1, 1)
ax.plot([s for _, s in heard], [n for n, _ in heard], ".", markersize=3)
ax.set_xlabel("stamp in the bag [s]")
ax.set_ylabel("listener's ROS time [s]")
ax.set_title("rosbag play --clock: the listener lives in bag time")
fig

# %% tags=["digest"]
print(hashlib.sha256(" ".join(digests).encode()).hexdigest())

# %% [markdown]
# ## Try this
#
# Exercise 4d (`exercises/ex4d_bags/`, coming) records a run and analyses it offline. Here,
# play the bag with `rate=2.0` and look at the listener's wall time, or record `-a`
# (`Recorder(world, all=True, ...)`) and read `rosbag info` again.
