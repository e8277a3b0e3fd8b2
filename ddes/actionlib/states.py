"""actionlib's state machines as data: the server goal table, the client comm-state table.

Three machines live here, each as one table plus one function that applies it:

* the **server goal state machine** of ``server_goal_handle.py``
  (:data:`SERVER_TRANSITIONS`, :func:`server_transition`).  ROS only logs an
  error on an illegal call and leaves the state alone; ddes returns a
  :class:`ServerTransition` saying so, with ROS's log text, so the caller can
  record and count it;
* the **client comm-state machine** of ``action_client.py``
  (:data:`COMM_TRANSITIONS`, a copy of ``_transitions``;
  :func:`apply_comm_status` for a status array, :func:`apply_comm_result`
  for a result message), with the LOST rule and the DONE-on-result rule;
* **SimpleActionClient**'s simple state (:func:`simple_transition`) and its
  ``get_state()`` mapping (:func:`simple_get_state`).

Everything is pure: no clocks, no I/O, no mutable module state.  The tables
are read-only mappings.  :func:`render_tables` renders them as the Markdown
kept in ``docs/actionlib.md``.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from enum import Enum, IntEnum
from types import MappingProxyType

from ddes.errors import DdesTypeError, DdesValueError

__all__ = [
    "COMM_TRANSITIONS",
    "CommMarker",
    "CommState",
    "CommTarget",
    "CommUpdate",
    "GoalStatus",
    "INVALID_TRANSITION",
    "NO_TRANSITION",
    "SERVER_STATES",
    "SERVER_TRANSITIONS",
    "ServerEvent",
    "ServerTransition",
    "SimpleCallback",
    "SimpleGoalState",
    "SimpleUpdate",
    "TERMINAL_STATUSES",
    "apply_comm_cancel",
    "apply_comm_result",
    "apply_comm_status",
    "comm_state_name",
    "comm_target",
    "render_tables",
    "rospy_status_name",
    "server_transition",
    "simple_get_state",
    "simple_transition",
]


class GoalStatus(IntEnum):
    """``actionlib_msgs/GoalStatus`` status values (LOST is client-only, never sent)."""

    PENDING = 0
    ACTIVE = 1
    PREEMPTED = 2
    SUCCEEDED = 3
    ABORTED = 4
    REJECTED = 5
    PREEMPTING = 6
    RECALLING = 7
    RECALLED = 8
    LOST = 9


class CommState(IntEnum):
    """The client's communication state of one goal (``action_client.CommState``)."""

    WAITING_FOR_GOAL_ACK = 0
    PENDING = 1
    ACTIVE = 2
    WAITING_FOR_RESULT = 3
    WAITING_FOR_CANCEL_ACK = 4
    RECALLING = 5
    PREEMPTING = 6
    DONE = 7
    LOST = 8


class SimpleGoalState(IntEnum):
    """SimpleActionClient's three-valued view of its goal."""

    PENDING = 0
    ACTIVE = 1
    DONE = 2


#: The terminal statuses of the server (``get_terminal_state`` adds LOST on the client).
TERMINAL_STATUSES: frozenset[GoalStatus] = frozenset(
    {
        GoalStatus.PREEMPTED,
        GoalStatus.SUCCEEDED,
        GoalStatus.ABORTED,
        GoalStatus.REJECTED,
        GoalStatus.RECALLED,
    }
)

#: The statuses a server goal can be in (every wire status; LOST is never on the server).
SERVER_STATES: tuple[GoalStatus, ...] = tuple(s for s in GoalStatus if s is not GoalStatus.LOST)


def _coerce(enum: type[IntEnum], value: object, what: str) -> IntEnum:
    """``value`` as a member of ``enum``; a typed error naming it otherwise."""
    if isinstance(value, enum):
        return value
    if isinstance(value, bool) or not isinstance(value, int):
        raise DdesTypeError(
            f"{what} must be a {enum.__name__} or its int value, got {value!r} "
            f"({type(value).__name__})"
        )
    try:
        return enum(value)
    except ValueError:
        names = ", ".join(f"{m.name}={m.value}" for m in enum)
        raise DdesValueError(f"{what} {value} is not a {enum.__name__} ({names})") from None


# --- the server goal state machine (server_goal_handle.py) ---------------------------------


class ServerEvent(str, Enum):
    """What can happen to a server goal: the ``ServerGoalHandle`` methods."""

    ACCEPT = "accept"
    REJECT = "reject"
    CANCEL = "cancel"
    CANCEL_REQUEST = "cancel_request"
    SUCCEED = "succeed"
    ABORT = "abort"

    @property
    def ros_method(self) -> str:
        """The rospy ``ServerGoalHandle`` method that causes this event."""
        return _ROS_METHODS[self]


_ROS_METHODS: Mapping[ServerEvent, str] = MappingProxyType(
    {
        ServerEvent.ACCEPT: "set_accepted",
        ServerEvent.REJECT: "set_rejected",
        ServerEvent.CANCEL: "set_canceled",
        ServerEvent.CANCEL_REQUEST: "set_cancel_requested",
        ServerEvent.SUCCEED: "set_succeeded",
        ServerEvent.ABORT: "set_aborted",
    }
)


def _server_table() -> Mapping[GoalStatus, Mapping[ServerEvent, GoalStatus | None]]:
    S, E = GoalStatus, ServerEvent
    x = None  # illegal: ROS logs an error (or, for a cancel request, returns False)
    columns = (E.ACCEPT, E.REJECT, E.CANCEL, E.CANCEL_REQUEST, E.SUCCEED, E.ABORT)
    rows: dict[GoalStatus, tuple[GoalStatus | None, ...]] = {
        #               accept        reject      cancel       cancel_req    succeed      abort
        S.PENDING: (S.ACTIVE, S.REJECTED, S.RECALLED, S.RECALLING, x, x),
        S.ACTIVE: (x, x, S.PREEMPTED, S.PREEMPTING, S.SUCCEEDED, S.ABORTED),
        S.PREEMPTED: (x, x, x, x, x, x),
        S.SUCCEEDED: (x, x, x, x, x, x),
        S.ABORTED: (x, x, x, x, x, x),
        S.REJECTED: (x, x, x, x, x, x),
        S.PREEMPTING: (x, x, S.PREEMPTED, x, S.SUCCEEDED, S.ABORTED),
        S.RECALLING: (S.PREEMPTING, S.REJECTED, S.RECALLED, x, x, x),
        S.RECALLED: (x, x, x, x, x, x),
    }
    return MappingProxyType(
        {s: MappingProxyType(dict(zip(columns, targets))) for s, targets in rows.items()}
    )


#: ``SERVER_TRANSITIONS[state][event]`` is the new state, or None where the call is illegal.
SERVER_TRANSITIONS: Mapping[GoalStatus, Mapping[ServerEvent, GoalStatus | None]] = _server_table()

# rospy's logerr text for each illegal call (None: ROS refuses silently, returning False).
_ILLEGAL_TEXT: Mapping[ServerEvent, str | None] = MappingProxyType(
    {
        ServerEvent.ACCEPT: "To transition to an active state, the goal must be in a pending "
        "or recalling state, it is currently in state: %d",
        ServerEvent.REJECT: "To transition to a rejected state, the goal must be in a pending "
        "or recalling state, it is currently in state: %d",
        ServerEvent.CANCEL: "To transition to a cancelled state, the goal must be in a pending, "
        "recalling, active, or preempting state, it is currently in state: %d",
        ServerEvent.CANCEL_REQUEST: None,
        ServerEvent.SUCCEED: "To transition to a succeeded state, the goal must be in a "
        "preempting or active state, it is currently in state: %d",
        ServerEvent.ABORT: "To transition to an aborted state, the goal must be in a "
        "preempting or active state, it is currently in state: %d",
    }
)


@dataclass(frozen=True)
class ServerTransition:
    """The outcome of one :class:`ServerEvent` on a server goal.

    ``after == before`` when the call was illegal.  ``error`` is the text
    rospy logs for an illegal call; it is None for a legal one and for a
    refused cancel request, which ROS refuses silently (``set_cancel_requested``
    returns False and the user's cancel callback is not called).
    """

    before: GoalStatus
    event: ServerEvent
    after: GoalStatus
    legal: bool
    error: str | None = None

    @property
    def terminal(self) -> bool:
        """True iff the call moved the goal into a terminal state (a result is published)."""
        return self.legal and self.after in TERMINAL_STATUSES


def server_transition(state: GoalStatus | int, event: ServerEvent | str) -> ServerTransition:
    """Apply ``event`` to a server goal in ``state`` (pure; see :data:`SERVER_TRANSITIONS`)."""
    if type(state) is GoalStatus and type(event) is ServerEvent:
        done = _SERVER_OUTCOMES.get((state, event))
        if done is not None:
            return done
    return _server_transition(state, event)


def _server_transition(state: GoalStatus | int, event: ServerEvent | str) -> ServerTransition:
    before = GoalStatus(_coerce(GoalStatus, state, "server goal state"))
    if isinstance(event, str) and not isinstance(event, ServerEvent):
        try:
            event = ServerEvent(event)
        except ValueError:
            names = ", ".join(e.value for e in ServerEvent)
            raise DdesValueError(f"unknown server goal event {event!r}; use one of: {names}") from None
    if not isinstance(event, ServerEvent):
        raise DdesTypeError(f"server goal event must be a ServerEvent or its name, got {event!r}")
    target = SERVER_TRANSITIONS.get(before, {}).get(event)
    if target is None:
        text = _ILLEGAL_TEXT[event]
        error = None if text is None else text % before.value
        return ServerTransition(before, event, before, False, error)
    return ServerTransition(before, event, target, True)


#: Every outcome of :func:`server_transition` for a GoalStatus and a ServerEvent, worked out
#: once by the function itself (the outcomes are immutable).
_SERVER_OUTCOMES: Mapping[tuple[GoalStatus, ServerEvent], ServerTransition] = MappingProxyType(
    {(s, e): _server_transition(s, e) for s in GoalStatus for e in ServerEvent}
)


# --- the client comm-state machine (action_client.py) ---------------------------------------


class CommMarker(Enum):
    """The two non-state targets of the comm table (``action_client.py`` uses -1 and -2)."""

    NO_TRANSITION = -1
    INVALID_TRANSITION = -2


NO_TRANSITION = CommMarker.NO_TRANSITION
INVALID_TRANSITION = CommMarker.INVALID_TRANSITION

#: A cell of the comm table: the states passed through, in order, or a marker.
CommTarget = tuple[CommState, ...] | CommMarker


def _comm_table() -> Mapping[CommState, Mapping[GoalStatus, CommTarget]]:
    C, S = CommState, GoalStatus
    no, bad = NO_TRANSITION, INVALID_TRANSITION
    wfr = (C.WAITING_FOR_RESULT,)
    rows: dict[CommState, dict[GoalStatus, CommTarget]] = {
        C.WAITING_FOR_GOAL_ACK: {
            S.PENDING: (C.PENDING,),
            S.ACTIVE: (C.ACTIVE,),
            S.REJECTED: (C.PENDING, C.WAITING_FOR_RESULT),
            S.RECALLING: (C.PENDING, C.RECALLING),
            S.RECALLED: (C.PENDING, C.WAITING_FOR_RESULT),
            S.PREEMPTED: (C.ACTIVE, C.PREEMPTING, C.WAITING_FOR_RESULT),
            S.SUCCEEDED: (C.ACTIVE, C.WAITING_FOR_RESULT),
            S.ABORTED: (C.ACTIVE, C.WAITING_FOR_RESULT),
            S.PREEMPTING: (C.ACTIVE, C.PREEMPTING),
        },
        C.PENDING: {
            S.PENDING: no,
            S.ACTIVE: (C.ACTIVE,),
            S.REJECTED: wfr,
            S.RECALLING: (C.RECALLING,),
            S.RECALLED: (C.RECALLING, C.WAITING_FOR_RESULT),
            S.PREEMPTED: (C.ACTIVE, C.PREEMPTING, C.WAITING_FOR_RESULT),
            S.SUCCEEDED: (C.ACTIVE, C.WAITING_FOR_RESULT),
            S.ABORTED: (C.ACTIVE, C.WAITING_FOR_RESULT),
            S.PREEMPTING: (C.ACTIVE, C.PREEMPTING),
        },
        C.ACTIVE: {
            S.PENDING: bad,
            S.ACTIVE: no,
            S.REJECTED: bad,
            S.RECALLING: bad,
            S.RECALLED: bad,
            S.PREEMPTED: (C.PREEMPTING, C.WAITING_FOR_RESULT),
            S.SUCCEEDED: wfr,
            S.ABORTED: wfr,
            S.PREEMPTING: (C.PREEMPTING,),
        },
        C.WAITING_FOR_RESULT: {
            S.PENDING: bad,
            S.ACTIVE: no,
            S.REJECTED: no,
            S.RECALLING: bad,
            S.RECALLED: no,
            S.PREEMPTED: no,
            S.SUCCEEDED: no,
            S.ABORTED: no,
            S.PREEMPTING: bad,
        },
        C.WAITING_FOR_CANCEL_ACK: {
            S.PENDING: no,
            S.ACTIVE: no,
            S.REJECTED: wfr,
            S.RECALLING: (C.RECALLING,),
            S.RECALLED: (C.RECALLING, C.WAITING_FOR_RESULT),
            S.PREEMPTED: (C.PREEMPTING, C.WAITING_FOR_RESULT),
            S.SUCCEEDED: (C.PREEMPTING, C.WAITING_FOR_RESULT),
            S.ABORTED: (C.PREEMPTING, C.WAITING_FOR_RESULT),
            S.PREEMPTING: (C.PREEMPTING,),
        },
        C.RECALLING: {
            S.PENDING: bad,
            S.ACTIVE: bad,
            S.REJECTED: wfr,
            S.RECALLING: no,
            S.RECALLED: wfr,
            S.PREEMPTED: (C.PREEMPTING, C.WAITING_FOR_RESULT),
            S.SUCCEEDED: (C.PREEMPTING, C.WAITING_FOR_RESULT),
            S.ABORTED: (C.PREEMPTING, C.WAITING_FOR_RESULT),
            S.PREEMPTING: (C.PREEMPTING,),
        },
        C.PREEMPTING: {
            S.PENDING: bad,
            S.ACTIVE: bad,
            S.REJECTED: bad,
            S.RECALLING: bad,
            S.RECALLED: bad,
            S.PREEMPTED: wfr,
            S.SUCCEEDED: wfr,
            S.ABORTED: wfr,
            S.PREEMPTING: no,
        },
        C.DONE: {
            S.PENDING: bad,
            S.ACTIVE: bad,
            S.REJECTED: no,
            S.RECALLING: bad,
            S.RECALLED: no,
            S.PREEMPTED: no,
            S.SUCCEEDED: no,
            S.ABORTED: no,
            S.PREEMPTING: bad,
        },
    }
    return MappingProxyType({c: MappingProxyType(row) for c, row in rows.items()})


#: ``action_client._transitions``: CommState x received GoalStatus -> target.  As in ROS
#: there is no row for CommState.LOST and no column for GoalStatus.LOST.
COMM_TRANSITIONS: Mapping[CommState, Mapping[GoalStatus, CommTarget]] = _comm_table()


def comm_target(state: CommState | int, status: GoalStatus | int) -> CommTarget:
    """The raw cell ``COMM_TRANSITIONS[state][status]`` (a typed error outside the table)."""
    c = CommState(_coerce(CommState, state, "comm state"))
    s = GoalStatus(_coerce(GoalStatus, status, "goal status"))
    row = COMM_TRANSITIONS.get(c)
    if row is None or s not in row:
        raise DdesValueError(
            f"the comm table has no cell for ({c.name}, {s.name}): CommState.LOST and "
            "GoalStatus.LOST are outside it, as in action_client._transitions"
        )
    return row[s]


def rospy_status_name(status: int) -> str:
    """What ``GoalStatus.to_string(status)`` prints in rospy, quirks included.

    rospy looks the value up in the generated message class's ``__dict__``,
    where ``_has_header = False`` (an int 0) comes before ``PENDING = 0``;
    so 0 prints as ``"_has_header"`` in real ROS log lines.
    """
    if status == 0:
        return "_has_header"
    if 0 < status <= GoalStatus.LOST:
        return GoalStatus(status).name
    return f"NO_SUCH_STATE_{status}"


def comm_state_name(state: int) -> str:
    """What ``CommState.to_string(state)`` prints in rospy."""
    if 0 <= state <= CommState.LOST:
        return CommState(state).name
    return f"NO_SUCH_STATE_{state}"


@dataclass(frozen=True)
class CommUpdate:
    """What one status array or result did to a client goal (``CommStateMachine``).

    ``passed`` lists every state entered, in order; each entry fires the
    user's transition callback once.  ``latest_status`` is the new value of
    the goal's latest status (None: unchanged).  ``errors`` holds the texts
    rospy logs with ``logerr``.  ``lost`` is True when the LOST rule fired.
    """

    before: CommState
    after: CommState
    passed: tuple[CommState, ...] = ()
    latest_status: int | None = None
    errors: tuple[str, ...] = ()
    lost: bool = False


_NO_LOST_CHECK = frozenset(
    {CommState.WAITING_FOR_GOAL_ACK, CommState.WAITING_FOR_RESULT, CommState.DONE}
)


def _wire_status(status: object) -> int:
    if isinstance(status, bool) or not isinstance(status, int):
        raise DdesTypeError(f"goal status must be an int (uint8), got {status!r}")
    if not 0 <= status <= 255:
        raise DdesValueError(f"goal status {status} is not a uint8 (0..255)")
    return GoalStatus(status) if status <= GoalStatus.LOST else status


def apply_comm_status(state: CommState | int, status: GoalStatus | int | None) -> CommUpdate:
    """Apply the goal's entry of one status array (``CommStateMachine.update_status``).

    ``status`` is the status the array holds for this goal, or None when the
    goal is missing from it.  The rules, in ROS's order:

    * in DONE the array is ignored;
    * missing while not in WAITING_FOR_GOAL_ACK, WAITING_FOR_RESULT or DONE:
      the goal is LOST (latest status LOST, transition to DONE);
    * otherwise the latest status is updated and the table cell applied:
      a sequence of states, no transition, or an invalid transition (logged).
    """
    if type(state) is CommState and (status is None or type(status) is int
                                     or type(status) is GoalStatus):
        done = _COMM_STATUS_UPDATES.get((state, status))
        if done is not None:
            return done
    return _apply_comm_status(state, status)


def _apply_comm_status(state: CommState | int, status: GoalStatus | int | None) -> CommUpdate:
    before = CommState(_coerce(CommState, state, "comm state"))
    if before is CommState.DONE:
        return CommUpdate(before, before)
    if status is None:
        if before in _NO_LOST_CHECK:
            return CommUpdate(before, before)
        return CommUpdate(before, CommState.DONE, (CommState.DONE,), GoalStatus.LOST, lost=True)
    wire = _wire_status(status)
    row = COMM_TRANSITIONS.get(before)
    if row is None:
        return CommUpdate(
            before, before, latest_status=wire,
            errors=(f"CommStateMachine is in a funny state: {before.value}",),
        )
    if not isinstance(wire, GoalStatus) or wire not in row:
        return CommUpdate(
            before, before, latest_status=wire,
            errors=(f"Got an unknown status from the ActionServer: {int(wire)}",),
        )
    target = row[wire]
    if target is NO_TRANSITION:
        return CommUpdate(before, before, latest_status=wire)
    if target is INVALID_TRANSITION:
        text = (
            f"Invalid goal status transition from {comm_state_name(before)} "
            f"to {rospy_status_name(wire)}"
        )
        return CommUpdate(before, before, latest_status=wire, errors=(text,))
    assert isinstance(target, tuple)
    return CommUpdate(before, target[-1], target, wire)


def apply_comm_result(state: CommState | int, status: GoalStatus | int) -> CommUpdate:
    """Apply a result message for the goal (``CommStateMachine.update_result``).

    The result's status first goes through the table as a one-entry status
    array, then the goal moves to DONE: DONE is reached only this way (or by
    the LOST rule).  A result while already DONE only logs an error.  The
    latest status becomes the result's status in every case, as in ROS.
    """
    if type(state) is CommState and (type(status) is int or type(status) is GoalStatus):
        done = _COMM_RESULT_UPDATES.get((state, status))
        if done is not None:
            return done
    return _apply_comm_result(state, status)


def _apply_comm_result(state: CommState | int, status: GoalStatus | int) -> CommUpdate:
    before = CommState(_coerce(CommState, state, "comm state"))
    wire = _wire_status(status)
    if before is CommState.DONE:
        return CommUpdate(
            before, before, latest_status=wire,
            errors=("Got a result when we were already in the DONE state",),
        )
    if before is CommState.LOST:
        return CommUpdate(
            before, before, latest_status=wire, errors=(f"In a funny state: {before.value}",)
        )
    fed = _apply_comm_status(before, wire)
    return CommUpdate(
        before, CommState.DONE, fed.passed + (CommState.DONE,), wire, fed.errors
    )


def apply_comm_cancel(state: CommState | int) -> CommUpdate:
    """The client cancels the goal (``ClientGoalHandle.cancel``): it sends the cancel and
    moves to WAITING_FOR_CANCEL_ACK from *any* state, DONE included, as rospy does."""
    before = CommState(_coerce(CommState, state, "comm state"))
    target = CommState.WAITING_FOR_CANCEL_ACK
    return CommUpdate(before, target, (target,))


#: Every outcome of :func:`apply_comm_status` and :func:`apply_comm_result` for a CommState
#: and a status of the table (or None: missing from the array), worked out once by the
#: functions themselves (the updates are immutable), so the hot path is one lookup.
_COMM_STATUS_UPDATES: Mapping[tuple[CommState, int | None], CommUpdate] = MappingProxyType(
    {(c, s): _apply_comm_status(c, s) for c in CommState for s in (None, *GoalStatus)}
)
_COMM_RESULT_UPDATES: Mapping[tuple[CommState, int], CommUpdate] = MappingProxyType(
    {(c, s): _apply_comm_result(c, s) for c in CommState for s in GoalStatus}
)


# --- SimpleActionClient (simple_action_client.py) ---------------------------------------------


class SimpleCallback(str, Enum):
    """The user callback a comm transition fires in SimpleActionClient."""

    ACTIVE = "active_cb"
    DONE = "done_cb"


@dataclass(frozen=True)
class SimpleUpdate:
    """What one comm transition did to SimpleActionClient's simple state.

    ``callback`` is the user callback to run; for DONE it runs *before* the
    simple state is set to DONE (the order of ros/actionlib#190).
    """

    before: SimpleGoalState
    after: SimpleGoalState
    callback: SimpleCallback | None = None
    error: str | None = None


def simple_transition(
    simple_state: SimpleGoalState | int, comm_state: CommState | int, ns: str = "/"
) -> SimpleUpdate:
    """SimpleActionClient's ``_handle_transition`` for the tracked goal.

    ``ns`` is the resolved action namespace, used only in the error text.
    Comm states other than ACTIVE, PREEMPTING, RECALLING and DONE change nothing.
    """
    before = SimpleGoalState(_coerce(SimpleGoalState, simple_state, "simple goal state"))
    comm = CommState(_coerce(CommState, comm_state, "comm state"))
    P, A, D = SimpleGoalState.PENDING, SimpleGoalState.ACTIVE, SimpleGoalState.DONE
    error = (
        f"Received comm state {comm.name} when in simple state {before.name} "
        f"with SimpleActionClient in NS {ns}"
    )
    if comm in (CommState.ACTIVE, CommState.PREEMPTING):
        if before is P:
            return SimpleUpdate(before, A, SimpleCallback.ACTIVE)
        if before is D:
            return SimpleUpdate(before, before, error=error)
    elif comm is CommState.RECALLING:
        if before is not P:
            return SimpleUpdate(before, before, error=error)
    elif comm is CommState.DONE:
        if before in (P, A):
            return SimpleUpdate(before, D, SimpleCallback.DONE)
        return SimpleUpdate(before, before, error="SimpleActionClient received DONE twice")
    return SimpleUpdate(before, before)


def simple_get_state(latest_status: GoalStatus | int | None) -> int:
    """SimpleActionClient's ``get_state()``: LOST without a goal, RECALLING->PENDING,
    PREEMPTING->ACTIVE, otherwise the latest status (a GoalStatus when it is one)."""
    if latest_status is None:
        return GoalStatus.LOST
    wire = _wire_status(latest_status)
    if wire == GoalStatus.RECALLING:
        return GoalStatus.PENDING
    if wire == GoalStatus.PREEMPTING:
        return GoalStatus.ACTIVE
    return wire


# --- Markdown rendering ------------------------------------------------------------------------


def _cell(target: CommTarget) -> str:
    if target is NO_TRANSITION:
        return "no transition"
    if target is INVALID_TRANSITION:
        return "**invalid**"
    assert isinstance(target, tuple)
    return " → ".join(s.name for s in target)


def render_tables() -> str:
    """The state tables as Markdown (the block kept in ``docs/actionlib.md``)."""
    out: list[str] = []
    events = list(ServerEvent)
    out.append("### Server goal states (`ServerGoalHandle`)")
    out.append("")
    out.append("Rows: current status; columns: event (rospy method). — = illegal.")
    out.append("")
    out.append("| status | " + " | ".join(f"{e.value} (`{e.ros_method}`)" for e in events) + " |")
    out.append("| --- |" + " --- |" * len(events))
    for s in SERVER_STATES:
        cells = []
        for e in events:
            t = SERVER_TRANSITIONS[s][e]
            cells.append("—" if t is None else t.name)
        out.append(f"| {s.name} ({s.value}) | " + " | ".join(cells) + " |")
    out.append("")
    out.append("### Client comm states (`action_client._transitions`)")
    out.append("")
    out.append("Rows: comm state; columns: status received for the goal.")
    out.append("")
    statuses = [s for s in GoalStatus if s is not GoalStatus.LOST]
    out.append("| comm state | " + " | ".join(s.name for s in statuses) + " |")
    out.append("| --- |" + " --- |" * len(statuses))
    for c, row in COMM_TRANSITIONS.items():
        out.append(f"| {c.name} | " + " | ".join(_cell(row[s]) for s in statuses) + " |")
    out.append("")
    out.append("### SimpleActionClient (`_handle_transition`)")
    out.append("")
    out.append("Rows: simple state; columns: comm state entered. Cells: new simple state "
               "(callback), or error.")
    out.append("")
    comms = [CommState.ACTIVE, CommState.PREEMPTING, CommState.RECALLING, CommState.DONE]
    out.append("| simple state | " + " | ".join(c.name for c in comms) + " | others |")
    out.append("| --- |" + " --- |" * (len(comms) + 1))
    for ss in SimpleGoalState:
        cells = []
        for c in comms:
            u = simple_transition(ss, c)
            if u.error is not None:
                cells.append("error")
            elif u.callback is not None:
                cells.append(f"{u.after.name} (`{u.callback.value}`)")
            else:
                cells.append(f"{u.after.name}")
        out.append(f"| {ss.name} | " + " | ".join(cells) + f" | {ss.name} |")
    out.append("")
    out.append("### SimpleActionClient.get_state()")
    out.append("")
    out.append("| latest status | get_state() |")
    out.append("| --- | --- |")
    out.append(f"| (no goal) | {GoalStatus(simple_get_state(None)).name} |")
    for s in GoalStatus:
        out.append(f"| {s.name} | {GoalStatus(simple_get_state(s)).name} |")
    return "\n".join(out) + "\n"
