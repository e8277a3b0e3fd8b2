# ddes-digest: 65d06423037657c6ee941aa5cf9cbd81e0b175cac8ed454e03014038f3a93b3f
# %% [markdown]
# # Lecture 4a: services
#
# A topic is a one-way stream; a **service** is a request and its response, like a function
# call between nodes. A server advertises a name and a type (`.srv`: request fields, `---`,
# response fields); a client calls it and waits for the answer. Use a service for something
# short that needs an answer ("add these", "stop now?"), a topic for a continuous flow.
#
# First the lecture's `add_two_ints`, in the console and from Python.

# %%
import hashlib

import ddes
from ddes import Service, ServiceProxy, get_service_class, wait_for_service
from ddes.display.figure import new_figure
from ddes.msg import get_message_class
from ddes.rqt.plot import field_series
from ddes.sim import Simulator, WorldSpec

console = ddes.Console(seed=0)
sh = lambda command: print(console.run(command), end="")  # noqa: E731 - a shell prompt
sh("rosrun roscpp_tutorials add_two_ints_server &")
sh("rosservice list")
sh("rossrv show roscpp_tutorials/TwoInts")
sh('rosservice call /add_two_ints "{a: 10, b: 5}"')
sh("rosrun roscpp_tutorials add_two_ints_client 3 4")

# %% [markdown]
# In Python a call is an event to `yield`: the calling process waits for the response on
# simulated time, while the rest of the world goes on.

# %%
AddTwoInts = get_service_class("rospy_tutorials/AddTwoInts")
SetBool = get_service_class("std_srvs/SetBool")
Twist = get_message_class("geometry_msgs/Twist")
Vector3 = get_message_class("geometry_msgs/Vector3")

world = ddes.World(seed=0)
sim = Simulator(world, WorldSpec.load("empty"), noise=False)
adder = Service(world.create_node("adder"), "add_two_ints", AddTwoInts, lambda req: req.a + req.b)

# %% [markdown]
# ## An emergency stop as a service
#
# A driver node commands 0.8 m/s at 10 Hz, unless its `~estop` service (std_srvs/SetBool) has
# been called with `data: true`. The operator calls it at 3 s, releases it at 6 s, and, in
# passing, asks the adder for a sum.

# %%
driver = world.create_node("driver")
cmd = ddes.Publisher(driver, "/cmd_vel", Twist, queue_size=1)
stopped = False


def on_estop(req):
    global stopped
    stopped = req.data
    return True, "stopped" if stopped else "driving"


Service(driver, "~estop", SetBool, on_estop)
ddes.Timer(driver, 0.1, lambda event: cmd.publish(
    Twist() if stopped else Twist(linear=Vector3(x=0.8))))

operator = world.create_node("operator")
calls = []


def operate():
    yield wait_for_service(operator, "/driver/estop", timeout=1.0)
    estop = ServiceProxy(operator, "/driver/estop", SetBool)
    add = ServiceProxy(operator, "add_two_ints", AddTwoInts)
    for at, data in ((3.0, True), (6.0, False)):
        yield operator.sleep(at - operator.get_time())
        resp = yield estop(data)
        calls.append((operator.get_time(), data))
        print(f"{operator.get_time():.4f} s  estop({data}) -> success={resp.success}, "
              f"message={resp.message!r}")
    resp = yield add(20, 22)
    print(f"{operator.get_time():.4f} s  add_two_ints(20, 22) -> {resp.sum}")


operator.process(operate())
world.run(until=9.0)

# %% [markdown]
# The robot's speed with the two calls marked: it brakes at its acceleration limit after the
# stop, and speeds up again after the release.

# %% tags=["plot"]
speed = field_series(world, "/odom/twist/twist/linear/x")
fig = new_figure(figsize=(8, 3.5))
ax = fig.add_subplot(1, 1, 1)
ax.plot(speed.t, speed.y, label="/odom/twist/twist/linear/x")
for t, data in calls:
    ax.axvline(t, color="red" if data else "green", linestyle="--")
    ax.annotate(f"estop({data})", (t, 0.85), xytext=(4, 0), textcoords="offset points",
                fontsize=8)
ax.set_xlabel("time [s]")
ax.set_ylabel("speed [m/s]")
ax.set_ylim(-0.05, 1.0)
ax.set_title("speed, with the e-stop service calls")
fig

# %% [markdown]
# ## Topic, service or action?
#
# | | topic | service | action |
# |---|---|---|---|
# | direction | one to many, one way | one client, one server, both ways | client and server, both ways |
# | the caller waits | never | until the answer | no: feedback while it runs |
# | can be cancelled | — | no | yes |
# | typical use | sensor data, commands | settings, queries, a stop | long tasks: navigate, follow a path |
#
# The next notebook (`04b_actions`) runs the third column.

# %% tags=["digest"]
print(hashlib.sha256(f"{console.world.digest()} {world.digest()}".encode()).hexdigest())

# %% [markdown]
# ## Try this
#
# Exercise 4a (`exercises/ex4a_services/README.md`) adds such an emergency stop, as a service, to
# the pillar controller of exercise 3. Here, call the e-stop twice in a row, or call a service nobody offers
# (`/driver/brake`) and read the error.
