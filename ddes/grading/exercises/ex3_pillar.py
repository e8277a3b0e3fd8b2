"""Exercise 3: a P controller that drives the robot into the pillar, and a TF-transformed marker
(after ETH Zurich, Programming for Robotics, exercise 3: drives 20 %, hits the pillar 30 %, RViz
set-up 20 %, marker 30 %).  See ``solutions/ex3_pillar/README.md``.

Every check reads facts of the trusted world: the simulator's scans (the bearing the grader
computes itself from the very bytes the student's node received), its ground truth and
collisions, the grader's own TF buffer (a listener on the simulator's ``/tf`` and
``/tf_static``), and the submission's source and RViz config read as text.
"""

from __future__ import annotations

import math
from typing import Any

import yaml

from ddes.grading.course import (
    CourseExercise,
    hidden_random,
    notes,
    rviz_displays,
)
from ddes.grading.exercise import Criterion, Facts, Scenario
from ddes.grading.exercises.common import (
    PARAM_CALLS,
    argument,
    bound_to_self,
    launch_problem,
    private_param_reads,
    read_private,
    rospy_subscribers,
    student_script,
)
from ddes.transformations import cos, sin

__all__ = ["EX3"]

PKG = "smb_highlevel_controller"
LAUNCH = f"{PKG}/launch/{PKG}.launch"
NODE_TYPE = f"{PKG}_node.py"
SCRIPT = f"{PKG}/scripts/{NODE_TYPE}"
CREDIT = "after ETH Zurich, Programming for Robotics, exercise 3"
DURATION = 15.0
#: The public scenario starts the robot here in the course's world (pillar r=1 at (20, 5)).
PUBLIC_START = (9.0, 2.0, 0.0)
#: Tolerances: the P law (rad/s), the marker's distance from the pillar's surface (m).
P_TOL_ABS, P_TOL_REL = 1e-3, 0.01
MARKER_TOL = 0.15
W_MAX = 1.1  # the SMB's turn-rate limit: a command saturated there is accepted
MARKER_TYPE = "visualization_msgs/Marker"
#: hidden-1's pillar bearing (rad, either side): a large turn, where a wrong rotation shows.
WIDE_BEARING = (1.2, 1.45)
SPHERE = 2


def scenarios(seed: int, public: bool) -> list[Scenario]:
    x, y, yaw = PUBLIC_START
    out = [Scenario("public", seed, params={"x": x, "y": y, "yaw": yaw})]
    for i in range(2):
        rng = hidden_random(f"ex3_pillar/{i}", seed)
        yaw = round(rng.uniform(-3.0, 3.0), 3)
        dist = round(rng.uniform(4.0, 8.0), 3)
        bearing = round(rng.uniform(-1.0, 1.0), 3)        # about +-57 degrees
        radius = round(rng.uniform(0.2, 1.0), 3)
        cx = round(dist * cos(yaw + bearing), 3)
        cy = round(dist * sin(yaw + bearing), 3)
        out.append(Scenario(f"hidden-{i + 1}", seed, hidden=True, params={
            "x": 0.0, "y": 0.0, "yaw": yaw, "pillar": (cx, cy, radius),
            "p_gain": round(rng.uniform(0.6, 1.8), 3)}))
        if i == 0:  # the pillar far to the side: the robot turns by 1.2-1.45 rad towards it
            wide = round(math.copysign(rng.uniform(*WIDE_BEARING), bearing), 3)  # drawn last
            out[-1].params["pillar"] = (round(dist * cos(yaw + wide), 3),
                                        round(dist * sin(yaw + wide), 3), radius)
    return out


def build(world: Any, scenario: Scenario) -> None:
    """The grader's own TF buffer: a listener on the simulator's /tf and /tf_static."""
    from ddes.tf2_ros import Buffer, TransformListener

    node = world.create_node("/grader_tf", disable_rosout=True)
    buffer = Buffer(cache_time=DURATION + 5.0)
    TransformListener(node, buffer)
    world._ddes_grader_tf = buffer


def setup(world: Any, scenario: Scenario) -> tuple[dict[str, Any], dict[str, Any], dict[str, Any]]:
    p = scenario.params
    sim: dict[str, Any] = {"x": p["x"], "y": p["y"], "yaw": p["yaw"]}
    overrides: dict[str, Any] = {}
    if "pillar" in p:      # a hidden world with one pillar, and a hidden gain loaded last
        cx, cy, r = p["pillar"]
        sim["world_yaml"] = yaml.safe_dump({"name": "hidden_pillar", "obstacles": [
            {"type": "circle", "name": "pillar", "x": cx, "y": cy, "radius": r}]})
        overrides[NODE_TYPE] = {"p_gain": p["p_gain"]}
    return overrides, sim, {}


# -- facts shared by the checks -----------------------------------------------------------------

def _pillar(facts: Facts) -> tuple[tuple[float, float, float] | None, str]:
    """``(x, y, radius)`` of the world's single pillar, or None and why."""
    sim = notes(facts.world).sim
    if sim is None:
        return None, "the simulator did not start (the launch file must include ddes_sim.launch)"
    from ddes.sim.worlds import Circle

    circles = [o for o in sim.obstacles if isinstance(o, Circle)]
    if len(circles) != 1 or len(sim.obstacles) != 1:
        return None, (f"the simulator runs world {sim.spec.name!r}, not a world with a single "
                      "pillar (the launch file must start world single_pillar)")
    c = circles[0]
    return (c.x, c.y, c.radius), ""


def _gain(facts: Facts) -> tuple[float | None, str]:
    """The gain in force: the hidden override, or the student's own parameter file's."""
    p = facts.scenario.params
    if "p_gain" in p:
        return float(p["p_gain"]), "the hidden parameter file"
    n = notes(facts.world)
    if n.plan is None or not n.student_nodes:
        return None, "no node"
    value = n.plan.params.get(n.student_nodes[0].full_name + "/p_gain")
    if isinstance(value, (int, float)) and not isinstance(value, bool):
        return float(value), "your parameter file"
    return None, "your parameter file has no p_gain for the node"


def _student_messages(facts: Facts, topic: str) -> list[tuple[int, Any]]:
    return [(t, m) for t, who, m in facts.messages(topic) if who in facts.student_nodes]


def _scans(facts: Facts) -> list[tuple[int, Any]]:
    sim = notes(facts.world).sim
    if sim is None:
        return []
    return [(t, m) for t, who, m in facts.messages("/scan") if who == sim.node.name]


def pillar_bearings(scan: Any) -> list[float]:
    """The bearings of the scan's closest valid return (every beam tied at the minimum)."""
    lo, hi = scan.range_min, scan.range_max
    valid = [r for r in scan.ranges if lo <= r <= hi]
    if not valid:
        return []
    best = min(valid)
    return [scan.angle_min + i * scan.angle_increment
            for i, r in enumerate(scan.ranges) if r == best and lo <= r <= hi]


# -- 3.1 SMB drives: the P controller ------------------------------------------------------------

def check_drives(facts: Facts) -> tuple[float, list[str]]:
    why = launch_problem(facts)
    if why:
        return 0.0, [why]
    lines: list[str] = []
    points = 0.0
    cmds = _student_messages(facts, "/cmd_vel")
    sim = notes(facts.world).sim
    moved = 0.0
    if sim is not None:
        h = sim.history()
        for t, x, y in zip(h.t_ns, h.x, h.y):
            if t <= 3_000_000_000:
                moved = max(moved, math.hypot(x - h.x[0], y - h.y[0]))
    early = sum(1 for t, _m in cmds if t <= 3_000_000_000)
    if early >= 15 and moved >= 0.5:
        points += 5
    else:
        lines.append(f"{early} commands on /cmd_vel in the first 3 s (at least 15: 5 Hz) and the "
                     f"robot moved {moved:.2f} m by t=3 s (at least 0.5 m)")
    gain, source = _gain(facts)
    if gain is None:
        return points, [*lines, f"no gain to check the P law against: {source}"]
    scans = _scans(facts)
    total = ok = 0
    first = ""
    j = -1
    for t, cmd in cmds:
        while j + 1 < len(scans) and scans[j + 1][0] <= t:
            j += 1
        if j < 0:
            continue
        bearings = pillar_bearings(scans[j][1])
        if not bearings:
            continue
        total += 1
        z = cmd.angular.z
        good = False
        for b in bearings:
            want = gain * b
            tol = P_TOL_ABS + P_TOL_REL * abs(want)
            if abs(z - want) <= tol or (abs(want) > W_MAX and z * want > 0
                                        and W_MAX - tol <= abs(z) <= abs(want) + tol):
                good = True
        if good:
            ok += 1
        elif not first:
            first = (f"t={t / 1e9:.2f} s: the pillar is at bearing {bearings[0]:+.4f} rad, gain "
                     f"{gain:g} from {source}: expected angular.z {gain * bearings[0]:+.4f}, "
                     f"got {z:+.4f}")
    if total == 0:
        return points, [*lines, "no command on /cmd_vel while the laser saw the pillar"]
    frac = ok / total
    lines.append(f"{ok} of {total} commands follow angular.z = p_gain x bearing")
    if first:
        lines.append(first)
    points += 15.0 if frac >= 0.95 else 0.0
    return points, lines


# -- 3.2 SMB hits the pillar ---------------------------------------------------------------------

def check_hits(facts: Facts) -> tuple[float, list[str]]:
    why = launch_problem(facts)
    if why:
        return 0.0, [why]
    pillar, why = _pillar(facts)
    sim = notes(facts.world).sim
    if pillar is None or sim is None:
        return 0.0, [why]
    hits = [c for c in sim.collisions if c.obstacle == "pillar"]
    if hits:
        return 30.0, []
    cx, cy, r = pillar
    h = sim.history()
    gaps = [(math.hypot(x - cx, y - cy) - r, t) for t, x, y in zip(h.t_ns, h.x, h.y)]
    gap, t = min(gaps) if gaps else (math.inf, 0)
    return 0.0, [f"no contact with the pillar (r={r:.2f} m at ({cx:.2f}, {cy:.2f})) in "
                 f"{facts.exercise.duration:g} s; closest approach of base_link to its surface "
                 f"{gap:.2f} m at t={t / 1e9:.2f} s"]


# -- 3.3 RViz set-up and the node's structure ----------------------------------------------------

def _rviz(facts: Facts) -> tuple[float, list[str]]:
    glob, displays, why = rviz_displays(facts)
    if glob is None:
        return 0.0, [why]
    on = [d for d in displays if d.get("Enabled", True)]
    points, lines = 0.0, []
    wanted = (("rviz/TF", None), ("rviz/RobotModel", None), ("rviz/LaserScan", "Topic"),
              ("rviz/Marker", "Marker Topic"))
    for cls, key in wanted:
        found = [d for d in on if d.get("Class") == cls]
        if cls == "rviz/LaserScan":
            found = [d for d in found if d.get("Topic") == "/scan"]
        if cls == "rviz/Marker":
            found = [d for d in found if d.get("Marker Topic") in _marker_topics(facts)]
        if found:
            points += 2
        else:
            where = f" ({key}: {'/scan' if cls == 'rviz/LaserScan' else 'your marker topic'})" \
                if key else ""
            lines.append(f"no enabled {cls} display{where}")
    return points, lines


def _advertised(facts: Facts) -> set[str]:
    """The message types the student's nodes advertise (the grader's master)."""
    return {entry.type for entry in facts.world.master.topics.values()
            if any(p.node.name in facts.student_nodes for p in entry.publishers)}


def _structure(facts: Facts) -> tuple[float, list[str]]:
    """The node's structure: a class the main part builds (defined in the script or imported
    from the package), its Subscribers bound to its methods, its parameters private, its
    publishers and TF listener made by the class.  Read with :mod:`ast` where only the source
    can tell (where the code is, what a callback is bound to); the parameters read, the types
    advertised and the /tf subscription are facts of the run."""
    node = student_script(facts, SCRIPT)
    if node is None:
        return 0.0, [f"{SCRIPT} is missing or does not parse"]
    points, lines = 0.0, []
    if node.classes and node.built:
        points += 3
    else:
        lines.append("the node script does not define (or import) a class and build it in its "
                     "main part")
    subs = rospy_subscribers(node)
    if subs and all(bound_to_self(src, argument(c, 2, "callback"), method)
                    for src, c, method in subs):
        points += 3
    else:
        lines.append("the class creates no Subscriber, or one whose callback is not one of its "
                     "methods (self.scan_callback)")
    private, other = private_param_reads(facts)
    in_class = any(src.called(c) in PARAM_CALLS for src, c, _m in node.class_calls())
    if read_private(facts, "p_gain") and not other and in_class:
        points += 3
    else:
        where = "" if in_class else "; the class reads none itself"
        lines.append("the class must read its parameters as private names, ~p_gain among them "
                     f"(your node read: {', '.join([*private, *other]) or 'none'}{where})")
    made = {src.called(c) for src, c, _m in node.class_calls()}
    in_main = sorted(node.main_called() & {"Publisher", "Buffer", "TransformListener"})
    listens = any(s.node.name in facts.student_nodes
                  for s in getattr(facts.world.master.topics.get("/tf"), "subscribers", []))
    if ({"geometry_msgs/Twist", MARKER_TYPE} <= _advertised(facts) and listens and not in_main
            and {"Publisher", "TransformListener"} <= made):
        points += 3
    else:
        lines.append("the class must create Publishers of Twist and Marker and a tf2_ros Buffer "
                     "with a TransformListener" + (f" (the main part calls {', '.join(in_main)})"
                                                   if in_main else ""))
    return points, lines


def check_setup(facts: Facts) -> tuple[float, list[str]]:
    a, la = _rviz(facts)
    b, lb = _structure(facts)
    return a + b, [*la, *lb]


# -- 3.4 the marker ------------------------------------------------------------------------------

def _marker_topics(facts: Facts) -> list[str]:
    out = []
    for topic, entry in sorted(facts.world.master.topics.items()):
        if entry.type == MARKER_TYPE and any(p.node.name in facts.student_nodes
                                             for p in entry.publishers):
            out.append(topic)
    return out


def _truth_at(sim: Any) -> dict[int, tuple[float, float, float]]:
    h = sim.history()
    return {t: (x, y, yaw) for t, x, y, yaw in zip(h.t_ns, h.x, h.y, h.yaw)}


def _to_world(buffer: Any, truth: dict[int, tuple[float, float, float]], frame: str,
              stamp_ns: int, p: tuple[float, float, float]) -> tuple[float, float] | None:
    """A point of ``frame`` at ``stamp_ns`` in the world: the grader's TF to base_link, then the
    true pose of base_link at that instant (so odometry's drift does not count)."""
    from ddes.time.rostime import Time

    pose = truth.get(stamp_ns)
    if pose is None:
        return None
    tf = buffer.lookup_transform("base_link", frame, Time._from_ns(stamp_ns)).transform
    q, o = tf.rotation, tf.translation
    px, py, pz = p
    tx, ty, tz = 2.0 * (q.y * pz - q.z * py), 2.0 * (q.z * px - q.x * pz), 2.0 * (q.x * py - q.y * px)
    bx = px + q.w * tx + (q.y * tz - q.z * ty) + o.x
    by = py + q.w * ty + (q.z * tx - q.x * tz) + o.y
    x, y, yaw = pose
    c, s = cos(yaw), sin(yaw)
    return x + c * bx - s * by, y + s * bx + c * by


def _norm2(q: Any) -> float:
    """The squared norm of a quaternion message (RViz's ``validateQuaternions`` wants it within
    10e-3 of 1)."""
    return float(q.x * q.x + q.y * q.y + q.z * q.z + q.w * q.w)


def check_marker(facts: Facts) -> tuple[float, list[str]]:
    why = launch_problem(facts)
    if why:
        return 0.0, [why]
    pillar, why = _pillar(facts)
    sim = notes(facts.world).sim
    buffer = getattr(facts.world, "_ddes_grader_tf", None)
    if pillar is None or sim is None or buffer is None:
        return 0.0, [why or "no simulator"]
    topics = _marker_topics(facts)
    if not topics:
        return 0.0, ["your node publishes no visualization_msgs/Marker"]
    markers = [(t, m) for topic in topics for t, m in _student_messages(facts, topic)
               if t >= 1_000_000_000]
    markers.sort(key=lambda tm: tm[0])
    points, lines = 0.0, []
    span = facts.exercise.duration - 1.0
    spheres = [m for _t, m in markers if m.type == SPHERE]
    if len(spheres) >= span:
        points += 10
    else:
        lines.append(f"{len(spheres)} SPHERE markers on {', '.join(topics)} after t=1 s "
                     f"(at least 1 Hz: {span:g})")
    if not markers:
        return points, lines
    truth = _truth_at(sim)
    cx, cy, r = pillar
    good = 0
    first = ""
    for t, m in markers:
        stamp = m.header.stamp.to_nsec() or t
        frame = m.header.frame_id.lstrip("/")
        pos = m.pose.position
        miss = ""
        sc = m.scale
        if frame != "odom":
            miss = f"its frame is {frame!r}, not 'odom'"
        elif min(sc.x, sc.y, sc.z) <= 0 or m.color.a <= 0:
            miss = (f"has scale ({sc.x:g}, {sc.y:g}, {sc.z:g}) and colour alpha {m.color.a:g}: "
                    "RViz draws nothing (each must be above 0)")
        elif abs(_norm2(m.pose.orientation) - 1.0) >= 10e-3:
            q = m.pose.orientation
            miss = (f"has the orientation ({q.x:g}, {q.y:g}, {q.z:g}, {q.w:g}), not a unit "
                    "quaternion: RViz refuses such a marker (w = 1 for no rotation)")
        else:
            try:
                w = _to_world(buffer, truth, frame, stamp, (pos.x, pos.y, pos.z))
            except Exception as exc:  # noqa: BLE001 - tf2's errors: the marker cannot be placed
                w, miss = None, f"the grader's TF cannot place it: {str(exc)[:100]}"
            if w is None and not miss:
                miss = f"its stamp {stamp / 1e9:.3f} s is not an instant of the simulator"
            elif w is not None:
                off = abs(math.hypot(w[0] - cx, w[1] - cy) - r)
                if off > MARKER_TOL:
                    miss = (f"({pos.x:.2f}, {pos.y:.2f}) in odom is {off:.2f} m from the pillar's "
                            f"surface (at most {MARKER_TOL})")
        if miss:
            if not first:
                first = f"t={t / 1e9:.2f} s: marker {miss}"
        else:
            good += 1
    lines.append(f"{good} of {len(markers)} markers lie on the pillar's surface in odom")
    if first:
        lines.append(first)
    if good >= 0.9 * len(markers):
        points += 20
    return points, lines


EX3 = CourseExercise(
    id="ex3_pillar",
    title="A P controller drives the robot into the pillar; a marker shows the pillar",
    criteria=(
        Criterion("3.1", "SMB drives: /cmd_vel at 5 Hz or more, angular.z = p_gain x the "
                  "pillar's bearing", 20, check_drives, credit=CREDIT),
        Criterion("3.2", "SMB hits the pillar", 30, check_hits, credit=CREDIT),
        Criterion("3.3", "RViz set-up (TF, RobotModel, LaserScan, Marker) and the node's "
                  "structure (class, bound callbacks, private parameters)", 20, check_setup,
                  credit=CREDIT),
        Criterion("3.4", "the marker sits on the pillar, in odom, visible (scale and alpha above "
                  "0), at 1 Hz or more", 30,
                  check_marker, credit=CREDIT),
    ),
    scripts=(),
    duration=DURATION,
    build=build,
    scenarios=scenarios,
    required_files=(LAUNCH,),
    launch=LAUNCH,
    setup=setup,
)
