"""Exercise 2: a package with a laser subscriber and parameters (after ETH Zurich, Programming
for Robotics, exercise 2: changing laser output 40 %, template structure 30 %, parameter file
15 %, RViz 15 %).  See ``solutions/ex2_package/README.md``."""

from __future__ import annotations

import ast
import math
import xml.etree.ElementTree as ET
from typing import Any

import yaml

from ddes.errors import DdesError
from ddes.grading.course import (
    CourseExercise,
    find_package,
    hidden_random,
    min_valid_range,
    notes,
    parse_source,
    rviz_displays,
)
from ddes.grading.exercise import Criterion, Facts, Scenario
from ddes.grading.exercises.common import (
    NUMBER,
    add_driver,
    argument,
    bound_to_self,
    call_name,
    launch_problem,
    rospy_subscribers,
    student_logs,
    student_script,
    student_subscriptions,
)
from ddes.graph.yamlsafe import load_yaml

__all__ = ["EX2"]

PKG = "smb_highlevel_controller"
LAUNCH = f"{PKG}/launch/{PKG}.launch"
NODE_TYPE = f"{PKG}_node.py"
ALGORITHM = f"{PKG}/src/{PKG}/algorithm.py"
CREDIT = "after ETH Zurich, Programming for Robotics, exercise 2"
DURATION = 8.0


def scenarios(seed: int, public: bool) -> list[Scenario]:
    out = [Scenario("public", seed, params={"yaw": 0.0, "turn": 0.5})]
    for i in range(2):
        rng = hidden_random(f"ex2_package/{i}", seed)
        params = {
            "yaw": round(rng.uniform(-3.0, 3.0), 3), "turn": rng.choice([-0.6, -0.4, 0.4, 0.6]),
            "scan_topic": f"/scan_{rng.getrandbits(24):06x}", "queue_size": rng.randint(1, 9)}
        if i == 1:  # the node in a namespace of its own: private names follow it, absolute don't
            params["node_namespaces"] = {NODE_TYPE: f"/robot_{rng.getrandbits(16):04x}"}
        out.append(Scenario(f"hidden-{i + 1}", seed, hidden=True, params=params))
    return out


def build(world: Any, scenario: Scenario) -> None:
    turn = scenario.params["turn"]
    add_driver(world, [(3.0, 0.0, turn), (5.0, 0.4, 0.0), (DURATION, 0.0, -turn)])


def setup(world: Any, scenario: Scenario) -> tuple[dict[str, Any], dict[str, Any], dict[str, Any]]:
    p = scenario.params
    overrides: dict[str, Any] = {}
    remaps: dict[str, Any] = {}
    if "scan_topic" in p:   # a hidden YAML loaded after the student's, and the laser moved there
        overrides[NODE_TYPE] = {"scan_topic": p["scan_topic"], "queue_size": p["queue_size"]}
        remaps["simulator"] = {"scan": p["scan_topic"]}
    return overrides, {"yaw": p["yaw"], "world": "obstacle_field", "world_file": ""}, remaps


def _scan_topic(facts: Facts) -> str:
    return str(facts.scenario.params.get("scan_topic", "/scan"))


def _expected(facts: Facts) -> tuple[str, int | None, str]:
    """The topic and queue size the node must use here: the hidden overrides, or the values of
    the student's own parameter file."""
    p = facts.scenario.params
    if "scan_topic" in p:
        return p["scan_topic"], p["queue_size"], "the hidden parameter file"
    n = notes(facts.world)
    if n.plan is None or not n.student_nodes:
        return "/scan", None, "the default"
    prefix = n.student_nodes[0].full_name + "/"
    qs = n.plan.params.get(prefix + "queue_size")
    return (str(n.plan.params.get(prefix + "scan_topic", "/scan")),
            qs if isinstance(qs, int) else None, "your parameter file")


# -- 2.1 changing laser output ------------------------------------------------------------------

def _delivered_scans(facts: Facts, topic: str, sim: Any) -> list[tuple[int, Any]]:
    """The simulator's scans on ``topic`` that reached a student node (a scan published before
    the node subscribed, such as the one at t=0, cannot be logged and does not count)."""
    if sim is None:
        return []
    name = sim.node.name
    delivered = {ev.details.get("seq") for ev in facts.world.trace.select(kind="topic.deliver",
                                                                          topic=topic)
                 if ev.source in facts.student_nodes and ev.details.get("publisher") == name}
    seqs = [ev.details.get("seq") for ev in facts.world.trace.select(kind="topic.publish",
                                                                     topic=topic)
            if ev.source == name]
    scans = facts.messages(topic, publisher=name)
    return [(t, m) for (t, _who, m), seq in zip(scans, seqs) if seq in delivered]


def check_output(facts: Facts) -> tuple[float, list[str]]:
    why = launch_problem(facts)
    if why:
        return 0.0, [why]
    topic = _scan_topic(facts)
    sim = notes(facts.world).sim
    scans = _delivered_scans(facts, topic, sim)
    logs: dict[int, list[str]] = {}
    for t, _who, text in student_logs(facts):
        logs.setdefault(t, []).append(text)
    total = matched = 0
    values: set[str] = set()
    distinct: set[float] = set()
    first_miss = ""
    for t, scan in scans:
        best, _ = min_valid_range(scan)
        if not math.isfinite(best):
            continue
        total += 1
        distinct.add(best)
        ok = False
        for text in logs.get(t, []):
            m = NUMBER.search(text)
            if m is None:
                continue
            word = m.group(0)
            decimals = len(word.split(".")[1]) if "." in word and "e" not in word.lower() else 0
            if abs(float(word) - best) <= 0.5 * 10.0 ** -decimals + 1e-6:
                ok = True
                values.add(word)
                break
        if ok:
            matched += 1
        elif not first_miss:
            seen = logs.get(t, [])
            first_miss = (f"t={t / 1e9:.2f} s: smallest range {best:.3f} m on {topic}; your node "
                          f"logged {seen[0][:80]!r}" if seen else
                          f"t={t / 1e9:.2f} s: smallest range {best:.3f} m on {topic}; no log line "
                          "from your node at that instant")
    if total == 0:
        return 0.0, [f"no scan with a valid return on {topic}"]
    frac = matched / total
    lines = [f"{matched} of {total} scans logged with their smallest distance"]
    if first_miss:
        lines.append(first_miss)
    # at least 10 distinct values while driving, or as many as the scans had (a hidden world
    # where the laser sees an obstacle in a few scans only cannot show 10)
    need = min(10, len(distinct))
    if len(values) < need:
        lines.append(f"only {len(values)} distinct values printed (at least {need} while "
                     "driving)")
        return 0.0, lines
    return (40.0 if frac >= 0.95 else 40.0 * frac), lines


# -- 2.2 template structure ---------------------------------------------------------------------

def _package_xml(facts: Facts) -> tuple[bool, str]:
    text = facts.read_text(f"{PKG}/package.xml")
    if text is None:
        return False, f"{PKG}/package.xml is missing"
    if "<!DOCTYPE" in text or "<!ENTITY" in text:
        return False, "package.xml: DOCTYPE/ENTITY declarations are refused"
    try:
        root = ET.fromstring(text)
    except ET.ParseError as exc:
        return False, f"package.xml does not parse: {exc}"
    if (root.findtext("name") or "").strip() != PKG:
        return False, f"package.xml names the package {root.findtext('name')!r}, not {PKG}"
    deps = {(e.text or "").strip() for tag in ("depend", "exec_depend", "run_depend",
                                               "build_depend") for e in root.iter(tag)}
    if "sensor_msgs" not in deps:
        return False, "package.xml does not depend on sensor_msgs"
    return True, ""


def check_structure(facts: Facts) -> tuple[float, list[str]]:
    points, lines = 0.0, []
    ok, why = _package_xml(facts)
    points += 6 if ok else 0
    lines += [why] if why else []
    script = f"{PKG}/scripts/{NODE_TYPE}"
    node = student_script(facts, script)
    if node is None:
        return points, [*lines, f"{script} is missing or does not parse"]
    # the class may live in the script or in a module of the package it imports
    if node.classes and node.built:
        points += 6
    else:
        lines.append("the node script does not define (or import) a class and build it in its "
                     "main part")
    private, other = private_reads(facts)
    if private:
        points += 6
    elif other:
        lines.append(f"your node read {', '.join(other[:3])}, not a private parameter of its "
                     "own (~name, which follows the node's name and namespace)")
    else:
        lines.append("your node read no private parameter (rospy.get_param('~name'))")
    # self.cb, functools.partial(self.cb, ...), lambda msg: self.cb(msg), a name holding one
    bound = any(bound_to_self(src, argument(c, 2, "callback"), method)
                for src, c, method in rospy_subscribers(node))
    if bound:
        points += 6
    else:
        lines.append("the class creates no Subscriber whose callback is one of its methods "
                     "(self.scan_callback)")
    algo = parse_source(facts, ALGORITHM)
    if algo is None:
        lines.append(f"{ALGORITHM} is missing or does not parse")
        return points, lines
    ros = [a.name for n in ast.walk(algo) if isinstance(n, ast.Import) for a in n.names] + [
        n.module or "" for n in ast.walk(algo) if isinstance(n, ast.ImportFrom)]
    ros = [m for m in ros if m.split(".")[0] in ("rospy", "ddes", "sensor_msgs", "std_msgs",
                                                 "geometry_msgs")]
    funcs = {n.name for n in algo.body if isinstance(n, ast.FunctionDef)}
    # a call the imports resolve to algorithm.py (``from ...algorithm import f as g``,
    # ``import ...algorithm as alg; alg.f()``), or one of its functions by name
    used = any(call_name(c) in funcs or node.target_file(src, c) == ALGORITHM
               for src, c, _m in node.class_calls())
    if not ros and used:
        points += 6
    else:
        lines.append(f"algorithm.py imports ROS ({', '.join(ros)})" if ros else
                     "the class calls no function of algorithm.py")
    return points, lines


def private_reads(facts: Facts) -> tuple[list[str], list[str]]:
    """The parameters the student's node read that were set: ``(those in its own private
    namespace, the others)``, by their resolved names as the node read them from the parameter
    server (``~scan_topic``, ``rospy.get_name() + "/scan_topic"`` and ``"~" + name`` are one
    name; ``/smb_highlevel_controller/scan_topic`` is another as soon as the node runs under
    another name or namespace)."""
    private: list[str] = []
    other: list[str] = []
    nodes = set(facts.student_nodes)
    for _t, node, key, found in facts.param_reads:
        if node not in nodes or not found or key == "/use_sim_time":
            continue
        (private if key.startswith(node.rstrip("/") + "/") else other).append(key)
    return private, other


# -- 2.3 parameter file -------------------------------------------------------------------------

def check_parameters(facts: Facts) -> tuple[float, list[str]]:
    why = launch_problem(facts)
    if why:
        return 0.0, [why]
    points, lines = 0.0, []
    n = notes(facts.world)
    spec = n.student_nodes[0]
    pkg_dir = find_package(facts.submission, PKG)
    loaded = False
    if pkg_dir is not None and n.plan is not None:
        prefix = spec.full_name + "/"
        for cfg in sorted((pkg_dir / "config").glob("*.yaml")):
            try:
                data = load_yaml(cfg.read_text(encoding="utf-8")[:65536])
            except (yaml.YAMLError, DdesError):  # malformed, or past the loader's bounds
                continue
            if (isinstance(data, dict) and {"scan_topic", "queue_size"} <= set(data)
                    and all(prefix + k in n.plan.params for k in ("scan_topic", "queue_size"))):
                loaded = True
    if loaded:
        points += 5
    else:
        lines.append("the launch file loads no YAML of config/ with scan_topic and queue_size "
                     "into the node's private namespace")
    topic, qs, source = _expected(facts)
    subs = student_subscriptions(facts)
    if any(t == topic and (qs is None or q == qs) for _n, t, q in subs):
        points += 10
    else:
        have = ", ".join(f"{t} (queue {q})" for _n, t, q in subs if t != "/rosout") or "nothing"
        lines.append(f"expected a subscription to {topic} with queue size {qs} from {source}; "
                     f"your node subscribes {have}")
    return points, lines


# -- 2.4 RViz -----------------------------------------------------------------------------------

def check_rviz(facts: Facts) -> tuple[float, list[str]]:
    glob, displays, why = rviz_displays(facts)
    if glob is None:
        return 0.0, [why]
    points, lines = 0.0, []
    if glob.get("Fixed Frame") == "odom":
        points += 5
    else:
        lines.append(f"Fixed Frame is {glob.get('Fixed Frame')!r}, not 'odom'")
    scans = [d for d in displays if d.get("Class") == "rviz/LaserScan" and d.get("Enabled", True)]
    if any(d.get("Topic") == "/scan" for d in scans):
        points += 5
    else:
        lines.append("no enabled rviz/LaserScan display with Topic /scan")
    if any(isinstance(d.get("Size (m)"), (int, float)) and d.get("Size (m)") != 0.01
           for d in scans):
        points += 5
    else:
        lines.append("the LaserScan's 'Size (m)' is RViz's default 0.01 (or missing)")
    return points, lines


EX2 = CourseExercise(
    id="ex2_package",
    title="A package with a laser subscriber and parameters",
    criteria=(
        Criterion("2.1", "changing laser output: the smallest distance of every scan", 40,
                  check_output, credit=CREDIT),
        Criterion("2.2", "the node follows the template (package.xml, class, private "
                  "parameters, bound callback, ROS-free algorithm)", 30, check_structure,
                  credit=CREDIT),
        Criterion("2.3", "a parameter file sets the topic and the queue size", 15,
                  check_parameters, credit=CREDIT),
        Criterion("2.4", "RViz shows the laser scan (fixed frame odom)", 15, check_rviz,
                  credit=CREDIT),
    ),
    scripts=(),
    duration=DURATION,
    build=build,
    scenarios=scenarios,
    required_files=(LAUNCH,),
    launch=LAUNCH,
    setup=setup,
)
