"""ActionClient and ClientGoalHandle on the five action topics (rospy ``actionlib.ActionClient``).

The client publishes ``<ns>/goal`` and ``<ns>/cancel`` (queue
``actionlib_client_pub_queue_size``, default 10) and subscribes to
``<ns>/status``, ``<ns>/result`` and ``<ns>/feedback`` (queue
``actionlib_client_sub_queue_size``, default -1: unbounded).  Each goal it
sends has a comm-state machine driven by the pure table of
:mod:`ddes.actionlib.states`: ``apply_comm_status`` for each status array
(multi-step transitions, the LOST rule), ``apply_comm_result`` for the
result (DONE only then), ``apply_comm_cancel`` for a cancel.  Every state
entered fires the user's ``transition_cb(gh)`` once, as in rospy.

An invalid transition (the table's INVALID cell: a status array that
contradicts the goal's history) logs ROS's error, records an
``action.client.invalid`` trace event and is counted in
:attr:`ActionClient.invalid_transitions`.  A goal marked LOST records
``action.client.lost``.

Differences from rospy, on purpose: rospy keeps its goals through weak
references and forgets one when the user drops its last handle; ddes keeps
every goal until ``gh.stop_tracking()`` (SimpleActionClient does it for the
goal it replaces), so nothing depends on the garbage collector.
``wait_for_server`` is an event that fires when the condition holds instead of
a 10 ms wall-clock poll; its deadline is on ROS time, as in ROS.

User callbacks run as part of the subscriber callback that received the
message (status, result or feedback), through the node's one callback runner:
a generator callback (``yield node.sleep(1.0)``) takes simulated time and
holds the node's spinner until it ends, as a slow callback holds rospy's
thread.  Callbacks after it (the next transitions of the same message) run
when it has ended; the comm state machine itself has already moved, so they
see the goal's state as it is then.  A ``gh.cancel()`` whose transition
callback is a generator hands it to the node's callback queue.
"""

from __future__ import annotations

from collections.abc import Callable, Generator
from typing import TYPE_CHECKING, Any

from ddes.actionlib._common import (
    ActionTypes,
    CallbackChain,
    CallbackGenerator,
    NodeGoalIds,
    check_message,
    misuse,
    no_node,
    queue_size_param,
)
from ddes.actionlib.goal_id import GoalIdStyle
from ddes.actionlib.states import (
    CommState,
    CommUpdate,
    GoalStatus,
    apply_comm_cancel,
    apply_comm_result,
    apply_comm_status,
    comm_state_name,
)
from ddes.errors import DdesTypeError
from ddes.graph.rosout import WARN
from ddes.msg.message import Message
from ddes.time.rospy_calls import REQUIRED, is_node_like
from ddes.time.rostime import Time
from ddes.time.units import DurationLike, TimeLike, duration_to_ns, time_to_ns

if TYPE_CHECKING:
    import simpy

    from ddes.graph.node import Node

__all__ = ["ActionClient", "ClientGoalHandle"]

#: ``transition_cb(gh)``: a goal entered a comm state.
TransitionCallback = Callable[["ClientGoalHandle"], object]
#: ``feedback_cb(gh, feedback)``: feedback (a ``FooFeedback``) for a goal.
FeedbackCallback = Callable[["ClientGoalHandle", Message], object]
#: SimpleActionClient's own transition callback: told the state entered.
_StateCallback = Callable[["ClientGoalHandle", CommState], object]

_POLL_NS = 10_000_000  # wait_for_server re-checks the connections every 10 ms, as ROS (wall)

_TERMINAL_OR_LOST = frozenset({GoalStatus.PREEMPTED, GoalStatus.SUCCEEDED, GoalStatus.ABORTED,
                               GoalStatus.REJECTED, GoalStatus.RECALLED, GoalStatus.LOST})


def _status_name(status: int) -> str:
    return _STATUS_NAMES[status] if 0 <= status <= _LOST else str(status)


class _CommStateMachine:
    """One goal sent by a client (rospy ``CommStateMachine``)."""

    __slots__ = ("client", "action_goal", "goal_id", "state", "status", "text", "latest_result",
                 "transition_cb", "feedback_cb", "state_cb")

    def __init__(self, client: ActionClient, action_goal: Message, goal_id: str,
                 transition_cb: TransitionCallback | None,
                 feedback_cb: FeedbackCallback | None,
                 state_cb: _StateCallback | None = None) -> None:
        self.client = client
        self.action_goal = action_goal
        self.goal_id = goal_id
        self.state = _WAITING_FOR_GOAL_ACK
        self.status: int = _PENDING
        self.text = ""
        #: The ``FooActionResult`` once received.
        self.latest_result: Message | None = None
        self.transition_cb = transition_cb
        self.feedback_cb = feedback_cb
        self.state_cb = state_cb

    def apply(self, upd: CommUpdate, text: str | None, chain: CallbackChain) -> None:
        """Take a pure update: latest status, errors, each state entered (its callback on
        ``chain``)."""
        client = self.client
        if upd.latest_status is not None:
            self.status = int(upd.latest_status)
            if text is not None and not upd.lost:
                self.text = text
        for error in upd.errors:
            client._invalid(self, upd, error)
        if upd.lost:
            client.lost_goals += 1
            client.node.world.record("action.client.lost", client.node.name, ns=client.ns,
                                     id=self.goal_id, state=upd.before.name)
        for state in upd.passed:
            self.transition_to(state, chain)

    def transition_to(self, state: CommState, chain: CallbackChain) -> None:
        client = self.client
        before = self.state
        self.state = state
        client._trace.append_row((client._env.now_ns, "action.client.transition", client._source,
                                  _TRANSITION_KEYS, client.ns, self.goal_id, _COMM_NAMES[before],
                                  _COMM_NAMES[state], _status_name(self.status)))
        if self.transition_cb is not None:
            chain.call(self.transition_cb, ClientGoalHandle(self))
        if self.state_cb is not None:
            chain.call(self.state_cb, ClientGoalHandle(self), state)


class ClientGoalHandle:
    """A goal as the client's user sees it (rospy ``ClientGoalHandle``); equal by goal id."""

    __slots__ = ("_csm",)

    def __init__(self, csm: _CommStateMachine) -> None:
        self._csm = csm

    @property
    def comm_state_machine(self) -> _CommStateMachine:
        """The goal's comm-state machine (rospy's attribute name)."""
        return self._csm

    def get_goal_id(self) -> str:
        """The goal's id (``goal_id.id`` of the goal message)."""
        return self._csm.goal_id

    def cancel(self) -> None:
        """Send a cancel for this goal (id, stamp 0) and move to WAITING_FOR_CANCEL_ACK.

        As in rospy this happens from any state, DONE included.  The transition
        callback runs at once; if it is a generator, the node's callback queue
        runs it (it holds the spinner, as any generator callback).
        """
        csm = self._csm
        client = csm.client
        client._publish_cancel(csm.goal_id, 0)
        chain = CallbackChain()
        csm.apply(apply_comm_cancel(csm.state), None, chain)
        rest = chain.rest()
        if rest is not None:
            client.node.callbacks.invoke(_transition_callbacks, (rest,))

    def get_comm_state(self) -> CommState:
        """The goal's :class:`CommState`."""
        return self._csm.state

    def get_goal_status(self) -> int:
        """The latest status the server reported (``GoalStatus``), LOST once lost."""
        return self._csm.status

    def get_goal_status_text(self) -> str:
        """The text of the latest status."""
        return self._csm.text

    def get_result(self) -> Message | None:
        """The result (``FooResult``) once received, else None."""
        r = self._csm.latest_result
        return None if r is None else r.result

    def get_terminal_state(self) -> int:
        """The terminal status, with rospy's warning when asked before DONE."""
        csm = self._csm
        client = csm.client
        if csm.state != CommState.DONE:
            misuse(client.node, client.ns, f"Asking for the terminal state when we're in [{comm_state_name(csm.state)}]",
                   level=WARN)
        if csm.status in _TERMINAL_OR_LOST:
            return csm.status
        misuse(client.node, client.ns,
               f"Asking for a terminal state, but the goal status is {csm.status:d}")
        return GoalStatus.LOST

    def stop_tracking(self) -> None:
        """Stop updating this goal (rospy does it when the last handle is garbage collected)."""
        csm = self._csm
        tracked = csm.client._tracked
        if tracked.get(csm.goal_id) is csm:
            del tracked[csm.goal_id]

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, ClientGoalHandle):
            return NotImplemented
        return self._csm.goal_id == other._csm.goal_id

    def __ne__(self, other: object) -> bool:
        result = self.__eq__(other)
        return result if result is NotImplemented else not result

    def __hash__(self) -> int:
        return hash(self._csm.goal_id)

    def __repr__(self) -> str:
        return f"<ClientGoalHandle {self._csm.goal_id} {self._csm.state.name}>"


class ActionClient:
    """``ActionClient(node, ns, ActionSpec)``: send goals, follow them, cancel them."""

    def __init__(self, node: Node, ns: str,
                 ActionSpec: type[Message] | str = REQUIRED) -> None:  # noqa: N803 - rospy's
        if not is_node_like(node):  # rospy's ActionClient(ns, ActionSpec)
            no_node("ActionClient", "client", node,
                    [a for a in (ns, ActionSpec) if a is not REQUIRED], {})
        node.check_alive("create an action client")
        if not isinstance(ns, str) or not ns:
            raise DdesTypeError(f"action namespace must be a non-empty string, got {ns!r}")
        from ddes.msg import get_message_class

        self.node = node
        self.types = ActionTypes.of(ActionSpec)
        self.ActionSpec = self.types.spec
        self.ActionGoal = self.types.action_goal
        self.ActionResult = self.types.action_result
        self.ActionFeedback = self.types.action_feedback
        self._GoalID = get_message_class("actionlib_msgs/GoalID")
        self._Header = type(self.ActionGoal().header)
        GoalStatusArray = get_message_class("actionlib_msgs/GoalStatusArray")
        self._trace, self._env, self._source = node.world.trace, node.world.env, node.name
        #: The resolved action namespace.
        self.ns = node.resolve_name(ns)
        self._ids = NodeGoalIds(node, GoalIdStyle.CLIENT)
        self._tracked: dict[str, _CommStateMachine] = {}
        #: The last status array received (None before the first).
        self.last_status_msg: Message | None = None
        self._last_status_sender: str | None = None
        self._delivered: dict[int, int] = {}
        self._status_waiters: list[simpy.Event] = []
        #: Invalid comm transitions so far (each also an ``action.client.invalid`` event).
        self.invalid_transitions = 0
        #: Goals marked LOST so far.
        self.lost_goals = 0
        self._closed = False
        pub_q = queue_size_param(node, "actionlib_client_pub_queue_size", 10)
        sub_q = queue_size_param(node, "actionlib_client_sub_queue_size", -1)
        ns_r = self.ns
        self.pub_goal = node.advertise(ns_r + "/goal", self.ActionGoal, queue_size=pub_q)
        self.pub_cancel = node.advertise(ns_r + "/cancel", self._GoalID, queue_size=pub_q)
        self.status_sub = node.subscribe(ns_r + "/status", GoalStatusArray, self._status_cb,
                                         queue_size=sub_q)
        self.result_sub = node.subscribe(ns_r + "/result", self.ActionResult, self._result_cb,
                                         queue_size=sub_q)
        self.feedback_sub = node.subscribe(ns_r + "/feedback", self.ActionFeedback,
                                           self._feedback_cb, queue_size=sub_q)
        node.add_entity(self)

    # -- sending --------------------------------------------------------------------------
    def send_goal(self, goal: Message, transition_cb: TransitionCallback | None = None,
                  feedback_cb: FeedbackCallback | None = None) -> ClientGoalHandle:
        """Send ``goal`` (a ``FooGoal``) with a fresh goal id; returns its handle.

        A goal of another type raises :class:`~ddes.errors.ROSActionException`
        (rospy fails to serialize it).  ``transition_cb(gh)`` runs for every
        comm state the goal enters, ``feedback_cb(gh, feedback)`` for its
        feedback; either may be a generator (see the module docstring).
        """
        return self._send_goal(goal, transition_cb, feedback_cb, None)

    def _send_goal(self, goal: Message, transition_cb: TransitionCallback | None,
                   feedback_cb: FeedbackCallback | None,
                   state_cb: _StateCallback | None) -> ClientGoalHandle:
        self._check_open("send a goal")
        check_message(goal, self.types.goal, "send_goal: the goal",
                      f"build it with {self.types.goal.__name__}(...)")
        now_ns = self.node.clock.now_ns()
        gid_text, stamp_ns = self._ids.generate_id(now_ns)
        ag = self.ActionGoal(header=self._Header(0, Time._from_ns(now_ns), ""),
                             goal_id=self._GoalID(Time._from_ns(stamp_ns), gid_text), goal=goal)
        csm = _CommStateMachine(self, ag, gid_text, transition_cb, feedback_cb, state_cb)
        self._tracked[gid_text] = csm
        self._trace.append_row((self._env.now_ns, "action.client.send", self._source, _SEND_KEYS,
                                self.ns, gid_text, stamp_ns))
        self.pub_goal.publish(ag)
        return ClientGoalHandle(csm)

    def cancel_all_goals(self) -> None:
        """Cancel every goal of the server (id ``""``, stamp 0)."""
        self._publish_cancel("", 0)

    def cancel_goals_at_and_before_time(self, time: TimeLike) -> None:
        """Cancel the server's goals stamped at or before ``time`` (id ``""``, stamp ``time``).

        ``time`` is a :class:`~ddes.Time` or seconds of ROS time.
        """
        self._publish_cancel("", time_to_ns(time, "time"))

    def _publish_cancel(self, goal_id: str, stamp_ns: int) -> None:
        self._check_open("send a cancel request")
        msg = self._GoalID(stamp=Time.from_nsec(stamp_ns), id=goal_id)
        self.node.world.record("action.client.cancel", self.node.name, ns=self.ns, id=goal_id,
                               stamp=stamp_ns)
        self.pub_cancel.publish(msg)

    def _check_open(self, what: str) -> None:
        self.node.check_alive(what)
        if self._closed:
            from ddes.errors import ROSActionException

            raise ROSActionException(
                f"cannot {what}: the action client of {self.ns} was stopped; create a new one")

    # -- waiting --------------------------------------------------------------------------
    def wait_for_server(self, timeout: DurationLike = 0) -> simpy.Event:
        """Event whose value is True once the server is up (rospy ``wait_for_server``).

        The server is up when a status message has been received and its
        publisher is connected to this client's goal, cancel, result and
        feedback topics.  ``timeout`` (seconds or a Duration of ROS time; 0
        means for ever) makes the value False when it expires first.
        """
        return self.node.process(self._wait_for_server(duration_to_ns(timeout, "timeout")))

    wait_for_action_server_to_start = wait_for_server

    def _server_connected(self) -> bool:
        server = self._last_status_sender
        if self.last_status_msg is None or server is None:
            return False
        return (any(c.sub.node.name == server for c in self.pub_goal.connections)
                and any(c.sub.node.name == server for c in self.pub_cancel.connections)
                and any(c.pub.node.name == server for c in self.result_sub.connections)
                and any(c.pub.node.name == server for c in self.feedback_sub.connections))

    def _wait_for_server(self, timeout_ns: int) -> Generator[simpy.Event, Any, bool]:
        node = self.node
        env = node.world.env
        clock = node.clock
        deadline = None
        if timeout_ns != 0:
            deadline = clock.wait_until(clock.now_ns() + timeout_ns)
        while not node.is_shutdown() and not self._closed:
            if self._server_connected():
                return True
            if deadline is not None and deadline.processed:
                return False
            arrival = env.event()
            self._status_waiters.append(arrival)
            events = [arrival, node.spin()]
            if self.last_status_msg is not None:
                events.append(env.timeout(_POLL_NS))
            if deadline is not None:
                events.append(deadline)
            yield env.any_of(events)
            if not arrival.triggered and arrival in self._status_waiters:
                self._status_waiters.remove(arrival)
        return False

    # -- incoming -------------------------------------------------------------------------
    def _status_cb(self, msg: Message) -> CallbackGenerator | None:
        self.last_status_msg = msg
        for conn in self.status_sub.connections:
            if self._delivered.get(conn.id, 0) != conn.delivered:
                self._delivered[conn.id] = conn.delivered
                self._last_status_sender = conn.pub.node.name
        if self._status_waiters:
            waiters, self._status_waiters = self._status_waiters, []
            for ev in waiters:
                if not ev.triggered:
                    ev.succeed()
        if not self._tracked:
            return None
        entries: dict[str, Message] = {}
        for st in msg.status_list:
            entries.setdefault(st.goal_id.id, st)
        chain = CallbackChain()
        for csm in list(self._tracked.values()):
            if csm.state == _DONE:
                continue
            st = entries.get(csm.goal_id)
            if st is None:
                csm.apply(apply_comm_status(csm.state, None), None, chain)
            else:
                csm.apply(apply_comm_status(csm.state, st.status), st.text, chain)
        return chain.rest()

    def _result_cb(self, msg: Message) -> CallbackGenerator | None:
        csm = self._tracked.get(msg.status.goal_id.id)
        if csm is None:
            return None
        self._trace.append_row((self._env.now_ns, "action.client.result", self._source,
                                _RESULT_KEYS, self.ns, csm.goal_id, _status_name(msg.status.status)))
        csm.latest_result = msg
        chain = CallbackChain()
        csm.apply(apply_comm_result(csm.state, msg.status.status), msg.status.text, chain)
        return chain.rest()

    def _feedback_cb(self, msg: Message) -> CallbackGenerator | None:
        csm = self._tracked.get(msg.status.goal_id.id)
        if csm is None or csm.feedback_cb is None or csm.state == _DONE:
            return None
        self._trace.append_row((self._env.now_ns, "action.client.feedback", self._source,
                                _FEEDBACK_KEYS, self.ns, csm.goal_id))
        chain = CallbackChain()
        chain.call(csm.feedback_cb, ClientGoalHandle(csm), msg.feedback)
        return chain.rest()

    def _invalid(self, csm: _CommStateMachine, upd: CommUpdate, error: str) -> None:
        self.invalid_transitions += 1
        node = self.node
        node.world.record("action.client.invalid", node.name, ns=self.ns, id=csm.goal_id,
                          state=upd.before.name, status=_status_name(csm.status), error=error)
        node.logerr(error)

    # -- lifecycle ------------------------------------------------------------------------
    @property
    def goal_handles(self) -> list[ClientGoalHandle]:
        """Handles of the goals this client still tracks, oldest first."""
        return [ClientGoalHandle(c) for c in self._tracked.values()]

    def stop(self) -> None:
        """Unregister the five topics (rospy ``stop``)."""
        if self._closed:
            return
        self._closed = True
        for ent in (self.pub_goal, self.pub_cancel, self.status_sub, self.result_sub,
                    self.feedback_sub):
            ent.unregister()
        for ev in self._status_waiters:
            if not ev.triggered:
                ev.succeed()
        self._status_waiters = []

    def shutdown(self) -> None:
        """The node is shutting down."""
        self.stop()
        self.node.remove_entity(self)


def _transition_callbacks(rest: CallbackGenerator) -> CallbackGenerator:
    """The generator transition callbacks of a ``gh.cancel()``, as one queued callback."""
    return rest


# Defined last, so that every logging call above keeps its line: a log's file and line are in
# the trace (and in /rosout's bytes), so moving one would change the run's digest.
_STATUS_NAMES = tuple(s.name for s in GoalStatus)  # indexed by the status value
_COMM_NAMES = tuple(c.name for c in CommState)  # indexed by the comm state value
assert [s.value for s in GoalStatus] == list(range(len(_STATUS_NAMES)))
assert [c.value for c in CommState] == list(range(len(_COMM_NAMES)))

# Keys of this module's trace rows (``Trace.append_row``: the details dict is built when read).
_SEND_KEYS = ("ns", "id", "stamp")
_TRANSITION_KEYS = ("ns", "id", "before", "after", "status")
_RESULT_KEYS = ("ns", "id", "status")
_FEEDBACK_KEYS = ("ns", "id")

# Enum members as plain globals for the hot lines (a member read through its class is slower).
_WAITING_FOR_GOAL_ACK, _DONE = CommState.WAITING_FOR_GOAL_ACK, CommState.DONE
_PENDING, _LOST = GoalStatus.PENDING, GoalStatus.LOST
