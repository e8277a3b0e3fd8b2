"""Scripts run under real ROS 1 (system Python) to drive actionlib's own classes.

Each script reads JSON cases on stdin and prints JSON traces.  The same
cases are replayed on ddes's pure core by the ``replay_*`` functions here, so
a test can compare the two traces entry by entry.  rospy's ``logerr`` is
replaced by a recorder, so the traces hold ROS's exact log texts.
"""

from __future__ import annotations

from typing import Any

from ddes.actionlib import (
    CancelRequest,
    CommState,
    GoalIdGenerator,
    GoalStatus,
    GoalTracker,
    Publication,
    ServerEvent,
    ServerGoals,
    apply_comm_cancel,
    apply_comm_result,
    apply_comm_status,
    apply_goal_event,
    publish_status,
    receive_cancel,
    receive_goal,
    server_transition,
)

# A preamble shared by the scripts: simulated rospy time, a logerr recorder.
_PREAMBLE = r'''
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
'''

COMM_TABLE_SCRIPT = r'''
import json
from actionlib import action_client as ac
table = {}
for state, row in ac._transitions.items():
    cells = {}
    for status, target in row.items():
        if target == ac.NO_TRANSITION:
            cells[str(status)] = "NO_TRANSITION"
        elif target == ac.INVALID_TRANSITION:
            cells[str(status)] = "INVALID_TRANSITION"
        elif hasattr(target, "__getitem__"):
            cells[str(status)] = list(target)
        else:
            cells[str(status)] = [target]
    table[str(state)] = cells
print(json.dumps({"table": table, "no": ac.NO_TRANSITION, "invalid": ac.INVALID_TRANSITION}))
'''

GOAL_HANDLE_SCRIPT = _PREAMBLE + r'''
import actionlib_msgs.msg as am
from actionlib.server_goal_handle import ServerGoalHandle
from actionlib.status_tracker import StatusTracker
from actionlib.msg import TestActionGoal, TestResult

class FakeServer:
    def __init__(self):
        self.lock = threading.RLock()
        self.ActionResultType = TestResult
        self.pubs = []
    def publish_status(self):
        self.pubs.append("status")
    def publish_result(self, status, result):
        self.pubs.append("result")

METHODS = {"accept": "set_accepted", "reject": "set_rejected", "cancel": "set_canceled",
           "succeed": "set_succeeded", "abort": "set_aborted"}
out = []
set_now(10**9)
for seq in json.load(sys.stdin):
    server = FakeServer()
    goal = TestActionGoal()
    goal.goal_id = am.GoalID(id="g", stamp=rospy.Time(1))
    gh = ServerGoalHandle(StatusTracker(None, None, goal), server, None)
    steps = []
    for event in seq:
        del ERRORS[:]
        server.pubs = []
        if event == "cancel_request":
            ret = gh.set_cancel_requested()
        else:
            ret = None
            if event == "accept":
                gh.set_accepted("t")
            else:
                getattr(gh, METHODS[event])(None, "t")
        steps.append({"status": gh.status_tracker.status.status, "errors": list(ERRORS),
                      "pubs": server.pubs, "ret": ret,
                      "destruction": gh.status_tracker.handle_destruction_time.to_nsec()})
    out.append(steps)
print(json.dumps(out))
'''

SERVER_SCRIPT = _PREAMBLE + r'''
import actionlib.goal_id_generator as gidgen
from actionlib.action_server import ActionServer
from actionlib.msg import TestAction, TestActionGoal
from actionlib_msgs.msg import GoalID

class Pub:
    def __init__(self, topic, sink):
        self.topic, self.sink = topic, sink
    def publish(self, msg):
        if self.topic == "status":
            entries = msg.status_list
        else:
            entries = [msg.status]
        self.sink.append([self.topic, msg.header.stamp.to_nsec(),
                          [[s.goal_id.id, s.goal_id.stamp.to_nsec(), s.status, s.text]
                           for s in entries]])

def entry(st):
    return [st.status.goal_id.id, st.status.goal_id.stamp.to_nsec(), st.status.status,
            st.status.text, st.goal is not None, st.handle_tracker is not None,
            st.handle_destruction_time.to_nsec()]

def t(ns):
    return rospy.Time(ns // 10**9, ns % 10**9)

out = []
for case in json.load(sys.stdin):
    gidgen.s_goalcount = 0
    now = case["start"]
    set_now(now)
    handles, goal_cb, cancel_cb, pubs = [], [], [], []
    def on_goal(gh):
        goal_cb.append(gh.get_goal_id().id)
        handles.append(gh)
    def on_cancel(gh):
        cancel_cb.append(gh.get_goal_id().id)
    server = ActionServer("act", TestAction, on_goal, on_cancel, auto_start=False)
    server.status_pub = Pub("status", pubs)
    server.result_pub = Pub("result", pubs)
    server.status_list_timeout = rospy.Duration(0, case["timeout"])
    server.started = True
    trace = []
    for op in case["ops"]:
        del ERRORS[:]
        del goal_cb[:], cancel_cb[:], pubs[:]
        ret = None
        kind = op[0]
        if kind == "goal":
            g = TestActionGoal()
            g.goal_id = GoalID(id=op[1], stamp=t(op[2]))
            server.internal_goal_callback(g)
        elif kind == "cancel":
            server.internal_cancel_callback(GoalID(id=op[1], stamp=t(op[2])))
        elif kind == "advance":
            now += op[1]
            set_now(now)
        elif kind == "timer":
            server.publish_status()
        elif kind == "event" and handles:
            gh = handles[op[1] % len(handles)]
            event, text = op[2], op[3]
            if event == "cancel_request":
                ret = gh.set_cancel_requested()
            elif event == "accept":
                gh.set_accepted(text)
            else:
                name = {"reject": "set_rejected", "cancel": "set_canceled",
                        "succeed": "set_succeeded", "abort": "set_aborted"}[event]
                getattr(gh, name)(None, text)
        trace.append({"list": [entry(st) for st in server.status_list],
                      "last_cancel": server.last_cancel.to_nsec(), "pubs": list(pubs),
                      "goal_cb": list(goal_cb), "cancel_cb": list(cancel_cb),
                      "errors": list(ERRORS), "ret": ret})
    out.append(trace)
print(json.dumps(out))
'''

COMM_SCRIPT = _PREAMBLE + r'''
from actionlib import action_client as ac
from actionlib.msg import TestActionGoal, TestActionResult
from actionlib_msgs.msg import GoalID, GoalStatus, GoalStatusArray

out = []
for case in json.load(sys.stdin):
    passed = []
    goal = TestActionGoal()
    goal.goal_id = GoalID(id="g", stamp=rospy.Time(1))
    csm = ac.CommStateMachine(goal, lambda gh: passed.append(gh.get_comm_state()), None,
                              lambda g: None, lambda c: None)
    csm.state = case["start"]
    trace = []
    for op in case["ops"]:
        del ERRORS[:], passed[:]
        if op[0] == "status":
            arr = GoalStatusArray()
            arr.status_list.append(GoalStatus(goal_id=GoalID(id="other"), status=1))
            if op[1] is not None:
                arr.status_list.append(GoalStatus(goal_id=GoalID(id="g"), status=op[1]))
            csm.update_status(arr)
        elif op[0] == "result":
            r = TestActionResult()
            r.status = GoalStatus(goal_id=GoalID(id="g"), status=op[1])
            csm.update_result(r)
        else:
            ac.ClientGoalHandle(csm).cancel()
        trace.append({"state": csm.state, "passed": list(passed), "errors": list(ERRORS),
                      "latest": csm.latest_goal_status.status})
    out.append(trace)
print(json.dumps(out))
'''

SIMPLE_SCRIPT = _PREAMBLE + r'''
from actionlib import simple_action_client as sac

class FakeGH:
    def __init__(self, comm, status):
        self.comm, self.status = comm, status
    def get_comm_state(self):
        return self.comm
    def get_goal_status(self):
        return self.status
    def get_result(self):
        return None

class FakeAC:
    ns = "fib"

transitions = []
for simple in range(3):
    for comm in range(9):
        del ERRORS[:]
        calls = []
        c = object.__new__(sac.SimpleActionClient)
        c.action_client = FakeAC()
        c.done_condition = threading.Condition()
        c.simple_state = simple
        c.active_cb = lambda: calls.append("active_cb")
        c.done_cb = lambda s, r: calls.append(["done_cb", c.simple_state])
        c.gh = FakeGH(comm, 3)
        c._handle_transition(c.gh)
        transitions.append({"simple": simple, "comm": comm, "after": c.simple_state,
                            "calls": calls, "errors": list(ERRORS)})
states = []
for status in [None] + list(range(10)):
    c = object.__new__(sac.SimpleActionClient)
    c.gh = None if status is None else FakeGH(0, status)
    states.append([status, c.get_state()])
print(json.dumps({"transitions": transitions, "get_state": states}))
'''

IDS_SCRIPT = _PREAMBLE + r'''
import actionlib.goal_id_generator as gidgen
from actionlib import action_client as ac
from actionlib.msg import TestAction
cases = json.load(sys.stdin)
server_ids, client_ids = [], []
gen = gidgen.GoalIDGenerator("/srv_node")
for ns in cases:
    set_now(ns)
    g = gen.generate_ID()
    server_ids.append([g.id, g.stamp.to_nsec()])
rospy.get_caller_id = lambda: "/cli_node"
manager = ac.GoalManager(TestAction)
for ns in cases:
    set_now(ns)
    g = manager._generate_id()
    client_ids.append([g.id, g.stamp.to_nsec()])
print(json.dumps({"server": server_ids, "client": client_ids}))
'''


# --- the same cases replayed on ddes ----------------------------------------------------------


def replay_goal_handle(sequences: list[list[str]]) -> list[list[dict[str, Any]]]:
    """:data:`GOAL_HANDLE_SCRIPT` on ddes's server table."""
    out = []
    for seq in sequences:
        goals = ServerGoals((GoalTracker("g", 1_000_000_000, GoalStatus.PENDING, serial=1),))
        steps = []
        for event in seq:
            o = apply_goal_event(goals, "g", event, 1_000_000_000, "t")
            goals = o.goals
            pubs = [p.topic.value for p in o.publications if p.topic.value == "result"]
            if not pubs and o.publications:
                pubs = ["status"]
            steps.append({
                "status": int(o.tracker.status),
                "errors": [] if o.transition.error is None else [o.transition.error],
                "pubs": pubs,
                "ret": o.transition.legal if event == "cancel_request" else None,
                "destruction": o.tracker.destruction_time_ns,
            })
            # the table alone must agree with the bookkeeping
            assert server_transition(o.transition.before, event) == o.transition
        out.append(steps)
    return out


def _pub(p: Publication) -> list[Any]:
    return [p.topic.value, p.stamp_ns,
            [[t.goal_id, t.stamp_ns, int(t.status), t.text] for t in p.statuses]]


def _entry(t: GoalTracker) -> list[Any]:
    return [t.goal_id, t.stamp_ns, int(t.status), t.text, t.has_goal, t.has_handle,
            t.destruction_time_ns]


def replay_server(cases: list[dict[str, Any]]) -> list[list[dict[str, Any]]]:
    """:data:`SERVER_SCRIPT` on ddes's pure server bookkeeping."""
    out = []
    for case in cases:
        now = case["start"]
        goals = ServerGoals.create(case["timeout"])
        ids = GoalIdGenerator("/unnamed")
        handles: list[GoalTracker] = []
        trace = []
        for op in case["ops"]:
            pubs: tuple[Publication, ...] = ()
            goal_cb: list[str] = []
            cancel_cb: list[str] = []
            errors: list[str] = []
            ret = None
            kind = op[0]
            if kind == "goal":
                g = receive_goal(goals, op[1], op[2], now, ids)
                goals, pubs = g.goals, g.publications
                errors.extend(g.errors)
                if g.call_goal_callback:
                    goal_cb.append(g.tracker.goal_id)
                    handles.append(g.tracker)
            elif kind == "cancel":
                c = receive_cancel(goals, CancelRequest(op[1], op[2]), now)
                goals, pubs = c.goals, c.publications
                cancel_cb.extend(c.cancel_requested)
                errors.extend(c.errors)
            elif kind == "advance":
                now += op[1]
            elif kind == "timer":
                s = publish_status(goals, now)
                goals, pubs = s.goals, (s.publication,)
            elif kind == "event" and handles:
                k = op[1] % len(handles)
                e = apply_goal_event(goals, handles[k], op[2], now, op[3])
                goals, pubs = e.goals, e.publications
                handles[k] = e.tracker
                errors.extend(e.errors)
                if op[2] == ServerEvent.CANCEL_REQUEST.value:
                    ret = e.transition.legal
            current = {t.serial: t for t in goals.trackers}
            handles = [current.get(h.serial, h) for h in handles]
            trace.append({"list": [_entry(t) for t in goals.trackers],
                          "last_cancel": goals.last_cancel_ns, "pubs": [_pub(p) for p in pubs],
                          "goal_cb": goal_cb, "cancel_cb": cancel_cb, "errors": errors,
                          "ret": ret})
        out.append(trace)
    return out


def replay_comm(cases: list[dict[str, Any]]) -> list[list[dict[str, Any]]]:
    """:data:`COMM_SCRIPT` on ddes's comm-state functions."""
    out = []
    for case in cases:
        state = CommState(case["start"])
        latest: int = GoalStatus.PENDING
        trace = []
        for op in case["ops"]:
            if op[0] == "status":
                u = apply_comm_status(state, op[1])
            elif op[0] == "result":
                u = apply_comm_result(state, op[1])
            else:
                u = apply_comm_cancel(state)
            state = u.after
            if u.latest_status is not None:
                latest = u.latest_status
            trace.append({"state": int(state), "passed": [int(s) for s in u.passed],
                          "errors": list(u.errors), "latest": int(latest)})
        out.append(trace)
    return out
