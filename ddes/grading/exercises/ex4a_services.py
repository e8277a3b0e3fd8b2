"""Exercise 4a: a std_srvs/SetBool emergency stop in the controller class, and a console script
of ``rosservice call`` lines (after ETH Zurich, Programming for Robotics, exercise 5: stop
implemented 20 %, called 20 %, robot stops 10 %; start the same).  See
``solutions/ex4a_services/README.md``.

Every check reads facts of the trusted world: the grader's own calls of the student's service
(a trusted node with a ServiceProxy; the service crosses the sandbox as bytes, see
docs/grading.md), the ``/cmd_vel`` messages of the student's node, and the simulator's ground
truth (true speed and position).  The console script is read as text and run by the grader's
node line by line (``rosservice call NAME YAML...`` filled as rosservice fills it, ``sleep S``).
The polarity follows the lecture-5 emergency stop: ``data: true`` stops, ``data: false``
resumes.  The course's rule "logic in the class" (teaching.md's C0, -20 %) is graded as part of
4a.1's "the service exists" share (5 points): read with :mod:`ast`, the class must advertise
the Service with one of its methods as the handler and read a parameter, and the main part only
build the class; that the node read its private ``~stop_service_name`` is a fact of the run (see
docs/grading.md, "Source checks", for the forms accepted).
"""

from __future__ import annotations

import math
import shlex
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import yaml

from ddes.grading.course import CourseExercise, hidden_random, notes
from ddes.grading.exercise import Criterion, Facts, Scenario
from ddes.grading.exercises.common import (
    PARAM_CALLS,
    argument,
    bound_to_self,
    launch_problem,
    read_private,
    student_script,
)
from ddes.transformations import cos, sin

__all__ = ["EX4A", "parse_script", "scenarios"]

PKG = "smb_highlevel_controller"
LAUNCH = f"{PKG}/launch/{PKG}.launch"
NODE_TYPE = f"{PKG}_node.py"
SCRIPT = "stop.txt"
PARAM = "stop_service_name"
CREDIT = "after ETH Zurich, Programming for Robotics, exercise 5"
DURATION = 16.0
PUBLIC_START = (0.0, 0.0, 0.0)
#: Public call times (s): stop, resume, stop, resume; then the student's script.
PUBLIC_TIMES = (2.5, 4.5, 6.5, 8.0)
SCRIPT_DELAY = 2.0
#: The script's calls must be made within this long after it starts (s).
SCRIPT_SPAN = 3.0
#: A zero Twist within one control period (the 10 Hz scan) of a stop, with slack.
ZERO_WITHIN = 0.15
#: Non-zero Twists again within this long of a resume.
RESUME_WITHIN = 0.3
STOP_SPEED, STOP_WITHIN = 0.05, 1.0
#: ... and its true turn rate below this (rad/s) as well.
STOP_TURN = 0.05
#: Public: ``TURN_LEAD`` s before the second stop a pillar appears ``TURN_PILLAR[0]`` m from the
#: robot at bearing ``TURN_PILLAR[1]`` rad (radius ``TURN_PILLAR[2]``), closer than the far
#: pillar, so that the robot is turning towards it when the stop comes.
TURN_LEAD, TURN_PILLAR = 0.4, (9.0, 1.0, 0.3)
MOVE_DIST, MOVE_WITHIN = 0.3, 2.0
SETBOOL = "std_srvs/SetBool"


def scenarios(seed: int, public: bool) -> list[Scenario]:
    out = [Scenario("public", seed, params={"start": PUBLIC_START, "times": PUBLIC_TIMES,
                                            "turn": (TURN_LEAD, *TURN_PILLAR)})]
    for i in range(2):
        rng = hidden_random(f"ex4a_services/{i}", seed)
        yaw = round(rng.uniform(-3.0, 3.0), 3)
        dist = round(rng.uniform(17.0, 20.0), 3)
        bearing = round(rng.uniform(-0.8, 0.8), 3)
        radius = round(rng.uniform(0.3, 1.0), 3)
        t1 = round(rng.uniform(2.0, 3.0), 3)
        t2 = round(t1 + rng.uniform(1.5, 2.0), 3)
        t3 = round(t2 + rng.uniform(1.5, 2.0), 3)
        t4 = round(t3 + rng.uniform(1.2, 1.6), 3)
        name = f"/{rng.choice(['estop', 'halt', 'safety', 'panic'])}_{rng.randrange(100, 1000)}"
        out.append(Scenario(f"hidden-{i + 1}", seed, hidden=True, params={
            "start": (0.0, 0.0, yaw), "times": (t1, t2, t3, t4), "service": name,
            "pillar": (round(dist * cos(yaw + bearing), 3), round(dist * sin(yaw + bearing), 3),
                       radius)}))
        # drawn after the others, so that those keep their values
        out[-1].params["turn"] = (round(rng.uniform(0.3, 0.5), 3), round(rng.uniform(8.5, 9.5), 3),
                                  round(rng.choice([-1, 1]) * rng.uniform(0.9, 1.2), 3),
                                  round(rng.uniform(0.2, 0.4), 3))
    return out


def setup(world: Any, scenario: Scenario) -> tuple[dict[str, Any], dict[str, Any], dict[str, Any]]:
    p = scenario.params
    x, y, yaw = p["start"]
    sim: dict[str, Any] = {"x": x, "y": y, "yaw": yaw}
    overrides: dict[str, Any] = {}
    if "pillar" in p:
        cx, cy, r = p["pillar"]
        sim["world_yaml"] = yaml.safe_dump({"name": "hidden_pillar", "obstacles": [
            {"type": "circle", "name": "pillar", "x": cx, "y": cy, "radius": r}]})
    if "service" in p:
        overrides[NODE_TYPE] = {PARAM: p["service"]}
    return overrides, sim, {}


# -- the console script ---------------------------------------------------------------------------

@dataclass(frozen=True)
class ScriptLine:
    """One line of the student's script: a call (``name``, ``data``) or a ``sleep``."""

    number: int
    text: str
    name: str = ""
    data: bool | None = None
    sleep: float = 0.0
    error: str = ""


def parse_script(text: str) -> list[ScriptLine]:
    """The script's lines, each a call, a sleep, or an error that says what is wrong."""
    from ddes.errors import DdesError
    from ddes.graph.names import is_legal_name
    from ddes.graph.yamlsafe import load_yaml
    from ddes.msg.convert import fill_message_args
    from ddes.msg.registry import get_service_class

    request_class = get_service_class(SETBOOL)._request_class
    out = []
    for n, raw in enumerate(text.splitlines(), 1):
        line = raw.strip()
        if not line or line.startswith("#"):
            continue
        try:
            words = shlex.split(line, comments=True)
        except ValueError as exc:
            out.append(ScriptLine(n, line, error=f"cannot be parsed: {exc}"))
            continue
        if len(words) == 2 and words[0] == "sleep":
            try:
                secs = float(words[1])
            except ValueError:
                secs = -1.0
            ok = 0.0 <= secs <= SCRIPT_SPAN and math.isfinite(secs)
            out.append(ScriptLine(n, line, sleep=secs) if ok else ScriptLine(
                n, line, error=f"sleep takes seconds between 0 and {SCRIPT_SPAN:g}"))
            continue
        if words[:2] != ["rosservice", "call"] or len(words) < 4:
            out.append(ScriptLine(n, line, error="not 'rosservice call NAME ARGS' or 'sleep S'"))
            continue
        name = words[2]
        if not (name.startswith("/") and is_legal_name(name)):
            out.append(ScriptLine(n, line, error=f"{name!r} is not a global service name"))
            continue
        try:
            request = request_class()
            fill_message_args(request, [load_yaml(a) for a in words[3:]])
        except (DdesError, yaml.YAMLError, ValueError, TypeError) as exc:
            out.append(ScriptLine(n, line, error=f"its arguments do not fill a SetBool request: "
                                                 f"{str(exc)[:120]}"))
            continue
        out.append(ScriptLine(n, line, name=name, data=bool(request.data)))
    return out


# -- the grader's calls ---------------------------------------------------------------------------

@dataclass
class CallRecord:
    source: str           # "grader" or "script line N"
    t_ns: int
    name: str
    data: bool
    done_ns: int = -1
    success: bool | None = None
    message: str = ""
    error: str = ""


def _start_driver(world: Any, scenario: Scenario, script: list[ScriptLine],
                  configured: str) -> None:
    from ddes.errors import ServiceException
    from ddes.services.client import ServiceProxy

    p = scenario.params
    name = p.get("service", configured)
    node = world.create_node("/grader_estop", disable_rosout=True)
    setbool = world.messages.get_service_class(SETBOOL)
    records: list[CallRecord] = []
    world._ddes_estop_calls = records
    plan: list[tuple[float, str, str, bool]] = [
        (t, "grader", name, i % 2 == 0) for i, t in enumerate(p["times"])]
    t = p["times"][-1] + SCRIPT_DELAY
    for line in script:
        if line.error:
            continue
        if line.data is None:
            t += line.sleep
            continue
        target = name if line.name == configured else line.name  # substituted by value
        plan.append((t, f"script line {line.number}", target, line.data))

    def turn():  # type: ignore[no-untyped-def]
        from ddes.sim import Circle

        lead, dist, bearing, radius = p["turn"]
        stops = [t for i, t in enumerate(p["times"]) if i % 2 == 0]
        wait_ns = round((stops[1] - lead) * 1e9) - world.now
        if wait_ns > 0:
            yield node.sleep(wait_ns / 1e9)
        sim = notes(world).sim
        if sim is not None:
            t = sim.truth
            sim.add(Circle(t.x + dist * cos(t.yaw + bearing), t.y + dist * sin(t.yaw + bearing),
                           radius, "turn_pillar"))

    def drive():  # type: ignore[no-untyped-def]
        for at, source, target, data in plan:
            wait_ns = round(at * 1e9) - world.now  # the plan is in s, world.now in ns
            if wait_ns > 0:
                yield node.sleep(wait_ns / 1e9)
            rec = CallRecord(source, world.now, target, data)
            records.append(rec)
            try:
                resp = yield ServiceProxy(node, target, setbool).call(data, timeout=0.5)
                rec.success, rec.message = bool(resp.success), str(resp.message)[:200]
            except ServiceException as exc:
                rec.error = str(exc)[:300]
            rec.done_ns = world.now

    node.process(drive())
    if "turn" in p:
        node.process(turn())


def _configured_name(world: Any) -> str:
    n = notes(world)
    if n.plan is None or not n.student_nodes:
        return ""
    value = n.plan.params.get(n.student_nodes[0].full_name + "/" + PARAM)
    return value if isinstance(value, str) else ""


@dataclass(frozen=True)
class _Ex4a(CourseExercise):
    def student_scripts(self, world: Any, scenario: Scenario,
                        submission: Path) -> list[tuple[str, list[str]]]:
        scripts = super().student_scripts(world, scenario, submission)
        path = submission / SCRIPT
        text = path.read_text(errors="replace")[:20_000] if path.is_file() else ""
        configured = _configured_name(world) or "/emergency_stop"
        _start_driver(world, scenario, parse_script(text), configured)
        return scripts


# -- facts ----------------------------------------------------------------------------------------

def _calls(facts: Facts, script: bool) -> list[CallRecord]:
    recs = getattr(facts.world, "_ddes_estop_calls", [])
    return [r for r in recs if r.source.startswith("script") == script]


def _twists(facts: Facts) -> list[tuple[int, bool]]:
    """``(t, non-zero)`` of every Twist a student node published on /cmd_vel."""
    out = []
    for t, who, m in facts.messages("/cmd_vel"):
        if who in facts.student_nodes:
            moving = any(abs(v) > 1e-9 for v in (m.linear.x, m.linear.y, m.linear.z,
                                                 m.angular.x, m.angular.y, m.angular.z))
            out.append((t, moving))
    return out


def _next_change(recs: list[CallRecord], i: int, end_ns: int) -> int:
    for r in recs[i + 1:]:
        if r.data != recs[i].data:
            return r.t_ns
    return end_ns


def _answered(r: CallRecord) -> str:
    if r.error:
        return f"{r.source}: {r.name} data={str(r.data).lower()} at t={r.t_ns / 1e9:.2f} s " \
               f"failed: {r.error}"
    if r.success is not True:
        return f"{r.source}: {r.name} data={str(r.data).lower()} at t={r.t_ns / 1e9:.2f} s " \
               f"answered success={r.success}"
    return ""


def _twist_after_stop(facts: Facts, recs: list[CallRecord], i: int) -> str:
    r = recs[i]
    end = _next_change(recs, i, int(DURATION * 1e9))
    tw = [(t, mv) for t, mv in _twists(facts) if r.t_ns <= t < end]
    zeros = [t for t, mv in tw if not mv and t <= r.t_ns + ZERO_WITHIN * 1e9]
    if not zeros:
        return (f"{r.source}: no zero Twist on /cmd_vel within {ZERO_WITHIN:g} s of the stop at "
                f"t={r.t_ns / 1e9:.2f} s")
    if zeros[0] > r.done_ns:  # "at once": published by the stop call, before it answers
        return (f"{r.source}: the stop at t={r.t_ns / 1e9:.3f} s was answered at "
                f"t={r.done_ns / 1e9:.3f} s, but the first zero Twist came only at "
                f"t={zeros[0] / 1e9:.3f} s; publish it at once, in the stop call, before it "
                "answers")
    late = [t for t, mv in tw if mv and t > r.done_ns]  # once the stop has been answered
    if late:
        m = next(m for t, who, m in facts.messages("/cmd_vel")
                 if t == late[0] and who in facts.student_nodes)
        return (f"{r.source}: a driving command (linear.x {m.linear.x:.2f} m/s, angular.z "
                f"{m.angular.z:.2f} rad/s) at t={late[0] / 1e9:.2f} s after the stop at "
                f"t={r.t_ns / 1e9:.2f} s and before any resume")
    return ""


def _twist_after_resume(facts: Facts, r: CallRecord) -> str:
    if any(mv and r.t_ns <= t <= r.t_ns + RESUME_WITHIN * 1e9 for t, mv in _twists(facts)):
        return ""
    return (f"{r.source}: no non-zero Twist on /cmd_vel within {RESUME_WITHIN:g} s of the resume "
            f"at t={r.t_ns / 1e9:.2f} s")


def _stops(facts: Facts, recs: list[CallRecord], i: int) -> str:
    sim = notes(facts.world).sim
    if sim is None:
        return "the simulator did not start"
    r = recs[i]
    failed = _answered(r)
    if failed:  # a robot that stops by itself (at the pillar) was not stopped by the service
        return failed
    end = _next_change(recs, i, int(DURATION * 1e9))
    h = sim.history()
    before = [abs(v) for t, v in zip(h.t_ns, h.v) if t <= r.t_ns]
    if not before or before[-1] < 0.2:
        return (f"{r.source}: the robot was not driving when it was stopped at "
                f"t={r.t_ns / 1e9:.2f} s (nothing to stop)")
    settle = r.t_ns + int(STOP_WITHIN * 1e9)
    after = [(t, abs(v)) for t, v in zip(h.t_ns, h.v) if settle <= t < end]
    fast = [(t, v) for t, v in after if v >= STOP_SPEED]
    if fast:
        t, v = fast[0]
        return (f"{r.source}: true speed {v:.2f} m/s at t={t / 1e9:.2f} s, {STOP_WITHIN:g} s or "
                f"more after the stop at t={r.t_ns / 1e9:.2f} s (below {STOP_SPEED} m/s wanted)")
    turning = [(t, abs(w)) for t, w in zip(h.t_ns, h.w)
               if settle <= t < end and abs(w) >= STOP_TURN]
    if turning:
        t, w = turning[0]
        return (f"{r.source}: at t={t / 1e9:.2f} s, {STOP_WITHIN:g} s or more after the stop at "
                f"t={r.t_ns / 1e9:.2f} s, the robot was still turning at {w:.2f} rad/s (below "
                f"{STOP_TURN} rad/s wanted)")
    return ""


def _moves(facts: Facts, r: CallRecord) -> str:
    sim = notes(facts.world).sim
    if sim is None:
        return "the simulator did not start"
    failed = _answered(r)
    if failed:  # a robot that never stopped was not started by the service
        return failed
    h = sim.history()
    pts = [(x, y) for t, x, y in zip(h.t_ns, h.x, h.y)
           if r.t_ns <= t <= r.t_ns + MOVE_WITHIN * 1e9]
    moved = math.hypot(pts[-1][0] - pts[0][0], pts[-1][1] - pts[0][1]) if pts else 0.0
    if moved >= MOVE_DIST:
        return ""
    return (f"{r.source}: the robot moved {moved:.2f} m in the {MOVE_WITHIN:g} s after the resume "
            f"at t={r.t_ns / 1e9:.2f} s (at least {MOVE_DIST} m wanted)")


def _share(items: list[str], n: int) -> float:
    return (n - len([x for x in items if x])) / n if n else 0.0


# -- the course's class rule (part of 4a.1's "service exists" share) ------------------------------

NODE_SCRIPT = f"{PKG}/scripts/{NODE_TYPE}"


def _class_rule(facts: Facts) -> str:
    """Why the node script breaks the course's rule "logic in the class" for the stop (empty
    when it keeps it): read with :mod:`ast`, never imported.  The class (defined in the script
    or imported from the package) advertises the Service with one of its methods as the
    handler, and reads a parameter; the main part builds the class and advertises no Service
    itself; the node read its private ``~stop_service_name`` (a fact of the run, in any
    spelling of the name)."""
    node = student_script(facts, NODE_SCRIPT)
    if node is None:
        return f"{NODE_SCRIPT} is missing or does not parse"
    if not node.classes or not node.built:
        return "the node script does not define (or import) a class and build it in its main part"
    if "Service" in node.main_called():
        return "the main part advertises the Service; keep all logic in the class"
    calls = node.class_calls()
    services = [(src, c, m) for src, c, m in calls if src.called(c) == "Service"]
    for src, c, method in services:
        # self.cb, functools.partial(self.cb, ...), lambda req: self.cb(req), a name holding one
        if not bound_to_self(src, argument(c, 2, "handler"), method):
            return "the class's Service must have one of its methods as the handler " \
                   "(self.stop_callback)"
    if not services:
        return "the class advertises no Service"
    if not (read_private(facts, PARAM) and any(src.called(c) in PARAM_CALLS
                                               for src, c, _m in calls)):
        return f"the class does not read the private parameter ~{PARAM}"
    return ""

# -- 4a.1 / 4a.3 / 4a.4 / 4a.6: the grader's calls ------------------------------------------------

def check_stop(facts: Facts) -> tuple[float, list[str]]:
    why = launch_problem(facts)
    if why:
        return 0.0, [why]
    recs = _calls(facts, script=False)
    name = recs[0].name if recs else ""
    entry = facts.world.master.lookup_service(name)
    points, lines = 0.0, []
    rule = _class_rule(facts)
    if entry is None or entry.type != SETBOOL or entry.node.name not in facts.student_nodes:
        lines.append(f"no {SETBOOL} service of your node under {name} (the name the hidden "
                     f"parameter {PARAM} gives)" if facts.scenario.hidden else
                     f"no {SETBOOL} service of your node under {name} (your {PARAM})")
    elif rule:
        lines.append(f"the service works, but the course's rule 'logic in the class' is broken: "
                     f"{rule}")
    else:
        points += 5
    stops = [i for i, r in enumerate(recs) if r.data]
    answered = [_answered(recs[i]) for i in stops]
    points += 5 * _share(answered, len(stops))
    twist = [_twist_after_stop(facts, recs, i) if not _answered(recs[i]) else "not answered"
             for i in stops]
    points += 10 * _share(twist, len(stops))
    return points, [*lines, *[x for x in answered + twist if x and x != "not answered"]]


def check_robot_stops(facts: Facts) -> tuple[float, list[str]]:
    why = launch_problem(facts)
    if why:
        return 0.0, [why]
    recs = _calls(facts, script=False)
    stops = [i for i, r in enumerate(recs) if r.data]
    got = [_stops(facts, recs, i) for i in stops]
    return 10 * _share(got, len(stops)), [x for x in got if x]


def check_start(facts: Facts) -> tuple[float, list[str]]:
    why = launch_problem(facts)
    if why:
        return 0.0, [why]
    recs = [r for r in _calls(facts, script=False) if not r.data]
    answered = [_answered(r) for r in recs]
    twist = [_answered(r) or _twist_after_resume(facts, r) for r in recs]
    return (10 * _share(answered, len(recs)) + 10 * _share(twist, len(recs)),
            list(dict.fromkeys(x for x in answered + twist if x)))


def check_robot_starts(facts: Facts) -> tuple[float, list[str]]:
    why = launch_problem(facts)
    if why:
        return 0.0, [why]
    recs = [r for r in _calls(facts, script=False) if not r.data]
    got = [_moves(facts, r) for r in recs]
    return 10 * _share(got, len(recs)), [x for x in got if x]


# -- 4a.2 / 4a.5: the console script --------------------------------------------------------------

def _script_check(facts: Facts, stop: bool) -> tuple[float, list[str]]:
    text = facts.read_text(SCRIPT)
    if text is None:
        return 0.0, [f"{SCRIPT} is missing"]
    parsed = parse_script(text)
    bad = [f"{SCRIPT}:{x.number}: {x.error}" for x in parsed if x.error]
    configured = _configured_name(facts.world) or "/emergency_stop"
    word = "true" if stop else "false"
    mine = [x for x in parsed if not x.error and x.data is stop]
    lines = list(bad)
    points = 0.0
    if mine and not bad and all(x.name == configured for x in mine):
        points += 10
    elif not mine:
        lines.append(f"{SCRIPT} has no well-formed 'rosservice call {configured} \"data: {word}\"'")
    elif not bad:
        lines.append(f"{SCRIPT}:{mine[0].number} calls {mine[0].name}, not the {PARAM} of your "
                     f"parameter file ({configured})")
    recs = _calls(facts, script=True)
    recs_all = recs
    mine_recs = [i for i, r in enumerate(recs_all) if r.data is stop]
    if not mine_recs:
        return points, lines
    results = []
    for i in mine_recs:
        r = recs_all[i]
        why = _answered(r) or (_stops(facts, recs_all, i) if stop else _moves(facts, r))
        results.append(why)
    points += 10 * _share(results, len(results))
    return points, [*lines, *[x for x in results if x]]


def check_script_stop(facts: Facts) -> tuple[float, list[str]]:
    why = launch_problem(facts)
    return (0.0, [why]) if why else _script_check(facts, stop=True)


def check_script_start(facts: Facts) -> tuple[float, list[str]]:
    why = launch_problem(facts)
    return (0.0, [why]) if why else _script_check(facts, stop=False)


EX4A = _Ex4a(
    id="ex4a_services",
    title="A SetBool emergency stop in the controller, called from a console script",
    criteria=(
        Criterion("4a.1", "stop implemented: the SetBool service under the parameter's name, "
                  "advertised by the class, answers success, a zero Twist follows each stop at once and the controller "
                  "stays quiet", 20, check_stop, credit=CREDIT),
        Criterion("4a.2", "stop called correctly: the console script's 'rosservice call ... "
                  "\"data: true\"' is well-formed and stops the robot", 20, check_script_stop,
                  credit=CREDIT),
        Criterion("4a.3", "the robot actually stops (true speed below 0.05 m/s and turn rate "
                  "below 0.05 rad/s within 1 s)", 10,
                  check_robot_stops, credit=CREDIT),
        Criterion("4a.4", "start implemented: data false answers success and the controller "
                  "drives again at once", 20, check_start, credit=CREDIT),
        Criterion("4a.5", "start called correctly: the script's '\"data: false\"' call is "
                  "well-formed and the robot drives again", 20, check_script_start,
                  credit=CREDIT),
        Criterion("4a.6", "the robot actually starts (0.3 m within 2 s)", 10,
                  check_robot_starts, credit=CREDIT),
    ),
    scripts=(),
    duration=DURATION,
    scenarios=scenarios,
    required_files=(LAUNCH, SCRIPT),
    launch=LAUNCH,
    setup=setup,
)
