"""The goal storm of actionlib's deadlock test, small: its rate is set by the round trip.

actionlib's ``test_simple_action_server_deadlock`` runs five companions that loop
``send_goal(); wait_for_result(d)`` against a SimpleActionServer whose execute callback waits on
a condition that the preempt callback notifies.  The server holds two goals at most (the current
one and the next), so every goal that arrives ends another at once (the current one PREEMPTED, or
the pending next one RECALLED), and that goal's client sends its next goal as soon as the result
arrives: goals are in flight for ever, as fast as a round trip allows.  Real Noetic on a two-core
machine runs about 85 goals a second (3,891 goals in 46 s: 3,110 RECALLED, 778 PREEMPTED,
3 SUCCEEDED), its round trip slowed by the CPU the status arrays cost.  Here two clients and the
same server: with ddes's instant delivery a round trip takes no time, so the storm is a zero-time
livelock that the instant budget stops; with a link latency each client's goals are one round trip
apart and the server keeps executing goals.
"""

from __future__ import annotations

import textwrap
from collections import defaultdict
from pathlib import Path

import pytest

import ddes
from ddes.compat.scripts import run_script
from ddes.errors import RunawayError

SERVER = textwrap.dedent("""
    import threading

    import actionlib
    import rospy
    from actionlib.msg import TestAction

    rospy.init_node("storm_server")
    condition = threading.Condition()


    def execute(goal):
        with condition:
            if not server.is_preempt_requested():
                condition.wait(1.0)
        if server.is_preempt_requested():
            server.set_preempted()
        else:
            server.set_succeeded()


    def preempt():
        with condition:
            condition.notify()


    server = actionlib.SimpleActionServer("storm", TestAction, execute_cb=execute,
                                          auto_start=False)
    server.register_preempt_callback(preempt)
    server.start()
    rospy.spin()
""")

CLIENT = textwrap.dedent("""
    import actionlib
    import rospy
    from actionlib.msg import TestAction, TestGoal

    rospy.init_node("storm_client")
    client = actionlib.SimpleActionClient("storm", TestAction)
    client.wait_for_server()
    while not rospy.is_shutdown():
        client.send_goal(TestGoal())
        client.wait_for_result()
""")


def _world(tmp_path: Path, latency: float, budget: int) -> ddes.World:
    (tmp_path / "server.py").write_text(SERVER)
    (tmp_path / "client.py").write_text(CLIENT)
    world = ddes.World(seed=1, instant_budget=budget)
    world.log_output = False
    world.set_link(latency=latency)
    run_script(world, tmp_path / "server.py")
    for i in (1, 2):
        run_script(world, tmp_path / "client.py", [f"__name:=client_{i}"])
    return world


def test_at_zero_latency_the_goal_storm_is_a_zero_time_livelock(tmp_path: Path) -> None:
    world = _world(tmp_path, 0.0, 1500)
    with pytest.raises(RunawayError, match=r"zero-time livelock at simulated t=0\.001000000 s"):
        world.run(until=5.0)
    sends = world.trace.select(kind="action.client.send")
    assert len(sends) > 50 and {e.t for e in sends} == {1_000_000}
    statuses = {e.details["status"] for e in world.trace.select(kind="action.client.result")}
    assert statuses == {"PREEMPTED", "RECALLED"}  # every goal ended by the next one


def test_with_a_latency_each_goal_waits_a_round_trip(tmp_path: Path) -> None:
    world = _world(tmp_path, 0.05, 1500)
    world.run(until=5.0)
    sent: dict[str, list[int]] = defaultdict(list)
    for e in world.trace.select(kind="action.client.send"):
        sent[e.source].append(e.t)
    assert set(sent) == {"/client_1", "/client_2"}
    for times in sent.values():  # goal to the server and result back: 2 x 50 ms at least
        assert len(times) > 10
        assert min(b - a for a, b in zip(times, times[1:])) >= 100_000_000
    starts = [e.t for e in world.trace.select(kind="action.simple.execute")
              if e.details["phase"] == "start"]
    assert len(starts) > 20 and starts[-1] > 4_500_000_000  # no deadlock: it keeps executing
    again = _world(tmp_path, 0.05, 1500)
    again.run(until=5.0)
    assert again.digest() == world.digest()
