"""The wire protocol: five real topics, their types, latching, queue sizes and status timing."""

from __future__ import annotations

from collections.abc import Generator
from typing import Any

import pytest

import ddes
from ddes.actionlib import ActionServer, SimpleActionClient
from ddes.console.tooling import run_command
from ddes.msg import get_message_class
from ddes.rosbag import Recorder

from .servers import RefAction, RefGoal, RefServer

GoalStatusArray = get_message_class("actionlib_msgs/GoalStatusArray")
Clock = get_message_class("rosgraph_msgs/Clock")

TOPICS = {
    "/reference_action/goal": "actionlib/TestActionGoal",
    "/reference_action/cancel": "actionlib_msgs/GoalID",
    "/reference_action/status": "actionlib_msgs/GoalStatusArray",
    "/reference_action/feedback": "actionlib/TestActionFeedback",
    "/reference_action/result": "actionlib/TestActionResult",
}


def up(world: ddes.World) -> tuple[RefServer, SimpleActionClient]:
    server = RefServer(world.create_node("ref_server"))
    client = SimpleActionClient(world.create_node("client"), "reference_action", RefAction)
    world.run(until=client.wait_for_server())
    return server, client


def test_five_topics_with_actionlib_types(world: ddes.World) -> None:
    up(world)
    types = dict(world.master.get_topic_types())
    assert {t: types[t] for t in TOPICS} == TOPICS
    listing = run_command(world, "rostopic list").split()
    assert all(t in listing for t in TOPICS)
    info = run_command(world, "rostopic info /reference_action/status")
    assert "actionlib_msgs/GoalStatusArray" in info and "/ref_server" in info


def test_status_is_latched_and_published_at_5_hz(world: ddes.World) -> None:
    up(world)
    assert world.master.topics["/reference_action/status"].publishers[0].latch is True
    world.run(until=2.0)
    late: list[int] = []
    world.create_node("late").subscribe("/reference_action/status", GoalStatusArray,
                                        lambda m: late.append(world.now))
    world.run(until=2.5)
    # the latched copy on connect (2.001), then the timer at 2.2 and 2.4
    assert late == [2_001_000_000, 2_200_000_000, 2_400_000_000]


def test_status_frequency_and_list_timeout_parameters(world: ddes.World) -> None:
    world.params.set_param("/actionlib_status_frequency", 2.0)
    world.params.set_param("/reference_action/status_list_timeout", 1.0)
    server, _ = up(world)
    assert server.server.status_frequency == 2.0
    assert server.server.status_list_timeout_ns == 1_000_000_000
    assert server.server.status_list_timeout == ddes.Duration(1)  # rospy's attribute
    world.run(until=1.6)
    fires = [e.t for e in world.trace.filter(kind="timer.fire", source="/ref_server")]
    assert fires == [500_000_000, 1_000_000_000, 1_500_000_000]


def test_deprecated_status_frequency_warns(world: ddes.World) -> None:
    world.params.set_param("/reference_action/status_frequency", 0)
    server, _ = up(world)
    assert server.server.status_frequency == 0.0 and server.server.status_timer is None
    assert ("You're using the deprecated status_frequency parameter, please switch to "
            "actionlib_status_frequency.") in [e.details["text"]
                                               for e in world.trace.filter(kind="action.misuse")]


@pytest.mark.parametrize(("params", "expected"), [
    ({}, {"server_pub": 50, "server_sub": None, "client_pub": 10, "client_sub": None}),
    ({"actionlib_server_pub_queue_size": 7, "actionlib_server_sub_queue_size": 3,
      "actionlib_client_pub_queue_size": 2, "actionlib_client_sub_queue_size": 4},
     {"server_pub": 7, "server_sub": 3, "client_pub": 2, "client_sub": 4}),
    ({"actionlib_server_pub_queue_size": -5, "actionlib_client_pub_queue_size": -1},
     {"server_pub": 50, "server_sub": None, "client_pub": 10, "client_sub": None}),
])
def test_queue_sizes_from_parameters(world: ddes.World, params: dict[str, int],
                                     expected: dict[str, Any]) -> None:
    for key, value in params.items():
        world.params.set_param("/" + key, value)
    server, client = up(world)
    s, c = server.server, client.action_client
    got = {"server_pub": s.status_pub.queue_size, "server_sub": s.goal_sub.queue_size,
           "client_pub": c.pub_goal.queue_size, "client_sub": c.status_sub.queue_size}
    assert got == expected
    assert {s.result_pub.queue_size, s.feedback_pub.queue_size} == {expected["server_pub"]}
    assert c.pub_cancel.queue_size == expected["client_pub"]
    assert {c.result_sub.queue_size, c.feedback_sub.queue_size} == {expected["client_sub"]}
    assert s.cancel_sub.queue_size == expected["server_sub"]


def test_a_bag_records_the_five_topics(world: ddes.World) -> None:
    rec = Recorder(world, list(TOPICS), in_memory=True)
    _, client = up(world)
    client.send_goal(RefGoal(1))
    world.run(until=1.0)
    rec.stop()
    counts: dict[str, int] = {}
    for topic, msg, _t in rec.bag.read_messages():
        counts[topic] = counts.get(topic, 0) + 1
        assert msg._type == TOPICS[topic]
    assert counts["/reference_action/goal"] == 1
    assert counts["/reference_action/result"] == 1
    assert counts["/reference_action/status"] >= 5
    info = rec.bag.get_type_and_topic_info()
    assert info.topics["/reference_action/status"].msg_type == "actionlib_msgs/GoalStatusArray"


def test_status_timer_runs_on_ros_time_under_sim_time(world: ddes.World) -> None:
    world.use_sim_time = True
    RefServer(world.create_node("ref_server"))
    clock_node = world.create_node("clock", use_sim_time=False)
    pub = clock_node.advertise("/clock", Clock, queue_size=1)

    def tick() -> Generator[Any, Any, None]:
        t = ddes.Time(100)
        while True:
            yield clock_node.wall_sleep(0.1)
            t = t + ddes.Duration(0.05)  # ROS time runs at half speed
            pub.publish(Clock(clock=t))

    clock_node.process(tick())
    got: list[float] = []
    world.create_node("obs", use_sim_time=False).subscribe(
        "/reference_action/status", GoalStatusArray,
        lambda m: got.append(m.header.stamp.to_sec()))
    world.run(until=1.05)
    # 10 ticks of 0.05 s: ROS time 100.05 .. 100.5; the 5 Hz timer (a rospy.Timer, created
    # at ROS time 0) first sleeps from the first valid ROS time (100.05) to 100.25, where its
    # Rate, far behind, fires a second time at once; then 100.45, 0.4 s of kernel time later
    assert [round(s, 2) for s in got if s > 100.0] == [100.25, 100.25, 100.45]


def test_a_server_created_through_the_node_is_its_entity(world: ddes.World) -> None:
    node = world.create_node("s")
    server = ActionServer(node, "~private_action", RefAction, lambda gh: None)
    server.start()
    assert server.ns == "/s/private_action"
    assert "/s/private_action/status" in dict(world.master.get_published_topics())
    assert server in node._entities
