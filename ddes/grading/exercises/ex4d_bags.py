"""Exercise 4d: bags, ROS time and localisation (after ETH Zurich, Programming for Robotics,
exercise 4).  See ``solutions/ex4d_bags/README.md`` and docs/localization.md.

The student writes launch files and configuration only; every node is a bundled, trusted one
(robot_localization's ``ekf_localization_node``, ``ddes_sim/robot_frames``,
``tf2_ros/static_transform_publisher``, ``rosbag play``/``record``, the simulator), started in
the grader's world from the student's launch files.  Each scenario plays a bag through
``launch/ekf_bag.launch``: the public one the kit bag (``ddes course make-bag``, seed 2021), the
two hidden ones bags regenerated from hidden drive seeds; the grader writes the scenario's bag
to ``smb_highlevel_controller/bag/smb_navigation.bag`` of the prepared submission, where the
launch's ``$(find ...)`` points.  A launch without a ``rosbag play`` node gets the grader's
(``--clock``, rate 1): only the bonus items need the student's.

Criteria (ETH's percentages; the two bonus items of 5 points count in the total, so the
reference's 110 points are 100 %):

* 4d.1 (10) ``answers.yaml`` ``ekf.subscribes`` / ``ekf.publishes`` equal what the master lists
  for the EKF node in the running launch (``rosnode info``, without ``/rosout`` and
  ``/clock``), and ``ekf.fuses`` names the states of each ``_config`` vector loaded.
* 4d.2 (10) ``bag.topics`` equals the bag's topics and types; ``bag.how`` is a
  ``rosbag info …bag`` command line.
* 4d.3 (20) ``launch/ekf_sim.launch`` run by the grader (its trusted nodes, started from the
  bundled packages; a node of any package the submission holds is left out, so nothing of the
  submission executes in the grader's process; driven by the grader for 31 s): ``sim_run.bag`` holds ``/odometry/filtered`` at the EKF's ``frequency``
  (±10 %) and exactly one node publishes odom → base_link (10); the multiplot config has a
  curve of ``/odometry/filtered`` whose x and y fields resolve to ``pose.pose.position.x``/``y``
  values on that bag (10).  Run once per grade (the public scenario's seed) and shared by the
  scenarios.
* 4d.4 (30) ``/odometry/filtered`` covers ≥ 90 % of the bag's time (15) and its last pose is
  within 0.05 m of the grader's own EKF run on the same bag (15).
* 4d.5 (10) ``rviz/ekf.rviz`` has an enabled PointCloud2 display of ``/rslidar_points``.
* 4d.6 (10) that display: ``Color Transformer: AxisColor``, ``Axis: X`` (teaching.md's
  deviation: the cloud of a 2D laser has z = 0 everywhere), ``Size (m): 0.05``.
* 4d.7 (10) the grader's TF buffer (every /tf and /tf_static message of the run) gives
  ``odom → smb_top_view`` = ``odom → base_link`` ∘ (0, 0, 2) within 1e-9 at 5 times of the bag.
* 4d.B1 (5) a ``rosbag/play`` node in ``ekf_bag.launch``; 4d.B2 (5) it plays at rate 0.5 (the
  player's ``rosbag.play`` trace record).
"""

from __future__ import annotations

import math
import shlex
import tempfile
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import yaml

from ddes.errors import DdesError
from ddes.grading.course import CourseExercise, find_package, hidden_random, notes, start_launch
from ddes.grading.exercise import Criterion, Facts, Scenario
from ddes.grading.exercises.common import add_driver
from ddes.grading.kitbag import KIT_SEED, TOPICS, ekf_track, make_bag
from ddes.graph.yamlsafe import load_yaml

__all__ = ["EX4D", "reference_final", "scenarios"]

PKG = "smb_highlevel_controller"
LAUNCH_BAG = f"{PKG}/launch/ekf_bag.launch"
LAUNCH_SIM = f"{PKG}/launch/ekf_sim.launch"
MULTIPLOT = f"{PKG}/config/xy_multiplot.xml"
RVIZ = f"{PKG}/rviz/ekf.rviz"
ANSWERS = "answers.yaml"
BAG = f"{PKG}/bag/smb_navigation.bag"
CREDIT = "after ETH Zurich, Programming for Robotics, exercise 4"
#: Kernel seconds a scenario may run: the 38 s bag at rate 0.5, and slack.
DURATION = 90.0
SIM_SECONDS = 31.0
SIM_IMU_RATE = 20.0
#: The grader's drive in the simulator run: (until_s, v, w).
SIM_DRIVE = [(1.0, 0.0, 0.0), (7.0, 0.5, 0.0), (12.0, 0.4, 0.5), (20.0, 0.6, 0.0),
             (25.0, 0.4, -0.5), (31.0, 0.5, 0.0)]
FINAL_TOLERANCE = 0.05
COVERAGE = 0.9
STATE = ("x", "y", "z", "roll", "pitch", "yaw", "vx", "vy", "vz", "vroll", "vpitch", "vyaw",
         "ax", "ay", "az")
EKF = ("robot_localization", "ekf_localization_node")
INFRASTRUCTURE = ("/rosout", "/clock")

# Per-process caches, each bounded (a batch grades many submissions in one process): the bags
# and reference ends of drive seeds, the simulator runs of (submission files, seed).
_BAGS: dict[int, tuple[bytes, float, float]] = {}  # drive seed -> (bytes, start s, end s)
_REFERENCE: dict[int, tuple[float, float]] = {}
_SIM: dict[tuple[str, int], SimRun] = {}
_CACHE_SIZE = 8


def _keep(cache: dict[Any, Any], key: Any, value: Any) -> Any:
    """Store ``value`` under ``key``, dropping the oldest entries past :data:`_CACHE_SIZE`."""
    cache[key] = value
    while len(cache) > _CACHE_SIZE:
        del cache[next(iter(cache))]
    return value


def scenarios(seed: int, public: bool) -> list[Scenario]:
    out = [Scenario("public", seed, params={"drive_seed": KIT_SEED})]
    for i in range(2):
        rng = hidden_random(f"ex4d_bags/{i}", seed)
        out.append(Scenario(f"hidden-{i + 1}", seed, hidden=True,
                            params={"drive_seed": rng.randrange(10_000, 1_000_000)}))
    return out


def _bag(drive_seed: int) -> tuple[bytes, float, float]:
    """The bag of a drive seed (made once per process: the same bytes every time)."""
    if drive_seed not in _BAGS:
        with tempfile.TemporaryDirectory(prefix="ddes-ex4d-") as tmp:
            kit = make_bag(Path(tmp) / "smb_navigation.bag", drive_seed)
            from ddes.rosbag import Bag

            with Bag(str(kit.path)) as bag:
                span = (bag.get_start_time(), bag.get_end_time())
            return _keep(_BAGS, drive_seed, (kit.path.read_bytes(), *span))
    return _BAGS[drive_seed]


def _start(world: Any, pkg: str, type_: str, **kw: Any) -> Any:
    from ddes.nodes import start_node

    return start_node(world, pkg, type_, **kw)


def reference_final(drive_seed: int) -> tuple[float, float]:
    """The last x/y of the grader's own EKF (the kit's localization.yaml, the robot's frames) on
    the bag of ``drive_seed`` (:func:`ddes.grading.kitbag.ekf_track`)."""
    if drive_seed in _REFERENCE:
        return _REFERENCE[drive_seed]
    data, _start_s, _end_s = _bag(drive_seed)
    with tempfile.TemporaryDirectory(prefix="ddes-ex4d-ref-") as tmp:
        path = Path(tmp) / "smb_navigation.bag"
        path.write_bytes(data)
        track = ekf_track(path)
    if not track:
        raise DdesError(f"the grader's reference EKF fused nothing on bag {drive_seed}")
    return _keep(_REFERENCE, drive_seed, (track[-1][1], track[-1][2]))


class _Ex4d(CourseExercise):
    def student_scripts(self, world: Any, scenario: Scenario,
                        submission: Path) -> list[tuple[str, list[str]]]:
        data, start_s, end_s = _bag(int(scenario.params["drive_seed"]))
        path = submission / BAG
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_bytes(data)
        world.log_output = False  # rosbag play's and the nodes' own lines: not the grader's output
        scripts = start_launch(world, scenario, submission, LAUNCH_BAG)
        n = notes(world)
        n.extra["bag_span"] = (start_s, end_s)
        players = [s.full_name for s in n.trusted_nodes if (s.pkg, s.type) == ("rosbag", "play")]
        if n.plan is not None and not players:
            _start(world, "rosbag", "play", name="/grader_player", argv=["--clock", str(path)])
            players = ["/grader_player"]
        n.extra["players"] = players
        return scripts


def finished(world: Any) -> bool:
    """The scenario is over once every bag player has exited."""
    players = notes(world).extra.get("players")
    if not players:
        return not notes(world).plan and world.now > 0
    return all(world.master.lookup_node(name) is None for name in players)


# -- helpers ----------------------------------------------------------------------------------------

def _answers(facts: Facts) -> tuple[dict[str, Any], str]:
    text = facts.read_text(ANSWERS)
    if text is None:
        return {}, f"{ANSWERS} is missing"
    try:
        data = load_yaml(text)
    except (yaml.YAMLError, DdesError) as exc:
        return {}, f"{ANSWERS} is not YAML: {str(exc)[:120]}"
    return (data, "") if isinstance(data, dict) else ({}, f"{ANSWERS} is not a mapping")


def _get(data: Any, *keys: str) -> Any:
    for k in keys:
        if not isinstance(data, dict):
            return None
        data = data.get(k)
    return data


def _ekf_spec(facts: Facts) -> Any:
    n = notes(facts.world)
    for spec in n.trusted_nodes:
        if (spec.pkg, spec.type) == EKF:
            return spec
    return None


def _names(value: Any) -> list[str] | None:
    if not isinstance(value, list) or not all(isinstance(v, str) for v in value):
        return None
    return sorted(v.strip() for v in value)


# -- 4d.1 -------------------------------------------------------------------------------------------

def check_ekf(facts: Facts) -> tuple[float, list[str]]:
    answers, why = _answers(facts)
    if why:
        return 0.0, [why]
    spec = _ekf_spec(facts)
    if spec is None:
        return 0.0, [f"{LAUNCH_BAG} starts no robot_localization/ekf_localization_node"]
    name = spec.full_name
    subs, pubs = [], []
    for topic, entry in sorted(facts.world.master.topics.items()):
        if topic in INFRASTRUCTURE:
            continue
        if name in entry.subscriber_nodes():
            subs.append(topic)
        if name in entry.publisher_nodes():
            pubs.append(topic)
    lines: list[str] = []
    ok = 0
    for key, truth in (("subscribes", subs), ("publishes", pubs)):
        got = _names(_get(answers, "ekf", key))
        if got == sorted(truth):
            ok += 1
        else:
            lines.append(f"ekf.{key}: {got} but rosnode info {name} lists {sorted(truth)}")
    params = facts.world.params
    fuses = _get(answers, "ekf", "fuses")
    truth_f: dict[str, list[str]] = {}
    for kind in ("odom", "imu"):
        i = 0
        while params.has_param(f"{name}/{kind}{i}"):
            config = params.get_param(f"{name}/{kind}{i}_config", [False] * 15)
            truth_f[f"{kind}{i}"] = sorted(
                STATE[k] for k, v in enumerate(config if isinstance(config, list) else [])
                if v is True and k < 15)
            i += 1
    got_f = ({k: _names(v) for k, v in fuses.items()} if isinstance(fuses, dict) else None)
    if truth_f and got_f == truth_f:
        ok += 1
    else:
        lines.append(f"ekf.fuses: {got_f} but the _config vectors loaded fuse {truth_f}")
    return 10.0 * ok / 3, lines


# -- 4d.2 -------------------------------------------------------------------------------------------

def check_bag_answer(facts: Facts) -> tuple[float, list[str]]:
    answers, why = _answers(facts)
    if why:
        return 0.0, [why]
    points, lines = 0.0, []
    topics = _get(answers, "bag", "topics")
    if isinstance(topics, dict) and {str(k): v for k, v in topics.items()} == TOPICS:
        points += 5.0
    else:
        lines.append(f"bag.topics: {topics!r} is not the bag's topic: type list")
    how = _get(answers, "bag", "how")
    try:
        words = shlex.split(how) if isinstance(how, str) else []
    except ValueError:
        words = []
    if words[:2] == ["rosbag", "info"] and any(w.endswith(".bag") for w in words[2:]):
        points += 5.0
    else:
        lines.append(f"bag.how: {how!r} is not a 'rosbag info FILE.bag' command line")
    return points, lines


# -- 4d.3: the simulator run ----------------------------------------------------------------------

@dataclass
class SimRun:
    """What the grader's run of ekf_sim.launch showed."""

    rate_ok: bool = False
    one_authority: bool = False
    why: list[str] = field(default_factory=list)
    #: (topic, field path) -> values read from sim_run.bag
    bag_values: dict[str, list[Any]] = field(default_factory=dict)


def _fingerprint(submission: Path) -> str:
    """A hash of the submission's files (the bag the grader writes left out): the simulator run
    depends on nothing else."""
    import hashlib

    h = hashlib.sha256()
    root = submission.resolve()
    for path in sorted(p for p in root.rglob("*") if p.is_file() and not p.is_symlink()):
        rel = path.relative_to(root).as_posix()
        if rel == BAG:
            continue
        h.update(rel.encode() + b"\0" + path.read_bytes() + b"\0")
    return h.hexdigest()


def _sim_run(submission: Path, seed: int) -> SimRun:
    key = (_fingerprint(submission), seed)
    if key in _SIM:
        return _SIM[key]
    out = _keep(_SIM, key, SimRun())
    from ddes.graph.world import World
    from ddes.launch import load_launch
    from ddes.rospack import RosPack

    path = submission / LAUNCH_SIM
    if not path.is_file():
        out.why.append(f"{LAUNCH_SIM} is missing")
        return out
    try:
        plan = load_launch(path, {}, RosPack([submission]), environ={})
    except (DdesError, ValueError, OSError, KeyError) as exc:
        out.why.append(f"{LAUNCH_SIM} does not load: {exc}")
        return out
    world = World(seed, wall_budget=None)
    world.log_output = False
    for k, v in plan.params.items():
        world.params.set_param(k, v)
    for spec in plan.nodes:  # the grader's scenario: no laser, the IMU at the kit bag's 20 Hz
        if (spec.pkg, spec.type) == ("ddes_sim", "simulator"):
            world.params.set_param(f"{spec.full_name}/imu_rate", SIM_IMU_RATE)
            world.params.set_param(f"{spec.full_name}/laser_enabled", False)
    frequency = 30.0
    ekf_name = ""
    with tempfile.TemporaryDirectory(prefix="ddes-ex4d-sim-") as tmp:
        trusted = RosPack([])  # bundled packages only: nothing of the submission is started
        for spec in plan.nodes:
            if spec.pkg in (PKG, "rviz") or find_package(submission, spec.pkg) is not None:
                # the student's own nodes (an E3 controller, any package of the submission) are
                # not run, here in the grader's process: the grader drives
                continue
            if (spec.pkg, spec.type) == EKF:
                ekf_name = spec.full_name
                value: Any = plan.params.get(f"{ekf_name}/frequency", 30.0)
                try:
                    frequency = float(value)
                except (TypeError, ValueError):
                    out.why.append(f"{ekf_name}/frequency {value!r} is not a number")
            try:
                _start(world, spec.pkg, spec.type, rospack=trusted, name=spec.name,
                       namespace=spec.namespace, cwd=tmp,
                       argv=[*spec.args, *(f"{a}:={b}" for a, b in spec.remappings)])
            except Exception as exc:  # noqa: BLE001 - a node the launch names that cannot start
                out.why.append(f"{spec.pkg}/{spec.type} did not start: {exc}")
        add_driver(world, SIM_DRIVE)
        try:
            world.run(until=SIM_SECONDS + 2.0)
        except DdesError as exc:
            out.why.append(f"the simulator run failed: {exc}")
            return out
        authorities = _tf_authorities(world)
        out.one_authority = len(authorities) == 1
        if not out.one_authority:
            out.why.append(f"odom -> base_link is published by {sorted(authorities) or 'nobody'}"
                           " (exactly one authority expected: the EKF; the simulator needs "
                           "publish_odom_tf false)")
        bag_path = Path(tmp) / "sim_run.bag"
        if not bag_path.is_file():
            out.why.append("ekf_sim.launch recorded no sim_run.bag")
            return out
        _read_sim_bag(bag_path, out, frequency, ekf_name)
    return out


def _tf_authorities(world: Any) -> set[str]:
    from ddes.msg import get_message_class

    tfm = get_message_class("tf2_msgs/TFMessage")
    who = set()
    for ev in world.trace.select(kind="topic.publish", topic="/tf"):
        msg = tfm.__new__(tfm)._deserialize_from(ev.details["data"])
        for t in msg.transforms:
            if (t.header.frame_id.lstrip("/"), t.child_frame_id.lstrip("/")) == ("odom",
                                                                                  "base_link"):
                who.add(ev.source)
    return who


def _read_sim_bag(path: Path, out: SimRun, frequency: float, ekf_name: str) -> None:
    from ddes.rosbag import Bag

    try:
        with Bag(str(path)) as bag:
            msgs: dict[str, list[Any]] = {}
            for topic, msg, _t in bag.read_messages():
                msgs.setdefault(topic, []).append(msg)
    except (DdesError, OSError) as exc:
        out.why.append(f"sim_run.bag does not read: {exc}")
        return
    filtered = msgs.get("/odometry/filtered", [])
    out.bag_values = {"/odometry/filtered": filtered}
    if len(filtered) < 2:
        out.why.append("sim_run.bag holds no /odometry/filtered")
        return
    stamps = [m.header.stamp.to_sec() for m in filtered]
    span = stamps[-1] - stamps[0]
    rate = (len(filtered) - 1) / span if span > 0 else 0.0
    out.rate_ok = abs(rate - frequency) <= 0.1 * frequency
    if not out.rate_ok:
        out.why.append(f"/odometry/filtered at {rate:.1f} Hz in sim_run.bag, the EKF's "
                       f"frequency is {frequency:g} Hz")


def _field(msg: Any, path: str) -> Any:
    value = msg
    for part in path.strip("/").split("/"):
        if not part or not hasattr(value, part):
            return None
        value = getattr(value, part)
    return value


def _curves(text: str) -> list[dict[str, str]]:
    """The curves of an rqt_multiplot config: ``{x_topic, x_field, y_topic, y_field}``."""
    from ddes.launch.xmltree import Element, parse_xml

    root = parse_xml(text.encode("utf-8"), MULTIPLOT)
    found: list[dict[str, str]] = []

    def child(e: Element, tag: str) -> Element | None:
        return next((c for c in e.children if c.tag == tag), None)

    def text_of(e: Element | None, tag: str) -> str:
        c = child(e, tag) if e is not None else None
        return c.text.strip() if c is not None else ""

    def walk(e: Element) -> None:
        if e.tag.startswith("curve_"):
            axes = child(e, "axes")
            curve: dict[str, str] = {}
            for axis in ("x_axis", "y_axis"):
                a = child(axes, axis) if axes is not None else None
                curve[axis[0] + "_topic"] = text_of(a, "topic")
                curve[axis[0] + "_field"] = text_of(a, "field")
            found.append(curve)
        for c in e.children:
            walk(c)

    walk(root)
    return found


def check_sim(facts: Facts) -> tuple[float, list[str]]:
    run = _sim_run(facts.submission, facts.scenario.seed)
    points = 10.0 if (run.rate_ok and run.one_authority) else 0.0
    lines = list(run.why)
    text = facts.read_text(MULTIPLOT)
    if text is None:
        return points, [*lines, f"{MULTIPLOT} is missing"]
    try:
        curves = _curves(text)
    except DdesError as exc:
        return points, [*lines, f"{MULTIPLOT} is not XML: {str(exc)[:120]}"]
    if not curves:
        return points, [*lines, f"{MULTIPLOT} has no curve"]
    for c in curves:
        if c["x_topic"] != "/odometry/filtered" or c["y_topic"] != "/odometry/filtered":
            lines.append(f"a curve plots {c['x_topic'] or '?'} / {c['y_topic'] or '?'}, not the "
                         "EKF's /odometry/filtered")
            continue
        msgs = run.bag_values.get("/odometry/filtered", [])
        xs = [_field(m, c["x_field"]) for m in msgs]
        ys = [_field(m, c["y_field"]) for m in msgs]
        truth = [(m.pose.pose.position.x, m.pose.pose.position.y) for m in msgs]
        if len(msgs) >= 2 and list(zip(xs, ys)) == truth:
            return points + 10.0, lines
        lines.append(f"the curve's fields {c['x_field']!r}, {c['y_field']!r} do not give "
                     "pose.pose.position x and y on sim_run.bag")
    return points, lines


# -- 4d.4 -------------------------------------------------------------------------------------------

def check_track(facts: Facts) -> tuple[float, list[str]]:
    start_s, end_s = notes(facts.world).extra.get("bag_span", (0.0, 0.0))
    msgs = [m for _t, _who, m in facts.messages("/odometry/filtered")]
    if not msgs:
        return 0.0, ["no /odometry/filtered while the bag played (use_sim_time and "
                     "rosbag play --clock?)"]
    stamps = [m.header.stamp.to_sec() for m in msgs]
    points, lines = 0.0, []
    covered = (max(stamps) - min(stamps)) / (end_s - start_s) if end_s > start_s else 0.0
    if covered >= COVERAGE and min(stamps) >= start_s - 1.0:
        points += 15.0
    else:
        lines.append(f"/odometry/filtered covers {100 * covered:.0f} % of the bag's "
                     f"{end_s - start_s:.1f} s (at least {100 * COVERAGE:.0f} %)")
    last = max(msgs, key=lambda m: m.header.stamp.to_nsec())
    x, y = last.pose.pose.position.x, last.pose.pose.position.y
    rx, ry = reference_final(int(facts.scenario.params["drive_seed"]))
    err = math.hypot(x - rx, y - ry)
    if err <= FINAL_TOLERANCE:
        points += 15.0
    else:
        lines.append(f"the last pose ({x:.3f}, {y:.3f}) is {err:.3f} m from the grader's EKF "
                     f"({rx:.3f}, {ry:.3f}); at most {FINAL_TOLERANCE} m")
    return points, lines


# -- 4d.5, 4d.6 -------------------------------------------------------------------------------------

def _cloud_display(facts: Facts) -> tuple[dict[str, Any] | None, str]:
    text = facts.read_text(RVIZ)
    if text is None:
        return None, f"{RVIZ} is missing"
    try:
        data = load_yaml(text)
    except (yaml.YAMLError, DdesError) as exc:
        return None, f"{RVIZ} is not YAML: {str(exc)[:120]}"
    displays: list[dict[str, Any]] = []

    def walk(items: Any) -> None:
        for d in items if isinstance(items, list) else []:
            if isinstance(d, dict):
                displays.append(d)
                walk(d.get("Displays"))

    walk(_get(data, "Visualization Manager", "Displays"))
    for d in displays:
        if d.get("Class") == "rviz/PointCloud2" and d.get("Topic") == "/rslidar_points" \
                and d.get("Enabled", True) is True:
            return d, ""
    return None, f"{RVIZ} has no enabled PointCloud2 display of /rslidar_points"


def check_cloud(facts: Facts) -> tuple[float, list[str]]:
    d, why = _cloud_display(facts)
    return (10.0, []) if d is not None else (0.0, [why])


def check_cloud_style(facts: Facts) -> tuple[float, list[str]]:
    d, why = _cloud_display(facts)
    if d is None:
        return 0.0, [why]
    points, lines = 0.0, []
    for key, want, worth in (("Color Transformer", "AxisColor", 4.0), ("Axis", "X", 3.0),
                             ("Size (m)", 0.05, 3.0)):
        got = d.get(key)
        same = (isinstance(got, (int, float)) and not isinstance(got, bool)
                and abs(got - want) < 1e-9) if isinstance(want, float) else got == want
        if same:
            points += worth
        else:
            lines.append(f"PointCloud2 '{key}': {got!r}, expected {want!r}")
    return points, lines


# -- 4d.7 -------------------------------------------------------------------------------------------

def check_top_view(facts: Facts) -> tuple[float, list[str]]:
    from ddes.tf2.buffer_core import BufferCore
    from ddes.tf2.exceptions import TransformException
    from ddes.time import Duration, Time

    buf = BufferCore(Duration(120))
    ekf_stamps: list[int] = []
    for _t, who, msg in facts.messages("/tf_static"):
        for t in msg.transforms:
            buf.set_transform_static(t, who)
    for _t, who, msg in facts.messages("/tf"):
        for t in msg.transforms:
            buf.set_transform(t, who)
            if (t.header.frame_id, t.child_frame_id) == ("odom", "base_link"):
                ekf_stamps.append(t.header.stamp.to_nsec())
    if len(ekf_stamps) < 10:
        return 0.0, ["no odom -> base_link from the EKF while the bag played"]
    picks = [ekf_stamps[(k * (len(ekf_stamps) - 1)) // 6] for k in range(1, 6)]
    for ns in picks:
        when = Time._from_ns(ns)
        try:
            top = buf.lookup_transform_core("odom", "smb_top_view", when)
            base = buf.lookup_transform_core("odom", "base_link", when)
        except TransformException as exc:
            return 0.0, [f"odom -> smb_top_view at {when.to_sec():.2f}: {exc}"]
        bt, br = base.transform.translation, base.transform.rotation
        tt, tr = top.transform.translation, top.transform.rotation
        want = (bt.x, bt.y, bt.z + 2.0, br.x, br.y, br.z, br.w)
        got = (tt.x, tt.y, tt.z, tr.x, tr.y, tr.z, tr.w)
        if any(abs(a - b) > 1e-9 for a, b in zip(got, want)):
            return 0.0, [f"odom -> smb_top_view at {when.to_sec():.2f} is "
                         f"{tuple(round(v, 4) for v in got)}, not odom -> base_link raised 2 m "
                         f"{tuple(round(v, 4) for v in want)}"]
    return 10.0, []


# -- bonus ------------------------------------------------------------------------------------------

def _player_specs(facts: Facts) -> list[Any]:
    return [s for s in notes(facts.world).trusted_nodes if (s.pkg, s.type) == ("rosbag", "play")]


def check_play_in_launch(facts: Facts) -> tuple[float, list[str]]:
    return (5.0, []) if _player_specs(facts) else (0.0, [f"{LAUNCH_BAG} has no rosbag play node"])


def check_half_speed(facts: Facts) -> tuple[float, list[str]]:
    names = {s.full_name for s in _player_specs(facts)}
    rates = [ev.details.get("rate") for ev in facts.world.trace.select(kind="rosbag.play")
             if ev.source in names]
    if not rates:
        return 0.0, ["no rosbag play node of the launch played"]
    if all(isinstance(r, float) and abs(r - 0.5) < 1e-9 for r in rates):
        return 5.0, []
    return 0.0, [f"rosbag play ran at rate {rates[0]}, not 0.5"]


EX4D = _Ex4d(
    id="ex4d_bags",
    title="Bags, ROS time and localisation: robot_localization's EKF on a bag and in the "
          "simulator",
    criteria=(
        Criterion("4d.1", "the ekf_localization_node explained: answers.yaml's topics equal "
                  "rosnode info, and the states each sensor fuses", 10, check_ekf, credit=CREDIT),
        Criterion("4d.2", "the bag's topics and types, and the rosbag info command", 10,
                  check_bag_answer, credit=CREDIT),
        Criterion("4d.3", "the simulated SMB: sim_run.bag with /odometry/filtered at the EKF's "
                  "frequency, one odom->base_link authority, and the x/y multiplot curve", 20,
                  check_sim, credit=CREDIT),
        Criterion("4d.4", "the recorded SMB: /odometry/filtered over the whole bag, ending where "
                  "the grader's EKF ends", 30, check_track, credit=CREDIT),
        Criterion("4d.5", "the point cloud in RViz", 10, check_cloud, credit=CREDIT),
        Criterion("4d.6", "AxisColor on the X axis, points of 0.05 m", 10, check_cloud_style,
                  credit=CREDIT),
        Criterion("4d.7", "smb_top_view 2 m above base_link, moving with the robot", 10,
                  check_top_view, credit=CREDIT),
        Criterion("4d.B1", "bonus: the bag played from the launch file", 5,
                  check_play_in_launch, credit=CREDIT),
        Criterion("4d.B2", "bonus: played at 50 % of the nominal speed", 5, check_half_speed,
                  credit=CREDIT),
    ),
    scripts=(),
    duration=DURATION,
    scenarios=scenarios,
    required_files=(LAUNCH_BAG, LAUNCH_SIM, MULTIPLOT, RVIZ, ANSWERS),
    finished=finished,
    launch=LAUNCH_BAG,
)
