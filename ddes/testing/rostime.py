"""A hypothesis state machine for ROS time: rates, timers and sleeps under a ``/clock`` that
runs, pauses, jumps forward, jumps back and runs at any real-time factor.

The machine builds a world where a clock node publishes ``rosgraph_msgs/Clock``
and every other node runs on simulated time (``use_sim_time``), and drives
the clock through random schedules of:

* ``tick(dt, count, rtf)``: ``count`` messages, each ``dt`` seconds of ROS time
  later, ``dt / rtf`` seconds of wall (kernel) time apart: a simulator or
  ``rosbag play --clock -r rtf``;
* ``pause(seconds)``: wall time passes, no ``/clock`` (a paused simulator);
* ``jump(seconds)`` / ``jump_back(seconds)``: one message that far ahead /
  behind (a simulator reset, ``rosbag play --loop``).

Probes on their own node check rospy's rules after every step (docs/time.md,
``rospy/timer.py``, ``rospy/rostime.py``):

* **Timer** (``ddes.Timer``, a 0.11 s period, so its Rate sleeps 109,999,999
  ns): the k-th callback has ``current_expected = period · k`` from its
  creation (never re-aligned); ``last_expected`` / ``last_real`` are the
  previous call's; ``current_real`` is the clock when it runs; it never runs
  early while time has not jumped back (``current_real >= current_expected``,
  less the Rate's truncation of one ns per period); and it is not late: once
  the clock has passed the previous call by a period, it has run again.
* **Rate** (``ddes.Rate``, 10 Hz, ``reset=False``) and **sleep**
  (``node.sleep(0.25)``): a sleep returns once the clock reaches its target
  (``last_time + period``; ``start + d``), not before and not later; it raises
  ``ROSTimeMovedBackwardsException`` exactly when the clock jumped back below
  the sleep's start while it slept.

Your node is built by ``make_node(world, node)`` on a simulated-time node;
``check(subject, node)`` (what ``make_node`` returned, and the node) is your
property, called after every step (raise AssertionError or return False);
an exception in one of your node's callbacks fails too.  A failure shrinks
(hypothesis, then step deletion) and prints a one-line
:func:`replay_time_schedule` call; :meth:`TimeReplay.plot` draws the clock
against wall time with the callbacks, the violating step marked.
See docs/testing.md.
"""

from __future__ import annotations

import re
import unittest
from collections.abc import Callable, Generator
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, ClassVar

from hypothesis import HealthCheck, settings
from hypothesis import strategies as st
from hypothesis.stateful import (
    RuleBasedStateMachine,
    initialize,
    invariant,
    rule,
    run_state_machine_as_test,
)

from ddes.errors import DdesTypeError, DdesValueError, ROSTimeMovedBackwardsException
from ddes.graph.timer import Timer, TimerEvent, rospy_timer_sleep_ns
from ddes.msg import get_message_class
from ddes.testing._draws import same_draws_everywhere
from ddes.testing._replay import Source, call_text, factory_name, mark_violation
from ddes.time.rate import Rate
from ddes.time.rostime import Duration, Time
from ddes.time.units import duration_to_ns, ns_to_sec
from ddes.world import World

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

    from ddes.graph.node import Node

__all__ = [
    "TimeProtocolMachine",
    "TimeReplay",
    "TimeViolation",
    "replay_time_schedule",
    "run_time_machine",
]

#: ``make_node(world, node)``: builds the node under test on ``node`` (simulated time).
NodeFactory = Callable[[World, "Node"], object]
#: ``check(subject, node)``: the property; raise AssertionError or return False when broken.
Check = Callable[[Any, "Node"], object]
Step = tuple[object, ...]

#: ROS time (seconds) between two ``/clock`` messages of a ``tick``.
TICKS: tuple[float, ...] = (0.01, 0.001, 0.05, 0.1)
#: Real-time factors of a ``tick`` (ROS seconds per wall second).
RTFS: tuple[float, ...] = (1.0, 0.5, 2.0, 10.0)
#: Sizes (seconds) of a jump, forward or back.
JUMPS: tuple[float, ...] = (0.05, 0.3, 1.0, 5.0)
#: Wall seconds of a pause.
PAUSES: tuple[float, ...] = (0.05, 0.5, 2.0)
TIMER_PERIOD = 0.11
RATE_HZ = 10.0
SLEEP = 0.25
_RULES = ("tick", "pause", "jump", "jump_back")
_FIRST_CLOCK_NS = 1_000_000_000  # where the clock starts (one second: never zero)


class TimeViolation(AssertionError):
    """ROS time broke rospy's rules, or your node broke its property; the message says how.

    Attributes as :class:`ddes.testing.actions.ProtocolViolation`.
    """

    problem: str = ""
    seed: int = 0
    steps: list[Step]
    step: int = 0
    t_ns: int = 0
    replay: str = ""


@dataclass
class _Sleep:
    """One Rate.sleep or sleep of a probe."""

    what: str
    start: int  # the clock when it began
    target: int  # the clock it waits for
    pub: int  # publications before it began
    kernel: int
    end: int | None = None
    raised: bool = False
    pub_end: int = 0


def _norm(text: str) -> str:
    return re.sub(r"\S*\d\S*", "#", text)


class TimeProtocolMachine(RuleBasedStateMachine):
    """The ROS-time machine; make one with :meth:`machine_for` or :meth:`for_node`."""

    make_node: ClassVar[NodeFactory | None] = None
    check: ClassVar[Check | None] = None

    def __init__(self) -> None:
        super().__init__()
        self.world: World | None = None
        self.seed = 0
        self.steps: list[Step] = []
        self.spans: list[tuple[int, int]] = []
        self.schedule: list[str] = []
        self.clock_ns = 0
        #: (kernel ns, clock ns) of every /clock message.
        self.published: list[tuple[int, int]] = []
        self.fires: list[tuple[TimerEvent, int, int, int]] = []  # event, clock, kernel, pubs
        self.sleeps: list[_Sleep] = []
        self.violations: list[str] = []
        self._failed = False
        self._in_teardown = False
        self._step_start = 0

    # -- set-up -----------------------------------------------------------------------------
    @classmethod
    def machine_for(cls, make_node: NodeFactory | None = None, check: Check | None = None,
                    ) -> type[TimeProtocolMachine]:
        """A machine class for your node (both optional: the probes run anyway)."""
        for what, fn in (("make_node", make_node), ("check", check)):
            if fn is not None and not callable(fn):
                raise DdesTypeError(f"{what} must be callable, got {fn!r}")

        class Machine(cls):  # type: ignore[valid-type,misc]
            pass

        Machine.make_node = None if make_node is None else staticmethod(make_node)
        Machine.check = None if check is None else staticmethod(check)
        Machine.__name__ = Machine.__qualname__ = "TimeMachine_" + (
            getattr(make_node, "__name__", "probes"))
        return Machine

    @classmethod
    def for_node(cls, make_node: NodeFactory | None = None, check: Check | None = None, *,
                 max_examples: int = 50, stateful_step_count: int = 20,
                 **settings_kw: Any) -> type[unittest.TestCase]:
        """A ``unittest.TestCase`` class (pytest collects it) running the machine."""
        machine = cls.machine_for(make_node, check)

        class Case(machine.TestCase):  # type: ignore[name-defined,misc]
            def runTest(self) -> None:  # noqa: N802 - unittest's name
                try:
                    super().runTest()
                except TimeViolation as exc:
                    raise _shrink_further(machine, exc) from None

        Case.settings = _settings(max_examples, stateful_step_count, **settings_kw)
        Case.__name__ = Case.__qualname__ = machine.TestCase.__name__
        return Case

    @initialize(seed=st.integers(0, 2**16))
    def start(self, seed: int) -> None:
        """Build the world: the clock node, the probes and your node; let them connect."""
        self.seed = seed
        world = self.world = World(seed, strict=False)
        self.schedule.append(f"world seed {seed}")
        clock_node = world.create_node("clock", use_sim_time=False)
        self._clock_cls = get_message_class("rosgraph_msgs/Clock")
        self._pub = clock_node.advertise("/clock", self._clock_cls, queue_size=1)
        probe = self.probe = world.create_node("time_probe", use_sim_time=True)
        Timer(probe, TIMER_PERIOD, self._on_timer)
        self._timer_period = duration_to_ns(TIMER_PERIOD, "period")
        self._timer_eps = self._timer_period - rospy_timer_sleep_ns(self._timer_period)
        probe.process(self._rate_loop())
        probe.process(self._sleep_loop())
        self.user_node = world.create_node("node_under_test", use_sim_time=True)
        cls = type(self)
        self.subject = None if cls.make_node is None else cls.make_node(world, self.user_node)
        world.run_for(0.01)  # connections form (world.connect_delay_ns)
        self._publish(_FIRST_CLOCK_NS)

    def _publish(self, clock_ns: int) -> None:
        assert self.world is not None
        secs, nsecs = divmod(clock_ns, 1_000_000_000)
        self.clock_ns = clock_ns
        self.published.append((self.world.now, clock_ns))
        self._pub.publish(self._clock_cls(clock=Time(secs, nsecs)))
        self.world.run_for(0)

    # -- the probes ---------------------------------------------------------------------------
    def _on_timer(self, event: TimerEvent) -> None:
        assert self.world is not None
        self.fires.append((event, self.probe.clock.now_ns(), self.world.now, len(self.published)))

    def _probe_sleep(self, what: str, target: int, event: Any) -> Generator[Any, Any, None]:
        assert self.world is not None
        now = self.probe.clock.now_ns()
        rec = _Sleep(what, now, target, len(self.published), self.world.now)
        self.sleeps.append(rec)
        try:
            yield event
        except ROSTimeMovedBackwardsException:
            rec.raised = True
        rec.end = self.probe.clock.now_ns()
        rec.pub_end = len(self.published)

    def _rate_loop(self) -> Generator[Any, Any, None]:
        yield self.probe.clock.wait_valid()
        rate = Rate(self.probe, RATE_HZ)
        while True:
            curr = self.probe.clock.now_ns()
            target = min(rate.last_time_ns, curr) + rate._period
            yield from self._probe_sleep("Rate(10).sleep()", target, rate.sleep())

    def _sleep_loop(self) -> Generator[Any, Any, None]:
        yield self.probe.clock.wait_valid()
        d = duration_to_ns(SLEEP, "sleep")
        while True:
            target = self.probe.clock.now_ns() + d
            yield from self._probe_sleep(f"sleep({SLEEP})", target, self.probe.sleep(SLEEP))

    # -- rules ------------------------------------------------------------------------------
    def _begin(self, *step: object) -> None:
        assert self.world is not None
        self.steps.append(tuple(step))
        self._step_start = self.world.now
        self.schedule.append(f"{len(self.steps):3d}. wall {ns_to_sec(self.world.now):9.4f}s  "
                             f"ROS {ns_to_sec(self.clock_ns):9.4f}s  "
                             + " ".join(str(s) for s in step))

    def _end(self) -> None:
        assert self.world is not None
        self.spans.append((self._step_start, self.world.now))

    @rule(dt=st.sampled_from(TICKS), count=st.integers(1, 10), rtf=st.sampled_from(RTFS))
    def tick(self, dt: float, count: int, rtf: float) -> None:
        """``count`` clock messages ``dt`` apart in ROS time, ``dt / rtf`` apart in wall time."""
        assert self.world is not None
        self._begin("tick", dt, count, rtf)
        step = duration_to_ns(dt, "dt")
        wall = duration_to_ns(dt / rtf, "wall")
        for _ in range(count):
            self.world.run_for(Duration(0, wall))
            self._publish(self.clock_ns + step)
        self._end()

    @rule(seconds=st.sampled_from(PAUSES))
    def pause(self, seconds: float) -> None:
        """Wall time passes; no /clock (the clock is paused)."""
        assert self.world is not None
        self._begin("pause", seconds)
        self.world.run_for(seconds)
        self._end()

    @rule(seconds=st.sampled_from(JUMPS))
    def jump(self, seconds: float) -> None:
        """The clock jumps forward."""
        self._begin("jump", seconds)
        self._publish(self.clock_ns + duration_to_ns(seconds, "jump"))
        self._end()

    @rule(seconds=st.sampled_from(JUMPS))
    def jump_back(self, seconds: float) -> None:
        """The clock jumps back (never to zero: a zero clock means 'no time yet')."""
        self._begin("jump_back", seconds)
        self._publish(max(self.clock_ns - duration_to_ns(seconds, "jump"), 1_000_000))
        self._end()

    # -- checks -----------------------------------------------------------------------------
    def _back_jumps(self, first: int, last: int) -> list[int]:
        """Publications ``first..last-1`` that went back."""
        return [i for i in range(max(first, 1), last)
                if self.published[i][1] < self.published[i - 1][1]]

    def _check_timer(self) -> None:
        period, eps = self._timer_period, self._timer_eps
        prev: TimerEvent | None = None
        for k, (ev, clock, _kernel, pubs) in enumerate(self.fires, start=1):
            ce, cr = ev._ce, ev._cr
            if ce != k * period:
                self.violations.append(
                    f"Timer({TIMER_PERIOD}): call {k} has current_expected "
                    f"{ns_to_sec(ce or 0):.9f}s, not {ns_to_sec(k * period):.9f}s (created at 0, "
                    "it advances by exactly one period per call, never re-aligned)")
                return
            want = (None, None) if prev is None else (prev._ce, prev._cr)
            if (ev._le, ev._lr) != want:
                self.violations.append(f"Timer({TIMER_PERIOD}): call {k} has last_expected/"
                                       f"last_real {ev._le}/{ev._lr} ns, not the previous call's "
                                       f"{want}")
                return
            if cr != clock:
                self.violations.append(f"Timer({TIMER_PERIOD}): call {k} has current_real "
                                       f"{cr} ns but the clock read {clock} ns")
                return
            if not self._back_jumps(0, pubs) and cr is not None and cr < ce - k * eps:
                self.violations.append(
                    f"Timer({TIMER_PERIOD}): call {k} ran early, at ROS time "
                    f"{ns_to_sec(cr):.9f}s for current_expected {ns_to_sec(ce):.9f}s, "
                    "and time never went back")
                return
            prev = ev
        # not late: once the clock passed the last call (or the first /clock) by a period
        if self.fires:
            base, since = self.fires[-1][1], self.fires[-1][3]
        else:
            base, since = _FIRST_CLOCK_NS, 1
        if not self._back_jumps(since, len(self.published)) and \
                self.clock_ns >= base + period:
            self.violations.append(
                f"Timer({TIMER_PERIOD}): the clock reads {ns_to_sec(self.clock_ns):.9f}s, a "
                f"period past the last call at {ns_to_sec(base):.9f}s, and the timer has not run")

    def _check_sleeps(self) -> None:
        for rec in self.sleeps:
            last = rec.pub_end if rec.end is not None else len(self.published)
            back = [i for i in range(rec.pub, last) if self.published[i][1] < rec.start]
            label = (f"{rec.what} from ROS time {ns_to_sec(rec.start):.9f}s (target "
                     f"{ns_to_sec(rec.target):.9f}s)")
            if rec.end is None:
                if back:
                    self.violations.append(f"{label}: the clock jumped back below its start to "
                                           f"{ns_to_sec(self.published[back[0]][1]):.9f}s and it "
                                           "did not raise ROSTimeMovedBackwardsException")
                elif self.clock_ns >= rec.target:
                    self.violations.append(f"{label}: the clock reads "
                                           f"{ns_to_sec(self.clock_ns):.9f}s and it has not "
                                           "returned")
                continue
            if rec.raised and not back:
                self.violations.append(f"{label}: raised ROSTimeMovedBackwardsException at "
                                       f"{ns_to_sec(rec.end):.9f}s, but the clock never went "
                                       "below its start")
            elif not rec.raised and back:
                self.violations.append(f"{label}: returned at {ns_to_sec(rec.end):.9f}s "
                                       "although the clock jumped back below its start")
            elif not rec.raised and rec.end < rec.target:
                self.violations.append(f"{label}: returned early, at "
                                       f"{ns_to_sec(rec.end):.9f}s")

    @invariant()
    def time_holds(self) -> None:
        """The probes' rules, your node's callbacks and your property, after every step."""
        if self.world is None:
            return
        self._check_timer()
        self._check_sleeps()
        self.sleeps = [s for s in self.sleeps if s.end is None]  # each checked once, when done
        if self.violations:
            self._fail(self.violations[0])
        errors = [e for e in self.world.callback_errors if e[0] == self.user_node.name]
        if errors:
            self._fail(f"a callback of your node raised: {errors[0][1]}: {errors[0][2]!r}")
        cls = type(self)
        if cls.check is not None:
            try:
                ok = cls.check(self.subject, self.user_node)
            except AssertionError as exc:
                first = str(exc).splitlines()[0] if str(exc) else "assertion failed"
                self._fail(f"your check failed: {first}")
            else:
                if ok is False:
                    self._fail("your check returned False")

    def replay_call(self) -> str:
        cls = type(self)
        kwargs: dict[str, object] = {"seed": self.seed}
        if cls.make_node is not None:
            kwargs["make_node"] = Source(factory_name(cls.make_node, "make_node"))
        if cls.check is not None:
            kwargs["check"] = Source(factory_name(cls.check, "check"))
        return call_text("replay_time_schedule", [self.steps], kwargs)

    def _fail(self, problem: str) -> None:
        self._failed = True
        assert self.world is not None
        lines = ["ROS time went wrong:", f"  {problem}", "",
                 f"replay: world seed {self.seed}; clock schedule (step, wall and ROS time "
                 "before it, what):"]
        lines += [f"  {s}" for s in self.schedule]
        replay = self.replay_call()
        lines += ["", "replay it (ddes.testing.rostime):", f"  {replay}"]
        exc = TimeViolation("\n".join(lines))
        exc.problem, exc.seed, exc.steps = problem, self.seed, list(self.steps)
        exc.step = len(self.steps) if self._in_teardown else len(self.steps) - 1
        exc.t_ns, exc.replay = self.world.now, replay
        raise exc


def _settings(max_examples: int, stateful_step_count: int, **kw: Any) -> settings:
    kw.setdefault("deadline", None)
    kw.setdefault("suppress_health_check", [HealthCheck.too_slow, HealthCheck.data_too_large])
    return settings(max_examples=max_examples, stateful_step_count=stateful_step_count, **kw)


def run_time_machine(make_node: NodeFactory | None = None, check: Check | None = None, *,
                     max_examples: int = 50, stateful_step_count: int = 20,
                     **settings_kw: Any) -> None:
    """Run the machine now; raises :class:`TimeViolation` (shrunk) on a failure."""
    machine = TimeProtocolMachine.machine_for(make_node, check)
    try:
        with same_draws_everywhere():
            run_state_machine_as_test(machine, settings=_settings(max_examples, stateful_step_count,
                                                                  **settings_kw))
    except TimeViolation as exc:
        raise _shrink_further(machine, exc) from None


def _shrink_further(machine: type[TimeProtocolMachine], exc: TimeViolation) -> TimeViolation:
    """Delete the steps the failure does not need (see ddes.testing.actions)."""
    steps, best = list(exc.steps), exc
    for i in reversed(range(len(steps))):
        trial = steps[:i] + steps[i + 1:]
        v = _replay(machine, trial, best.seed).violation
        if v is not None and _norm(v.problem) == _norm(exc.problem):
            steps, best = trial, v
    return best


@dataclass
class TimeReplay:
    """One schedule run again by :func:`replay_time_schedule` (see ActionReplay)."""

    world: World
    steps: list[Step]
    violation: TimeViolation | None
    spans: list[tuple[int, int]] = field(default_factory=list)
    published: list[tuple[int, int]] = field(default_factory=list)
    fires: list[tuple[int, int]] = field(default_factory=list)  # (kernel, clock)

    @property
    def step(self) -> int | None:
        return None if self.violation is None else self.violation.step

    def raise_violation(self) -> None:
        if self.violation is not None:
            raise self.violation

    def plot(self, ax: Axes | None = None) -> Figure:
        """ROS time (the ``/clock`` messages) against wall time, the probe timer's calls as
        dots, the violating step marked."""
        from matplotlib.figure import Figure

        if ax is None:
            fig = Figure(figsize=(8.0, 3.5))
            ax = fig.add_subplot(1, 1, 1)
        else:
            fig = ax.figure  # type: ignore[assignment]
        xs = [ns_to_sec(k) for k, _c in self.published]
        ys = [ns_to_sec(c) for _k, c in self.published]
        ax.step(xs + [ns_to_sec(self.world.now)], ys + ys[-1:], where="post", color="#4c9be8",
                label="/clock")
        ax.plot([ns_to_sec(k) for k, _c in self.fires], [ns_to_sec(c) for _k, c in self.fires],
                "o", markersize=3, color="#2e9d4f", label=f"Timer({TIMER_PERIOD}) calls")
        ax.set_xlabel("wall (kernel) time [s]")
        ax.set_ylabel("ROS time [s]")
        ax.legend(loc="upper left", fontsize=7, frameon=False)
        v = self.violation
        if v is not None:
            start = self.spans[v.step][0] if 0 <= v.step < len(self.spans) else (
                self.spans[-1][1] if self.spans else 0)
            what = "final check" if v.step >= len(self.steps) else \
                " ".join(str(s) for s in self.steps[v.step])
            mark_violation(ax, ns_to_sec(start), ns_to_sec(v.t_ns),
                           f"step {v.step}: {what}\n{v.problem[:80]}")
        fig.tight_layout()
        return fig


def replay_time_schedule(steps: list[Step], seed: int = 0, *,
                         make_node: NodeFactory | None = None,
                         check: Check | None = None) -> TimeReplay:
    """Run a schedule (as a :class:`TimeViolation` prints it) again, with every check."""
    return _replay(TimeProtocolMachine.machine_for(make_node, check), steps, seed)


def _replay(machine_cls: type[TimeProtocolMachine], steps: list[Step], seed: int) -> TimeReplay:
    m = machine_cls()
    violation: TimeViolation | None = None
    try:
        m.start(seed)
        m.time_holds()
        for step in steps:
            kind, args = str(step[0]), step[1:]
            if kind not in _RULES:
                raise DdesValueError(f"unknown step {step!r}: a step is one of {_RULES}")
            getattr(m, kind)(*args)
            m.time_holds()
    except TimeViolation as exc:
        violation = exc
    assert m.world is not None
    fires = [(kernel, clock) for _ev, clock, kernel, _p in m.fires]
    return TimeReplay(m.world, list(steps), violation, list(m.spans), list(m.published), fires)
