"""Exercise 1: the simulator, teleop from source, console tools and a launch file (after ETH
Zurich, Programming for Robotics, exercise 1: teleop built from source 40 %, launch file works
60 %; here scaled to 32 and 48 points, and 20 points for the console answers the sheet asks
for).  See ``solutions/ex1_console/README.md``.

Every check reads facts of the trusted world: the student's launch file as :mod:`ddes.launch`
read it (the world argument, which package the teleop node comes from), the trusted master
(who publishes and subscribes what), the messages recorded there, and the simulator's ground
truth.  The grader types the keys itself: a node of its own publishes a key script on the
teleop node's ``~keys`` topic (std_msgs/String, one key per character).  Hidden scenarios
draw the key script (drive key, speed key, key rate, how long, stop key) and the world (a room
with pillars, another heading) from the scenario seed.
"""

from __future__ import annotations

import math
from typing import Any

import yaml

from ddes.errors import DdesError
from ddes.grading.course import CourseExercise, hidden_random, notes
from ddes.grading.exercise import Criterion, Facts, Scenario
from ddes.graph.yamlsafe import load_yaml

__all__ = ["EX1", "key_script"]

LAUNCH = "smb_common/launch/smb_teleop.launch"
ANSWERS = "answers.yaml"
TELEOP_PKG = "teleop_twist_keyboard"
TELEOP_TYPE = "teleop_twist_keyboard.py"
CREDIT = "after ETH Zurich, Programming for Robotics, exercise 1"
DURATION = 6.0
KEYS_START = 1.0
#: The robot must cover this much ground (true path) while the keys drive it, and be slower
#: than STOP_SPEED from STOP_AFTER seconds after the stop key to the end.
MIN_PATH = 1.0
STOP_SPEED = 0.05
STOP_AFTER = 1.0
#: A reply of the teleop to a key counts within this many nanoseconds of the key.
REPLY_NS = 200_000_000
RATE_TOL = 0.05
DEFAULT_WORLDS = ("", "empty")
QUESTIONS = ("laser_topic", "cmd_vel_type", "odom_publisher", "imu_topic", "scan_rate_hz")


# -- scenarios and the key script -----------------------------------------------------------------

def key_script(params: dict[str, Any]) -> list[tuple[int, str]]:
    """``(t_ns, text)`` the grader publishes on ``~keys``: the speed keys with the first drive
    key at ``KEYS_START``, the drive key at ``rate`` Hz for ``drive_s`` seconds, then the stop
    key."""
    start = round(KEYS_START * 1e9)
    period = round(1e9 / params["rate"])
    n = round(params["drive_s"] * params["rate"])
    keys = [(start + i * period, params["drive"]) for i in range(n)]
    keys[0] = (start, params["prefix"] + params["drive"])
    keys.append((_stop_ns(params), params["stop"]))
    return keys


def _stop_ns(params: dict[str, Any]) -> int:
    return round((KEYS_START + params["drive_s"]) * 1e9)


def _room(rng: Any) -> tuple[str, float]:
    """A hidden world: a room of four walls (at least 3 m from the robot) with two pillars
    (at least 2.8 m away), and the robot's heading."""
    hx, hy = round(rng.uniform(3.5, 5.0), 3), round(rng.uniform(3.0, 4.0), 3)
    obstacles: list[dict[str, Any]] = [
        {"type": "segment", "name": "wall_north", "x1": -hx, "y1": hy, "x2": hx, "y2": hy},
        {"type": "segment", "name": "wall_west", "x1": -hx, "y1": -hy, "x2": -hx, "y2": hy},
        {"type": "segment", "name": "wall_south", "x1": hx, "y1": -hy, "x2": -hx, "y2": -hy},
        {"type": "segment", "name": "wall_east", "x1": hx, "y1": hy, "x2": hx, "y2": -hy},
    ]
    for k in range(2):
        while True:
            px = round(rng.uniform(-hx + 0.6, hx - 0.6), 3)
            py = round(rng.uniform(-hy + 0.6, hy - 0.6), 3)
            if math.hypot(px, py) >= 2.8:
                break
        obstacles.append({"type": "circle", "name": f"pillar_{k}", "x": px, "y": py,
                          "radius": round(rng.uniform(0.1, 0.3), 3)})
    text = yaml.safe_dump({"name": "hidden_room", "obstacles": obstacles}, sort_keys=False)
    return text, round(rng.uniform(-3.0, 3.0), 3)


def scenarios(seed: int, public: bool) -> list[Scenario]:
    out = [Scenario("public", seed, params={
        "drive": "i", "prefix": "", "rate": 20, "drive_s": 3.0, "stop": "k",
        "after_launch": start_keys})]
    for i in range(2):
        rng = hidden_random(f"ex1_console/{i}", seed)
        world, yaw = _room(rng)
        out.append(Scenario(f"hidden-{i + 1}", seed, hidden=True, params={
            "drive": rng.choice(["i", "u", "o", "I"]), "prefix": rng.choice(["", "q", "w", "e"]),
            "rate": rng.choice([10, 16, 20]), "drive_s": rng.choice([3.0, 3.25, 3.5]),
            "stop": rng.choice(["k", " ", "s", "g"]), "world_yaml": world, "yaw": yaw,
            "after_launch": start_keys}))
    return out


def setup(world: Any, scenario: Scenario) -> tuple[dict[str, Any], dict[str, Any], dict[str, Any]]:
    p = scenario.params
    if "world_yaml" in p:  # a hidden room and heading instead of the student's world
        return {}, {"world_yaml": p["world_yaml"], "x": 0.0, "y": 0.0, "yaw": p["yaw"]}, {}
    return {}, {}, {}


def start_keys(world: Any, scenario: Scenario) -> None:
    """After the launch: the grader's typist publishes the key script on the teleop's ``~keys``
    (the launch's teleop node, the student's or a bundled one; its default name otherwise)."""
    import ddes
    from ddes.kernel.events import post
    from ddes.msg import get_message_class

    spec = _teleop_spec(world)
    topic = (spec.full_name if spec is not None else "/" + TELEOP_PKG) + "/keys"
    string = get_message_class("std_msgs/String")
    node = world.create_node("/grader_keys", disable_rosout=True)
    pub = ddes.Publisher(node, topic, string, queue_size=100)
    for t_ns, text in key_script(scenario.params):
        post(world.env, t_ns - world.now, text,
             lambda ev: pub.publish(string(data=ev.payload)))


# -- facts shared by the checks ---------------------------------------------------------------------

def _teleop_spec(world: Any) -> Any:
    """The launch's teleop node (type teleop_twist_keyboard.py), or None."""
    n = notes(world)
    if n.plan is None:
        return None
    for spec in n.plan.nodes:
        if spec.type == TELEOP_TYPE:
            return spec
    return None


def _publications(facts: Facts, node: str, type_: str) -> list[str]:
    return [topic for topic, entry in sorted(facts.world.master.topics.items())
            if entry.type == type_ and any(p.node.name == node for p in entry.publishers)]


def _sim_cmd_topic(facts: Facts) -> str | None:
    sim = notes(facts.world).sim
    if sim is None:
        return None
    for topic, entry in sorted(facts.world.master.topics.items()):
        if entry.type == "geometry_msgs/Twist" and any(
                s.node.name == sim.node.name for s in entry.subscribers):
            return topic
    return None


def _no_launch(facts: Facts) -> str:
    n = notes(facts.world)
    return n.error or ("" if n.plan is not None else "the launch file was not read")


# -- 1.1 teleop from source ---------------------------------------------------------------------------

def check_from_source(facts: Facts) -> tuple[float, list[str]]:
    why = _no_launch(facts)
    if why:
        return 0.0, [why]
    spec = _teleop_spec(facts.world)
    if spec is None:
        return 0.0, [f"{LAUNCH} starts no node of type {TELEOP_TYPE}"]
    n = notes(facts.world)
    if spec not in n.student_nodes:
        where = "a package of your submission" if spec in n.trusted_nodes else "anywhere"
        return 0.0, [f"the launch's {TELEOP_TYPE} comes from package {spec.pkg!r}, which is not "
                     f"{where}: put the source copy in your workspace "
                     f"({TELEOP_PKG}/scripts/{TELEOP_TYPE}) so it overlays the installed one"]
    points = 16.0
    lines: list[str] = []
    name = spec.full_name
    if name not in facts.student_nodes:
        return points, lines + [f"your teleop node {name} never came up in the sandbox "
                                f"({facts.outcome.state}: {facts.outcome.reason})"]
    p = facts.scenario.params
    twists = [(t, m) for topic in _publications(facts, name, "geometry_msgs/Twist")
              for t, _who, m in facts.messages(topic, publisher=name)]
    start, stop = round(KEYS_START * 1e9), _stop_ns(p)
    drove = any(start <= t <= start + REPLY_NS and m.linear.x > 0 for t, m in twists)
    halted = any(stop <= t <= stop + REPLY_NS and _is_zero(m) for t, m in twists)
    if drove and halted:
        return points + 16.0, lines
    if not twists:
        return points, [f"your teleop node {name} published no geometry_msgs/Twist"]
    if not drove:
        lines.append(f"no forward twist (linear.x > 0) within 0.2 s of the key {p['drive']!r} "
                     f"at t={KEYS_START:.2f} s")
    if not halted:
        lines.append(f"no zero twist within 0.2 s of the stop key {p['stop']!r} at "
                     f"t={stop / 1e9:.2f} s")
    return points, lines


def _is_zero(m: Any) -> bool:
    return (m.linear.x, m.linear.y, m.linear.z, m.angular.x, m.angular.y, m.angular.z) == \
        (0, 0, 0, 0, 0, 0)


# -- 1.2 the launch file works ---------------------------------------------------------------------------

def _world_argument(facts: Facts) -> tuple[str | None, str]:
    n = notes(facts.world)
    assert n.plan is not None
    for spec in n.plan.nodes:
        if spec.pkg == "ddes_sim" and spec.type == "simulator":
            prefix = spec.full_name + "/"
            value = n.plan.params.get(prefix + "world_file") or n.plan.params.get(
                prefix + "world", "empty")
            return str(value), ""
    return None, f"{LAUNCH} does not start the simulator (include ddes_sim.launch)"


def check_launch(facts: Facts) -> tuple[float, list[str]]:
    why = _no_launch(facts)
    if why:
        return 0.0, [why]
    n = notes(facts.world)
    points, lines = 0.0, []
    world, why = _world_argument(facts)
    if world is None:
        return 0.0, [why]
    sim = n.sim
    if sim is None:
        return 0.0, [f"the simulator did not start: {'; '.join(n.problems) or 'unknown'}"]
    if world in DEFAULT_WORLDS:
        lines.append(f"the simulator runs the default world {world or 'empty'!r}: give the "
                     "include another one (<arg name=\"world\" value=\"...\"/>)")
    elif not _world_loads(world):
        lines.append(f"the world {world!r} does not load")
    else:
        points += 12
    spec = _teleop_spec(facts.world)
    cmd = _sim_cmd_topic(facts)
    if spec is None:
        return points, [*lines, f"{LAUNCH} starts no node of type {TELEOP_TYPE}"]
    teleop_topics = _publications(facts, spec.full_name, "geometry_msgs/Twist")
    if cmd is not None and cmd in teleop_topics:
        points += 12
    else:
        lines.append(f"the teleop node {spec.full_name} publishes Twists on "
                     f"{', '.join(teleop_topics) or 'no topic'}; the simulator listens on {cmd}")
    p = facts.scenario.params
    start, stop = round(KEYS_START * 1e9), _stop_ns(p)
    h = sim.history()
    path = 0.0
    for i in range(1, len(h.t_ns)):
        if start < h.t_ns[i] <= stop:
            path += math.hypot(h.x[i] - h.x[i - 1], h.y[i] - h.y[i - 1])
    if path >= MIN_PATH:
        points += 12
    else:
        lines.append(f"the keys moved the robot {path:.2f} m (true path from t={start / 1e9:.2f} s "
                     f"to the stop key at t={stop / 1e9:.2f} s); at least {MIN_PATH:.1f} m needed")
    after = [abs(v) for t, v in zip(h.t_ns, h.v) if t >= stop + round(STOP_AFTER * 1e9)]
    last = [m for t, _who, m in (facts.messages(cmd, publisher=spec.full_name) if cmd else [])
            if t >= stop]
    if path < MIN_PATH / 2:
        lines.append("the stop key cannot be checked: the robot hardly moved")
    elif after and max(after) < STOP_SPEED and last and _is_zero(last[-1]):
        points += 12
    else:
        fast = max(after) if after else math.nan
        lines.append(f"after the stop key {p['stop']!r}: the robot's top speed from "
                     f"{STOP_AFTER:.0f} s later was {fast:.2f} m/s, the teleop's last command "
                     f"{'zero' if last and _is_zero(last[-1]) else 'not zero' if last else 'missing'}")
    return points, lines


def _world_loads(world: str) -> bool:
    from ddes.errors import DdesError
    from ddes.sim import WorldSpec

    try:
        WorldSpec.load(world)
    except (DdesError, ValueError, OSError):
        return False
    return True


# -- 1.3 console answers --------------------------------------------------------------------------------

def _facts_for_answers(facts: Facts) -> dict[str, tuple[str, Any]]:
    """What each question's answer must be: ``(kind, expected)``."""
    sim = notes(facts.world).sim
    assert sim is not None
    me = sim.node.name
    topics = facts.world.master.topics
    laser = _publications(facts, me, "sensor_msgs/LaserScan")
    imu = _publications(facts, me, "sensor_msgs/Imu")
    cmd = topics.get("/cmd_vel")
    odom = topics.get("/odom")
    stamps = [t for t, _who, _m in facts.messages(laser[0], publisher=me)] if laser else []
    rate = (len(stamps) - 1) * 1e9 / (stamps[-1] - stamps[0]) if len(stamps) > 2 else None
    return {
        "laser_topic": ("names", laser),
        "cmd_vel_type": ("type", [cmd.type] if cmd is not None else []),
        "odom_publisher": ("names", sorted(p.node.name for p in odom.publishers)
                           if odom is not None else []),
        "imu_topic": ("names", imu),
        "scan_rate_hz": ("rate", rate),
    }


def _name(value: Any) -> str:
    text = str(value).strip()
    return text if text.startswith("/") else "/" + text


def check_answers(facts: Facts) -> tuple[float, list[str]]:
    text = facts.read_text(ANSWERS, limit=65536)
    if text is None:
        return 0.0, [f"{ANSWERS} is missing"]
    try:
        answers = load_yaml(text)
    except (yaml.YAMLError, DdesError) as exc:  # malformed, or past the loader's bounds
        return 0.0, [f"{ANSWERS} is not YAML: {str(exc)[:120]}"]
    if not isinstance(answers, dict):
        return 0.0, [f"{ANSWERS} must map each question to its answer ({', '.join(QUESTIONS)})"]
    if notes(facts.world).sim is None:
        return 0.0, ["the answers cannot be checked: your launch file started no simulator"]
    expected = _facts_for_answers(facts)
    points, lines = 0.0, []
    for q in QUESTIONS:
        given = answers.get(q)
        kind, want = expected[q]
        if given is None or isinstance(given, (dict, list)):
            lines.append(f"{q}: no answer")
            continue
        if kind == "names":
            ok = bool(want) and _name(given) in want
        elif kind == "type":
            ok = bool(want) and str(given).strip() in want
        else:
            ok = (want is not None and isinstance(given, (int, float))
                  and not isinstance(given, bool) and abs(given - want) <= RATE_TOL * want)
        if ok:
            points += 4
        else:
            lines.append(f"{q}: {given!r} is not what the running system shows")
    return points, lines


EX1 = CourseExercise(
    id="ex1_console",
    title="The simulator, teleop from source, console tools and a launch file",
    criteria=(
        Criterion("1.1", "teleop_twist_keyboard runs from the source in your workspace and "
                  "turns keys into twists", 32, check_from_source, credit=CREDIT),
        Criterion("1.2", "the launch file brings up a non-default world and the teleop, and the "
                  "keys drive and stop the robot", 48, check_launch, credit=CREDIT),
        Criterion("1.3", "console tools: the answers match the running system", 20,
                  check_answers, credit=CREDIT),
    ),
    scripts=(),
    duration=DURATION,
    scenarios=scenarios,
    required_files=(LAUNCH, ANSWERS),
    launch=LAUNCH,
    setup=setup,
)
