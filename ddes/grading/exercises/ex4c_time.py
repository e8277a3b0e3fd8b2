"""Exercise 4c: ROS time — a watchdog node with a heartbeat on ROS time, a ROS-time odometry
watchdog and a wall-time status line, under every clock source of lecture 4.  See
``solutions/ex4c_time/README.md`` and teaching.md's E4c.

The student's launch file starts the node ``watchdog`` (``smb_watchdog/watchdog_node.py``, class
``Watchdog``) with its parameters ``~rate`` (heartbeat, Hz) and ``~timeout`` (odometry silence,
s).  The grader owns the clock source, as the person who starts Gazebo or ``rosbag play`` does,
and sets ``/use_sim_time`` for the student's process (it crosses into the sandbox):

* ``kernel`` (S1, with S5's silence): ``use_sim_time`` false, so ROS time is the kernel's clock,
  which plays the wall clock.  The simulator (laser off, no ``/clock``) drives ``/odom``; the
  grader's relay drops ``/odom`` for a while (the odometry stops while time runs).
* ``simulator`` (S2, S4, S5): ``ddes_sim`` at ``real_time_factor`` 0.5 with ``/use_sim_time``
  true; the odometry stops while ``/clock`` runs; the grader pauses the simulator for 5 wall
  seconds through ``/simulator/pause_physics`` (ROS time stands still); at the end the simulator
  is restarted, so ``/clock`` jumps back to zero (as when Gazebo is restarted under running
  nodes).
* ``bag`` (S3, S6): 1.5 s after the node starts (ROS time is 0 until then),
  ``rosbag play --clock -r 2`` of a recorded odometry bag with a gap, to its end
  (ROS time then stands still), then ``rosbag play --clock --loop`` of a short bag: the clock jumps
  back at every pass.

Every check reads the trusted world: ``/clock`` as published there (the ROS time a sim-time node
reads at a kernel instant is the last ``/clock`` value published by then), ``/odom`` as
forwarded, and what the student's node published on ``/heartbeat``, ``/cmd_vel`` and
``/rosout``.  Public scenarios use the rates of the student's parameter file; hidden ones set
``~rate`` 2.5 Hz (which catches ``Rate(int(rate))``) and a hidden ``~timeout``.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from typing import Any

from ddes.grading.course import CourseExercise, hidden_random
from ddes.grading.exercise import Criterion, Facts, Scenario
from ddes.grading.exercises.common import launch_problem

__all__ = ["EX4C", "scenarios"]

PKG = "smb_watchdog"
LAUNCH = f"{PKG}/launch/{PKG}.launch"
NODE_TYPE = "watchdog_node.py"
#: The kernel ("wall") seconds every scenario runs.
DURATION = 28.0
PUBLIC_RATE, PUBLIC_TIMEOUT = 2.0, 1.0
HIDDEN_RATE = 2.5
RAW_ODOM = "/ddes_grader/odom_raw"
#: The bag's odometry rate (Hz of bag time) and where its first message lies (bag s).
BAG_HZ, BAG_START = 50, 100.0
#: The ``-r 2`` bag spans this many bag seconds; the ``--loop`` bag this many.
BAG_SPAN, LOOP_SPAN = 14.0, 4.0
#: The ``--loop`` player is stopped (Ctrl+C) after this many kernel seconds.
LOOP_FOR = 9.0
#: 4c.1: heartbeats are counted over this many seconds of ROS time, +- this many.
COUNT_WINDOW, COUNT_SLACK = 10.0, 1
#: 4c.3: zero Twists begin within timeout + one 10 Hz tick + one /clock step of ROS time.
FIRE_SLACK = 0.12
#: 4c.3: consecutive zero Twists of one silence at most this far apart (10 Hz, with slack).
ZERO_GAP = 0.15
#: 4c.4: a zero Twist earlier than timeout - this after the last /odom is a false alarm.
EARLY_SLACK = 0.02
#: 4c.5: the values of a status line within this of the kernel and ROS times (%.1f rounding).
STATUS_SLACK = 0.11
#: 4c.6: after a backward jump a heartbeat within two periods + this of ROS time.
JUMP_SLACK = 0.2
STATUS_RE = re.compile(r"wall=\s*([-+]?\d+(?:\.\d*)?)\s+ros=\s*([-+]?\d+(?:\.\d*)?)")
CREDIT = "teaching.md E4c (lecture 4, ROS time); new, in the style of ETH's checklists"


def _jitter(rng: Any, value: float, spread: float) -> float:
    return round(value + rng.uniform(-spread, spread), 3)


def scenarios(seed: int, public: bool) -> list[Scenario]:
    out = []
    for kind in ("kernel", "simulator", "bag"):
        out.append(Scenario(f"{kind}", seed, params=_timeline(kind, None, PUBLIC_RATE,
                                                                PUBLIC_TIMEOUT)))
    for i, kind in enumerate(("kernel", "simulator", "bag")):
        rng = hidden_random(f"ex4c_time/{i}", seed)
        timeout = round(rng.uniform(0.6, 1.4), 2)
        out.append(Scenario(f"hidden-{i + 1}", seed, hidden=True,
                            params=_timeline(kind, rng, HIDDEN_RATE, timeout)))
    return out


def _timeline(kind: str, rng: Any, rate: float, timeout: float) -> dict[str, Any]:
    """A scenario's clock source and phases (kernel seconds unless named ``bag``/``ros``)."""
    j = (lambda v, s: _jitter(rng, v, s)) if rng is not None else (lambda v, _s: v)
    p: dict[str, Any] = {"kind": kind, "rate": rate, "timeout": timeout,
                         "hidden": rng is not None}
    silence = round(timeout + 0.8, 3)  # ROS seconds without /odom
    if kind == "kernel":
        p["silence"] = (j(12.0, 2.0), silence)
    elif kind == "simulator":
        p["rtf"] = 0.5
        p["silence"] = (j(4.0, 0.5), silence)  # kernel start; ROS length
        p["pause"] = (j(11.0, 0.5), 5.0)  # kernel start, kernel length
        p["restart"] = j(26.5, 0.2)
    else:
        p["gap"] = (j(104.0, 1.0), silence)  # bag time of the odometry gap, its length
        p["play_at"] = j(1.5, 0.3)
        p["loop_at"] = j(11.5, 0.5)
    return p


# -- the trusted world ------------------------------------------------------------------------------

def _relay(world: Any, silent: Any, every: int = 1) -> None:
    """``/odom`` from the simulator's raw odometry (every ``every``-th message), except while
    ``silent(kernel_ns)``."""
    from ddes.msg import get_message_class

    odom = get_message_class("nav_msgs/Odometry")
    node = world.create_node("/ddes_grader/odom_relay", disable_rosout=True, use_sim_time=False)
    pub = node.advertise("/odom", odom, queue_size=10)
    count = [0]

    def forward(m: Any) -> None:
        count[0] += 1
        if count[0] % every == 0 and not silent(world.now):
            pub.publish(m)

    node.subscribe(RAW_ODOM, odom, forward, queue_size=10)


def _simulator(world: Any, name: str, rtf: float, clock: bool) -> Any:
    from ddes.sim import Simulator, WorldSpec

    node = world.create_node(name, use_sim_time=False)
    return Simulator(world, WorldSpec.load("empty"), noise=False, node=node, laser=False,
                     real_time_factor=rtf, publish_clock=clock, imu_rate=10.0,
                     publish_odom_tf=False, odom_topic=RAW_ODOM)


def _odom_bag(first: float, span: float, gap: tuple[float, float] | None) -> Any:
    from ddes.msg import get_message_class
    from ddes.rosbag import Bag
    from ddes.time import Time

    odom = get_message_class("nav_msgs/Odometry")
    bag = Bag()
    start_ns, step_ns = round(first * 1e9), 10**9 // BAG_HZ
    g0 = g1 = -1
    if gap is not None:
        g0, g1 = round(gap[0] * 1e9), round((gap[0] + gap[1]) * 1e9)
    for i in range(round(span * BAG_HZ) + 1):
        t = start_ns + i * step_ns
        if g0 <= t < g1:
            continue
        m = odom()
        m.header.stamp = Time._from_ns(t)
        m.header.seq = i
        m.header.frame_id, m.child_frame_id = "odom", "base_link"
        m.pose.pose.orientation.w = 1.0
        bag.write("/odom", m, Time._from_ns(t))
    return bag


def build(world: Any, scenario: Scenario) -> None:
    p = scenario.params
    kind = p["kind"]
    if kind == "kernel":
        world.use_sim_time = False
        _simulator(world, "/simulator", 1.0, clock=False)
        s0, length = p["silence"]
        _relay(world, lambda t: s0 * 1e9 <= t < (s0 + length) * 1e9, every=2)  # 25 Hz
    elif kind == "simulator":
        world.use_sim_time = True
        rtf = p["rtf"]
        sims = [_simulator(world, "/simulator", rtf, clock=True)]
        s0, length = p["silence"]
        s1 = s0 + length / rtf
        _relay(world, lambda t: s0 * 1e9 <= t < s1 * 1e9)
        _pauser(world, p["pause"])
        _restarter(world, sims, p["restart"], rtf)
    else:
        world.use_sim_time = True
        from ddes.rosbag import Player

        bag = _odom_bag(BAG_START, BAG_SPAN, p["gap"])
        loop_bag = _odom_bag(BAG_START, LOOP_SPAN, None)
        node = world.create_node("/ddes_grader/player", disable_rosout=True, use_sim_time=False)

        def later() -> Any:
            # rosbag play is started by hand after the node: ROS time is 0 until its first /clock
            yield node.sleep(p["play_at"])
            Player(world, bag, clock=True, rate=2.0, quiet=True)
            yield node.sleep(p["loop_at"] - p["play_at"])
            player = Player(world, loop_bag, clock=True, loop=True, quiet=True)
            yield node.sleep(LOOP_FOR)
            player.stop("stopped by the grader (Ctrl+C)")

        node.process(later())


def _pauser(world: Any, pause: tuple[float, float]) -> None:
    """Pause the simulator through its service for ``pause[1]`` kernel seconds."""
    from ddes.services.client import ServiceProxy

    node = world.create_node("/ddes_grader/pauser", disable_rosout=True, use_sim_time=False)
    empty = world.messages.get_service_class("std_srvs/Empty")

    def run() -> Any:
        yield node.sleep(pause[0])
        yield ServiceProxy(node, "/simulator/pause_physics", empty).call()
        yield node.sleep(pause[1])
        yield ServiceProxy(node, "/simulator/unpause_physics", empty).call()

    node.process(run())


def _restarter(world: Any, sims: list[Any], at: float, rtf: float) -> None:
    """Shut the simulator down and start a new one: /clock starts from zero again."""
    node = world.create_node("/ddes_grader/restarter", disable_rosout=True, use_sim_time=False)

    def run() -> Any:
        yield node.sleep(at)
        sims[0].node.shutdown("restarted by the grader")
        sims.append(_simulator(world, "/simulator_restarted", rtf, clock=True))

    node.process(run())


def setup(world: Any, scenario: Scenario) -> tuple[dict[str, Any], dict[str, Any], dict[str, Any]]:
    p = scenario.params
    overrides = {NODE_TYPE: {"rate": p["rate"], "timeout": p["timeout"]}} if p["hidden"] else {}
    return overrides, {}, {}


# -- facts ------------------------------------------------------------------------------------------

@dataclass
class _Run:
    """One scenario's facts in the time bases the checks need."""

    sim: bool
    #: (kernel ns, clock ns) of every /clock publication (sim time only).
    clocks: list[tuple[int, int]]
    #: (kernel ns, ROS ns) of every /odom delivered.
    odoms: list[tuple[int, int]]
    #: (kernel ns, stamp ns) of every heartbeat of the student's node.
    beats: list[tuple[int, int]]
    #: kernel ns of every zero Twist of the student's node on /cmd_vel.
    zeros: list[int]
    #: (kernel ns, level, text) of the student's /rosout lines.
    logs: list[tuple[int, int, str]]
    rate: float
    timeout: float
    end_ns: int

    def ros(self, t: int) -> int:
        """The ROS time a node of this scenario reads at kernel ``t`` (the latest /clock)."""
        if not self.sim:
            return t
        lo, hi = 0, len(self.clocks)
        while lo < hi:
            mid = (lo + hi) // 2
            if self.clocks[mid][0] <= t:
                lo = mid + 1
            else:
                hi = mid
        return self.clocks[lo - 1][1] if lo else 0

    def could_read(self, t: int) -> set[int]:
        """Every ROS time a node may read at kernel ``t``: the value before the instant, and
        those published at it (which a message of the same instant may follow or precede)."""
        if not self.sim:
            return {t}
        out = {self.ros(t - 1)}
        out.update(c for k, c in self.clocks if k == t)
        return out

    def last_odom(self, t: int) -> int | None:
        """The ROS time of the last /odom delivered at or before kernel ``t``."""
        found = None
        for k, ros in self.odoms:
            if k > t:
                break
            found = ros
        return found


def _published(facts: Facts, topics: tuple[str, ...]) -> dict[str, list[tuple[int, str, bytes]]]:
    """``(t_ns, publisher, bytes)`` of every message on ``topics``, in one pass over the trace
    (a select per topic scans the whole trace each time)."""
    out: dict[str, list[tuple[int, str, bytes]]] = {name: [] for name in topics}
    for ev in facts.world.trace.select(kind="topic.publish"):
        got = out.get(str(ev.details.get("topic")))
        if got is not None:
            got.append((ev.t, ev.source, ev.details["data"]))
    return out


def _decode(facts: Facts, topic: str, raw: list[tuple[int, str, bytes]]) -> list[tuple[int, str, Any]]:
    entry = facts.world.master.topics.get(topic)
    if entry is None or entry.type == "*" or not raw:
        return []
    cls = facts.world.messages.get_message_class(entry.type)
    return [(t, who, cls.__new__(cls)._deserialize_from(data)) for t, who, data in raw]


def _facts(facts: Facts) -> _Run:
    cache = getattr(facts.world, "_ddes_ex4c_run", None)
    if isinstance(cache, _Run):
        return cache
    p = facts.scenario.params
    sim = p["kind"] != "kernel"
    mine = set(facts.student_nodes)
    raw = _published(facts, ("/clock", "/odom", "/heartbeat", "/cmd_vel", "/rosout"))
    clocks = [(t, m.clock.secs * 10**9 + m.clock.nsecs)
              for t, _w, m in _decode(facts, "/clock", raw["/clock"])]
    run = _Run(sim=sim, clocks=clocks, odoms=[], beats=[], zeros=[], logs=[],
               rate=float(p["rate"]), timeout=float(p["timeout"]), end_ns=round(DURATION * 1e9))
    run.odoms = [(t, run.ros(t)) for t, _w, _d in raw["/odom"]]  # times only: never decoded
    mine_only = {k: [x for x in v if x[1] in mine] for k, v in raw.items()}
    run.beats = [(t, m.stamp.secs * 10**9 + m.stamp.nsecs)
                 for t, _w, m in _decode(facts, "/heartbeat", mine_only["/heartbeat"])]
    for t, _w, m in _decode(facts, "/cmd_vel", mine_only["/cmd_vel"]):
        if not any(abs(v) > 1e-9 for v in (
                m.linear.x, m.linear.y, m.linear.z, m.angular.x, m.angular.y, m.angular.z)):
            run.zeros.append(t)
    run.logs = [(t, int(m.level), str(m.msg))
                for t, _w, m in _decode(facts, "/rosout", mine_only["/rosout"])]
    facts.world._ddes_ex4c_run = run  # type: ignore[attr-defined]
    return run


def _s(ns: int) -> str:
    return f"{ns / 1e9:.3f}"


def _silences(facts: Facts, run: _Run) -> list[tuple[int, int]]:
    """``(kernel start, kernel end)`` of each stretch without /odom while ROS time runs."""
    p = facts.scenario.params
    if p["kind"] == "kernel":
        s0, length = p["silence"]
        return [(round(s0 * 1e9), round((s0 + length) * 1e9))]
    if p["kind"] == "simulator":
        s0, length = p["silence"]
        return [(round(s0 * 1e9), round((s0 + length / p["rtf"]) * 1e9))]
    g0, length = p["gap"]
    start = next((k for k, c in run.clocks if c >= round(g0 * 1e9)), run.end_ns)
    end = next((k for k, c in run.clocks if c >= round((g0 + length) * 1e9)), run.end_ns)
    return [(start, end)]


# -- 4c.1 heartbeat rate -----------------------------------------------------------------------

def _window(facts: Facts, run: _Run) -> tuple[int, int]:
    """The ROS-time window heartbeats are counted in (10 s of ROS time while the clock runs)."""
    kind = facts.scenario.params["kind"]
    first = {"kernel": 0.5, "simulator": 0.5, "bag": BAG_START + 0.5}[kind]
    a = round(first * 1e9)
    return a, a + round(COUNT_WINDOW * 1e9)


def check_rate(facts: Facts) -> tuple[float, list[str]]:
    why = launch_problem(facts)
    if why:
        return 0.0, [why]
    run = _facts(facts)
    a, b = _window(facts, run)
    # the first pass of the clock over the window (before any jump back)
    stop = next((k for (k, c), (_k0, c0) in zip(run.clocks[1:], run.clocks) if c < c0),
                run.end_ns) if run.sim else run.end_ns
    n = sum(1 for t, _s in run.beats if t < stop and a <= run.ros(t) < b)
    want = round(COUNT_WINDOW * run.rate)
    if abs(n - want) <= COUNT_SLACK:
        return 20.0, []
    return 0.0, [f"{n} heartbeats in the 10 s of ROS time from {_s(a)} s, {want} +- "
                 f"{COUNT_SLACK} wanted at ~rate {run.rate:g} Hz"
                 + (" (ROS time here is /clock, not the wall clock)" if run.sim else "")]


# -- 4c.2 stamps are ROS time -----------------------------------------------------------------

def check_stamps(facts: Facts) -> tuple[float, list[str]]:
    why = launch_problem(facts)
    if why:
        return 0.0, [why]
    run = _facts(facts)
    if not run.beats:
        return 0.0, ["no heartbeat on /heartbeat"]
    bad = [(t, s) for t, s in run.beats if s not in run.could_read(t)]
    if not bad:
        return 15.0, []
    t, s = bad[0]
    return 0.0, [f"{len(bad)} of {len(run.beats)} heartbeat stamps are not the node's ROS time: "
                 f"the first, published at wall {_s(t)} s, says {_s(s)} s where ROS time was "
                 f"{_s(run.ros(t))} s"]


# -- 4c.3 / 4c.4 the watchdog -----------------------------------------------------------------

def _fired(run: _Run, start: int, end: int) -> tuple[str, int | None]:
    """Why the watchdog did not fire as it should in the silence ``[start, end)`` ('' if it
    did), and the kernel time of its first zero Twist there."""
    last = run.last_odom(start - 1)
    if last is None:
        return "no /odom before the silence", None
    zeros = [t for t in run.zeros if start <= t < end]
    limit = last + round((run.timeout + FIRE_SLACK) * 1e9)
    if not zeros:
        return (f"no zero Twist on /cmd_vel in the odometry silence from ROS time {_s(last)} s "
                f"(~timeout {run.timeout:g} s)"), None
    first = run.ros(zeros[0])
    if first > limit:
        return (f"the first zero Twist came at ROS time {_s(first)} s, "
                f"{(first - last) / 1e9:.3f} s after the last /odom (at most ~timeout "
                f"{run.timeout:g} + {FIRE_SLACK:g} s wanted)"), zeros[0]
    until = min(end, run.clocks[-1][0] if run.sim and run.clocks else end)
    stamps = [run.ros(t) for t in zeros] + [run.ros(until)]
    gaps = [(b - a_) for a_, b in zip(stamps, stamps[1:])]
    if gaps and max(gaps) > round(ZERO_GAP * 1e9):
        return (f"zero Twists at 10 Hz wanted while /odom is silent; a gap of "
                f"{max(gaps) / 1e9:.3f} s of ROS time"), zeros[0]
    return "", zeros[0]


#: 4c.3's share for the zero Twists in every silence, and for the one warning (of 20).
FIRES_POINTS, WARN_POINTS = 16.0, 4.0
#: rosgraph_msgs/Log's WARN.
WARN_LEVEL = 4


def check_fires(facts: Facts) -> tuple[float, list[str]]:
    why = launch_problem(facts)
    if why:
        return 0.0, [why]
    run = _facts(facts)
    got = [_fired(run, a, b)[0] for a, b in _silences(facts, run)]
    bad = [x for x in got if x]
    points = FIRES_POINTS * (len(got) - len(bad)) / len(got)
    if run.zeros:  # it fired: the statement's warning, once (rospy.logwarn_once)
        warns = [(t, text) for t, level, text in run.logs if level == WARN_LEVEL]
        if len(warns) == 1 and warns[0][0] >= run.zeros[0]:
            points += WARN_POINTS
        elif not warns:
            bad.append(f"no warning from your node when the watchdog fired (at wall "
                       f"{_s(run.zeros[0])} s): warn once, with rospy.logwarn_once")
        elif len(warns) > 1:
            bad.append(f"{len(warns)} warnings from your node (the first at wall "
                       f"{_s(warns[0][0])} s: {warns[0][1][:80]!r}); warn once, with "
                       "rospy.logwarn_once")
        else:
            bad.append(f"your node warned at wall {_s(warns[0][0])} s, before the watchdog "
                       f"fired (at {_s(run.zeros[0])} s)")
    return points, bad


def _false_alarms(run: _Run) -> list[str]:
    out = []
    first_clock = run.clocks[0][1] if run.sim and run.clocks else 0
    for t in run.zeros:
        now = run.ros(t)
        last = run.last_odom(t - 1)  # an /odom of the same instant may come after the tick
        since = now - (last if last is not None else first_clock)
        if since < round((run.timeout - EARLY_SLACK) * 1e9):
            out.append(f"a zero Twist at wall {_s(t)} s, ROS time {_s(now)} s, only "
                       f"{since / 1e9:.3f} s of ROS time after the last /odom (~timeout "
                       f"{run.timeout:g} s)")
    return out


def check_silent(facts: Facts) -> tuple[float, list[str]]:
    why = launch_problem(facts)
    if why:
        return 0.0, [why]
    run = _facts(facts)
    if any(_fired(run, a, b)[1] is None for a, b in _silences(facts, run)):
        return 0.0, ["the watchdog never fired in the odometry silence, so its silence elsewhere "
                     "proves nothing (see 4c.3)"]
    bad = _false_alarms(run)
    if not bad:
        return 15.0, []
    kind = facts.scenario.params["kind"]
    where = {"simulator": " (ROS time stands still while the simulator is paused)",
             "bag": " (ROS time stands still after the end of the bag)"}.get(kind, "")
    return 0.0, [f"{len(bad)} false alarm(s){where}: {bad[0]}"]


# -- 4c.5 the wall-time status line ------------------------------------------------------------

def check_status(facts: Facts) -> tuple[float, list[str]]:
    why = launch_problem(facts)
    if why:
        return 0.0, [why]
    run = _facts(facts)
    lines = []
    for t, _level, text in run.logs:
        m = STATUS_RE.search(text)
        if m:
            lines.append((t, float(m.group(1)), float(m.group(2))))
    want = int(DURATION)
    if abs(len(lines) - want) > 1:
        return 0.0, [f"{len(lines)} status lines 'wall=%.1f ros=%.1f' in {DURATION:g} s of wall "
                     f"time, one per wall second ({want} +- 1) wanted"]
    for (t0, _w0, _r0), (t1, _w1, _r1) in zip(lines, lines[1:]):
        if abs((t1 - t0) - 10**9) > 50_000_000:
            return 0.0, [f"status lines at wall {_s(t0)} s and {_s(t1)} s: one per second of "
                         "wall time wanted"]
    for t, wall, ros in lines:
        if abs(wall - t / 1e9) > STATUS_SLACK:
            return 0.0, [f"the status line at wall {_s(t)} s says wall={wall:.1f}"]
        if all(abs(ros - c / 1e9) > STATUS_SLACK for c in run.could_read(t)):
            return 0.0, [f"the status line at wall {_s(t)} s says ros={ros:.1f}, where ROS time "
                         f"was {_s(run.ros(t))} s"]
    return 10.0, []


# -- 4c.6 survives backward jumps --------------------------------------------------------------

def _jumps(run: _Run) -> list[tuple[int, int]]:
    """``(kernel ns, new ROS ns)`` of every backward jump of /clock."""
    return [(k, c) for (k, c), (_k0, c0) in zip(run.clocks[1:], run.clocks) if c < c0]


def _errors(run: _Run) -> list[str]:
    """The student's ERROR and FATAL lines (a failing callback is logged as an error)."""
    return [text[:160] for _t, level, text in run.logs if level >= 8]


def check_jumps(facts: Facts) -> tuple[float, list[str]]:
    why = launch_problem(facts)
    if why:
        return 0.0, [why]
    run = _facts(facts)
    if not run.beats:
        return 0.0, ["no heartbeat on /heartbeat"]
    period = round((2.0 / run.rate + JUMP_SLACK) * 1e9)
    for k, c in _jumps(run):
        if not any(t >= k and c <= run.ros(t) <= c + period for t, _s in run.beats):
            return 0.0, [f"/clock jumped back to {_s(c)} s at wall {_s(k)} s and no heartbeat "
                         f"followed within {period / 1e9:.2f} s of ROS time (Rate(reset=True), or "
                         "catch ROSTimeMovedBackwardsException)"]
    last = run.beats[-1][0]
    end_ros, last_ros = run.ros(run.end_ns - 1), run.ros(last)
    if end_ros - last_ros > period:
        return 0.0, [f"the last heartbeat was at wall {_s(last)} s (ROS {_s(last_ros)} s); ROS "
                     f"time went on to {_s(end_ros)} s"]
    errors = _errors(run)
    if errors:
        return 0.0, [f"your node logged an error: {errors[0]}"]
    return 10.0, []


# -- 4c.7 nothing before the first /clock ------------------------------------------------------

def check_first_clock(facts: Facts) -> tuple[float, list[str]]:
    why = launch_problem(facts)
    if why:
        return 0.0, [why]
    run = _facts(facts)
    if not run.beats:
        return 0.0, ["no heartbeat on /heartbeat"]
    zero = [t for t, s in run.beats if s == 0]
    if zero:
        return 0.0, [f"a heartbeat stamped 0 at wall {_s(zero[0])} s: ROS time is zero before "
                     "the first /clock (wait for it: rate.sleep() first, then publish)"]
    if run.sim and run.clocks:
        first = run.clocks[0][0]
        early = [t for t, _s in run.beats if t < first]
        if early:
            return 0.0, [f"a heartbeat at wall {_s(early[0])} s, before the first /clock at "
                         f"{_s(first)} s"]
    return 10.0, []


EX4C = CourseExercise(
    id="ex4c_time",
    title="ROS time: a watchdog with a heartbeat on Rate, a ROS-time odometry watchdog and a "
          "wall-time status line",
    criteria=(
        Criterion("4c.1", "heartbeat at ~rate in ROS time (10 s of ROS time: 10 x rate +- 1)",
                  20, check_rate, credit=CREDIT),
        Criterion("4c.2", "heartbeat stamps are the node's ROS time at publish (in ns)", 15,
                  check_stamps, credit=CREDIT),
        Criterion("4c.3", "the watchdog fires on ROS-time odometry silence (zero Twists at 10 Hz "
                  "from ~timeout + 0.12 s of ROS time; 16) and warns once (4)", 20, check_fires,
                  credit=CREDIT),
        Criterion("4c.4", "the watchdog is silent while ROS time stands still (paused simulator, "
                  "end of the bag) and while /odom arrives", 15, check_silent, credit=CREDIT),
        Criterion("4c.5", "a status line 'wall=%.1f ros=%.1f' every second of wall time", 10,
                  check_status, credit=CREDIT),
        Criterion("4c.6", "survives backward time jumps (rosbag --loop, a restarted simulator): "
                  "heartbeats go on, no error", 10, check_jumps, credit=CREDIT),
        Criterion("4c.7", "nothing published before the first /clock (no heartbeat stamped 0)",
                  10, check_first_clock, credit=CREDIT),
    ),
    scripts=(),
    duration=DURATION,
    build=build,
    scenarios=scenarios,
    required_files=(LAUNCH,),
    launch=LAUNCH,
    setup=setup,
)
