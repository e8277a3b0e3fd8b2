"""ddes's action servers against real ROS 1 (system Python; skipped without ROS).

* the bytes ddes puts on the five topics decode with genpy's generated
  classes to the same values, with the same md5sums;
* rospy's own ``SimpleActionServer`` (goal policy, preempt flags,
  accept_new_goal, set_* and their log texts), driven offline through its
  internal callbacks, ends every random sequence of goals, cancels and calls
  in the same states as ddes's SimpleActionServer on topics.
"""

from __future__ import annotations

import json
from typing import Any

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import ddes
from ddes.actionlib import ActionClient, SimpleActionServer
from ddes.graph.topics import AnyMsg
from ddes.msg import get_message_class

from .servers import RefAction, RefGoal, RefServer

pytestmark = pytest.mark.ros

DECODE_SCRIPT = r'''
import json, sys, binascii
import roslib.message
out = []
for topic, type_, md5, hexdata in json.load(sys.stdin):
    cls = roslib.message.get_message_class(type_)
    msg = cls().deserialize(binascii.unhexlify(hexdata))
    row = {"topic": topic, "md5_ok": cls._md5sum == md5}
    if type_ == "actionlib_msgs/GoalStatusArray":
        row["value"] = [[s.goal_id.id, s.goal_id.stamp.to_nsec(), s.status, s.text]
                        for s in msg.status_list]
    elif type_ == "actionlib_msgs/GoalID":
        row["value"] = [msg.id, msg.stamp.to_nsec()]
    elif type_.endswith("ActionGoal"):
        row["value"] = [msg.goal_id.id, msg.goal_id.stamp.to_nsec(), msg.goal.goal]
    elif type_.endswith("ActionResult"):
        row["value"] = [msg.status.goal_id.id, msg.status.status, msg.status.text,
                        msg.result.result]
    else:
        row["value"] = [msg.status.goal_id.id, msg.status.status, msg.feedback.feedback]
    out.append(row)
print(json.dumps(out))
'''


def _ddes_value(type_: str, msg: Any) -> list[Any]:
    if type_ == "actionlib_msgs/GoalStatusArray":
        return [[s.goal_id.id, s.goal_id.stamp.to_nsec(), s.status, s.text]
                for s in msg.status_list]
    if type_ == "actionlib_msgs/GoalID":
        return [msg.id, msg.stamp.to_nsec()]
    if type_.endswith("ActionGoal"):
        return [msg.goal_id.id, msg.goal_id.stamp.to_nsec(), msg.goal.goal]
    if type_.endswith("ActionResult"):
        return [msg.status.goal_id.id, msg.status.status, msg.status.text, msg.result.result]
    return [msg.status.goal_id.id, msg.status.status, msg.feedback.feedback]


def test_wire_bytes_decode_with_genpy(world: ddes.World, ros_python: Any) -> None:
    wire: list[tuple[str, str, str, bytes]] = []
    spy = world.create_node("spy")
    for topic in ("goal", "cancel", "status", "feedback", "result"):
        name = f"/reference_action/{topic}"
        spy.subscribe(name, AnyMsg, lambda m, n=name: wire.append(
            (n, m._connection_header["type"], m._connection_header["md5sum"], m._buff)))
    RefServer(world.create_node("ref_server"))
    client = ActionClient(world.create_node("client"), "reference_action", RefAction)
    world.run(until=0.5)
    for g in (4, 4, 1, 2, 3, 7, 8):
        client.send_goal(RefGoal(g))
        world.run_for(0.3)
    client.cancel_all_goals()
    world.run_for(0.5)
    ros = ros_python(DECODE_SCRIPT, as_json=True,
                     stdin=json.dumps([(t, ty, md5, data.hex()) for t, ty, md5, data in wire]))
    assert len(ros) == len(wire) > 20
    assert {r["topic"] for r in ros} == {f"/reference_action/{t}" for t in
                                         ("goal", "cancel", "status", "feedback", "result")}
    for row, (_topic, type_, _md5, data) in zip(ros, wire):
        assert row["md5_ok"]
        msg = get_message_class(type_)().deserialize(data)
        assert row["value"] == _ddes_value(type_, msg)


SIMPLE_SCRIPT = r'''
import json, sys, threading
import rospy, rospy.rostime
ERRORS = []
def _logerr(msg, *args):
    ERRORS.append(msg % args if args else msg)
rospy.logerr = _logerr
rospy.rostime.set_rostime_initialized(True)
def set_now(ns):
    rospy.rostime._set_rostime(rospy.Time(ns // 10**9, ns % 10**9))
set_now(0)
from actionlib.simple_action_server import SimpleActionServer
from actionlib.server_goal_handle import ServerGoalHandle
from actionlib.status_tracker import StatusTracker
from actionlib.msg import TestAction, TestActionGoal, TestResult
from actionlib_msgs.msg import GoalID

class Fake:
    def __init__(self):
        self.lock = threading.RLock()
        self.ActionResultType = TestResult
    def publish_status(self):
        pass
    def publish_result(self, status, result):
        self.publish_status()

out = []
for case in json.load(sys.stdin):
    sas = SimpleActionServer("x", TestAction, None, False)
    fake = Fake()
    handles = {}
    steps = []
    for op in case:
        set_now(op["now"])
        kind = op["op"]
        if kind == "goal":
            g = TestActionGoal(goal_id=GoalID(id=op["id"], stamp=rospy.Time(op["stamp"])))
            gh = ServerGoalHandle(StatusTracker(None, None, g), fake, None)
            handles[op["id"]] = gh
            sas.internal_goal_callback(gh)
        elif kind == "cancel":
            gh = handles[op["id"]]
            if gh.set_cancel_requested():
                sas.internal_preempt_callback(gh)
        elif kind == "accept":
            sas.accept_new_goal()
        elif kind == "succeed":
            sas.set_succeeded()
        elif kind == "abort":
            sas.set_aborted()
        elif kind == "preempt":
            sas.set_preempted()
        steps.append({"status": {i: h.get_goal_status().status for i, h in handles.items()},
                      "new_goal": sas.is_new_goal_available(),
                      "preempt": sas.is_preempt_requested(),
                      "next_preempt": sas.new_goal_preempt_request,
                      "active": sas.is_active(), "errors": list(ERRORS)})
        del ERRORS[:]
    out.append(steps)
print(json.dumps(out))
'''

_STEP_NS = 10_000_000


def _ops() -> st.SearchStrategy[list[dict[str, Any]]]:
    op = st.one_of(
        st.builds(lambda s: {"op": "goal", "stamp": s}, st.integers(1, 3)),
        st.builds(lambda i: {"op": "cancel", "index": i}, st.integers(0, 5)),
        st.sampled_from([{"op": "accept"}, {"op": "succeed"}, {"op": "abort"},
                         {"op": "preempt"}]),
    )
    return st.lists(op, min_size=1, max_size=14)


def _concrete(raw: list[dict[str, Any]]) -> list[dict[str, Any]]:
    """Give goals ids, turn cancel indexes into ids (dropping cancels before any goal)."""
    ops, ids = [], []
    for k, op in enumerate(raw):
        op = dict(op, now=(k + 1) * _STEP_NS + 500_000_000)
        if op["op"] == "goal":
            op["id"] = f"g{len(ids)}"
            ids.append(op["id"])
        elif op["op"] == "cancel":
            if not ids:
                continue
            op["id"] = ids[op.pop("index") % len(ids)]
        ops.append(op)
    return ops


def _run_ddes(ops: list[dict[str, Any]]) -> list[dict[str, Any]]:
    world = ddes.World(seed=0)
    world.connect_delay = 0
    node = world.create_node("x_server")
    sas = SimpleActionServer(node, "x", RefAction, auto_start=False)
    sas.start()
    raw = world.create_node("raw")
    ActionGoal = get_message_class("actionlib/TestActionGoal")
    GoalID = get_message_class("actionlib_msgs/GoalID")
    goal_pub = raw.advertise("/x/goal", ActionGoal, queue_size=100)
    cancel_pub = raw.advertise("/x/cancel", GoalID, queue_size=100)
    world.run(until=0.5)
    steps, seen = [], 0
    for op in ops:
        world.run(until=ddes.Time.from_nsec(op["now"] - 5_000_000))
        kind = op["op"]
        if kind == "goal":
            goal_pub.publish(ActionGoal(goal_id=GoalID(id=op["id"], stamp=ddes.Time(op["stamp"]))))
        elif kind == "cancel":
            cancel_pub.publish(GoalID(id=op["id"]))
        elif kind == "accept":
            sas.accept_new_goal()
        elif kind == "succeed":
            sas.set_succeeded()
        elif kind == "abort":
            sas.set_aborted()
        elif kind == "preempt":
            sas.set_preempted()
        world.run(until=ddes.Time.from_nsec(op["now"] + 1_000_000))
        events = world.trace.events[seen:]
        seen = len(world.trace)
        errors = [e.details["text"] if e.kind == "action.misuse" else e.details["error"]
                  for e in events
                  if (e.kind == "action.misuse" and e.details["level"] == "ERROR")
                  or e.kind == "action.server.illegal"]
        statuses = {t.goal_id: int(t.status) for t in sas.action_server.status_list}
        steps.append({"status": {i: statuses[i] for i in
                                 [o["id"] for o in ops if o["op"] == "goal"] if i in statuses},
                      "new_goal": sas.is_new_goal_available(),
                      "preempt": sas.is_preempt_requested(),
                      "next_preempt": sas.new_goal_preempt_request,
                      "active": sas.is_active(), "errors": errors})
    return steps


def test_simple_action_server_matches_rospy(ros_python: Any) -> None:
    cases: list[list[dict[str, Any]]] = []

    @settings(max_examples=150, database=None, derandomize=True)
    @given(_ops())
    def collect(raw: list[dict[str, Any]]) -> None:
        ops = _concrete(raw)
        if ops:
            cases.append(ops)

    collect()
    ros = ros_python(SIMPLE_SCRIPT, as_json=True, stdin=json.dumps(cases))
    assert len(ros) == len(cases)
    for ops, ros_steps in zip(cases, ros):
        ours = _run_ddes(ops)
        for op, mine, theirs in zip(ops, ours, ros_steps):
            assert mine == theirs, (ops, op)
