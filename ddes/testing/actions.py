"""A hypothesis state machine that checks ANY action server against the actionlib protocol.

Point it at a server factory ``make_server(world, node) -> server`` (a
student's server, say) and it drives the server through random schedules:
goals, cancels of one goal, of all goals and of goals before a stamp, newer
goals that preempt older ones, latency changes on the five topics
(``world.set_link``) and the passing of simulated time.  A protocol client
(:class:`~ddes.actionlib.ActionClient`) sends the goals; a spy node records
every status array, result and feedback on the wire.  After every step it
checks:

1. **only legal transitions**: each goal's statuses, in the order the status
   arrays carry them, follow the server goal table; no ``LOST`` on the wire;
   the server recorded no illegal goal-handle call (``action.server.illegal``)
   and raised no exception in a callback; the client saw no invalid transition;
2. **terminal states are final**: after a terminal status (or the result) no
   array shows the goal in another status;
3. **exactly one result per goal**: never two results for one goal id; at the
   end (after cancelling everything and letting ``settle`` seconds pass) every
   goal the server reported has its one result, placeholders of cancels
   excepted;
4. **client and server agree**: a goal the client has DONE has the result's
   status; every status the client reports was on the wire;
5. **LOST only when the protocol says so**: a goal leaves the status array
   only once it has been terminal for longer than ``status_list_timeout`` (or
   was a cancel placeholder), and the client marks a goal LOST only after the
   server dropped it;
6. **preemption is honoured**: once the server has taken a cancel request
   for a goal (the status array shows it PREEMPTING or RECALLING) or a
   SimpleActionServer has asked its callback to preempt it for a newer goal
   (``action.simple.preempt_request``), the goal ends within
   ``preempt_timeout`` seconds (default 5) of the server's time, as the
   result's stamp says.  actionlib lets a server refuse a cancel only by
   finishing the goal anyway; a server that ignores cancel requests and
   keeps working fails here.  ``preempt_timeout=None`` turns the check off
   (for a server whose goals may legitimately run on after a cancel).

The schedule has no mandatory step: every step is a rule hypothesis may
drop, so a failure shrinks to the shortest schedule that still fails.  The
machine never draws a step that would change nothing (a *no-op*: a latency
set to the value it has, a zero-length ``advance`` with nothing due), so no
shrunk schedule holds one; a replayed schedule marks its no-ops.  Hypothesis prints it as the steps of
the machine (``state.send_goal(goal={...})``, with ``print_blob`` the
``@reproduce_failure`` line), and the :class:`ProtocolViolation` message holds
the world seed, the numbered schedule with simulated times, the last wire
events, and a one-line Python call that replays it::

    replay_action_schedule(make_server, [('send_goal', {'order': 3}), ('advance', 2.0)], seed=0,
                           action='actionlib_tutorials/FibonacciAction', ns='/fibonacci')

:func:`replay_action_schedule` runs the schedule again, step by step with the
same checks, and returns an :class:`ActionReplay`: the world (its trace), the
violation, the violating step, and :meth:`ActionReplay.plot`, the goal
timeline (:func:`ddes.actionlib.plot_goals`) with the violating step marked.

Use it from pytest::

    from ddes.testing.actions import ActionProtocolMachine

    def make_server(world, node):
        return MyServer(node)            # anything on the five topics of `ns`

    TestMyServer = ActionProtocolMachine.for_server(
        make_server, action="actionlib_tutorials/FibonacciAction", ns="/fibonacci")

or run it directly: ``run_protocol_machine(make_server, max_examples=50)``.
See docs/testing.md.
"""

from __future__ import annotations

import re
import unittest
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from types import MappingProxyType
from typing import TYPE_CHECKING, Any, ClassVar

from hypothesis import HealthCheck, settings
from hypothesis import strategies as st
from hypothesis.stateful import (
    RuleBasedStateMachine,
    initialize,
    invariant,
    precondition,
    rule,
    run_state_machine_as_test,
)

from ddes.actionlib._common import ActionTypes
from ddes.actionlib.client import ActionClient, ClientGoalHandle
from ddes.actionlib.states import (
    SERVER_STATES,
    SERVER_TRANSITIONS,
    TERMINAL_STATUSES,
    CommState,
    GoalStatus,
)
from ddes.errors import DdesTypeError, DdesValueError
from ddes.graph.world import World
from ddes.msg import dict_to_message, get_message_class, message_to_dict
from ddes.msg.message import Message
from ddes.testing._draws import same_draws_everywhere
from ddes.testing._replay import Source, call_text, factory_name, mark_violation
from ddes.testing.strategies import messages
from ddes.time.units import duration_to_ns, ns_to_sec, time_to_ns

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

    from ddes.graph.node import Node
    from ddes.kernel.trace import TraceEvent

__all__ = [
    "LATENCIES",
    "STEPS",
    "ActionProtocolMachine",
    "ActionReplay",
    "ProtocolViolation",
    "Step",
    "replay_action_schedule",
    "run_protocol_machine",
]

#: ``make_server(world, node) -> server``: builds the action server under test on ``node``.
ServerFactory = Callable[[World, "Node"], object]
#: What a goal strategy draws: a ``FooGoal`` message, or a dict of its fields.
GoalDraw = Message | Mapping[str, object]
#: The latencies (seconds) the machine puts on the five topics.
LATENCIES: tuple[float, ...] = (0.0, 0.001, 0.02, 0.1, 0.3)
#: The spans of simulated time (seconds) one ``advance`` step lets pass (``run_due_events`` is
#: the zero-length step: it runs what is due now, and only when something is).
STEPS: tuple[float, ...] = (0.01, 0.05, 0.2, 0.5, 1.0, 2.0)
_TOPICS = ("goal", "cancel", "status", "feedback", "result")
#: One step of a schedule, as the replay call writes it: ``('send_goal', {'order': 2})``,
#: ``('cancel_goal', 0)``, ``('cancel_all_goals',)``, ``('cancel_goals_at_and_before_time', 1)``,
#: ``('set_latency', 'status', 0.1)``, ``('advance', 2.0)``.
Step = tuple[object, ...]
#: Slack (ns) for a result still on its way when the preemption deadline is checked.
_IN_FLIGHT_NS = 1_000_000_000


def _closure() -> Mapping[GoalStatus, frozenset[GoalStatus]]:
    """For each server status, the statuses reachable in one or more legal transitions."""
    out: dict[GoalStatus, frozenset[GoalStatus]] = {}
    for start in SERVER_STATES:
        seen: set[GoalStatus] = set()
        todo = [start]
        while todo:
            s = todo.pop()
            for target in SERVER_TRANSITIONS[s].values():
                if target is not None and target not in seen:
                    seen.add(target)
                    todo.append(target)
        out[start] = frozenset(seen)
    return MappingProxyType(out)


#: Read-only cache of the server table's transitive closure (computed once from pure data).
_REACHABLE = _closure()


class ProtocolViolation(AssertionError):
    """The server (or the wire) broke the actionlib protocol; the message says how and when.

    Attributes: ``problem`` (what broke), ``seed`` (the world seed), ``steps``
    (the schedule, as :data:`Step` tuples), ``noops`` (indices of steps that
    changed nothing), ``step`` (the index of the
    violating step in ``steps``; ``len(steps)`` when the final check after the
    schedule failed), ``t_ns`` (when it was seen) and ``replay`` (the call
    that replays it).
    """

    problem: str = ""
    seed: int = 0
    steps: list[Step]
    noops: list[int]
    step: int = 0
    t_ns: int = 0
    replay: str = ""


def _name(status: int) -> str:
    return GoalStatus(status).name if 0 <= status <= GoalStatus.LOST else f"<invalid {status}>"


@dataclass
class _Goal:
    """What the spy saw of one goal id."""

    arrays: list[tuple[int, int, int]] = field(default_factory=list)  # (arrival, stamp, status)
    results: list[tuple[int, int, int]] = field(default_factory=list)
    present: bool = False
    dropped: tuple[int, int] | None = None  # (arrival, stamp) of the first array without it
    asked: int | None = None  # stamp of the first array showing it PREEMPTING or RECALLING

    @property
    def placeholder(self) -> bool:
        """Only ever seen RECALLING, without a result: a cancel placeholder."""
        return not self.results and all(s == GoalStatus.RECALLING for _a, _t, s in self.arrays)

    def statuses(self) -> set[int]:
        return {s for _a, _t, s in self.arrays} | {s for _a, _t, s in self.results}


class _Spy:
    """A node that records the wire and checks each message as it arrives."""

    def __init__(self, world: World, ns: str, types: ActionTypes, timeout_ns: int) -> None:
        self.world = world
        self.timeout_ns = timeout_ns
        self.goals: dict[str, _Goal] = {}
        self.violations: list[str] = []
        self.events: list[str] = []
        node = world.create_node("protocol_spy", disable_rosout=True)
        status_cls = get_message_class("actionlib_msgs/GoalStatusArray")
        node.subscribe(ns + "/status", status_cls, self._status)
        node.subscribe(ns + "/result", types.action_result, self._result)
        node.subscribe(ns + "/feedback", types.action_feedback, self._feedback)

    def _log(self, text: str) -> None:
        self.events.append(f"{ns_to_sec(self.world.now):10.6f}s  {text}")
        del self.events[:-40]

    def _bad(self, text: str) -> None:
        self.violations.append(f"at {ns_to_sec(self.world.now):.6f}s: {text}")

    def _goal(self, gid: str) -> _Goal:
        g = self.goals.get(gid)
        if g is None:
            g = self.goals[gid] = _Goal()
        return g

    def _status(self, msg: Message) -> None:
        now, stamp = self.world.now, time_to_ns(msg.header.stamp)
        listed: dict[str, int] = {}
        for st_ in msg.status_list:
            listed.setdefault(st_.goal_id.id, st_.status)
        self._log("status " + ", ".join(f"{gid}={_name(s)}" for gid, s in listed.items()))
        for gid, status in listed.items():
            g = self._goal(gid)
            self._check_status(gid, g, status, stamp)
            if g.dropped is not None:
                self._bad(f"goal {gid} is back in the status array after it was dropped")
            g.arrays.append((now, stamp, status))
            g.present = True
            if g.asked is None and status in (GoalStatus.PREEMPTING, GoalStatus.RECALLING):
                g.asked = stamp
        for gid, g in self.goals.items():
            if g.present and gid not in listed:
                g.present = False
                g.dropped = (now, stamp)
                self._check_drop(gid, g, stamp)

    def _check_status(self, gid: str, g: _Goal, status: int, stamp: int) -> None:
        if not 0 <= status < GoalStatus.LOST:
            self._bad(f"goal {gid}: status {_name(status)} on the wire (LOST is client-only; "
                      "valid statuses are 0..8)")
            return
        new = GoalStatus(status)
        if g.arrays:
            old = GoalStatus(g.arrays[-1][2])
            if new != old and new not in _REACHABLE[old]:
                what = "terminal state is not final" if old in TERMINAL_STATUSES else \
                    "illegal transition"
                self._bad(f"goal {gid}: {what}: the status array went {old.name} -> {new.name}")
        for _arr, rstamp, rstatus in g.results:
            if stamp > rstamp and new != rstatus:
                self._bad(f"goal {gid}: the status array says {new.name} after its result "
                          f"({_name(rstatus)}, stamped {ns_to_sec(rstamp):.6f}s)")

    def _check_drop(self, gid: str, g: _Goal, stamp: int) -> None:
        if g.placeholder:
            return
        if not g.results:
            self._bad(f"goal {gid} left the status array without a result (last status "
                      f"{_name(g.arrays[-1][2])})")
            return
        rstamp = g.results[0][1]
        if stamp - rstamp <= self.timeout_ns:
            self._bad(f"goal {gid} left the status array {ns_to_sec(stamp - rstamp):.6f}s after "
                      f"its result; it must stay status_list_timeout = "
                      f"{ns_to_sec(self.timeout_ns)}s")

    def _result(self, msg: Message) -> None:
        gid, status = msg.status.goal_id.id, msg.status.status
        stamp = time_to_ns(msg.header.stamp)
        self._log(f"result {gid}={_name(status)}")
        g = self._goal(gid)
        if g.results:
            self._bad(f"goal {gid}: a second result ({_name(status)}) after "
                      f"{_name(g.results[0][2])}: every goal gets exactly one result")
        if status not in TERMINAL_STATUSES:
            self._bad(f"goal {gid}: result with the non-terminal status {_name(status)}")
        for _arr, astamp, astatus in g.arrays:
            if (astamp < stamp and 0 <= astatus < GoalStatus.LOST and status != astatus
                    and status not in _REACHABLE.get(GoalStatus(astatus), frozenset())):
                self._bad(f"goal {gid}: result {_name(status)} cannot follow the status "
                          f"{_name(astatus)} reported before it")
                break
        g.results.append((self.world.now, stamp, status))

    def _feedback(self, msg: Message) -> None:
        self._log(f"feedback {msg.status.goal_id.id}={_name(msg.status.status)}")
        if msg.status.status == GoalStatus.LOST:
            self._bad(f"goal {msg.status.goal_id.id}: feedback carries the status LOST")


class ActionProtocolMachine(RuleBasedStateMachine):
    """The protocol machine; make one for a server with :meth:`for_server` or :meth:`machine_for`.

    Class attributes set by :meth:`machine_for`: ``make_server``, ``action``
    (the ActionSpec), ``ns``, ``settle`` (seconds given at the end to finish
    every goal), ``preempt_timeout`` (seconds a goal may run on after a cancel
    or preempt request; None: no limit), ``server_node`` (the server node's name).
    """

    make_server: ClassVar[ServerFactory | None] = None
    action: ClassVar[type[Message] | None] = None
    ns: ClassVar[str] = ""
    settle: ClassVar[float] = 30.0
    preempt_timeout: ClassVar[float | None] = 5.0
    server_node: ClassVar[str] = "action_server"

    def __init__(self) -> None:
        super().__init__()
        self.world: World | None = None
        self.handles: list[ClientGoalHandle] = []
        self.schedule: list[str] = []
        #: The steps run so far, as :data:`Step` tuples (what the replay call lists).
        self.steps: list[Step] = []
        #: (start, end) kernel ns of each step; the seed of the world.
        self.spans: list[tuple[int, int]] = []
        #: Indices of the steps that changed nothing (no trace event, no link, no time).
        self.noops: list[int] = []
        self.seed = 0
        self._latency: dict[str, float] = {}
        self._acked: set[str] = set()
        self._failed = False
        self._in_teardown = False
        self._step_start = 0
        self._scanned = 0
        self._illegal: list[TraceEvent] = []
        self._invalid: list[TraceEvent] = []
        self._preempts: list[TraceEvent] = []

    # -- set-up ---------------------------------------------------------------------------
    @classmethod
    def machine_for(
        cls,
        make_server: ServerFactory,
        *,
        action: type[Message] | str | None = None,
        ns: str | None = None,
        goals: st.SearchStrategy[GoalDraw] | None = None,
        settle: float = 30.0,
        preempt_timeout: float | None = 5.0,
        name: str | None = None,
    ) -> type[ActionProtocolMachine]:
        """A machine class for ``make_server(world, node) -> server``.

        ``action`` (the ``FooAction`` class or its name) and ``ns`` default to
        the server's own ``ActionSpec`` and ``ns`` attributes (ddes's servers
        have them); ``goals`` draws the goals to send (default: any ``FooGoal``
        from :func:`ddes.testing.messages`); ``preempt_timeout`` is check 6.
        """
        if not callable(make_server):
            raise DdesTypeError(f"make_server must be callable (world, node) -> server, "
                                f"got {make_server!r}")
        if preempt_timeout is not None and not (
                isinstance(preempt_timeout, (int, float)) and preempt_timeout > 0):
            raise DdesValueError(f"preempt_timeout must be seconds > 0 or None, "
                                 f"got {preempt_timeout!r}")
        if action is None or ns is None:
            found_action, found_ns = _discover(make_server)
            action = found_action if action is None else action
            ns = found_ns if ns is None else ns
        types = ActionTypes.of(action)
        if not isinstance(ns, str) or not ns.startswith("/"):
            raise DdesValueError(f"ns must be the server's resolved action namespace "
                                 f"('/fibonacci'), got {ns!r}")
        goal_cls = types.goal
        strategy = goals if goals is not None else messages(goal_cls, max_size=3)
        goal_dicts = strategy.map(lambda g: g if isinstance(g, Mapping) else message_to_dict(g))

        class Machine(cls):  # type: ignore[valid-type,misc]
            @rule(goal=goal_dicts)
            def send_goal(self, goal: Mapping[str, object]) -> None:
                """Send a goal (given as a dict of its fields)."""
                self._begin("send_goal", dict(goal))
                self._send(dict_to_message(goal_cls, goal))
                self._end()

        Machine.make_server = staticmethod(make_server)
        Machine.action = types.spec
        Machine.ns = ns
        Machine.settle = float(settle)
        Machine.preempt_timeout = None if preempt_timeout is None else float(preempt_timeout)
        Machine.__name__ = Machine.__qualname__ = name or (
            f"ProtocolMachine_{getattr(make_server, '__name__', 'server')}")
        return Machine

    @classmethod
    def for_server(
        cls,
        make_server: ServerFactory,
        *,
        action: type[Message] | str | None = None,
        ns: str | None = None,
        goals: st.SearchStrategy[GoalDraw] | None = None,
        settle: float = 30.0,
        preempt_timeout: float | None = 5.0,
        max_examples: int = 50,
        stateful_step_count: int = 20,
        **settings_kw: Any,
    ) -> type[unittest.TestCase]:
        """A ``unittest.TestCase`` class (pytest collects it) running the machine on the server."""
        machine = cls.machine_for(make_server, action=action, ns=ns, goals=goals, settle=settle,
                                  preempt_timeout=preempt_timeout)

        class Case(machine.TestCase):  # type: ignore[name-defined,misc]
            def runTest(self) -> None:  # noqa: N802 - unittest's name
                try:
                    super().runTest()
                except ProtocolViolation as exc:
                    raise _shrink_further(machine, exc) from None

        Case.settings = _settings(max_examples, stateful_step_count, **settings_kw)
        Case.__name__ = Case.__qualname__ = machine.TestCase.__name__
        return Case

    @initialize(seed=st.integers(0, 2**16))
    def start(self, seed: int) -> None:
        """Build the world: the server, a protocol client and the spy; wait for the server."""
        make = type(self).make_server
        if make is None:
            raise DdesValueError("use ActionProtocolMachine.machine_for(make_server) or "
                                 "for_server(make_server): the base class has no server")
        world = self.world = World(seed)
        world.raise_callback_errors = False
        self.seed = seed
        types = ActionTypes.of(type(self).action)
        node = world.create_node(type(self).server_node)
        self.server = make(world, node)
        timeout = world.params.get_param(self.ns + "/status_list_timeout", 5.0)
        # as the server reads it (Duration.from_sec: truncated to whole ns)
        self.spy = _Spy(world, self.ns, types, duration_to_ns(float(timeout), "status_list_timeout"))
        self.client = ActionClient(world.create_node("protocol_client", disable_rosout=True),
                                   self.ns, types.spec)
        self.schedule.append(f"world seed {seed}")
        up = self.client.wait_for_server(5.0)
        world.run(until=up)
        world.run_for(0)  # what is due at this instant too: the schedule starts from a quiet world
        if up.value is not True:
            self._fail(f"the server did not come up on {self.ns} within 5 s (no status on "
                       f"{self.ns}/status, or not connected to goal/cancel/result/feedback)")

    # -- rules ------------------------------------------------------------------------------
    def _begin(self, *step: object) -> None:
        """A step starts: record it for the schedule and the replay call."""
        assert self.world is not None
        self.steps.append(tuple(step))
        self._step_start = self.world.now
        self._trace_len = len(self.world.trace)
        self._due = self.world.env.peek() <= self.world.now
        self._note(" ".join(str(s) for s in step))

    def _end(self, changed: bool = False) -> None:
        """A step ended: note whether it changed anything at all (no event was due, none
        was recorded, time stayed, no link changed)."""
        assert self.world is not None
        world = self.world
        self.spans.append((self._step_start, world.now))
        if not changed and not self._due and world.now == self._step_start \
                and len(world.trace) == self._trace_len:
            self.noops.append(len(self.steps) - 1)
            self.schedule[-1] += "   (no-op)"

    def _note(self, text: str) -> None:
        assert self.world is not None
        n = f"{len(self.steps):3d}." if self.steps and not text.startswith("teardown") else "    "
        self.schedule.append(f"{n} {ns_to_sec(self.world.now):10.6f}s  {text}")

    def _send(self, goal: Message) -> None:
        gh = self.client.send_goal(goal, transition_cb=self._transition)
        self.handles.append(gh)
        self.schedule[-1] += f"  (goal id {gh.get_goal_id()})"

    def _transition(self, gh: ClientGoalHandle) -> None:
        self._acked.add(gh.get_goal_id())

    def _cancellable(self) -> list[ClientGoalHandle]:
        """Goals the server has acknowledged and the client still follows."""
        return [h for h in self.handles
                if h.get_goal_id() in self._acked and h.get_comm_state() != CommState.DONE]

    def _live(self) -> list[ClientGoalHandle]:
        return [h for h in self.handles if h.get_comm_state() != CommState.DONE]

    @precondition(lambda self: bool(self._cancellable()))
    @rule(index=st.integers(0, 7))
    def cancel_goal(self, index: int) -> None:
        """Cancel one goal the server has acknowledged and the client still follows.

        (A goal cancelled before its acknowledgement is marked LOST by rospy's
        client on the next status array that does not list it yet: a client
        quirk, not a server fault, so the machine cancels such goals only
        through ``cancel_all_goals`` and ``cancel_goals_at_and_before_time``.)
        """
        live = self._cancellable()
        gh = live[index % len(live)]
        self._begin("cancel_goal", index)
        self.schedule[-1] += f"  ({gh.get_goal_id()})"
        gh.cancel()
        self._end()

    @precondition(lambda self: bool(self.handles))
    @rule()
    def cancel_all_goals(self) -> None:
        """Cancel everything (id "", stamp 0)."""
        self._begin("cancel_all_goals")
        self.client.cancel_all_goals()
        self._end()

    @precondition(lambda self: bool(self.handles))
    @rule(index=st.integers(0, 7))
    def cancel_goals_at_and_before_time(self, index: int) -> None:
        """Cancel the goals stamped at or before the stamp of one goal sent."""
        gh = self.handles[index % len(self.handles)]
        stamp = gh.comm_state_machine.action_goal.goal_id.stamp
        self._begin("cancel_goals_at_and_before_time", index)
        self.schedule[-1] += f"  (stamp {stamp.to_sec():.6f})"
        self.client.cancel_goals_at_and_before_time(stamp)
        self._end()

    @rule(topic=st.sampled_from(_TOPICS), change=st.integers(0, len(LATENCIES) - 2))
    def change_latency(self, topic: str, change: int) -> None:
        """Change the latency of one of the five topics to another of :data:`LATENCIES`
        (never to the value it has: that step would change nothing)."""
        now = self._latency.get(topic, 0.0)
        self.set_latency(topic, [x for x in LATENCIES if x != now][change])

    def set_latency(self, topic: str, latency: float) -> None:
        """Set the latency of one of the five topics (FIFO per connection is kept)."""
        assert self.world is not None
        self._begin("set_latency", topic, latency)
        changed = self._latency.get(topic, 0.0) != latency
        self._latency[topic] = latency
        self.world.set_link(f"{self.ns}/{topic}", latency=latency)
        self._end(changed)

    @rule(seconds=st.sampled_from(STEPS))
    def advance(self, seconds: float) -> None:
        """Let simulated time pass."""
        assert self.world is not None
        self._begin("advance", seconds)
        self.world.run_for(seconds)
        self._end()

    @precondition(lambda self: self.world is not None and self.world.env.peek() <= self.world.now)
    @rule()
    def run_due_events(self) -> None:
        """Run what is due at this instant (only when something is: else it would be a no-op)."""
        self.advance(0.0)

    # -- checks -----------------------------------------------------------------------------
    def replay_call(self) -> str:
        """The one-line call that replays the schedule run so far (see :func:`replay_action_schedule`)."""
        cls = type(self)
        kwargs: dict[str, object] = {"seed": self.seed, "action": cls.action._type,  # type: ignore[union-attr]
                                     "ns": cls.ns}
        if cls.settle != 30.0:
            kwargs["settle"] = cls.settle
        if cls.preempt_timeout != 5.0:
            kwargs["preempt_timeout"] = cls.preempt_timeout
        return call_text("replay_action_schedule",
                         [Source(factory_name(cls.make_server, "make_server")), self.steps], kwargs)

    def _fail(self, problem: str) -> None:
        self._failed = True
        assert self.world is not None
        lines = [f"actionlib protocol violated by the server on {self.ns}:", f"  {problem}", "",
                 f"replay: world seed {self.seed}; schedule (step, simulated time, what):"]
        lines += [f"  {s}" for s in self.schedule]
        lines += ["", "last messages on the wire:"] + [f"  {e}" for e in self.spy.events[-15:]]
        replay = self.replay_call()
        lines += ["", "replay it (ddes.testing.actions):", f"  {replay}"]
        exc = ProtocolViolation("\n".join(lines))
        exc.problem, exc.seed, exc.steps = problem, self.seed, list(self.steps)
        exc.noops = list(self.noops)
        exc.step = len(self.steps) if self._in_teardown else len(self.steps) - 1
        exc.t_ns, exc.replay = self.world.now, replay
        raise exc

    @invariant()
    def protocol_holds(self) -> None:
        """Checks 1-6 after every step (see the module docstring)."""
        if self.world is None:
            return
        world = self.world
        if self.spy.violations:
            self._fail(self.spy.violations[0])
        server_name = "/" + type(self).server_node
        self._scan(server_name)
        if self._illegal:
            d = self._illegal[0].details
            self._fail(f"the server made an illegal goal-handle call: {d['event']} on goal "
                       f"{d['id']} in state {d['state']} ({d['error']})")
        errors = [e for e in world.callback_errors if e[0] == server_name]
        if errors:
            self._fail(f"a server callback raised: {errors[0][1]}: {errors[0][2]!r}\n{errors[0][3]}")
        if self.client.invalid_transitions and self._invalid:
            ev = self._invalid[0]
            self._fail(f"the client saw an invalid status sequence for goal {ev.details['id']}: "
                       f"{ev.details['error']}")
        for gh in self.handles:
            self._check_agreement(gh)
        self._check_preemption(server_name)

    def _scan(self, server_name: str) -> None:
        """Read the trace events recorded since the last check (each event read once)."""
        assert self.world is not None
        trace = self.world.trace
        end = len(trace)
        for i in range(self._scanned, end):
            ev = trace[i]
            kind = ev.kind
            if not kind.startswith("action."):
                continue
            if kind == "action.server.illegal" and ev.source == server_name:
                self._illegal.append(ev)
            elif kind == "action.client.invalid":
                self._invalid.append(ev)
            elif kind == "action.simple.preempt_request" and ev.source == server_name:
                self._preempts.append(ev)
        self._scanned = end

    def _check_preemption(self, server_name: str) -> None:
        """Check 6: a goal asked to stop (cancel taken, or preempt request) ends in time."""
        timeout = type(self).preempt_timeout
        if timeout is None:
            return
        assert self.world is not None
        world = self.world
        limit = duration_to_ns(timeout, "preempt_timeout")
        asked: dict[str, tuple[int, str]] = {}
        for gh in self.handles:
            g = self.spy.goals.get(gh.get_goal_id())
            if g is not None and g.asked is not None:
                status = next(_name(s) for _a, t, s in g.arrays if t == g.asked
                              and s in (GoalStatus.PREEMPTING, GoalStatus.RECALLING))
                asked[gh.get_goal_id()] = (g.asked, f"the server took a cancel request ({status})")
        for ev in self._preempts:
            gid = ev.details.get("id")
            if gid and (gid not in asked or ev.t < asked[gid][0]):
                asked[gid] = (ev.t, f"the server was asked to preempt it ({ev.details['reason']})")
        for gid, (t_ask, why) in asked.items():
            g = self.spy.goals.get(gid)
            done = g.results[0][1] if g is not None and g.results else None
            late = done - t_ask > limit if done is not None else \
                world.now - t_ask > limit + _IN_FLIGHT_NS
            if late:
                ended = ("it ended only " + f"{ns_to_sec(done - t_ask):.3f}s later"
                         if done is not None else f"it is still not finished at "
                         f"{ns_to_sec(world.now):.3f}s")
                self._fail(f"preemption ignored: goal {gid}: at {ns_to_sec(t_ask):.6f}s {why}; "
                           f"{ended} (preempt_timeout = {timeout}s): a server must end a goal "
                           "it was asked to cancel or preempt (set_preempted / set_canceled)")

    def _check_agreement(self, gh: ClientGoalHandle) -> None:
        gid = gh.get_goal_id()
        g = self.spy.goals.get(gid)
        status = gh.get_goal_status()
        if status == GoalStatus.LOST:
            if g is None or g.dropped is None:
                self._fail(f"the client marked goal {gid} LOST but the server never dropped it "
                           "from the status array")
            return
        if g is None:
            return  # nothing on the wire yet: the client still waits for the goal's ack
        if gh.get_comm_state() == CommState.DONE:
            if not g.results:
                self._fail(f"goal {gid} is DONE on the client without a result on the wire")
            elif g.results[0][2] != status:
                self._fail(f"client and server disagree on goal {gid}: the client says "
                           f"{_name(status)}, the result says {_name(g.results[0][2])}")
        elif status not in g.statuses() and status != GoalStatus.PENDING:
            self._fail(f"the client reports {_name(status)} for goal {gid}, a status the server "
                       "never sent")

    def teardown(self) -> None:
        """Cancel everything, let ``settle`` seconds pass, then require one result per goal."""
        if self.world is None or self._failed:
            return
        world = self.world
        self._in_teardown = True
        self._note("teardown: cancel_all_goals, then run until every goal is done")
        for topic in _TOPICS:
            world.set_link(f"{self.ns}/{topic}", latency=0.0)
        self.client.cancel_all_goals()
        deadline = world.now + duration_to_ns(type(self).settle, "settle")
        while world.now < deadline and (self._live() or self._unfinished()):
            world.run_for(0.5)
            self.protocol_holds()
        self.protocol_holds()
        late = self._unfinished()
        if late:
            gid = late[0]
            self._fail(f"goal {gid} never got a result ({len(late)} goal(s) unfinished "
                       f"{type(self).settle}s after cancelling everything; last status "
                       f"{_name(self.spy.goals[gid].arrays[-1][2])})")
        for gh in self.handles:
            if gh.get_comm_state() != CommState.DONE:
                self._fail(f"goal {gh.get_goal_id()} is not DONE on the client "
                           f"{type(self).settle}s after cancelling everything (comm state "
                           f"{gh.get_comm_state().name})")

    def _unfinished(self) -> list[str]:
        return [gid for gid, g in self.spy.goals.items()
                if g.arrays and not g.results and not g.placeholder]


def _discover(make_server: ServerFactory) -> tuple[type[Message], str]:
    """The ActionSpec and namespace of the server a factory makes (built in a scratch world)."""
    world = World(0)
    node = world.create_node("action_server")
    server = make_server(world, node)
    inner = getattr(server, "action_server", None) or getattr(server, "server", None)
    for obj in (server, inner, getattr(inner, "action_server", None)):
        spec, ns = getattr(obj, "ActionSpec", None), getattr(obj, "ns", None)
        if spec is not None and isinstance(ns, str):
            return spec, ns
    raise DdesValueError(
        f"cannot tell the action type and namespace of {server!r}: pass action= and ns= "
        "(e.g. action='actionlib_tutorials/FibonacciAction', ns='/fibonacci')")


def _settings(max_examples: int, stateful_step_count: int, **kw: Any) -> settings:
    kw.setdefault("deadline", None)
    kw.setdefault("suppress_health_check", [HealthCheck.too_slow, HealthCheck.filter_too_much,
                                            HealthCheck.data_too_large])
    kw.setdefault("print_blob", True)
    return settings(max_examples=max_examples, stateful_step_count=stateful_step_count, **kw)


def run_protocol_machine(make_server: ServerFactory, *,
                         action: type[Message] | str | None = None, ns: str | None = None,
                         goals: st.SearchStrategy[GoalDraw] | None = None,
                         settle: float = 30.0, preempt_timeout: float | None = 5.0,
                         max_examples: int = 50, stateful_step_count: int = 20,
                         **settings_kw: Any) -> None:
    """Run the machine on a server now; raises (after shrinking) on a violation."""
    machine = ActionProtocolMachine.machine_for(make_server, action=action, ns=ns, goals=goals,
                                                settle=settle, preempt_timeout=preempt_timeout)
    try:
        with same_draws_everywhere():
            run_state_machine_as_test(machine, settings=_settings(max_examples, stateful_step_count,
                                                                  **settings_kw))
    except ProtocolViolation as exc:
        raise _shrink_further(machine, exc) from None


def _same_problem(a: str, b: str) -> bool:
    """The same violation, up to numbers and goal ids (``/protocol_client-1-0.061``)."""
    return re.sub(r"\S*\d\S*", "#", a) == re.sub(r"\S*\d\S*", "#", b)


def _shrink_further(machine: type[ActionProtocolMachine],
                    exc: ProtocolViolation) -> ProtocolViolation:
    """Delete the steps the failure does not need, one at a time, by replaying without them.

    Hypothesis's shrinker seldom deletes the first steps of a stateful run
    (they carry its choice of enabled rules), so a shrunk schedule may still
    open with steps that play no part; each is dropped here when the schedule
    without it, from the same seed, still fails the same way.
    """
    steps = list(exc.steps)
    best = exc
    for i in reversed(range(len(steps))):
        trial = steps[:i] + steps[i + 1:]
        try:
            replay = _replay(machine, trial, best.seed)
        except DdesValueError:
            continue  # the step made a later one possible (a cancel needs a goal)
        v = replay.violation
        if v is not None and _same_problem(v.problem, exc.problem):
            steps, best = trial, v
    return best


# -- replay ---------------------------------------------------------------------------------------

_RULES = ("send_goal", "cancel_goal", "cancel_all_goals", "cancel_goals_at_and_before_time",
          "set_latency", "advance")  # (run_due_events: ("advance", 0.0))


@dataclass
class ActionReplay:
    """One schedule run again by :func:`replay_action_schedule`.

    ``world`` is the replayed world (its trace holds every event); ``violation``
    the :class:`ProtocolViolation` raised, or None when the schedule passed;
    ``steps`` the schedule.
    """

    world: World
    ns: str
    steps: list[Step]
    violation: ProtocolViolation | None
    #: (start, end) kernel ns of each step run.
    spans: list[tuple[int, int]] = field(default_factory=list)
    #: Indices of the steps that changed nothing (a shrunk schedule has none).
    noops: list[int] = field(default_factory=list)

    @property
    def step(self) -> int | None:
        """Index of the violating step (``len(steps)``: the final check after the schedule;
        -1: the start), or None."""
        return None if self.violation is None else self.violation.step

    def raise_violation(self) -> None:
        """Raise the violation again (no-op when the schedule passed)."""
        if self.violation is not None:
            raise self.violation

    def plot(self, ax: Axes | None = None) -> Figure:
        """The goal timeline of the replay (:func:`ddes.actionlib.plot_goals`), the violating
        step marked: a red band over the step, a dashed line where the violation was seen."""
        from ddes.actionlib.plot import plot_goals

        fig = plot_goals(self.world.trace, self.ns, ax=ax)
        v = self.violation
        if v is not None:
            target = fig.axes[0] if ax is None else ax
            spans = self.spans
            start = spans[v.step][0] if 0 <= v.step < len(spans) else \
                (spans[-1][1] if spans and v.step >= 0 else 0)
            what = "final check (cancel everything, settle)" if v.step >= len(self.steps) else \
                "start" if v.step < 0 else " ".join(str(s) for s in self.steps[v.step])
            mark_violation(target, ns_to_sec(start), ns_to_sec(v.t_ns),
                           f"step {v.step}: {what}\n{v.problem[:80]}")
        return fig


def replay_action_schedule(make_server: ServerFactory, steps: list[Step], seed: int = 0, *,
                           action: type[Message] | str | None = None, ns: str | None = None,
                           settle: float = 30.0,
                           preempt_timeout: float | None = 5.0) -> ActionReplay:
    """Run a schedule (as a :class:`ProtocolViolation` prints it) again, with every check.

    Returns an :class:`ActionReplay` (it does not raise): ``replay.violation``,
    ``replay.step`` (the violating step), ``replay.world.trace`` and
    ``replay.plot()``.
    """
    machine_cls = ActionProtocolMachine.machine_for(make_server, action=action, ns=ns,
                                                    settle=settle, preempt_timeout=preempt_timeout)
    return _replay(machine_cls, steps, seed)


def _replay(machine_cls: type[ActionProtocolMachine], steps: list[Step], seed: int) -> ActionReplay:
    machine = machine_cls()
    violation: ProtocolViolation | None = None
    try:
        machine.start(seed)
        machine.protocol_holds()
        for step in steps:
            name, args = str(step[0]), step[1:]
            if name not in _RULES:
                raise DdesValueError(f"unknown step {step!r}: a step is one of {_RULES}")
            if name == "cancel_goal" and not machine._cancellable() or \
                    name.startswith("cancel_") and not machine.handles:
                raise DdesValueError(f"step {len(machine.steps)} {step!r} cannot run here: "
                                     "no goal to cancel (is the seed the one printed?)")
            getattr(machine, name)(*args)
            machine.protocol_holds()
        machine.teardown()
    except ProtocolViolation as exc:
        violation = exc
    world = machine.world
    assert world is not None
    return ActionReplay(world, machine.ns, list(steps), violation, list(machine.spans),
                        list(machine.noops))
