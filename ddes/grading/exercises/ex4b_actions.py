"""Exercise 4b: a preemptable FollowPath action server on the robot (lecture 4, "ROS Actions
(actionlib)"; the lecture's own action, ``lecture4_actions/FollowPath``).  See
``solutions/ex4b_actions/README.md``.

The student's server runs in the sandbox; the grader drives it with its own protocol client
(:class:`ddes.actionlib.ActionClient`) across the bridge -- the five action topics are plain
topics, so they cross like any other -- through a fixed schedule drawn from the scenario seed:

0. **warm-up**: the grader itself drives the robot forward and round a curve for 1.5 s (a
   Twist on ``/cmd_vel``), so that ``odom`` and ``base_link`` differ when the first goal comes;
1. **follow**: a path of three waypoints in odom (drawn relative to the robot's pose then, so
   ``odom`` differs from ``base_link``), followed to SUCCEEDED;
2. **empty**: an empty path, ABORTED;
3. **cancel**: a long path cancelled after a hidden delay: PREEMPTED, a zero Twist from the
   student's node within 0.2 s, the robot stopped within 1 s;
4. **newer**: a path replaced after a hidden delay by a newer goal (SimpleActionServer's
   policy): the first PREEMPTED, the second followed to SUCCEEDED;
5. **blocked**: one waypoint straight ahead behind a pillar the grader adds 1.1 m ahead at
   that instant (``Simulator.add``): ABORTED within 6 s of the contact;
6. **teardown**: cancel every goal and require every goal to end.

The student's client (4b.7), ``follow_path_client.py`` from the package, runs beside the server
in the same sandbox from the start, with ``_action_name`` set to a grader action server of its
own (``/ddes_grader/follow_path_client``) and a hidden ``_side`` and ``_cancel_after``: that
server accepts the goal, publishes feedback and never finishes by itself; it records the goal
(a square of the given side in ``odom``) and the cancel (at ``cancel_after``), answers the
cancel 0.3 s later with PREEMPTED and notes whether the client still listens for the result then
(it waits for the terminal state).

The course's class rule (teaching.md's C0, "all logic in a class", -20 % in the ETH sheets) is
read with :mod:`ast`, never imported: each script defines a class, its main part builds it and
calls none of the action API itself.  It is a share of 4b.1 (the server script, 5) and of 4b.7
(the client script, 2), so that the criteria keep the design's weights and sum to 100.

The run ends when the schedule is over (:attr:`~ddes.grading.exercise.Exercise.finished`;
``DURATION``, longer than all the schedule's waits, is the cap for a server that stalls it).
The simulator runs without odometry noise (odom is the truth in the start frame) and without
the laser; the server's ``~action_name`` is a hidden one in hidden scenarios.

The protocol check (4b.6) reuses :mod:`ddes.testing.actions`: the machine class of
:meth:`~ddes.testing.actions.ActionProtocolMachine.machine_for` with its wire spy, its
agreement and preemption checks (``protocol_holds``) run every 0.1 s on the grader's world.  The
hypothesis-driven random schedule cannot run here, because the student's server lives in the
sandbox and is never imported by the grader; its schedule is the fixed one above.  What the
machine reads from the server's own trace (illegal goal-handle calls, callback exceptions)
stays in the child, so the grader reads rospy's error texts for them from the student's
``/rosout``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from ddes._floats import left_sum
from ddes.grading.course import CourseExercise, find_package, hidden_random, notes
from ddes.grading.exercise import Criterion, Facts, Scenario
from ddes.grading.exercises.common import (
    launch_problem,
    relative,
    student_logs,
    student_script,
)
from ddes.transformations import cos, sin

__all__ = ["EX4B", "scenarios"]

PKG = "smb_follow_path"
LAUNCH = f"{PKG}/launch/{PKG}.launch"
NODE_TYPE = "follow_path_server.py"
CLIENT = "follow_path_client.py"
#: The grader's own FollowPath server the student's client talks to (4b.7).
CLIENT_NS = "/ddes_grader/follow_path_client"
#: The grader's server answers a cancel this long after it arrives (s).
CLIENT_PREEMPT_S = 0.3
#: The client's cancel counts within [cancel_after - EARLY, cancel_after + LATE] of the goal (s).
CANCEL_EARLY_S, CANCEL_LATE_S = 0.05, 0.3
ACTION = "lecture4_actions/FollowPathAction"
DURATION = 55.0  # the cap: the schedule's waits add up to about 53 s; the reference ends by 26 s
SEC = 1_000_000_000
#: Tolerances (m): a waypoint passed, the end reached, feedback against the grader's numbers.
PASS_TOL, END_TOL, FB_TOL, MONO_TOL = 0.25, 0.2, 0.15, 0.15
ZERO_TWIST_S, STOPPED_S, STOPPED_V = 0.2, 1.0, 0.02
ABORT_AFTER_CONTACT_S = 6.0
#: The grader's warm-up drive before the first goal: 1.5 s at this speed (m/s) and turn (rad/s).
WARMUP_V, WARMUP_W = 0.5, 0.8
#: The run does not end before this (s) while the client's cancel is still to come.
CLIENT_SPAN = 10.0
FEEDBACK_HZ = 5.0
_SUFFIXES = ("goal", "cancel", "status", "feedback", "result")


def _box_path(rng: Any, n: int) -> list[tuple[float, float]]:
    """``n`` waypoints relative to the robot (x ahead, y left), each 0.8-1.4 m from the last,
    in a box ahead of it."""
    pts: list[tuple[float, float]] = []
    x, y = 0.0, 0.0
    while len(pts) < n:
        px, py = round(rng.uniform(0.6, 2.0), 3), round(rng.uniform(-1.0, 1.0), 3)
        if 0.8 <= math.hypot(px - x, py - y) <= 1.4:
            pts.append((px, py))
            x, y = px, py
    return pts


def scenarios(seed: int, public: bool) -> list[Scenario]:
    out = [Scenario("public", seed, params={
        "yaw": 0.0, "action": "follow_path", "pillar_r": 0.3,
        "follow": [(1.2, 0.0), (1.6, 1.0), (0.8, 1.2)], "cancel_after": 1.5,
        "cancel_path": [(3.0, 0.0), (6.0, 0.0)], "newer_after": 1.5,
        "old_path": [(1.5, -1.0), (3.0, -1.0)], "new_path": [(1.0, 0.5)],
        "client_side": 2.0, "client_cancel": 3.0})]
    for i in range(2):
        rng = hidden_random(f"ex4b_actions/{i}", seed)
        out.append(Scenario(f"hidden-{i + 1}", seed, hidden=True, params={
            "yaw": round(rng.uniform(-3.0, 3.0), 3), "action": f"follow_path_hidden_{i + 1}",
            "pillar_r": round(rng.uniform(0.2, 0.4), 3), "follow": _box_path(rng, 3),
            "cancel_after": round(rng.uniform(1.0, 2.5), 3),
            "cancel_path": [(3.0, round(rng.uniform(-0.5, 0.5), 3)), (6.0, 0.0)],
            "newer_after": round(rng.uniform(1.0, 2.0), 3), "old_path": _box_path(rng, 2),
            "new_path": _box_path(rng, 1), "client_side": round(rng.uniform(1.0, 3.0), 2),
            "client_cancel": round(rng.uniform(1.5, 3.5), 2)}))
    return out


def setup(world: Any, scenario: Scenario) -> tuple[dict[str, Any], dict[str, Any], dict[str, Any]]:
    p = scenario.params
    sim = {"x": 0.0, "y": 0.0, "yaw": p["yaw"], "world": "empty", "noise": False,
           "laser_enabled": False}
    sim.pop("world_file", None)
    return {NODE_TYPE: {"action_name": p["action"]}}, sim, {}


# -- the grader's driver ------------------------------------------------------------------------

@dataclass
class Goal:
    """One goal the grader sent."""

    phase: str
    handle: Any
    points: list[tuple[float, float]]
    sent_ns: int
    start: tuple[float, float, float]
    cancel_ns: int | None = None
    done_ns: int | None = None


@dataclass
class Run:
    """What the driver did, for the checks."""

    ns: str
    machine: Any
    goals: list[Goal] = field(default_factory=list)
    notes: list[str] = field(default_factory=list)
    violation: str = ""
    pillar: tuple[float, float, float] | None = None
    up: bool = False
    finished: bool = False
    #: The driver has returned (after the teardown, or without a server).
    over: bool = False


def _odom_pose(world: Any, scenario: Scenario) -> tuple[float, float, float]:
    """The robot's true pose in odom (odom starts at the robot's start pose)."""
    sim = notes(world).sim
    assert sim is not None
    t = sim.truth
    yaw0 = float(scenario.params["yaw"])
    c, s = cos(-yaw0), sin(-yaw0)
    return c * t.x - s * t.y, s * t.x + c * t.y, t.yaw - yaw0


def _to_odom(pose: tuple[float, float, float], rel: list[tuple[float, float]]
             ) -> list[tuple[float, float]]:
    x, y, yaw = pose
    c, s = cos(yaw), sin(yaw)
    return [(round(x + c * a - s * b, 6), round(y + s * a + c * b, 6)) for a, b in rel]


def _path(points: list[tuple[float, float]]) -> Any:
    from ddes.msg import get_message_class

    Path = get_message_class("nav_msgs/Path")
    PoseStamped = get_message_class("geometry_msgs/PoseStamped")
    path = Path()
    path.header.frame_id = "odom"
    for x, y in points:
        p = PoseStamped()
        p.header.frame_id = "odom"
        p.pose.position.x, p.pose.position.y = x, y
        p.pose.orientation.w = 1.0
        path.poses.append(p)
    return path


def _no_server(_world: Any, _node: Any) -> None:
    from ddes.errors import GradingError

    raise GradingError("the student's server runs in the sandbox, never in the grader")


def build(world: Any, scenario: Scenario) -> None:
    from ddes.actionlib._common import ActionTypes
    from ddes.actionlib.client import ActionClient
    from ddes.testing.actions import ActionProtocolMachine, ProtocolViolation, _Spy
    from ddes.time.units import duration_to_ns

    ns = "/" + scenario.params["action"]
    machine = ActionProtocolMachine.machine_for(_no_server, action=ACTION, ns=ns, settle=5.0,
                                                name="ex4b_protocol")()
    machine.world = world
    machine.seed = scenario.seed
    types = ActionTypes.of(ACTION)
    machine.spy = _Spy(world, ns, types, duration_to_ns(5.0, "status_list_timeout"))
    node = world.create_node("/grader_follow_path", disable_rosout=True)
    machine.client = ActionClient(node, ns, types.spec)
    machine.schedule.append(f"scenario {scenario.name}, seed {scenario.seed}")
    run = Run(ns, machine)
    world._ddes_ex4b = run

    def check(_event: Any) -> None:
        if run.violation or not run.up:
            return
        try:
            machine.protocol_holds()
        except ProtocolViolation as exc:
            run.violation = str(exc)

    import ddes

    ddes.Timer(node, 0.1, check)
    node.process(_drive(world, scenario, node, run))
    _client_server(world)


# -- the grader's server for the student's client (4b.7) -----------------------------------------

@dataclass
class ClientLog:
    """What the grader's FollowPath server saw of the student's client."""

    goals: list[tuple[int, Any, str]] = field(default_factory=list)  # (t_ns, goal, id)
    cancels: list[tuple[int, str]] = field(default_factory=list)  # (t_ns, id)
    result_ns: int = -1
    listening_at_result: bool = False
    missing: str = ""


def _client_server(world: Any) -> None:
    """A FollowPath server at CLIENT_NS that accepts every goal, publishes feedback at 5 Hz,
    never finishes by itself, and answers a cancel with PREEMPTED after CLIENT_PREEMPT_S."""
    from ddes.actionlib.server import ActionServer
    from ddes.actionlib.states import GoalStatus
    from ddes.msg import get_message_class

    log = ClientLog()
    world._ddes_ex4b_client = log
    node = world.create_node("/grader_follow_path_client_check", disable_rosout=True)
    Feedback = get_message_class("lecture4_actions/FollowPathFeedback")
    Result = get_message_class("lecture4_actions/FollowPathResult")

    def listening() -> bool:
        entry = world.master.topics.get(CLIENT_NS + "/result")
        return entry is not None and any(e.node is not node and not e.node.is_shutdown()
                                         for e in entry.subscribers)

    def feed(gh: Any, length: float) -> Any:
        start = world.now
        while gh.status in (GoalStatus.ACTIVE, GoalStatus.PREEMPTING):
            left = max(0.0, length - 0.5 * (world.now - start) / SEC)
            gh.publish_feedback(Feedback(remaining_distance=left, initial_distance=length))
            yield node.sleep(0.2)

    def on_goal(gh: Any) -> None:
        goal = gh.get_goal()
        log.goals.append((world.now, goal, gh.get_goal_id().id))
        gh.set_accepted()
        pts = [(q.pose.position.x, q.pose.position.y) for q in goal.path.poses]
        node.process(feed(gh, left_sum(math.dist(a, b) for a, b in zip(pts, pts[1:]))))

    def preempt(gh: Any) -> Any:
        yield node.sleep(CLIENT_PREEMPT_S)
        if gh.status == GoalStatus.PREEMPTING:
            log.result_ns = world.now
            log.listening_at_result = listening()
            gh.set_canceled(Result(success=False))

    def on_cancel(gh: Any) -> None:
        log.cancels.append((world.now, gh.get_goal_id().id))
        node.process(preempt(gh))

    server = ActionServer(node, CLIENT_NS, ACTION, on_goal, on_cancel, auto_start=False)
    server.start()


def _drive(world: Any, scenario: Scenario, node: Any, run: Run) -> Any:
    from ddes.actionlib.states import CommState

    p = scenario.params
    m = run.machine
    goal_cls = m.client.types.goal if hasattr(m.client, "types") else None
    from ddes.msg import get_message_class

    goal_cls = goal_cls or get_message_class("lecture4_actions/FollowPathGoal")
    ok = yield m.client.wait_for_server(5.0)
    if not ok:
        run.notes.append(f"no action server on {run.ns} within 5 s (no status on "
                         f"{run.ns}/status, or goal/cancel not subscribed)")
        run.over = True
        return
    run.up = True
    # 0. warm-up: the grader drives the robot off its start pose (odom != base_link then)
    import ddes

    Twist = get_message_class("geometry_msgs/Twist")
    cmd = ddes.Publisher(node, "/cmd_vel", Twist, queue_size=1)
    for _ in range(15):
        twist = Twist()
        twist.linear.x, twist.angular.z = WARMUP_V, WARMUP_W
        cmd.publish(twist)
        yield node.sleep(0.1)
    cmd.publish(Twist())
    yield node.sleep(0.5)

    def send(phase: str, rel: list[tuple[float, float]]) -> Goal:
        start = _odom_pose(world, scenario)
        pts = _to_odom(start, rel)
        m._begin("send_goal", {"path": [list(q) for q in pts]})
        m._send(goal_cls(path=_path(pts)))
        m._end()
        g = Goal(phase, m.handles[-1], pts, world.now, start)
        run.goals.append(g)
        return g

    def wait(g: Goal, limit: float) -> Any:
        end = world.now + int(limit * SEC)
        while world.now < end and g.handle.get_comm_state() != CommState.DONE:
            yield node.sleep(0.05)
        if g.handle.get_comm_state() == CommState.DONE:
            g.done_ns = world.now

    # 2. follow
    g = send("follow", [tuple(q) for q in p["follow"]])
    yield from wait(g, 14.0)
    # 3. empty
    g = send("empty", [])
    yield from wait(g, 2.0)
    # 4. cancel
    g = send("cancel", [tuple(q) for q in p["cancel_path"]])
    yield node.sleep(float(p["cancel_after"]))
    if g.handle.get_comm_state() != CommState.DONE:
        m._begin("cancel_goal", len(m.handles) - 1)
        g.cancel_ns = world.now
        g.handle.cancel()
        m._end()
    yield from wait(g, 3.0)
    yield node.sleep(1.2)  # the robot must stay stopped
    # 4. newer goal
    old = send("old", [tuple(q) for q in p["old_path"]])
    yield node.sleep(float(p["newer_after"]))
    new = send("new", [tuple(q) for q in p["new_path"]])
    yield from wait(old, 3.0)
    yield from wait(new, 8.0)
    # 5. blocked: a pillar 1.1 m ahead of the robot, the waypoint behind it
    from ddes.sim.worlds import Circle

    sim = notes(world).sim
    assert sim is not None
    r = float(p["pillar_r"])
    t = sim.truth
    cx, cy = t.x + (1.1 + r) * cos(t.yaw), t.y + (1.1 + r) * sin(t.yaw)
    sim.add(Circle(cx, cy, r, "grader_pillar"))
    run.pillar = (cx, cy, r)
    g = send("blocked", [(2.2 + 2 * r, 0.0)])
    yield from wait(g, 10.0)
    # 6. teardown: cancel everything, every goal must end
    m._note("teardown: cancel_all_goals, then wait until every goal is done")
    m.client.cancel_all_goals()
    end = world.now + 5 * SEC
    while world.now < end and (m._live() or m._unfinished()):
        yield node.sleep(0.1)
    run.finished = True
    run.over = True


def finished(world: Any) -> bool:
    """The schedule is over, and so is the client's part (its result came, it has no client, or
    CLIENT_SPAN passed): the run can end before DURATION."""
    run = getattr(world, "_ddes_ex4b", None)
    log = getattr(world, "_ddes_ex4b_client", None)
    if not isinstance(run, Run) or not run.over:
        return False
    return (not isinstance(log, ClientLog) or log.result_ns >= 0 or bool(log.missing)
            or world.now >= CLIENT_SPAN * SEC)


# -- facts shared by the checks -----------------------------------------------------------------

@dataclass(frozen=True)
class _Ex4b(CourseExercise):
    """The launch file's nodes, and the student's client beside them (4b.7)."""

    def student_scripts(self, world: Any, scenario: Scenario,
                        submission: Path) -> list[tuple[str, list[str]]]:
        from ddes.nodes import find_script

        scripts = super().student_scripts(world, scenario, submission)
        pkg = find_package(submission, PKG)
        script = find_script(pkg, CLIENT) if pkg is not None else None
        log = getattr(world, "_ddes_ex4b_client", None)
        if script is None:
            if isinstance(log, ClientLog):
                log.missing = f"{PKG} has no scripts/{CLIENT}"
            return scripts
        p = scenario.params
        rel = str(script.resolve().relative_to(submission.resolve()))
        return [*scripts, (rel, ["__name:=follow_path_client", f"_action_name:={CLIENT_NS}",
                                 f"_side:={p['client_side']}",
                                 f"_cancel_after:={p['client_cancel']}"])]


def _run(facts: Facts) -> tuple[Run | None, str]:
    why = launch_problem(facts)
    if why:
        return None, why
    run = getattr(facts.world, "_ddes_ex4b", None)
    if not isinstance(run, Run):
        return None, "the grader's driver did not run"
    if not run.up:
        return None, "; ".join(run.notes) or f"no action server on {run.ns}"
    return run, ""


def _goal(run: Run, phase: str) -> Goal | None:
    return next((g for g in run.goals if g.phase == phase), None)


def _result(facts: Facts, run: Run, g: Goal) -> tuple[int, int, Any] | None:
    """``(t_ns, status, result)`` of the goal's result message on the wire, or None."""
    gid = g.handle.get_goal_id()
    for t, _who, msg in facts.messages(run.ns + "/result"):
        if msg.status.goal_id.id == gid:
            return t, msg.status.status, msg.result
    return None


def _feedback(facts: Facts, run: Run, g: Goal) -> list[tuple[int, Any]]:
    gid = g.handle.get_goal_id()
    return [(t, m.feedback) for t, _who, m in facts.messages(run.ns + "/feedback")
            if m.status.goal_id.id == gid]


def _truth_odom(facts: Facts) -> list[tuple[int, float, float, float, float]]:
    """``(t_ns, x, y, yaw, v)`` of the robot's true state in odom, 10 Hz."""
    sim = notes(facts.world).sim
    if sim is None:
        return []
    h = sim.history()
    yaw0 = float(facts.scenario.params["yaw"])
    c, s = cos(-yaw0), sin(-yaw0)
    return [(t, c * x - s * y, s * x + c * y, yaw - yaw0, v)
            for t, x, y, yaw, v in zip(h.t_ns, h.x, h.y, h.yaw, h.v)]


def _status_name(status: int) -> str:
    from ddes.actionlib.states import GoalStatus

    return GoalStatus(status).name if 0 <= status <= 9 else str(status)


def _followed(facts: Facts, run: Run, g: Goal | None, what: str) -> tuple[bool, str]:
    """The goal SUCCEEDED with success: true, the robot passed every waypoint in order within
    PASS_TOL and ended within END_TOL of the last one."""
    from ddes.actionlib.states import GoalStatus

    if g is None:
        return False, f"{what}: the grader never sent it (an earlier phase ran out of time)"
    res = _result(facts, run, g)
    if res is None:
        return False, f"{what}: no result"
    t_end, status, result = res
    if status != GoalStatus.SUCCEEDED or not result.success:
        return False, (f"{what}: ended {_status_name(status)} with success: {result.success} "
                       "(expected SUCCEEDED, success: true)")
    track = [(x, y) for t, x, y, _yaw, _v in _truth_odom(facts) if g.sent_ns <= t <= t_end]
    i = 0
    for x, y in track:
        if i < len(g.points) and math.hypot(g.points[i][0] - x, g.points[i][1] - y) <= PASS_TOL:
            i += 1
    if i < len(g.points):
        wx, wy = g.points[i]
        near = min((math.hypot(wx - x, wy - y) for x, y in track), default=math.inf)
        return False, (f"{what}: waypoint {i + 1} ({wx:.2f}, {wy:.2f}) in odom was not passed "
                       f"within {PASS_TOL} m in order (closest {near:.2f} m)")
    if track:
        x, y = track[-1]
        off = math.hypot(g.points[-1][0] - x, g.points[-1][1] - y)
        if off > END_TOL:
            return False, (f"{what}: at SUCCEEDED the robot is {off:.2f} m from the last pose "
                           f"(at most {END_TOL})")
    return True, ""


# -- the course's class rule (C0: a share of 4b.1 and 4b.7) --------------------------------------

#: Calls the main part of each script must leave to its class.
_SERVER_CALLS = ("SimpleActionServer", "ActionServer", "Publisher", "Subscriber", "Rate",
                 "publish", "publish_feedback", "set_succeeded", "set_aborted", "set_preempted")
_CLIENT_CALLS = ("SimpleActionClient", "ActionClient", "wait_for_server", "send_goal",
                 "cancel_goal", "cancel_all_goals", "wait_for_result", "get_result")


def _class_rule(facts: Facts, script: str, calls: tuple[str, ...]) -> str:
    """Why ``scripts/<script>`` breaks the course's rule "logic in the class" (empty when it
    keeps it): read with :mod:`ast`, never imported.  The script defines a class or imports one
    from the package, its main part (everything outside the script's classes) builds it and
    calls none of ``calls`` in any spelling (``import actionlib as al``, ``from actionlib import
    SimpleActionServer as Server``), except as methods of the student's own objects
    (``client = FollowPathClient(); client.send_goal(...)`` is the class's logic)."""
    rel = f"{PKG}/scripts/{script}"
    node = student_script(facts, rel)
    if node is None:
        return f"{rel} is missing or does not parse"
    if not node.classes or not node.built:
        return f"{script} does not define (or import) a class and build it in its main part"
    bad = sorted(node.main_called() & set(calls))
    if bad:
        return f"{script}'s main part calls {', '.join(bad)}: keep all logic in the class"
    return ""


# -- 4b.1 the server ----------------------------------------------------------------------------

def check_server(facts: Facts) -> tuple[float, list[str]]:
    why = launch_problem(facts)
    if why:
        return 0.0, [why]
    run = getattr(facts.world, "_ddes_ex4b", None)
    ns = run.ns if isinstance(run, Run) else "/" + str(facts.scenario.params["action"])
    want = {"goal": ("lecture4_actions/FollowPathActionGoal", "subscribers"),
            "cancel": ("actionlib_msgs/GoalID", "subscribers"),
            "status": ("actionlib_msgs/GoalStatusArray", "publishers"),
            "feedback": ("lecture4_actions/FollowPathActionFeedback", "publishers"),
            "result": ("lecture4_actions/FollowPathActionResult", "publishers")}
    missing = []
    for suffix, (type_, side) in want.items():
        entry = facts.world.master.topics.get(f"{ns}/{suffix}")
        ends = getattr(entry, side, []) if entry is not None else []
        if entry is None or entry.type != type_ or not any(e.node.name in facts.student_nodes
                                                            for e in ends):
            missing.append(f"{ns}/{suffix} ({type_}, {side[:-1]} in your node)")
    if missing:
        return 0.0, [f"no FollowPath server on {ns} (the ~action_name in force): "
                     + ", ".join(missing)]
    rule = _class_rule(facts, NODE_TYPE, _SERVER_CALLS)
    if rule:
        return 5.0, [f"the server works, but the course's rule 'logic in the class' is broken: "
                     f"{rule}"]
    return 10.0, []


# -- 4b.2 following -----------------------------------------------------------------------------

def _stops_at_end(facts: Facts, run: Run, g: Goal, what: str) -> str:
    """Why the server did not stop the robot when ``g`` ended (empty when it did): a zero Twist
    from the student's node within ZERO_TWIST_S of the result, and the robot at rest from
    STOPPED_S after it until the next goal."""
    res = _result(facts, run, g)
    if res is None:
        return f"{what}: no result"
    t_end = res[0]
    later = [x.sent_ns for x in run.goals if x.sent_ns > g.sent_ns]
    until = min(later) if later else facts.world.now
    zero = [t for t, who, m in facts.messages("/cmd_vel") if who in facts.student_nodes
            and abs(t - t_end) <= int(ZERO_TWIST_S * SEC)
            and m.linear.x == 0.0 and m.angular.z == 0.0]
    truth = _truth_odom(facts)
    v_end = next((abs(v) for t, _x, _y, _yaw, v in truth if t >= t_end), 0.0)
    if not zero:
        return (f"{what}: {_status_name(res[1])} at t={t_end / 1e9:.2f} s with the robot driving at "
                f"{v_end:.2f} m/s, but your node published no zero Twist on /cmd_vel within "
                f"{ZERO_TWIST_S} s of it: stop the robot when the goal ends")
    moving = [(t, v) for t, _x, _y, _yaw, v in truth
              if t_end + int(STOPPED_S * SEC) <= t <= until and abs(v) > STOPPED_V]
    if moving:
        return (f"{what}: the robot still moves at {moving[0][1]:.2f} m/s "
                f"{relative(moving[0][0] - t_end, 'the end of the goal')}")
    return ""


def check_follow(facts: Facts) -> tuple[float, list[str]]:
    """20 for the path followed to SUCCEEDED, 5 for the robot stopped when it ends."""
    run, why = _run(facts)
    if run is None:
        return 0.0, [why]
    g = _goal(run, "follow")
    ok, why = _followed(facts, run, g, "the path")
    if not ok or g is None:
        return 0.0, [why]
    why = _stops_at_end(facts, run, g, "the path")
    return (25.0, []) if not why else (20.0, [why])


# -- 4b.3 feedback ------------------------------------------------------------------------------

def check_feedback(facts: Facts) -> tuple[float, list[str]]:
    run, why = _run(facts)
    if run is None:
        return 0.0, [why]
    g = _goal(run, "follow")
    res = _result(facts, run, g) if g is not None else None
    if g is None or res is None:
        return 0.0, ["the path's goal has no result: no span to check the feedback over"]
    t_end = res[0]
    fbs = _feedback(facts, run, g)
    points, lines = 0.0, []
    span = (t_end - g.sent_ns) / SEC
    need = max(1, int(FEEDBACK_HZ * span) - 1)
    if len(fbs) >= need:
        points += 5
    else:
        lines.append(f"{len(fbs)} feedback messages in the goal's {span:.1f} s (at least "
                     f"{need}: {FEEDBACK_HZ:g} Hz)")
    if not fbs:
        return points, lines
    x0, y0, _ = g.start
    pts = [(x0, y0), *g.points]
    length = left_sum(math.dist(a, b) for a, b in zip(pts, pts[1:]))
    initials = [fb.initial_distance for _t, fb in fbs]
    if max(initials) - min(initials) <= 1e-3 and abs(initials[0] - length) <= FB_TOL:
        points += 5
    else:
        lines.append(f"initial_distance must stay the path's length from the start pose "
                     f"({length:.2f} m, within {FB_TOL}); it went {min(initials):.2f} to "
                     f"{max(initials):.2f}")
    truth = _truth_odom(facts)
    bad = ""
    last = math.inf
    end = g.points[-1]
    j = k = 0
    legs = [left_sum(math.dist(a, b) for a, b in zip(g.points[i:], g.points[i + 1:]))
            for i in range(len(g.points))]
    for t, fb in fbs:
        rem = fb.remaining_distance
        while j + 1 < len(truth) and truth[j + 1][0] <= t:
            j += 1
        x, y = truth[j][1], truth[j][2]
        if rem > last + MONO_TOL:
            bad = f"t={t / 1e9:.2f} s: remaining_distance rose from {last:.2f} to {rem:.2f} m"
            break
        if rem < math.hypot(end[0] - x, end[1] - y) - FB_TOL:
            bad = (f"t={t / 1e9:.2f} s: remaining_distance {rem:.2f} m is less than the straight "
                   f"distance from the robot to the path's end")
            break
        while k < len(g.points) and math.hypot(g.points[k][0] - x, g.points[k][1] - y) <= 0.05:
            k += 1
        bound = (math.hypot(g.points[k][0] - x, g.points[k][1] - y) + legs[k]
                 if k < len(g.points) else 0.0)
        if rem > bound + FB_TOL:
            bad = (f"t={t / 1e9:.2f} s: remaining_distance {rem:.2f} m is more than the path "
                   f"left from the robot ({bound:.2f} m)")
            break
        last = min(last, rem)
    if not bad and fbs[-1][1].remaining_distance > END_TOL + 0.1:
        bad = f"the last remaining_distance is {fbs[-1][1].remaining_distance:.2f} m (at most 0.3)"
    if bad:
        lines.append(bad)
    else:
        points += 5
    return points, lines


# -- 4b.4 aborts --------------------------------------------------------------------------------

def check_aborts(facts: Facts) -> tuple[float, list[str]]:
    from ddes.actionlib.states import GoalStatus

    run, why = _run(facts)
    if run is None:
        return 0.0, [why]
    points, lines = 0.0, []
    g = _goal(run, "empty")
    res = _result(facts, run, g) if g is not None else None
    if g is None:
        res = None
    if g is not None and res is not None and res[1] == GoalStatus.ABORTED \
            and not res[2].success and res[0] - g.sent_ns <= SEC:
        points += 5
    else:
        got = "no result" if res is None or g is None else f"{_status_name(res[1])} " \
            f"(success: {res[2].success}) after {(res[0] - g.sent_ns) / 1e9:.2f} s"
        lines.append(f"an empty path: {got}; expected ABORTED, success: false, within 1 s")
    g = _goal(run, "blocked")
    sim = notes(facts.world).sim
    if g is None or sim is None:
        lines.append("a path behind a pillar: the grader never sent it (an earlier phase ran "
                     "out of time)")
        return points, lines
    res = _result(facts, run, g)
    hits = [c for c in sim.collisions if c.obstacle == "grader_pillar" and c.t_ns >= g.sent_ns]
    if not hits:
        lines.append("a path behind a pillar: the robot never touched the pillar")
    elif res is None or res[1] != GoalStatus.ABORTED or res[2].success \
            or res[0] - hits[0].t_ns > ABORT_AFTER_CONTACT_S * SEC:
        got = "no result" if res is None else \
            f"{_status_name(res[1])} {relative(res[0] - hits[0].t_ns, 'the contact')}"
        lines.append(f"a path behind a pillar: {got}; expected ABORTED, success: false, within "
                     f"{ABORT_AFTER_CONTACT_S:g} s of the contact")
    else:
        points += 3
        why = _stops_at_end(facts, run, g, "a path behind a pillar")
        if why:
            lines.append(why)
        else:
            points += 2
    return points, lines


# -- 4b.5 preemption ----------------------------------------------------------------------------

def check_preemption(facts: Facts) -> tuple[float, list[str]]:
    from ddes.actionlib.states import GoalStatus

    run, why = _run(facts)
    if run is None:
        return 0.0, [why]
    points, lines = 0.0, []
    g = _goal(run, "cancel")
    if g is None or g.cancel_ns is None:
        lines.append("cancel: the grader never cancelled a running goal (it had ended, or an "
                     "earlier phase ran out of time)")
    else:
        res = _result(facts, run, g)
        if res is not None and res[1] == GoalStatus.PREEMPTED and res[0] - g.cancel_ns <= SEC:
            points += 4
        else:
            got = "no result" if res is None else \
                f"{_status_name(res[1])} {relative(res[0] - g.cancel_ns, 'the cancel')}"
            lines.append(f"cancel: {got}; expected PREEMPTED within 1 s")
        zero = [t for t, who, m in facts.messages("/cmd_vel") if who in facts.student_nodes
                and g.cancel_ns <= t <= g.cancel_ns + int(ZERO_TWIST_S * SEC)
                and m.linear.x == 0.0 and m.angular.z == 0.0]
        nxt = _goal(run, "old")
        until = min(g.cancel_ns + int(2 * STOPPED_S * SEC),
                    nxt.sent_ns if nxt is not None else facts.world.now)
        moving = [(t, v) for t, _x, _y, _yaw, v in _truth_odom(facts)
                  if g.cancel_ns + int(STOPPED_S * SEC) <= t <= until and abs(v) > STOPPED_V]
        if zero and not moving:
            points += 4
        else:
            if not zero:
                lines.append(f"cancel: no zero Twist on /cmd_vel from your node within "
                             f"{ZERO_TWIST_S} s of the cancel")
            if moving:
                lines.append(f"cancel: the robot still moves at {moving[0][1]:.2f} m/s "
                             f"{relative(moving[0][0] - g.cancel_ns, 'the cancel')}")
    old, new = _goal(run, "old"), _goal(run, "new")
    res = _result(facts, run, old) if old is not None else None
    if res is not None and res[1] == GoalStatus.PREEMPTED and new is not None \
            and res[0] - new.sent_ns <= SEC:
        points += 4
    else:
        got = "no result" if res is None or new is None else \
            f"{_status_name(res[1])} {relative(res[0] - new.sent_ns, 'the newer goal')}"
        lines.append(f"a newer goal: the older goal got {got}; expected PREEMPTED within 1 s")
    ok, why = _followed(facts, run, new, "the newer goal")
    if ok:
        points += 3
    else:
        lines.append(why)
    return points, lines


# -- 4b.6 the protocol --------------------------------------------------------------------------

#: rospy's texts for an illegal goal-handle call and a callback exception (the server's trace,
#: which the protocol machine reads in-process, stays in the sandbox).
_ILLEGAL = ("To transition to ", "Exception in your execute callback", "Exception in execute")


def check_protocol(facts: Facts) -> tuple[float, list[str]]:
    run, why = _run(facts)
    if run is None:
        return 0.0, [why]
    m = run.machine
    if run.violation:
        steps = [s.strip() for s in m.schedule[1:]]
        shown = steps[:15] + ([f"… and {len(steps) - 15} more step(s)"] if len(steps) > 15 else [])
        return 0.0, [run.violation.splitlines()[1].strip(),
                     "the grader's schedule of goals and cancels (step, simulated time, what):",
                     *shown]
    for t, _who, text in student_logs(facts):
        if text.startswith(_ILLEGAL):
            return 0.0, [f"t={t / 1e9:.2f} s: your server logged: {text.splitlines()[0][:200]}"]
    ended = [(path, o) for path, o in facts.outcomes
             if o.state in ("killed", "exited") and path.endswith(f"/{NODE_TYPE}")]
    if ended:  # a server that stopped answering served no schedule, whatever the goals did
        return 0.0, [f"your server's process was ended before the schedule's end: "
                     f"{ended[0][1].reason}"]
    if not run.finished:
        return 0.0, ["the schedule did not reach its end (cancel everything, every goal ends)"]
    late = m._unfinished()
    if late:
        return 0.0, [f"goal {late[0]} never got a result after the grader cancelled everything"]
    return 15.0, []


# -- 4b.7 the client ----------------------------------------------------------------------------

def _square_problem(path: Any, side: float) -> str:
    """Why ``path`` is not a square of ``side`` in odom (empty when it is one): at least four
    poses, the first four corners with four sides of ``side`` and diagonals of side * sqrt(2)."""
    frames = {path.header.frame_id, *(q.header.frame_id for q in path.poses)} - {""}
    if frames != {"odom"}:
        return f"the path's poses are in {sorted(frames) or 'no frame'}, not in odom"
    pts = [(q.pose.position.x, q.pose.position.y) for q in path.poses]
    if len(pts) < 4:
        return f"the path has {len(pts)} poses, not the four corners of a square"
    a, b, c, d = pts[:4]
    sides = [math.dist(a, b), math.dist(b, c), math.dist(c, d), math.dist(d, a)]
    diag = [math.dist(a, c), math.dist(b, d)]
    if any(abs(s - side) > 0.01 for s in sides) or any(abs(x - side * math.sqrt(2)) > 0.01
                                                         for x in diag):
        return (f"the first four poses are not a square of side {side:g} (_side): sides "
                + ", ".join(f"{s:.2f}" for s in sides) + " m")
    return ""


def check_client(facts: Facts) -> tuple[float, list[str]]:
    """3 a square goal of ~side; 3 the cancel at ~cancel_after; 2 still waiting for the result
    when the PREEMPTED result comes; 2 the class rule (once the client sends its goal)."""
    why = launch_problem(facts)
    if why:
        return 0.0, [why]
    log = getattr(facts.world, "_ddes_ex4b_client", None)
    if not isinstance(log, ClientLog):
        return 0.0, ["the grader's server for your client did not run"]
    if log.missing:
        return 0.0, [log.missing]
    p = facts.scenario.params
    side, after = float(p["client_side"]), float(p["client_cancel"])
    run = (f"{CLIENT} _action_name:={CLIENT_NS} _side:={side:g} _cancel_after:={after:g}")
    if not log.goals:
        return 0.0, [f"{run}: no goal reached the server"]
    t0, goal, gid = log.goals[0]
    points, lines = 0.0, []
    square = _square_problem(goal.path, side)
    if square:
        lines.append(f"{run}: {square}")
    else:
        points += 3
    cancels = [t for t, g in log.cancels if g == gid]
    if not cancels:
        lines.append(f"{run}: the goal was never cancelled (the server does not finish it; "
                     f"cancel it after {after:g} s)")
    else:
        late = (cancels[0] - t0) / SEC - after
        if not -CANCEL_EARLY_S <= late <= CANCEL_LATE_S:
            lines.append(f"{run}: the cancel came {(cancels[0] - t0) / SEC:.2f} s after the "
                         f"goal (expected {after:g} s)")
        else:
            points += 3
            if log.listening_at_result:
                points += 2
            else:
                lines.append(f"{run}: when the server answered the cancel "
                             f"({CLIENT_PREEMPT_S:g} s later, PREEMPTED) your client no longer "
                             "listened for the result: wait for the terminal state")
    rule = _class_rule(facts, CLIENT, _CLIENT_CALLS)
    if rule:
        lines.append(f"the course's rule 'logic in the class' is broken: {rule}")
    else:
        points += 2
    return points, lines


CREDIT = "lecture 4 (ETH Zurich, Programming for Robotics), ROS Actions; a ddes exercise"

EX4B = _Ex4b(
    id="ex4b_actions",
    title="A preemptable FollowPath action server on the robot",
    criteria=(
        Criterion("4b.1", "the FollowPath server is advertised under ~action_name (its five "
                  "topics, the lecture's types; 5) from a class its script builds (5)", 10,
                  check_server, credit=CREDIT),
        Criterion("4b.2", "follows the path: every waypoint passed in order within 0.25 m, the "
                  "end within 0.2 m, SUCCEEDED with success: true (20), the robot stopped "
                  "there (5)", 25, check_follow, credit=CREDIT),
        Criterion("4b.3", "feedback at 5 Hz or more; initial_distance constant and right; "
                  "remaining_distance decreasing, consistent with the robot, ending near 0", 15,
                  check_feedback, credit=CREDIT),
        Criterion("4b.4", "aborts an empty path (5) and a path it cannot follow (no progress: "
                  "3), stopping the robot (2)", 10,
                  check_aborts, credit=CREDIT),
        Criterion("4b.5", "preemption: a cancel gives PREEMPTED and stops the robot (zero "
                  "Twist); a newer goal preempts the older and is followed", 15,
                  check_preemption, credit=CREDIT),
        Criterion("4b.6", "the actionlib protocol (ddes.testing.actions' checks) holds over "
                  "the grader's schedule of goals and cancels", 15, check_protocol,
                  credit=CREDIT),
        Criterion("4b.7", "the client sends a square path of ~side, cancels it after "
                  "~cancel_after and waits for the terminal state, from a class its script "
                  "builds", 10, check_client, credit=CREDIT),
    ),
    scripts=(),
    duration=DURATION,
    build=build,
    scenarios=scenarios,
    required_files=(LAUNCH,),
    finished=finished,
    launch=LAUNCH,
    setup=setup,
)
