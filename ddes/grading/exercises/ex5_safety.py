"""Exercise 5: automatic emergency stops (after ETH Zurich, Programming for Robotics, exercise 5's
bonus; lecture 5's case study): a proximity stop from the laser and a crash detector from the
IMU, two rospy nodes that call the exercise-4a ``std_srvs/SetBool`` emergency stop.  See
``solutions/ex5_safety/README.md``.

**Attribution.**  Student nodes cannot call grader services (docs/grading.md), so the e-stop
servers are the student's own controller: the grader starts it twice in the sandbox, the
launch file's instance serving the proximity stop under a hidden name A and a second instance
(``/ddes_estop_crash``, the same script and parameters) serving the crash detector under a
hidden name B; each node's ``~stop_service_name`` is overridden accordingly.  Each controller's
``/cmd_vel`` is remapped to a grader topic: the zero Twist a SetBool stop publishes there at
once (exercise 4a's contract) is the fact "this node called the e-stop", with its time.

**The run** (one per scenario, 14 simulated s): a grader driver drives the robot through
manoeuvres that must not trigger anything — a start (+2 m/s²) beside a pillar on the left
within ``~min_distance`` but outside the front sector, passing a pillar at more than twice the
hidden ``~min_distance``, braking (-2 m/s²), a start, a sharp S-turn (lateral
acceleration v·ω up to 1.2 m/s²), a wheel over a cable while driving straight (a 60 ms
sideways and upward jolt of the IMU, 5-8 m/s² and 3-5 m/s², the forward acceleration
unchanged: ``Simulator.bump``) — then, driving straight, the grader adds a pillar ahead
(``Simulator.add``) at ``min_distance`` + 1 m of the laser: the proximity stop must call A when
the range drops below ``min_distance`` (the driver then brakes, as the e-stop would), once;
0.5 s later the driver backs the robot off to 1.07-1.13 ``min_distance`` (inside the 20 % of
hysteresis: the same approach, no second call) and pushes it into that pillar: the crash
detector must call B within 0.2 s of the impact the simulator records, and not before.  A stop
at a time it is not expected is recorded, not obeyed, so that one fault does not hide the
others.  Hidden scenarios draw the start heading, ``min_distance`` (0.8-1.5 m), the speeds
(0.4-1.1 m/s), the passing pillar, the service names, then the side pillar, the back-off and
the bump from the scenario seed.

**Deviations from teaching.md (E5).**  The design's grader-side SetBool stand-in cannot be
called from the sandbox, hence the student's controller twice (above); one run per scenario
holds all three kinds of event instead of 10 worlds and separate crash-free runs (the grader
averages every criterion over scenarios, so each run must judge each criterion); the weights
are 40/40/20 (5.1 stop 30 + once per approach 10; 5.2 within 0.2 s and none before 30 + latency
≤ 0.05 s 10; 5.3 no false stop, 10 per node, gated on that node's own criterion so that a node
that never calls earns nothing); the crash is the push into the pillar the proximity stop
stopped at (0.4-1.1 m/s at impact), not a separate world.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import yaml

from ddes.grading.course import CourseExercise, hidden_random, notes
from ddes.grading.exercise import Criterion, Facts, Scenario
from ddes.grading.exercises.common import launch_problem
from ddes.transformations import cos, sin

__all__ = ["EX5", "scenarios"]

PKG = "smb_highlevel_controller"
LAUNCH = f"{PKG}/launch/{PKG}.launch"
CTRL = f"{PKG}_node.py"
PROX = "proximity_stop.py"
CRASH = "crash_detector.py"
CREDIT = "after ETH Zurich, Programming for Robotics, exercise 5 (bonus)"
DURATION = 14.0
#: The grader topics the two controllers' /cmd_vel are remapped to.
TOPIC_A = "/ddes_grader/estop_proximity"
TOPIC_B = "/ddes_grader/estop_crash"
CRASH_NODE = "ddes_estop_crash"
#: The laser's offset ahead of base_link (m): ranges are measured from there.
LASER_X = 0.20
#: The stop must come when the true range is below min_distance + EARLY (noise), and no later
#: than one scan (0.1 s) + LATE_S of driving past it.
EARLY, LATE_S, LATE_M = 0.05, 0.05, 0.05
#: The crash detector's call within this long after the impact (s); full latency points within
#: FAST.
CRASH_WITHIN, FAST = 0.2, 0.05
#: The driver's phases (s from the start): start + pass, brake, start, turn left, turn right,
#: straight; then the approach.
PHASES = (("start and pass", 2.6), ("brake", 3.4), ("start", 4.4), ("turn left", 5.6),
          ("turn right", 6.8), ("straight", 7.6))
APPROACH_AT = PHASES[-1][1]
#: After the proximity stop, the robot rests this long before the push.
REST = 0.5
#: The side pillar (``params["side"]``: its centre's distance ahead of the start, the gap from
#: the robot's centre line to its surface on the left, its radius) is passed at the start
#: within min_distance but outside the front sector: the gap is at most 0.65 min_distance and
#: at least this (m; the laser's range_min is 0.45 m), so its beams within 0.5 rad of ahead
#: stay beyond gap / sin(0.5) > 1.1 min_distance.
SIDE_GAP_MIN = 0.55
#: After the proximity stop and the rest, the driver backs the robot off at this speed until
#: the laser is ``params["backoff"]`` x min_distance from the pillar (inside the 20 % of
#: hysteresis: the same approach), rests BACKOFF_REST, then pushes.
BACKOFF_V, BACKOFF_REST = 0.4, 0.3
#: During the straight phase a wheel rolls over a cable (``params["bump"]``: the time, the
#: lateral and the vertical peak in m/s^2): a half-sine jolt of the IMU this long, sideways and
#: up, the forward acceleration unchanged; not a crash.
BUMP_S = 0.06


def scenarios(seed: int, public: bool) -> list[Scenario]:
    out = [Scenario("public", seed, params={
        "yaw": 0.0, "min_distance": 1.0, "v1": 1.1, "v_turn": 0.9, "w_turn": 1.1,
        "v_approach": 0.8, "v_push": 1.0, "pass": (2.0, 3.5, 0.3),
        "service_a": "/emergency_stop", "service_b": "/crash_stop",
        "side": (1.0, 0.6, 0.15), "backoff": 1.1, "bump": (7.2, 6.0, 4.0)})]
    for i in range(2):
        rng = hidden_random(f"ex5_safety/{i}", seed)
        m = round(rng.uniform(0.8, 1.5), 3)
        v1 = round(rng.uniform(0.8, 1.1), 3)
        w = round(rng.uniform(0.9, 1.1), 3)
        v_turn = round(min(1.1, 1.2 / w) * rng.uniform(0.85, 1.0), 3)
        out.append(Scenario(f"hidden-{i + 1}", seed, hidden=True, params={
            "yaw": round(rng.uniform(-3.0, 3.0), 3), "min_distance": m, "v1": v1,
            "v_turn": v_turn, "w_turn": w,
            "v_approach": round(rng.uniform(0.4, 1.1), 3),
            "v_push": round(rng.uniform(0.6, 1.1), 3),
            "pass": (round(rng.uniform(1.2, 2.0), 3), round(2 * m + rng.uniform(0.8, 1.2), 3),
                     round(rng.uniform(0.2, 0.5), 3)),
            "service_a": f"/{rng.choice(['estop', 'halt', 'safety'])}_{rng.randrange(100, 1000)}",
            "service_b": f"/{rng.choice(['crash', 'impact', 'bump'])}_{rng.randrange(100, 1000)}",
        }))
        # drawn after the others, so that those keep their values
        out[-1].params["side"] = (round(rng.uniform(0.8, 1.4), 3),
                                  round(max(SIDE_GAP_MIN, m * rng.uniform(0.55, 0.65)), 3),
                                  round(rng.uniform(0.1, 0.2), 3))
        out[-1].params["backoff"] = round(rng.uniform(1.07, 1.13), 3)
        out[-1].params["bump"] = (round(rng.uniform(6.9, 7.4), 3),
                                  round(rng.choice((-1, 1)) * rng.uniform(5.0, 8.0), 3),
                                  round(rng.uniform(3.0, 5.0), 3))
    return out


def _rot(yaw: float, x: float, y: float) -> tuple[float, float]:
    c, s = cos(yaw), sin(yaw)
    return round(c * x - s * y, 6), round(s * x + c * y, 6)


def setup(world: Any, scenario: Scenario) -> tuple[dict[str, Any], dict[str, Any], dict[str, Any]]:
    p = scenario.params
    fwd, lateral, r = p["pass"]
    px, py = _rot(p["yaw"], fwd + r, -(lateral + r))  # the passing pillar, on the right
    obstacles = [{"type": "circle", "name": "passing_pillar", "x": px, "y": py, "radius": r}]
    if "side" in p:  # close on the left, outside the front sector
        sf, sg, sr = p["side"]
        sx, sy = _rot(p["yaw"], sf, sg + sr)
        obstacles.append({"type": "circle", "name": "side_pillar", "x": sx, "y": sy, "radius": sr})
    sim = {"x": 0.0, "y": 0.0, "yaw": p["yaw"], "world_yaml": yaml.safe_dump({
        "name": "passing_pillar", "obstacles": obstacles})}
    overrides = {CTRL: {"stop_service_name": p["service_a"]},
                 PROX: {"stop_service_name": p["service_a"], "min_distance": p["min_distance"]},
                 CRASH: {"stop_service_name": p["service_b"]}}
    return overrides, sim, {CTRL: {"/cmd_vel": TOPIC_A}}


# -- the driver -----------------------------------------------------------------------------------

@dataclass
class RunLog:
    """What the grader's driver saw: the stops on each topic ``(t_ns, laser gap to the target
    pillar or nan)``, the phase times, the target pillar."""

    stops_a: list[tuple[int, float]] = field(default_factory=list)
    stops_b: list[tuple[int, float]] = field(default_factory=list)
    approach_ns: int = -1
    target: tuple[float, float, float] | None = None
    braked_ns: int = -1
    push_ns: int = -1
    backed_ns: int = -1
    bump_ns: int = -1


def _gap(sim: Any, target: tuple[float, float, float] | None) -> float:
    """The true range from the laser to the target pillar's surface now (nan without one)."""
    if target is None:
        return math.nan
    t = sim.truth
    lx, ly = t.x + LASER_X * cos(t.yaw), t.y + LASER_X * sin(t.yaw)
    return math.hypot(target[0] - lx, target[1] - ly) - target[2]


def _start_driver(world: Any, scenario: Scenario) -> None:
    import ddes
    from ddes.msg import get_message_class
    from ddes.sim import Circle

    sim = notes(world).sim
    if sim is None:
        return
    p = scenario.params
    log = RunLog()
    world._ddes_ex5 = log
    Twist = get_message_class("geometry_msgs/Twist")
    node = world.create_node("/grader_driver", disable_rosout=True)
    pub = ddes.Publisher(node, "/cmd_vel", Twist, queue_size=1)
    approach_ns = round(APPROACH_AT * 1e9)

    def send(v: float, w: float) -> None:
        msg = Twist()
        msg.linear.x, msg.angular.z = v, w
        pub.publish(msg)

    def is_zero(m: Any) -> bool:
        return not any(abs(x) > 1e-9 for x in (m.linear.x, m.linear.y, m.linear.z, m.angular.x,
                                                m.angular.y, m.angular.z))

    def on_a(m: Any) -> None:
        if not is_zero(m):
            return
        log.stops_a.append((world.now, _gap(sim, log.target)))
        if log.target is not None and log.braked_ns < 0 and not sim.collisions:
            log.braked_ns = world.now  # the e-stop brakes the robot at once
            send(0.0, 0.0)

    def on_b(m: Any) -> None:
        if is_zero(m):
            log.stops_b.append((world.now, _gap(sim, log.target)))
            if sim.collisions:
                send(0.0, 0.0)

    ddes.Subscriber(node, TOPIC_A, Twist, on_a)
    ddes.Subscriber(node, TOPIC_B, Twist, on_b)
    w = p["w_turn"]
    plan = [(PHASES[0][1], p["v1"], 0.0), (PHASES[1][1], 0.0, 0.0), (PHASES[2][1], p["v1"], 0.0),
            (PHASES[3][1], p["v_turn"], w), (PHASES[4][1], p["v_turn"], -w),
            (PHASES[5][1], p["v_approach"], 0.0)]

    bump = p.get("bump")
    bump_ns = round(bump[0] * 1e9) if bump else -1

    def tick(_event: Any) -> None:
        now = world.now
        if bump and log.bump_ns < 0 and now >= bump_ns:
            log.bump_ns = now  # a wheel over a cable: a sideways jolt of the IMU, no crash
            sim.bump(bump[1], bump[2], BUMP_S)
        if now < approach_ns:
            for until, v, om in plan:
                if now < round(until * 1e9):
                    send(v, om)
                    return
        if log.target is None:  # the approach: a pillar ahead at min_distance + 1 m
            t = sim.truth
            r = 0.3
            d = LASER_X + p["min_distance"] + 1.0 + r
            log.target = (t.x + d * cos(t.yaw), t.y + d * sin(t.yaw), r)
            sim.add(Circle(log.target[0], log.target[1], r, "target_pillar"))
            log.approach_ns = now
        if sim.collisions and (log.stops_b or now > sim.collisions[0].t_ns + round(0.5e9)):
            send(0.0, 0.0)  # crashed: stopped by the crash detector, or given up
        elif log.braked_ns < 0:
            send(p["v_approach"], 0.0)
        elif now < log.braked_ns + round((0.6 + REST) * 1e9):
            send(0.0, 0.0)
        elif "backoff" in p and log.backed_ns < 0:
            # back off a little (the robot's braking adds about 0.045 m), within the hysteresis
            if _gap(sim, log.target) < p["backoff"] * p["min_distance"] - 0.045:
                send(-BACKOFF_V, 0.0)
            else:
                log.backed_ns = now
                send(0.0, 0.0)
        elif log.backed_ns >= 0 and now < log.backed_ns + round(BACKOFF_REST * 1e9):
            send(0.0, 0.0)
        else:
            if log.push_ns < 0:
                log.push_ns = now
            send(p["v_push"], 0.0)

    ddes.Timer(node, 0.02, tick)


def _crash_instance(scripts: list[tuple[str, list[str]]],
                    scenario: Scenario) -> list[tuple[str, list[str]]]:
    """The controller's script a second time, serving the crash detector's name B."""
    for path, args in scripts:
        if path.endswith("/" + CTRL):
            keep = [a for a in args if not a.startswith(("__name:=", "_stop_service_name:=",
                                                         "/cmd_vel:=", "cmd_vel:="))]
            return [(path, [*keep, f"__name:={CRASH_NODE}",
                            f"_stop_service_name:={scenario.params['service_b']}",
                            f"/cmd_vel:={TOPIC_B}"])]
    return []


@dataclass(frozen=True)
class _Ex5(CourseExercise):
    def student_scripts(self, world: Any, scenario: Scenario,
                        submission: Path) -> list[tuple[str, list[str]]]:
        scripts = super().student_scripts(world, scenario, submission)
        _start_driver(world, scenario)
        return [*scripts, *_crash_instance(scripts, scenario)]


# -- facts ----------------------------------------------------------------------------------------

def _log(facts: Facts) -> RunLog:
    log = getattr(facts.world, "_ddes_ex5", None)
    return log if isinstance(log, RunLog) else RunLog()


def _node_launched(facts: Facts, node_type: str) -> str:
    n = notes(facts.world)
    if not any(s.type == node_type for s in n.student_nodes):
        return f"{LAUNCH} starts no {node_type} node of your package"
    return ""


def _phase(t_ns: int) -> str:
    for name, until in PHASES:
        if t_ns < round(until * 1e9):
            return name
    return "approach"


def _s(t_ns: int) -> str:
    return f"t={t_ns / 1e9:.2f} s"


def _while(log: RunLog, t_ns: int) -> str:
    """What the driver was doing at ``t_ns``: its phase, or the bump just before."""
    if 0 <= log.bump_ns <= t_ns <= log.bump_ns + round(0.3e9):
        return (f"{_phase(t_ns)}; a wheel had rolled over a cable "
                f"{(t_ns - log.bump_ns) / 1e9:.2f} s before: a sideways and upward jolt of the "
                "IMU, the forward acceleration unchanged")
    return _phase(t_ns)


def _proximity(facts: Facts) -> tuple[float, list[str]]:
    """(share of 5.1 in [0, 1], why): 0.75 for the stop in the window, 0.25 for one call."""
    why = launch_problem(facts) or _node_launched(facts, PROX)
    if why:
        return 0.0, [why]
    p, log = facts.scenario.params, _log(facts)
    sim = notes(facts.world).sim
    m = p["min_distance"]
    if log.approach_ns < 0 or sim is None:
        return 0.0, ["the approach did not start"]
    calls = [(t, g) for t, g in log.stops_a if t >= log.approach_ns]
    hit = [c for c in sim.collisions if c.obstacle == "target_pillar"]
    if not calls:
        more = (f"; the robot hit it at {_s(hit[0].t_ns)} at {hit[0].speed:.2f} m/s"
                if hit else "")
        return 0.0, [f"no emergency stop while driving at {p['v_approach']:.2f} m/s towards a "
                     f"pillar (min_distance {m:.2f} m){more}"]
    t, gap = calls[0]
    late = m - p["v_approach"] * (0.1 + LATE_S) - LATE_M
    if gap > m + EARLY:
        return 0.0, [f"the emergency stop at {_s(t)} came with the pillar still {gap:.2f} m "
                     f"from the laser (min_distance {m:.2f} m): too early"]
    if gap < late:
        return 0.0, [f"the emergency stop at {_s(t)} came with the pillar {gap:.2f} m from the "
                     f"laser, below {late:.2f} m (min_distance {m:.2f} m, one scan at "
                     f"{p['v_approach']:.2f} m/s): too late"]
    if hit and hit[0].t_ns < t:
        return 0.0, [f"the robot hit the pillar at {_s(hit[0].t_ns)}, before the stop"]
    if len(calls) > 1:
        more = ""
        if 0 <= log.backed_ns < calls[1][0] and "backoff" in p:
            more = (f"; after the first the robot backed off to {p['backoff'] * m:.2f} m from "
                    f"the pillar, less than 20 % beyond min_distance ({m:.2f} m), and drove on: "
                    "still the same approach")
        return 0.75, [f"{len(calls)} emergency stops during one approach (at "
                      f"{', '.join(_s(c[0]) for c in calls[:4])}): call once per approach"
                      f"{more}"]
    return 1.0, []


def _crash(facts: Facts) -> tuple[float, list[str]]:
    """(share of 5.2, why): 0.75 for a call within 0.2 s of the impact and none before, 0.25
    for a latency within 0.05 s."""
    why = launch_problem(facts) or _node_launched(facts, CRASH)
    if why:
        return 0.0, [why]
    log = _log(facts)
    sim = notes(facts.world).sim
    if sim is None or not sim.collisions:
        return 0.0, ["the robot never hit the pillar (the grader's push failed)"]
    impact = sim.collisions[0]
    before = [t for t, _ in log.stops_b if t < impact.t_ns]
    if before:
        return 0.0, [f"the crash detector stopped the robot at {_s(before[0])} "
                     f"({_while(log, before[0])}), before the impact at {_s(impact.t_ns)}"]
    after = [t for t, _ in log.stops_b if t <= impact.t_ns + round(CRASH_WITHIN * 1e9)]
    if not after:
        return 0.0, [f"no emergency stop within {CRASH_WITHIN:g} s of the impact at "
                     f"{_s(impact.t_ns)} ({impact.speed:.2f} m/s)"]
    latency = (after[0] - impact.t_ns) / 1e9
    if latency > FAST:
        return 0.75, [f"the crash was detected {latency:.3f} s after the impact (within "
                      f"{FAST:g} s for full points)"]
    return 1.0, []


def _side_range(facts: Facts, t_ns: int) -> float | None:
    """The true range from the laser to the side pillar at ``t_ns`` when it is within
    min_distance (None otherwise)."""
    from ddes.sim import Circle

    sim = notes(facts.world).sim
    side = next((o for o in sim.obstacles if isinstance(o, Circle) and o.name == "side_pillar"),
                None) if sim is not None else None
    if sim is None or side is None:
        return None
    h = sim.history()
    best = None
    for t, x, y, yaw in zip(h.t_ns, h.x, h.y, h.yaw):
        if t > t_ns:
            break
        best = (x, y, yaw)
    if best is None:
        return None
    x, y, yaw = best
    gap = math.hypot(side.x - x - LASER_X * cos(yaw), side.y - y - LASER_X * sin(yaw)) \
        - side.radius
    return gap if gap < facts.scenario.params["min_distance"] else None


def check_proximity(facts: Facts) -> tuple[float, list[str]]:
    share, lines = _proximity(facts)
    return 40 * share, lines


def check_crash(facts: Facts) -> tuple[float, list[str]]:
    share, lines = _crash(facts)
    return 40 * share, lines


def check_no_false_stop(facts: Facts) -> tuple[float, list[str]]:
    """10 per node: no call during the manoeuvres, counted only when that node stopped the
    robot when it should (in this run)."""
    why = launch_problem(facts)
    if why:
        return 0.0, [why]
    log = _log(facts)
    sim = notes(facts.world).sim
    points, lines = 0.0, []
    prox_ok, _ = _proximity(facts)
    end = log.approach_ns if log.approach_ns >= 0 else round(DURATION * 1e9)
    early_a = [t for t, _ in log.stops_a if t < end]
    if early_a:
        side = _side_range(facts, early_a[0])
        what = ("nothing within min_distance" if side is None else
                f"nothing ahead within min_distance (a pillar {side:.2f} m from the laser on "
                "the left, outside the front sector)")
        lines.append(f"proximity stop: an emergency stop at {_s(early_a[0])} while "
                     f"{_phase(early_a[0])}, {what}")
    elif prox_ok < 0.75:
        lines.append("proximity stop: no false stop, but it earns this only once it stops "
                     "the robot at the pillar (5.1)")
    else:
        points += 10
    crash_ok, _ = _crash(facts)
    impact = sim.collisions[0].t_ns if sim is not None and sim.collisions else end
    early_b = [t for t, _ in log.stops_b if t < min(impact, end)]
    if early_b:
        lines.append(f"crash detector: an emergency stop without a crash at {_s(early_b[0])} "
                     f"({_while(log, early_b[0])})")
    elif crash_ok < 0.75:
        lines.append("crash detector: no false stop, but it earns this only once it detects "
                     "the crash (5.2)")
    else:
        points += 10
    return points, lines


EX5 = _Ex5(
    id="ex5_safety",
    title="Automatic emergency stops: a proximity stop from the laser, a crash detector from "
          "the IMU",
    criteria=(
        Criterion("5.1", "automatically triggered emergency stop when too close to an obstacle: "
                  "the proximity stop calls the e-stop when the range drops below "
                  "~min_distance (30), once per approach (10)", 40, check_proximity,
                  credit=CREDIT),
        Criterion("5.2", "automatically triggered emergency stop after crashing with an "
                  "obstacle: the crash detector calls the e-stop within 0.2 s of the impact "
                  "and not before (30), within 0.05 s (10)", 40, check_crash, credit=CREDIT),
        Criterion("5.3", "no emergency stop without a reason: none while starting, braking, "
                  "turning sharply, rolling over a cable or passing a pillar at a distance (10 per node, once the "
                  "node stops the robot when it should)", 20, check_no_false_stop,
                  credit=CREDIT),
    ),
    scripts=(),
    duration=DURATION,
    scenarios=scenarios,
    required_files=(LAUNCH,),
    launch=LAUNCH,
    setup=setup,
)
