# ddes-digest: fd29c79b493e2e0743760a633e614acf45517d0bf55a087b5952d753daf130f4
# %% [markdown]
# # Lecture 4c: ROS time
#
# ROS nodes read time from a **clock**. Normally that is the computer's clock (wall time). With
# the parameter `/use_sim_time` set, they read **ROS time** from the `/clock` topic instead:
# a simulator (or `rosbag play --clock`) publishes it, possibly slower or faster than real
# time, and every `Rate`, `Timer` and `sleep` follows it. A node that must wait real time uses
# `WallRate` / `WallTimer`.
#
# In ddes the "wall" clock is the simulation kernel's clock, and everything is simulated, so
# the difference can be measured exactly.

# %%
import hashlib

import ddes
from ddes.display.figure import new_figure
from ddes.msg import get_message_class
from ddes.rosbag import Player, Recorder
from ddes.sim import Simulator, WorldSpec

digests = []

# %% [markdown]
# ## Rate and Timer
#
# A `Rate(10)` loop sleeps what is left of each 0.1 s period; a `Timer` calls back with a
# `TimerEvent` saying when the call was expected and when it really came.

# %%
world = ddes.World(seed=0)
node = world.create_node("ticker")
rate = ddes.Rate(node, 10)


def loop():
    for _ in range(3):
        print(f"rate tick at {node.get_time():.3f} s")
        yield rate.sleep()


def on_timer(event):
    print(f"timer: expected {event.current_expected.to_sec():.3f}, "
          f"real {event.current_real.to_sec():.3f}, "
          f"last_real {event.last_real.to_sec() if event.last_real else None}")


node.process(loop())
timer = ddes.Timer(node, 0.25, on_timer)
world.run(until=0.6)
digests.append(world.digest())

# %% [markdown]
# ## Simulated time slower than real time
#
# The simulator runs at `real_time_factor` 0.5 and publishes `/clock`. A node with
# `use_sim_time` reads that clock; it samples its ROS time and the wall time every 0.1 s of wall
# time (a `WallRate`), and ticks a ROS-time `Rate(2)` next to a `WallRate(2)`.

# %%
slow = ddes.World(seed=0)
Simulator(slow, WorldSpec.load("empty"), noise=False, real_time_factor=0.5)
watcher = slow.create_node("watcher", use_sim_time=True)
samples, ticks = {"rtf 0.5": []}, {"Rate(2) on ROS time": [], "WallRate(2)": []}


def sample(series, rate_hz=10):
    wall = watcher.create_wall_rate(rate_hz)
    while True:
        series.append((watcher.get_walltime().to_sec(), watcher.get_time()))
        yield wall.sleep()


def tick(series, make):
    r = make(2)
    while True:
        yield r.sleep()
        series.append(watcher.get_walltime().to_sec())


watcher.process(sample(samples["rtf 0.5"]))
watcher.process(tick(ticks["Rate(2) on ROS time"], watcher.create_rate))
watcher.process(tick(ticks["WallRate(2)"], watcher.create_wall_rate))
recorder = Recorder(slow, ["/odom"], in_memory=True)  # not /clock: play makes its own
slow.run(until=6.0)
recorder.stop()
digests.append(slow.digest())
print(f"after 6 s of wall time the simulated clock reads {watcher.get_time():.2f} s")

# %% [markdown]
# ## `rosbag play --clock -r 2`
#
# That run's `/odom`, recorded with the wall time of each message (6 s of bag time), played
# back twice as fast: the player publishes `/clock` from the bag's time, so a sim-time node now
# sees ROS time run at twice the wall time of the playback. (Recording `/clock` too would put
# two clocks on one topic: the bag's old one and the player's.)

# %%
replay = ddes.World(seed=0)
replay.use_sim_time = True
watcher = replay.create_node("watcher")
samples["play -r 2"] = []
watcher.process(sample(samples["play -r 2"]))
player = Player(replay, recorder.bag, clock=True, rate=2.0, quiet=True)
replay.run(player.done)
digests.append(replay.digest())
print(f"played {player.published} messages in {watcher.get_walltime().to_sec():.2f} s of wall time")

# %% [markdown]
# ROS time against wall time: the slope is the real-time factor (the dotted line is 1).
# A sim-time node reads 0 until the first `/clock` arrives.

# %% tags=["plot"]
fig = new_figure(figsize=(6, 4))
ax = fig.add_subplot(1, 1, 1)
for name, pts in samples.items():
    ax.plot([w for w, _ in pts], [r for _, r in pts], ".-", markersize=3, label=name)
ax.plot([0, 6], [0, 6], "k:", label="ROS time = wall time")
ax.set_xlabel("wall time [s]")
ax.set_ylabel("ROS time [s]")
ax.legend()
ax.set_title("ROS time against wall time")
fig

# %% [markdown]
# The tick rasters at `real_time_factor` 0.5: the ROS-time `Rate(2)` ticks every second of wall
# time, the `WallRate(2)` every half second.

# %% tags=["plot"]
fig = new_figure(figsize=(7, 2.2))
ax = fig.add_subplot(1, 1, 1)
for row, (name, ts) in enumerate(ticks.items()):
    ax.vlines(ts, row - 0.35, row + 0.35)
ax.set_yticks(range(len(ticks)), list(ticks))
ax.set_xlabel("wall time [s]")
ax.set_ylabel("loop")
ax.set_title("ticks at real_time_factor 0.5")
fig

# %% tags=["digest"]
print(hashlib.sha256(" ".join(digests).encode()).hexdigest())

# %% [markdown]
# ## Try this
#
# Exercise 4c (`exercises/ex4c_time/README.md`) is about a node that behaves right on wall and
# simulated time: a heartbeat on `rospy.Rate`, an odometry watchdog on ROS time, a status line on
# wall time, graded under the simulator at half speed, paused and restarted, and under
# `rosbag play --clock -r 2` and `--loop`. Here, play the bag with `loop=True` and watch the ROS time jump back at the
# end of each pass, or give the player `rate=0.5`.
