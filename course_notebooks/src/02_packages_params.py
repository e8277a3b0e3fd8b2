# ddes-digest: 106954acc673620e58f3e0fd006e4a0d7320c833935816b1fe0bb08cadb614f2
# %% [markdown]
# # Lecture 2: packages, parameters and launch files
#
# ROS code ships in **packages**: a folder with a `package.xml` (its name and dependencies),
# scripts, configuration and launch files; `rospack find` locates one on the package path.
# **Parameters** live on the parameter server; a name starting with `~` is *private*, under the
# node's own name, so two copies of a node can be configured apart. A **launch file** starts
# several nodes at once, loads parameter files into them and can remap their topic names.
#
# This notebook writes a tiny package — exercise 2's idea: a node that subscribes to the laser
# and reports the closest obstacle — and starts it with `roslaunch`, next to the simulator.

# %%
import math
import tempfile
from pathlib import Path

import ddes
from ddes.console.viz import find_simulator
from ddes.display.figure import new_figure
from ddes.rqt import rqt_plot
from ddes.rqt.messages import topic_messages
from ddes.sim.view import top_view

workspace = Path(tempfile.mkdtemp())
pkg = workspace / "closest_range"
(pkg / "scripts").mkdir(parents=True)
(pkg / "config").mkdir()
(pkg / "launch").mkdir()
(pkg / "package.xml").write_text("""<package format="2">
  <name>closest_range</name>
  <version>0.1.0</version>
  <description>Reports the closest laser return</description>
  <maintainer email="student@example.com">student</maintainer>
  <license>BSD</license>
  <buildtool_depend>catkin</buildtool_depend>
  <depend>rospy</depend>
  <depend>sensor_msgs</depend>
  <depend>std_msgs</depend>
</package>
""")

# %% [markdown]
# The node is ordinary rospy. It reads its **private** parameters `~scan_topic` and
# `~queue_size`, subscribes, and for each scan publishes the smallest valid range on
# `~closest` (std_msgs/Float32) and logs it.

# %%
(pkg / "scripts" / "closest_range_node.py").write_text('''\
import rospy
from sensor_msgs.msg import LaserScan
from std_msgs.msg import Float32


class ClosestRange:
    def __init__(self):
        topic = rospy.get_param("~scan_topic")
        queue_size = rospy.get_param("~queue_size", 1)
        self.pub = rospy.Publisher("~closest", Float32, queue_size=1)
        rospy.Subscriber(topic, LaserScan, self.scan_callback, queue_size=queue_size)

    def scan_callback(self, scan):
        valid = [r for r in scan.ranges if scan.range_min <= r <= scan.range_max]
        closest = min(valid) if valid else float("inf")
        self.pub.publish(closest)
        rospy.loginfo_throttle(2.0, "%.3f m is the smallest distance", closest)


rospy.init_node("closest_range")
ClosestRange()
rospy.spin()
''')
(pkg / "config" / "config.yaml").write_text("scan_topic: /scan\nqueue_size: 1\n")

# %% [markdown]
# The launch file starts the simulator (its own launch file, included with arguments) and our
# node, and loads `config.yaml` into the node's private namespace.

# %%
(pkg / "launch" / "closest_range.launch").write_text("""<launch>
  <include file="$(find ddes_sim)/launch/ddes_sim.launch">
    <arg name="world" value="pillars_field"/>
    <arg name="noise" value="false"/>
  </include>
  <node pkg="closest_range" type="closest_range_node.py" name="closest_range" output="screen">
    <rosparam command="load" file="$(find closest_range)/config/config.yaml"/>
  </node>
</launch>
""")

console = ddes.Console(ddes.World(seed=0, package_path=[str(workspace)]))
sh = lambda command: print(console.run(command), end="")  # noqa: E731 - a shell prompt

sh("rospack find closest_range")
sh("roslaunch closest_range closest_range.launch &")
sh("sleep 0.5")
sh("rosparam list")
sh("rosparam get /closest_range/scan_topic")

# %% [markdown]
# Drive in a slow circle for 12 s and watch the closest range change as obstacles pass.

# %%
sh("rostopic pub -r 10 --duration 12 /cmd_vel geometry_msgs/Twist "
   "'{linear: {x: 0.8}, angular: {z: -0.1}}'")
sh("rostopic echo -n 1 /closest_range/closest")

# %% [markdown]
# The closest range over time, as `rqt_plot /closest_range/closest/data` draws it:

# %% tags=["plot"]
rqt_plot(console.world, "/closest_range/closest/data", ylabel="closest range [m]")

# %% [markdown]
# One scan in polar form (what the node sees: range against bearing; beam *i* points at
# `angle_min + i * angle_increment`), and the same moment from above.

# %% tags=["plot"]
_, published = topic_messages(console.world, "/scan")
scan = published[-1].msg
angles = [scan.angle_min + i * scan.angle_increment for i in range(len(scan.ranges))]
fig = new_figure(figsize=(5, 5))
ax = fig.add_subplot(projection="polar")
ax.plot([a for a, r in zip(angles, scan.ranges) if math.isfinite(r)],
        [r for r in scan.ranges if math.isfinite(r)], ".", markersize=3)
ax.set_theta_zero_location("N")
ax.set_xlabel("bearing [°] (0 = straight ahead, counter-clockwise)")
ax.set_ylabel("range [m]", labelpad=28)
ax.set_title("the last /scan")
fig

# %% tags=["plot"]
top_view(find_simulator(console.world))

# %% tags=["digest"]
print(console.world.digest())

# %% [markdown]
# ## Try this
#
# Exercise 2 (`exercises/ex2_package/README.md`) builds this package properly: a class holding
# the ROS interface, the algorithm in a ROS-free module, a parameter file and an RViz
# configuration. Here, try a remap in the launch file (`<remap from="/scan" to="/front_scan"/>`)
# and see what `rosparam` and the plot say when the topic and the parameter disagree.
