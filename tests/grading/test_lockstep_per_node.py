"""A child per student node: one that hangs is ended by its own budget while the others keep
running; messages and service calls cross between children through the grader's world."""

from __future__ import annotations

import textwrap
from pathlib import Path

from ddes.grading.bridge import Lockstep
from ddes.grading.sandbox import Limits, Sandbox
from ddes.graph.world import World
from ddes.services.server import Service

TALKER = """\
import rospy
from std_msgs.msg import String
rospy.init_node("talker")
pub = rospy.Publisher("/chatter", String, queue_size=10)
rate = rospy.Rate(10)
n = 0
while not rospy.is_shutdown():
    pub.publish("hello %d" % n)
    n += 1
    rate.sleep()
"""

ECHO = """\
import rospy
from std_msgs.msg import String
rospy.init_node("echo")
pub = rospy.Publisher("/echo", String, queue_size=10)
rospy.Subscriber("/chatter", String, lambda m: pub.publish("echo " + m.data))
rospy.spin()
"""

HANG = """\
import rospy
from std_msgs.msg import String
rospy.init_node("hang")
rospy.sleep(0.35)
while True:
    pass
"""


def _boxes(tmp_path: Path, scripts: dict[str, str], limits: Limits | None = None) -> list[Sandbox]:
    for name, text in scripts.items():
        (tmp_path / name).write_text(textwrap.dedent(text))
    return [Sandbox(tmp_path, [(name, [])], limits=limits) for name in scripts]


def _texts(world: World, topic: str) -> list[tuple[int, str]]:
    string = world.messages.get_message_class("std_msgs/String")
    return [(ev.t, string().deserialize(ev.details["data"]).data)
            for ev in world.trace.select(kind="topic.publish", topic=topic)]


def test_messages_cross_from_one_child_to_another(tmp_path: Path) -> None:
    world = World(0, wall_budget=None)
    lock = Lockstep(world, _boxes(tmp_path, {"talker.py": TALKER, "echo.py": ECHO}))
    outcome = lock.run(1_000_000_000)
    assert outcome.state == "finished" and [o.state for o in lock.outcomes] == ["finished"] * 2
    said = _texts(world, "/chatter")
    echoed = _texts(world, "/echo")
    # t=0's message crosses before the grader knows the publisher (as with one child); the
    # others are echoed at the instant they were published
    assert [text for _t, text in said] == [f"hello {i}" for i in range(1, 10)]
    assert echoed == [(t, "echo " + text) for t, text in said]
    assert sorted(lock.proxies) == ["/echo", "/talker"]


def test_a_hanging_node_is_ended_alone_and_the_others_go_on(tmp_path: Path) -> None:
    world = World(0, wall_budget=None)
    boxes = _boxes(tmp_path, {"talker.py": TALKER, "hang.py": HANG}, Limits(step_wall_s=1.0))
    lock = Lockstep(world, boxes)
    outcome = lock.run(1_000_000_000)
    talker, hang = lock.outcomes
    assert talker.state == "finished"
    assert hang.state == "killed" and "1 s wall budget" in hang.reason and "t=0.350" in hang.reason
    assert outcome.state == "killed" and outcome.reason.startswith("hang.py: no answer within")
    assert len(_texts(world, "/chatter")) == 9  # the talker kept its rate to the end


SERVER = """\
import rospy
from rospy_tutorials.srv import AddTwoInts, AddTwoIntsResponse
rospy.init_node("adder")
rospy.Service("/add_two_ints", AddTwoInts, lambda req: AddTwoIntsResponse(req.a + req.b))
rospy.spin()
"""

CLIENT = """\
import rospy
from std_msgs.msg import String
from rospy_tutorials.srv import AddTwoInts
rospy.init_node("asker")
pub = rospy.Publisher("/sums", String, queue_size=10)
rospy.sleep(0.1)
rospy.wait_for_service("/add_two_ints", timeout=1.0)
add = rospy.ServiceProxy("/add_two_ints", AddTwoInts)
pub.publish("sum %d" % add(20, 22).sum)
grader = rospy.ServiceProxy("/grader_sum", AddTwoInts)
pub.publish("grader %d" % grader(1, 2).sum)
try:
    rospy.ServiceProxy("/nowhere", AddTwoInts)(1, 1)
except rospy.ServiceException as exc:
    pub.publish("error %s" % exc)
rospy.spin()
"""


def test_a_student_client_calls_another_childs_service_and_the_graders(tmp_path: Path) -> None:
    world = World(0, wall_budget=None)
    cls = world.messages.get_service_class("rospy_tutorials/AddTwoInts")
    grader = world.create_node("/grader")
    Service(grader, "/grader_sum", cls, lambda req: cls._response_class(req.a * 100 + req.b))
    lock = Lockstep(world, _boxes(tmp_path, {"adder.py": SERVER, "asker.py": CLIENT}))
    assert lock.run(2_000_000_000).state == "finished"
    texts = [text for _t, text in _texts(world, "/sums")]
    assert texts[:2] == ["sum 42", "grader 102"]
    assert texts[2].startswith("error ") and "/nowhere" in texts[2]
    # the calls were made in the grader's world from the asking node's proxy
    callers = {(ev.details.get("service"), ev.source)
               for ev in world.trace.select(kind="service.call")}
    assert ("/add_two_ints", "/asker") in callers and ("/grader_sum", "/asker") in callers


def test_a_lockstep_of_several_children_gives_the_same_trace_every_run(tmp_path: Path) -> None:
    digests = set()
    for i in range(2):
        world = World(0, wall_budget=None)
        run = tmp_path / str(i)
        run.mkdir()
        Lockstep(world, _boxes(run, {"talker.py": TALKER, "echo.py": ECHO})).run(1_000_000_000)
        digests.add(world.digest())
    assert len(digests) == 1
