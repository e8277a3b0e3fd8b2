"""The picture of a replayed scenario (``ddes grade replay --picture FILE``): what its criteria
judged, drawn from the trusted world after the run.

:func:`replay_picture` builds one :class:`~ddes.display.figure.DisplayFigure` per replay:

* **a map** on the left when the exercise runs the simulator: its top view at the end of the
  run (:func:`ddes.sim.view.top_view`: the world and its pillars, the robot's true path, the
  last scan, collisions, the student's markers), with what the exercise adds on it (exercise
  4b: each goal's path, in the world frame);  exercise 4d, which has no simulator, draws the
  tracks of its bag in ``odom`` instead;
* **time panels** on the right, one above the other over the same simulated time: the exercise's
  own (the goal timeline of exercise 4b, with the cancel and the newer goal; the speed with the
  e-stop calls of 4a and 5; the closest range of exercise 2; ...), and, last, the **topic
  rates** the criteria count (messages per second of simulated time, in windows of
  :data:`WINDOW_S`, with the rate a criterion asks for as a dotted line).

What each course exercise's criteria judge decides its panels (:data:`PLANS`, by exercise id);
an instructor's exercise gets the map when it runs a simulator and the rates of every topic its
student's nodes published on.  Goal timelines reuse :func:`ddes.actionlib.plot_goals`: the
student's action server runs in the sandbox, so its ``action.server.*`` trace events are not in
the trusted world; :func:`wire_goal_events` rebuilds them from what crossed the bridge (the
goals and cancels sent, the status arrays, feedback and results the server published), as the
server's own trace would say them.  Every axis is labelled with its unit.  Drawing reads the
world only: the digest of the replay is the grade's.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass, field
from typing import Any

from ddes.grading.exercise import Exercise, Facts, Scenario
from ddes.graph.world import World
from ddes.kernel.trace import TraceEvent

__all__ = ["PLANS", "WINDOW_S", "Panel", "Plan", "Scene", "replay_picture", "topic_rates",
           "wire_goal_events"]

#: Rates are counted in windows of this many simulated seconds.
WINDOW_S = 1.0
SEC = 1_000_000_000
_TIME = "simulated time [s]"
#: The rate rows' line styles (two topics at the same rate stay apart).
_STYLES = ("-", "--", "-.")


@dataclass
class Scene:
    """What a picture is drawn from: the replayed scenario's trusted world and its facts."""

    exercise: Exercise
    scenario: Scenario
    world: World
    facts: Facts
    sim: Any = None  # the first simulator of the world, or None

    @property
    def end_s(self) -> float:
        return max(self.world.now / SEC, WINDOW_S)

    @property
    def students(self) -> set[str]:
        return set(self.facts.student_nodes)

    def times(self, topic: str, publishers: Iterable[str] | None = None) -> list[int]:
        """The publish times (ns) of ``topic`` in the world, by ``publishers`` if given."""
        who = None if publishers is None else set(publishers)
        return [ev.t for ev in self.world.trace.select(kind="topic.publish", topic=topic)
                if who is None or ev.source in who]

    def published_by_students(self) -> list[str]:
        """The topics the student's nodes published on (``/rosout`` last), sorted."""
        found = sorted({ev.details["topic"] for ev in self.world.trace.select(kind="topic.publish")
                        if ev.source in self.students})
        return [t for t in found if t != "/rosout"] + [t for t in found if t == "/rosout"]


#: A rate row of the rates panel: ``(topic, publishers or None for anyone, label, the rate a
#: criterion asks for in Hz or None)``.
Rate = tuple[str, Sequence[str] | None, str, float | None]
#: What draws a time panel on its axes (x: simulated time in seconds).
Draw = Callable[[Any, Scene], None]


@dataclass(frozen=True)
class Panel:
    """A time panel: what draws it, and its height in inches (a number, or one of the scene)."""

    draw: Draw
    height: float | Callable[[Scene], float] = 2.4

    def inches(self, scene: Scene) -> float:
        return float(self.height(scene) if callable(self.height) else self.height)


@dataclass
class Plan:
    """What the picture of one exercise holds."""

    #: The rows of the rates panel (default: the student's publications).
    rates: Callable[[Scene], list[Rate]] | None = None
    #: The time panels above the rates, top to bottom.
    panels: list[Panel] = field(default_factory=list)
    #: Drawn on the top view, after it (in the world frame).
    overlay: Callable[[Any, Scene], None] | None = None
    #: The marker topic the top view draws (None: none).
    markers: str | None = None
    #: Drawn instead of a top view when the world has no simulator (x, y in metres).
    plane: Callable[[Any, Scene], None] | None = None
    #: Whether the top view is drawn (its criteria may not look at the robot).
    top_view: bool = True


# -- building blocks -------------------------------------------------------------------------------

def topic_rates(ax: Any, scene: Scene, rows: Sequence[Rate]) -> None:
    """Messages per second of each row's topic, in windows of :data:`WINDOW_S`, as steps; the
    rate a criterion asks for as a dotted line of the same colour."""
    n = max(1, math.ceil(scene.end_s / WINDOW_S))
    edges = [i * WINDOW_S for i in range(n + 1)]
    drawn = 0
    for i, (topic, who, label, wanted) in enumerate(rows):
        color = f"C{i % 10}"
        counts = [0] * n
        for t in scene.times(topic, who):
            counts[min(n - 1, int(t / SEC // WINDOW_S))] += 1
        rates = [c / WINDOW_S for c in counts]
        ax.step(edges, [*rates, rates[-1]], where="post", color=color,
                linewidth=max(1.0, 2.6 - 0.5 * i), linestyle=_STYLES[i % len(_STYLES)],
                label=f"{label} ({sum(counts)})", gid=f"rate:{topic}")
        if wanted is not None:
            ax.axhline(wanted, color=color, linestyle=":", linewidth=1.2,
                       label=f"{label}: {wanted:g} Hz asked", gid=f"wanted:{topic}")
        drawn += 1
    if not drawn:
        _say(ax, "no topic to count")
    ax.set_ylabel("rate [Hz]")
    ax.set_ylim(bottom=0)
    ax.set_title(f"messages per second ({WINDOW_S:g} s windows; total in brackets)", fontsize=10)
    _legend(ax)


def _say(ax: Any, text: str) -> None:
    ax.text(0.5, 0.5, text, transform=ax.transAxes, ha="center", va="center", color="#555555",
            fontsize=10, gid="message")


def _legend(ax: Any) -> None:
    """One legend right of the panel for the curves of ``ax`` and of its twin (if any)."""
    twins = [o for o in ax.get_shared_x_axes().get_siblings(ax)
             if o is not ax and o.bbox.bounds == ax.bbox.bounds]
    handles, labels = ax.get_legend_handles_labels()
    for twin in twins:
        more, names = twin.get_legend_handles_labels()
        handles, labels = handles + more, labels + names
    if handles:
        (twins[-1] if twins else ax).legend(
            handles, labels, loc="upper left", bbox_to_anchor=(1.09 if twins else 1.01, 1.0),
            fontsize=8, frameon=False)


def _vlines(ax: Any, marks: Sequence[tuple[Any, ...]]) -> None:
    """Vertical lines ``(t seconds, label, colour[, line style])``; one legend entry a label."""
    seen: set[str] = set()
    for t, label, color, *style in marks:
        ax.axvline(t, color=color, linestyle=style[0] if style else "--", linewidth=1.1,
                   label=None if label in seen else label, gid=f"event:{label}")
        seen.add(label)


def _speed(ax: Any, scene: Scene, *, turn: bool = False) -> None:
    """The robot's true speed (and turn rate, on a second y-axis) from the simulator."""
    if scene.sim is None:
        _say(ax, "no simulator")
        ax.set_ylabel("speed [m/s]")
        return
    h = scene.sim.history()
    ts = [t / SEC for t in h.t_ns]
    ax.plot(ts, h.v, color="black", linewidth=1.3, label="true speed", gid="speed")
    ax.set_ylabel("speed [m/s]")
    if turn:
        twin = ax.twinx()
        twin.plot(ts, h.w, color="tab:purple", linewidth=1.0, linestyle="--",
                  label="true turn rate", gid="turn")
        twin.set_ylabel("turn rate [rad/s]", color="tab:purple")


def _student_rates(scene: Scene) -> list[Rate]:
    return [(t, sorted(scene.students), f"{t} (yours)", None)
            for t in scene.published_by_students()]


def _sim_name(scene: Scene) -> list[str]:
    return [scene.sim.node.name] if scene.sim is not None else []


# -- exercise 1: teleop and launch -------------------------------------------------------------------

def _ex1_rates(scene: Scene) -> list[Rate]:
    from ddes.grading.exercises import ex1_console as ex1

    rows: list[Rate] = []
    spec = ex1._teleop_spec(scene.world)
    if spec is not None:
        keys = spec.full_name + "/keys"
        rows.append((keys, None, f"{keys} (the grader's keys)", None))
        for topic in ex1._publications(scene.facts, spec.full_name, "geometry_msgs/Twist"):
            rows.append((topic, [spec.full_name], f"{topic} (your teleop)", None))
    for topic in ("/scan", "/odom"):
        rows.append((topic, _sim_name(scene), f"{topic} (simulator)", None))
    return rows


def _ex1_speed(ax: Any, scene: Scene) -> None:
    from ddes.grading.exercises import ex1_console as ex1

    _speed(ax, scene)
    spec = ex1._teleop_spec(scene.world)
    if spec is not None:
        for topic in ex1._publications(scene.facts, spec.full_name, "geometry_msgs/Twist"):
            got = scene.facts.messages(topic, publisher=spec.full_name)
            ax.plot([t / SEC for t, _w, _m in got], [m.linear.x for _t, _w, m in got], ".",
                    markersize=4, color="tab:blue", label=f"{topic} linear.x (your teleop)",
                    gid="commands")
    p = scene.scenario.params
    marks = [(ex1.KEYS_START, "first drive key", "tab:green")]
    if "drive_s" in p:
        marks.append((ex1._stop_ns(p) / SEC, "stop key", "tab:red"))
    _vlines(ax, marks)
    ax.set_title("the keys drive and stop the robot (1.1, 1.2)", fontsize=10)
    _legend(ax)


# -- exercise 2: the closest range -------------------------------------------------------------------

def _ex2_topic(scene: Scene) -> str:
    return str(scene.scenario.params.get("scan_topic", "/scan"))


def _ex2_rates(scene: Scene) -> list[Rate]:
    topic = _ex2_topic(scene)
    return [(topic, _sim_name(scene), f"{topic} (simulator)", None),
            ("/rosout", sorted(scene.students), "/rosout (your node's log lines)", None)]


def _ex2_ranges(ax: Any, scene: Scene) -> None:
    from ddes.grading.course import min_valid_range
    from ddes.grading.exercises import ex2_package as ex2
    from ddes.grading.exercises.common import NUMBER, student_logs

    scans = ex2._delivered_scans(scene.facts, _ex2_topic(scene), scene.sim)
    truth = [(t / SEC, min_valid_range(m)[0]) for t, m in scans]
    truth = [(t, r) for t, r in truth if math.isfinite(r)]
    ax.plot([t for t, _ in truth], [r for _, r in truth], "o", markersize=5, mfc="none",
            color="black", label="smallest range of the scan", gid="truth")
    logged = []
    for t, _who, text in student_logs(scene.facts):
        m = NUMBER.search(text)
        if m is not None:
            try:
                value = float(m.group(0))
            except ValueError:  # pragma: no cover - NUMBER matches floats only
                continue
            if math.isfinite(value):
                logged.append((t / SEC, value))
    ax.plot([t for t, _ in logged], [v for _, v in logged], "x", markersize=5,
            color="tab:blue", label="the number your node logged", gid="logged")
    if not truth and not logged:
        _say(ax, "no scan reached your node, and it logged no number")
    ax.set_ylabel("distance [m]")
    ax.set_title("the smallest distance of every scan (2.1)", fontsize=10)
    _legend(ax)


# -- exercise 3: the P controller ---------------------------------------------------------------------

def _ex3_rates(scene: Scene) -> list[Rate]:
    students = sorted(scene.students)
    rows: list[Rate] = [("/cmd_vel", students, "/cmd_vel (yours)", 5.0)]
    markers = [t for t in scene.published_by_students() if t not in ("/cmd_vel", "/rosout")]
    rows += [(t, students, f"{t} (yours)", 1.0) for t in markers]
    return rows


def _ex3_law(ax: Any, scene: Scene) -> None:
    from ddes.grading.exercises import ex3_pillar as ex3

    cmds = ex3._student_messages(scene.facts, "/cmd_vel")
    ax.plot([t / SEC for t, _m in cmds], [m.angular.z for _t, m in cmds], ".", markersize=4,
            color="tab:blue", label="your /cmd_vel angular.z", gid="commands")
    gain, source = ex3._gain(scene.facts)
    if gain is not None:
        scans = ex3._scans(scene.facts)
        want: list[tuple[float, float]] = []
        j = -1
        for t, _cmd in cmds:
            while j + 1 < len(scans) and scans[j + 1][0] <= t:
                j += 1
            bearings = ex3.pillar_bearings(scans[j][1]) if j >= 0 else []
            if bearings:
                want.append((t / SEC, gain * bearings[0]))
        ax.plot([t for t, _ in want], [w for _, w in want], "-", color="black", linewidth=1.0,
                label=f"p_gain x bearing of the closest return (p_gain {gain:g})", gid="law")
    else:
        ax.text(0.01, 0.95, f"no p_gain: {source}", transform=ax.transAxes, va="top",
                fontsize=8, color="#555555")
    if not cmds:
        _say(ax, "your node published nothing on /cmd_vel")
    if scene.sim is not None and scene.sim.collisions:
        _vlines(ax, [(c.stamp_ns / SEC, "collision", "tab:red") for c in scene.sim.collisions])
    ax.set_ylabel("turn rate [rad/s]")
    ax.set_title("the P law: angular.z = p_gain x the pillar's bearing (3.1, 3.2)", fontsize=10)
    _legend(ax)


# -- exercise 4a: the e-stop service -----------------------------------------------------------------

def _ex4a_calls(ax: Any, scene: Scene) -> None:
    _speed(ax, scene, turn=True)
    calls = getattr(scene.world, "_ddes_estop_calls", [])
    _vlines(ax, [(c.t_ns / SEC, f"{'stop' if c.data else 'start'} call ({c.source.split()[0]})",
                  "tab:red" if c.data else "tab:green",
                  "--" if c.source == "grader" else ":") for c in calls])
    if not calls:
        ax.text(0.01, 0.95, "no service call was made", transform=ax.transAxes, va="top",
                fontsize=8)
    ax.set_title("the robot stops after each stop call and drives after each start "
                 "(4a.1-4a.6)", fontsize=10)
    _legend(ax)


def _ex4a_rates(scene: Scene) -> list[Rate]:
    return [("/cmd_vel", sorted(scene.students), "/cmd_vel (yours)", None),
            ("/odom", _sim_name(scene), "/odom (simulator)", None)]


# -- exercise 4b: actions ------------------------------------------------------------------------------

def wire_goal_events(facts: Facts, ns: str, names: dict[str, str] | None = None
                     ) -> list[TraceEvent]:
    """The ``action.server.*`` events a server on ``ns`` would have traced, rebuilt from the
    trusted world's wire: a goal's arrival when it was sent on ``ns/goal`` (PENDING), each
    change of its status in ``ns/status`` and its result (``action.server.transition``), each
    feedback, and each cancel sent on ``ns/cancel`` (matched as actionlib matches: by id, else
    every goal stamped at or before a non-zero stamp, else all).  ``names`` renames goal ids
    (the plot's row labels)."""
    from ddes.actionlib.states import TERMINAL_STATUSES, GoalStatus

    rename = names or {}
    events: list[TraceEvent] = []
    stamps: dict[str, int] = {}
    last: dict[str, int] = {}

    def name(gid: str) -> str:
        return rename.get(gid, gid)

    def status(t: int, source: str, gid: str, code: int) -> None:
        if gid not in stamps or last.get(gid) == code or not 0 <= code < GoalStatus.LOST:
            return
        last[gid] = code
        events.append(TraceEvent(t, "action.server.transition", source,
                                 {"ns": ns, "id": name(gid), "after": GoalStatus(code).name}))

    wire: list[tuple[int, int, str, str, Any]] = []
    for order, suffix in enumerate(("goal", "cancel", "status", "feedback", "result")):
        for t, who, msg in facts.messages(f"{ns}/{suffix}"):
            wire.append((t, order, suffix, who, msg))
    server = next((who for _t, _o, s, who, _m in wire if s == "status"), ns)
    for t, _order, suffix, _who, msg in sorted(wire, key=lambda w: (w[0], w[1])):
        if suffix == "goal":
            gid = msg.goal_id.id
            if gid in stamps:
                continue
            stamps[gid] = msg.goal_id.stamp.to_nsec() or t
            last[gid] = GoalStatus.PENDING
            events.append(TraceEvent(t, "action.server.goal", server,
                                     {"ns": ns, "id": name(gid), "arrival": "new"}))
        elif suffix == "cancel":
            gid, stamp = msg.id, msg.stamp.to_nsec()
            matched = ([gid] if gid in stamps else []) if gid else [
                g for g, s in stamps.items() if stamp == 0 or s <= stamp]
            matched = [g for g in matched if GoalStatus(last.get(g, 0)) not in TERMINAL_STATUSES]
            if matched:
                events.append(TraceEvent(t, "action.server.cancel", server,
                                         {"ns": ns, "id": "", "matched": [name(g) for g in matched]}))
        elif suffix == "status":
            for st in msg.status_list:
                status(t, server, st.goal_id.id, st.status)
        elif suffix == "feedback":
            if msg.status.goal_id.id in stamps:
                events.append(TraceEvent(t, "action.server.feedback", server,
                                         {"ns": ns, "id": name(msg.status.goal_id.id)}))
        else:
            status(t, server, msg.status.goal_id.id, msg.status.status)
    return events


def _ex4b_run(scene: Scene) -> Any:
    from ddes.grading.exercises.ex4b_actions import Run

    run = getattr(scene.world, "_ddes_ex4b", None)
    return run if isinstance(run, Run) else None


def _ex4b_height(scene: Scene) -> float:
    run = _ex4b_run(scene)
    return 1.4 + 0.62 * (len(run.goals) + 1 if run is not None else 1)


def _ex4b_goals(ax: Any, scene: Scene) -> None:
    from ddes.actionlib import plot_goals
    from ddes.grading.exercises.ex4b_actions import CLIENT_NS

    run = _ex4b_run(scene)
    ns = run.ns if run is not None else "/" + str(scene.scenario.params.get("action", ""))
    names: dict[str, str] = {}
    for i, g in enumerate(run.goals if run is not None else []):
        gid = g.handle.get_goal_id()
        names[getattr(gid, "id", gid)] = f"{i + 1} {g.phase}"
    events = wire_goal_events(scene.facts, ns, names)
    if run is not None:  # the newer goal preempts the older (SimpleActionServer's policy)
        phases = {g.phase: f"{i + 1} {g.phase}" for i, g in enumerate(run.goals)}
        newer = next((g for g in run.goals if g.phase == "new"), None)
        if newer is not None and "old" in phases:
            events.append(TraceEvent(newer.sent_ns, "action.simple.preempt_request", "",
                                     {"ns": ns, "id": phases["old"]}))
    theirs = dict.fromkeys(m.goal_id.id for _t, _w, m in scene.facts.messages(CLIENT_NS + "/goal"))
    events += wire_goal_events(scene.facts, CLIENT_NS, {
        gid: f"your client's goal {i + 1}" for i, gid in enumerate(theirs)})
    events.sort(key=lambda ev: ev.t)
    plot_goals(events, ax=ax, until=scene.world.now / SEC,
               title=f"the goals the grader sent to {ns}, and your client's "
                     "(4b.2-4b.5, 4b.7)")
    ax.set_ylabel("goal")


def _ex4b_paths(ax: Any, scene: Scene) -> None:
    """Each goal's path on the top view: odom is the simulator's start pose."""
    from ddes.transformations import cos, sin

    run = _ex4b_run(scene)
    if run is None or scene.sim is None:
        return
    start = scene.sim._start  # noqa: SLF001 - where odom lies in the world
    c, s = cos(start.yaw), sin(start.yaw)
    for i, g in enumerate(run.goals):
        if not g.points:
            continue
        x0, y0, _ = g.start
        pts = [(x0, y0), *g.points]
        xs = [start.x + c * x - s * y for x, y in pts]
        ys = [start.y + s * x + c * y for x, y in pts]
        ax.plot(xs, ys, "o--", markersize=4, linewidth=1.0, color=f"C{(i + 1) % 10}",
                label=f"goal {i + 1} ({g.phase})", gid=f"goal:{g.phase}")
    if ax.get_legend_handles_labels()[0]:
        ax.legend(loc="best", fontsize=7)


def _ex4b_rates(scene: Scene) -> list[Rate]:
    from ddes.grading.exercises.ex4b_actions import FEEDBACK_HZ

    run = _ex4b_run(scene)
    ns = run.ns if run is not None else "/" + str(scene.scenario.params.get("action", ""))
    students = sorted(scene.students)
    return [(f"{ns}/feedback", students, f"{ns}/feedback (yours)", FEEDBACK_HZ),
            (f"{ns}/status", students, f"{ns}/status (yours)", None),
            ("/cmd_vel", students, "/cmd_vel (yours)", None)]


# -- exercise 4c: ROS time ------------------------------------------------------------------------------

def _ex4c_time(ax: Any, scene: Scene) -> None:
    from ddes.grading.exercises import ex4c_time as ex4c

    run = ex4c._facts(scene.facts)
    if run.clocks:
        ax.plot([k / SEC for k, _c in run.clocks], [c / SEC for _k, c in run.clocks], ".",
                markersize=1.5, color="black", label="/clock (ROS time)", gid="clock")
    else:
        ax.plot([0.0, scene.end_s], [0.0, scene.end_s], "-", color="black", linewidth=1.0,
                label="ROS time (no /clock: the wall clock)", gid="clock")
    ax.plot([k / SEC for k, _s in run.beats], [s / SEC for _k, s in run.beats], "o",
            markersize=4, mfc="none", color="tab:blue", label="your /heartbeat's stamp",
            gid="heartbeats")
    ax.plot([k / SEC for k in run.zeros], [run.ros(k) / SEC for k in run.zeros], "v",
            markersize=4, color="tab:red", label="your zero /cmd_vel (watchdog)", gid="zeros")
    _vlines(ax, [(ev.t / SEC, "simulator paused" if ev.details.get("paused") else
                  "simulator resumed", "tab:gray" if ev.details.get("paused") else "tab:olive")
                 for ev in scene.world.trace.select(kind="sim.pause")])
    ax.set_ylabel("ROS time [s]")
    ax.set_title("ROS time against the kernel's (wall) time (4c.1-4c.7)", fontsize=10)
    _legend(ax)


def _ex4c_rates(scene: Scene) -> list[Rate]:
    students = sorted(scene.students)
    return [("/heartbeat", students, "/heartbeat (yours)", None),
            ("/cmd_vel", students, "/cmd_vel (yours)", None),
            ("/clock", None, "/clock", None), ("/odom", None, "/odom", None)]


# -- exercise 4d: bags and the EKF -----------------------------------------------------------------------

def _ex4d_tracks(ax: Any, scene: Scene) -> None:
    drawn = False
    for topic, style in (("/odometry/filtered", "-"), ("/smb_velocity_controller/odom", "--")):
        got = scene.facts.messages(topic)
        if got:
            ax.plot([m.pose.pose.position.x for _t, _w, m in got],
                    [m.pose.pose.position.y for _t, _w, m in got], style, linewidth=1.2,
                    label=topic, gid=f"track:{topic}")
            drawn = True
    if not drawn:
        _say(ax, "no odometry was published")
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel("x in odom [m]")
    ax.set_ylabel("y in odom [m]")
    ax.set_title("the tracks: the EKF's and the wheel odometry (4d.3, 4d.4)", fontsize=10)
    if drawn:
        ax.legend(loc="best", fontsize=8)


def _ex4d_rates(scene: Scene) -> list[Rate]:
    return [(t, None, t, None) for t in ("/odometry/filtered", "/smb_velocity_controller/odom",
                                         "/imu/data", "/rslidar_points")]


# -- exercise 5: automatic e-stops -----------------------------------------------------------------------

def _ex5_stops(ax: Any, scene: Scene) -> None:
    from ddes.rqt.plot import field_series

    _speed(ax, scene)
    try:
        imu = field_series(scene.world, "/imu/data/linear_acceleration/x")
    except Exception:  # noqa: BLE001 - no IMU: the speed alone
        imu = None
    if imu is not None:
        twin = ax.twinx()
        twin.plot(imu.t, imu.y, color="tab:orange", linewidth=0.8, alpha=0.8,
                  label="IMU a_x", gid="imu")
        twin.set_ylabel("IMU a_x [m/s²]", color="tab:orange")
    log = getattr(scene.world, "_ddes_ex5", None)
    marks: list[tuple[float, str, str]] = []
    if log is not None:
        marks += [(t / SEC, "proximity e-stop", "tab:red") for t, _gap in log.stops_a]
        marks += [(t / SEC, "crash e-stop", "tab:purple") for t, _gap in log.stops_b]
    if scene.sim is not None:
        marks += [(c.stamp_ns / SEC, "collision", "black") for c in scene.sim.collisions]
    _vlines(ax, marks)
    ax.set_title("e-stops: near the pillar, after the crash, never without a reason "
                 "(5.1-5.3)", fontsize=10)
    _legend(ax)


#: The pictures of the course's exercises, by id.
PLANS: dict[str, Plan] = {
    "ex1_console": Plan(rates=_ex1_rates, panels=[Panel(_ex1_speed)]),
    "ex2_package": Plan(rates=_ex2_rates, panels=[Panel(_ex2_ranges)]),
    "ex3_pillar": Plan(rates=_ex3_rates, panels=[Panel(_ex3_law)],
                       markers="/visualization_marker"),
    "ex4a_services": Plan(rates=_ex4a_rates, panels=[Panel(_ex4a_calls)],
                          markers="/visualization_marker"),
    "ex4b_actions": Plan(rates=_ex4b_rates, panels=[Panel(_ex4b_goals, _ex4b_height)],
                         overlay=_ex4b_paths),
    "ex4c_time": Plan(rates=_ex4c_rates, panels=[Panel(_ex4c_time)], top_view=False),
    "ex4d_bags": Plan(rates=_ex4d_rates, plane=_ex4d_tracks),
    "ex5_safety": Plan(panels=[Panel(_ex5_stops)], markers="/visualization_marker"),
}


def replay_picture(exercise: Exercise, scenario: Scenario, world: World, facts: Facts) -> Any:
    """The picture of a replayed scenario (see the module text): a DisplayFigure."""
    from ddes.display.figure import new_figure
    from ddes.grading.replay import simulators

    sims = simulators(world)
    scene = Scene(exercise, scenario, world, facts, sims[0] if sims else None)
    plan = PLANS.get(exercise.id, Plan())
    drawn_sim = scene.sim if plan.top_view else None
    rows = (plan.rates or _student_rates)(scene)
    panels = [*plan.panels, Panel(lambda ax, sc: topic_rates(ax, sc, rows),
                                  max(2.4, 1.0 + 0.35 * len(rows)))]
    heights = [p.inches(scene) for p in panels]
    left = drawn_sim is not None or plan.plane is not None
    fig = new_figure(figsize=(16.0 if left else 10.5, max(4.5, sum(heights) + 0.6)))
    grid = fig.add_gridspec(len(panels), 2 if left else 1, height_ratios=heights,
                            width_ratios=[1.0, 1.5] if left else None)
    if drawn_sim is not None:
        from ddes.sim.view import top_view

        ax = fig.add_subplot(grid[:, 0])
        top_view(drawn_sim, ax=ax, markers=plan.markers,
                 title=f"{scenario.name}: from above at t = {world.now / SEC:.2f} s")
        if plan.overlay is not None:
            plan.overlay(ax, scene)
    elif plan.plane is not None:
        plan.plane(fig.add_subplot(grid[:, 0]), scene)
    first = None
    column = 1 if left else 0
    for i, panel in enumerate(panels):
        ax = fig.add_subplot(grid[i, column], sharex=first)
        first = first or ax
        try:
            panel.draw(ax, scene)
        except Exception as exc:  # noqa: BLE001 - a picture never costs the replay
            for twin in [o for o in ax.get_shared_x_axes().get_siblings(ax)
                         if o is not ax and o.bbox.bounds == ax.bbox.bounds]:
                twin.remove()
            ax.cla()
            _say(ax, f"not drawn: {type(exc).__name__}: {exc}"[:200])
            ax.set_ylabel("(not drawn)")
        ax.grid(True, axis="x", color="0.9")
        ax.set_xlabel(_TIME if i == len(panels) - 1 else "")
        ax.tick_params(labelbottom=i == len(panels) - 1)
    assert first is not None
    first.set_xlim(0.0, scene.end_s)
    fig.suptitle(f"{exercise.id} — scenario {scenario.name}"
                 + ("" if scenario.hidden else f" (seed {scenario.seed})"), fontsize=12)
    fig.tight_layout()
    return fig
