"""Script pairs that show rospy behaviour real code relies on (issue 39, item 3).

Each scenario is a set of rospy scripts started together (in this order) on one master and
what each prints; they wait for one another through ROS itself (connections, messages), never
through wall-clock guesses, so they print the same lines under real rospy as processes and in
ddes as script nodes of one world.  ``tests/compat/test_rospy_behaviours.py`` runs them both
ways.  Every printed line is deterministic in ROS too (counts, texts, no times).
"""

from __future__ import annotations

#: name -> (params set on the master before the scripts start, {file: source} in start order)
SCENARIOS: dict[str, tuple[dict[str, object], dict[str, str]]] = {}

SCENARIOS["shared_publisher"] = ({}, {
    "share_listener.py": '''
import rospy
from std_msgs.msg import String

rospy.init_node("hearer")
heard = []
rospy.Subscriber("chatter", String, lambda m: heard.append(m.data))
done = rospy.Publisher("done", String, queue_size=1, latch=True)
while "end" not in heard and not rospy.is_shutdown():
    rospy.sleep(0.05)
print("heard %d of 20" % sum(h.startswith("m") for h in heard))
done.publish("done")
rospy.sleep(1.0)
''',
    "share_talker.py": '''
import rospy
from std_msgs.msg import String

rospy.init_node("sharer")
first = rospy.Publisher("chatter", String, queue_size=100)
while first.get_num_connections() == 0:
    rospy.sleep(0.05)
counts = set()
for i in range(20):
    pub = rospy.Publisher("chatter", String, queue_size=100)  # a new Publisher per message
    counts.add(pub.get_num_connections())
    pub.publish("m%d" % i)
first.publish("end")
print("connections of each new publisher", sorted(counts))
rospy.wait_for_message("done", String, timeout=30)
'''})

SCENARIOS["shared_subscriber"] = ({}, {
    "latch_talker.py": '''
import rospy
from std_msgs.msg import String

rospy.init_node("latcher")
pub = rospy.Publisher("latched", String, queue_size=1, latch=True)
pub.publish("L")
live = rospy.Publisher("live", String, queue_size=10)
rospy.wait_for_message("go", String, timeout=30)
live.publish("after")
rospy.wait_for_message("done", String, timeout=30)
''',
    "latch_listener.py": '''
import rospy
from std_msgs.msg import String

rospy.init_node("latch_listener")
got = {1: [], 2: []}
rospy.Subscriber("latched", String, lambda m: got[1].append(m.data))
while not got[1]:
    rospy.sleep(0.05)
second = rospy.Subscriber("latched", String, lambda m: got[2].append(m.data))
rospy.sleep(0.5)
print("second subscriber", got[2], "connections", second.get_num_connections())
print("wait_for_message", rospy.wait_for_message("latched", String, timeout=5).data)
live1, live2 = [], []
rospy.Subscriber("live", String, lambda m: live1.append(m.data))
go = rospy.Publisher("go", String, queue_size=1, latch=True)
rospy.sleep(1.0)
rospy.Subscriber("live", String, lambda m: live2.append(m.data))  # shares the connection
go.publish("go")
while not live1:
    rospy.sleep(0.05)
rospy.sleep(0.5)
print("live", live1, live2)
done = rospy.Publisher("done", String, queue_size=1, latch=True)
done.publish("done")
rospy.sleep(1.0)
'''})

SCENARIOS["shutdown_hook"] = ({}, {
    "hook_listener.py": '''
import rospy
from std_msgs.msg import String

rospy.init_node("mourner")
heard = []
rospy.Subscriber("chatter", String, lambda m: heard.append(m.data))
ready = rospy.Publisher("ready", String, queue_size=1, latch=True)
rospy.sleep(0.5)
ready.publish("ready")
while "I'm dead now" not in heard and not rospy.is_shutdown():
    rospy.sleep(0.05)
print("heard", heard)
''',
    "hook_talker.py": '''
import rospy
from std_msgs.msg import String

pub = rospy.Publisher("chatter", String, queue_size=10)
rospy.init_node("dying")


def on_shutdown():
    print("in the hook: is_shutdown", rospy.is_shutdown(), "is_shutdown_requested",
          rospy.core.is_shutdown_requested())
    pub.publish("I'm dead now")


rospy.on_shutdown(on_shutdown)
while pub.get_num_connections() == 0:
    rospy.sleep(0.05)
rospy.wait_for_message("ready", String, timeout=30)
rospy.signal_shutdown("done")
print("after signal_shutdown: is_shutdown", rospy.is_shutdown())
'''})

SCENARIOS["subscribe_listener"] = ({}, {
    "sl_talker.py": '''
import rospy
from std_msgs.msg import String

gone = []


class Listener(rospy.SubscribeListener):
    def peer_subscribe(self, topic_name, topic_publish, peer_publish):
        print("peer_subscribe", topic_name)
        peer_publish(String("hello peer"))
        topic_publish(String("hello all"))

    def peer_unsubscribe(self, topic_name, num_peers):
        print("peer_unsubscribe", topic_name, num_peers)
        gone.append(num_peers)


rospy.init_node("announcer")
pub = rospy.Publisher("announce", String, subscriber_listener=Listener(), queue_size=10)
while not gone and not rospy.is_shutdown():
    rospy.sleep(0.05)
''',
    "sl_listener.py": '''
import rospy
from std_msgs.msg import String

rospy.init_node("announced")
heard = []
sub = rospy.Subscriber("announce", String, lambda m: heard.append(m.data))
while len(heard) < 2:
    rospy.sleep(0.05)
rospy.sleep(0.2)
print("heard", heard)
sub.unregister()
rospy.sleep(1.0)
'''})

SCENARIOS["connection_headers"] = ({}, {
    "hdr_talker.py": '''
import rospy
from std_msgs.msg import String

rospy.init_node("cookie_jar")
pub = rospy.Publisher("hdr", String, queue_size=1, latch=True, headers={"cookies": "yum"})
pub.publish("x")
rospy.wait_for_message("done", String, timeout=30)
''',
    "hdr_listener.py": '''
import rospy
from std_msgs.msg import String

rospy.init_node("cookie_eater")
m = rospy.wait_for_message("hdr", String, timeout=30)
h = m._connection_header
print("header keys", sorted(h))
print("cookies", h["cookies"], "callerid", h["callerid"], "latching", h["latching"])
done = rospy.Publisher("done", String, queue_size=1, latch=True)
done.publish("done")
rospy.sleep(1.0)
'''})

SCENARIOS["statistics"] = ({"/enable_statistics": True}, {
    "stats_listener.py": '''
import rospy
from geometry_msgs.msg import PointStamped
from rosgraph_msgs.msg import TopicStatistics
from std_msgs.msg import String

rospy.init_node("measurer")
reports = []
rospy.Subscriber("/statistics", TopicStatistics, reports.append)
heard = []
rospy.Subscriber("a", String, lambda m: heard.append(m.data))
rospy.Subscriber("b", PointStamped, lambda m: None)
while "end" not in heard and not rospy.is_shutdown():
    rospy.sleep(0.05)
rospy.sleep(0.5)
for r in reports:
    if r.topic == "/b":
        print("b report", r.node_pub, r.node_sub, "delivered", r.delivered_msgs,
              "dropped", r.dropped_msgs, "traffic", r.traffic,
              "window", (r.window_stop - r.window_start).to_sec() < 0.5)
a = [r for r in reports if r.topic == "/a"]
print("a reports", len(a) >= 1, sorted(set((r.node_pub, r.node_sub) for r in a)),
      "traffic per message", sorted(set(r.traffic // max(r.delivered_msgs, 1) for r in a[1:])))
''',
    "stats_talker.py": '''
import rospy
from geometry_msgs.msg import PointStamped
from std_msgs.msg import String

rospy.init_node("measured")
a = rospy.Publisher("a", String, queue_size=10)
b = rospy.Publisher("b", PointStamped, queue_size=10)
while a.get_num_connections() == 0 or b.get_num_connections() == 0:
    rospy.sleep(0.05)
rospy.sleep(1.5)
rate = rospy.Rate(10)
for i in range(50):
    a.publish("a%02d" % i)
    if i in (10, 40):
        p = PointStamped()
        p.header.stamp = rospy.Time.now()
        p.header.frame_id = "map"
        b.publish(p)
    rate.sleep()
a.publish("end")
rospy.sleep(1.0)
'''})

SCENARIOS["texts"] = ({}, {
    "texts.py": '''
import rospy
from std_msgs.msg import String
from std_srvs.srv import Empty, SetBool, SetBoolResponse
from rosgraph_msgs.msg import Log

pub0 = rospy.Publisher("early", String)
rospy.init_node("texts")


def t(label, f):
    try:
        print(label, "->", repr(f()))
    except Exception as e:
        print(label, "raises", type(e).__name__ if type(e).__name__ in (
            "KeyError", "ServiceException", "ROSException", "TypeError") else "other",
              "ServiceException" if isinstance(e, rospy.ServiceException) else "", str(e))


t("has_param missing", lambda: rospy.has_param("~missing"))
t("get_param missing", lambda: rospy.get_param("~missing"))
t("get_param missing global", lambda: rospy.get_param("/missing"))
rospy.set_param("~x", 1)
t("delete_param", lambda: rospy.delete_param("~x"))
t("delete_param again", lambda: rospy.delete_param("~x"))


def boom(req):
    raise ValueError("boom happened")


rospy.Service("boom", Empty, boom)
rospy.Service("none", Empty, lambda req: None)
rospy.Service("setb", SetBool, lambda req: SetBoolResponse(True, "ok"))
rospy.Service("badresp", SetBool, lambda req: SetBoolResponse(success=[1]))
rospy.wait_for_service("boom")
t("handler error", lambda: rospy.ServiceProxy("boom", Empty)())
t("handler None", lambda: rospy.ServiceProxy("none", Empty)())
try:
    rospy.ServiceProxy("badresp", SetBool)(True)
except rospy.ServiceException as e:
    print("bad response is a ServiceException:",
          str(e).startswith("service [/badresp] responded with an error: b'error processing "
                            "request: "))
try:
    rospy.ServiceProxy("setb", SetBool)(data=[1, 2])
except Exception as e:
    print("bad request is a ServiceException:", isinstance(e, rospy.ServiceException))
t("unavailable", lambda: rospy.ServiceProxy("nosuch", Empty)())
print("repr", repr(rospy.Time(1, 5)), repr(rospy.Duration(2, 3)), repr(rospy.Time()),
      repr(rospy.Duration(-1, 5)), str(rospy.Time(1, 5)))
print("repr arithmetic", repr(rospy.Time(3) - rospy.Time(1)), repr(rospy.Time(3) + rospy.Duration(1)),
      repr(rospy.Duration(1) * 2), repr(rospy.Duration.from_sec(1.5)), repr(rospy.Time.from_sec(2.5)))
print("now", type(rospy.Time.now()).__name__, repr(rospy.get_rostime())[:11])
t("wait_for_message", lambda: rospy.wait_for_message("chatter", String, timeout=0.3))
t("wait_for_message private", lambda: rospy.wait_for_message("~chat", String, timeout=0.3))
logs = []
rospy.Subscriber("/rosout", Log, lambda m: logs.append(m) if m.name == "/texts" else None)
rospy.sleep(1.0)


class Talker:
    def go(self):
        rospy.loginfo("from a method")

    @staticmethod
    def static():
        rospy.loginfo("from a static method")


def func():
    rospy.loginfo("from a function")


Talker().go()
Talker.static()
func()
rospy.loginfo("from the module")
rospy.sleep(1.0)
for m in logs:
    if m.msg.startswith("from"):
        print("rosout", m.msg, "function", m.function, "file", m.file)
'''})

SCENARIOS["before_init"] = ({}, {
    "before_init.py": '''
import rospy
from std_msgs.msg import Empty as EmptyMsg
from std_srvs.srv import Empty, EmptyResponse

calls = []
srv = rospy.Service("early_svc", Empty, lambda req: calls.append(1) or EmptyResponse())
proxy = rospy.ServiceProxy("early_svc", Empty)
sub = rospy.Subscriber("early_topic", EmptyMsg)
print("name before init_node", rospy.get_name(), rospy.get_namespace())
rospy.set_param("/early_param", 5)
print("get_param", rospy.get_param("/early_param"), rospy.get_param("~private", "default"))
print("has_param", rospy.has_param("/early_param"), rospy.has_param("/nothing_here"))
try:
    rospy.get_param("/nothing_here")
except KeyError as e:
    print("KeyError", e)
try:
    rospy.wait_for_service("no_such_service", timeout=0.2)
except rospy.ROSException as e:
    print("wait_for_service:", e)
try:
    rospy.get_time()
except rospy.ROSInitException as e:
    print("get_time:", str(e).startswith("time is not initialized. Have you called init_node()?"))
rospy.on_shutdown(lambda: print("hook from before init_node"))
rospy.init_node("late_starter")
proxy.wait_for_service(timeout=5)
proxy()
print("calls", len(calls), "name", rospy.get_name())
rospy.signal_shutdown("bye")
'''})

SCENARIOS["modules"] = ({}, {
    "helper_user.py": '''
import os
import sys

import helper_mod
import rosgraph
import rosgraph.names
import rospy
from rospy.names import ns_join
from std_msgs.msg import *
from std_srvs.srv import *

rospy.init_node("module_user")
print("script folder first on sys.path", sys.path[0] == os.path.dirname(os.path.abspath(__file__)))
print("helper", helper_mod.who())
print("star std_msgs", sorted(k for k, v in list(globals().items())
                              if hasattr(v, "_type") and hasattr(v, "_md5sum")
                              and v._type.startswith("std_msgs/")))
print("star std_srvs", sorted(k for k, v in list(globals().items())
                              if hasattr(v, "_type") and v._type.startswith("std_srvs/")))
pub = rospy.Publisher("/modules_topic", String, queue_size=1)
master = rosgraph.Master("/module_user")
pubs, subs, srvs = master.getSystemState()
print("system state", [p for p in pubs if p[0] == "/modules_topic"])
print("topic types", [t for t in master.getTopicTypes() if t[0] == "/modules_topic"])
try:
    master.lookupNode("/no_such_node")
except rosgraph.MasterError as e:
    print("lookupNode:", e)
try:
    master.getParam("/no_such_param")
except rosgraph.MasterError as e:
    print("getParam:", e)
print("names", ns_join("/a", "b"), rosgraph.names.ns_join("a", "b"),
      rospy.names.canonicalize_name("//a//b/"), rospy.names.get_caller_id())
''',
    "helper_mod.py": '''
import rospy


def who():
    return "the helper runs in " + rospy.get_name()
'''})
