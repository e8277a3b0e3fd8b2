"""The action server's bookkeeping as pure functions: goals, cancels, status-list expiry.

This is ``actionlib/action_server.py`` (``internal_goal_callback``,
``internal_cancel_callback``, ``publish_status``) and the goal-handle calls of
``server_goal_handle.py``, without topics, threads or clocks.  The state is an
immutable :class:`ServerGoals` (the status list, ``last_cancel_ns`` and the
``status_list_timeout_ns``); each function takes it and the current time and
returns the new state plus what ROS would publish, in ROS's order
(:class:`Publication`).  A server built on top only forwards those
publications to its topics and runs the user callbacks the outcome names.
Every time here is an ``int`` of nanoseconds, in a parameter or field named
``*_ns`` (``now_ns``, ``stamp_ns``); convert a ``Time`` or seconds with
:mod:`ddes.time.units`.

The cancel policy (``internal_cancel_callback``): a tracked goal is cancelled
when the request is (id ``""``, stamp 0) (everything), names its id, or has a
nonzero stamp at or after the goal's stamp.  A nonzero id that matches no
goal leaves a placeholder in RECALLING, so the goal, when it comes, is
RECALLED.  ``last_cancel = max(last_cancel, stamp)``, and a new goal whose
nonzero stamp is ``<= last_cancel`` is cancelled at once.

ROS prunes the status list every time it publishes it: an entry goes once
``destruction_time + status_list_timeout < now`` (a destruction time of 0
means "not set", as ``rospy.Time()`` does in ROS).  The functions here prune
at exactly those points.

Deliberate deviation: ROS calls the user's cancel callback for each goal
*inside* its loop over the status list; :func:`receive_cancel` does the whole
loop and lists the goals whose callback must run (``cancel_requested``, in
order).  The two differ only when a cancel callback changes another goal that
the same request matches later in the list.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from enum import Enum
from typing import Any, TypeVar

from ddes.actionlib.goal_id import GoalIdGenerator, check_ns
from ddes.actionlib.states import (
    TERMINAL_STATUSES,
    GoalStatus,
    ServerEvent,
    ServerTransition,
    server_transition,
)
from ddes.errors import DdesKeyError, DdesTypeError, DdesValueError

__all__ = [
    "CANCELED_BY_STAMP_TEXT",
    "CancelOutcome",
    "CancelRequest",
    "EventOutcome",
    "GoalArrival",
    "GoalIdGenerator",
    "GoalOutcome",
    "GoalTracker",
    "Publication",
    "PublicationTopic",
    "STATUS_LIST_TIMEOUT_NS",
    "ServerGoals",
    "StatusOutcome",
    "UNINITIALIZED_GOAL_ID_TEXT",
    "UNINITIALIZED_HANDLE_TEXT",
    "apply_goal_event",
    "cancel_matches",
    "is_expired",
    "publish_status",
    "receive_cancel",
    "receive_goal",
]

#: Default ``<ns>/status_list_timeout``: 5 s.
STATUS_LIST_TIMEOUT_NS = 5_000_000_000

#: The status text of a goal cancelled on arrival because of ``last_cancel``.
CANCELED_BY_STAMP_TEXT = (
    "This goal handle was canceled by the action server because its timestamp is before "
    "the timestamp of the last cancel request"
)

#: rospy's log text for a ``set_*`` call on a handle without a goal (a cancel placeholder).
UNINITIALIZED_HANDLE_TEXT = "Attempt to set status on an uninitialized ServerGoalHandle"

#: rospy's log text for reading the goal id of such a handle.  Every ``set_*`` call
#: and cancel request reads it twice for its debug line, so ROS logs it twice per call.
UNINITIALIZED_GOAL_ID_TEXT = "Attempt to get a goal id on an uninitialized ServerGoalHandle"


@dataclass(frozen=True)
class CancelRequest:
    """An ``actionlib_msgs/GoalID`` received on ``<ns>/cancel`` (its stamp in int ns)."""

    id: str = ""
    stamp_ns: int = 0

    def __post_init__(self) -> None:
        if not isinstance(self.id, str):
            raise DdesTypeError(f"cancel request id must be a str, got {self.id!r}")
        check_ns(self.stamp_ns, "cancel request stamp_ns")

    @classmethod
    def all(cls) -> CancelRequest:
        """``cancel_all_goals()``: id ``""``, stamp 0."""
        return cls("", 0)

    @classmethod
    def by_id(cls, goal_id: str) -> CancelRequest:
        """``ClientGoalHandle.cancel()``: the goal's id, stamp 0."""
        return cls(goal_id, 0)

    @classmethod
    def at_and_before(cls, stamp_ns: int) -> CancelRequest:
        """``cancel_goals_at_and_before_time(t)``: id ``""``, stamp ``t`` (int ns)."""
        return cls("", check_ns(stamp_ns, "cancel stamp_ns"))

    @property
    def cancels_everything(self) -> bool:
        """True for the cancel-all request (id ``""`` and stamp 0)."""
        return self.id == "" and self.stamp_ns == 0


@dataclass(frozen=True)
class GoalTracker:
    """One entry of the server's status list (actionlib's ``StatusTracker``).

    ``stamp_ns`` is the goal id's stamp (int ns).  ``has_goal`` is False for
    a cancel placeholder (ROS: ``tracker.goal is None``); ``has_handle``
    mirrors ROS's ``handle_tracker is not None``.  ``destruction_time_ns`` is
    int ns, 0 meaning "not set" (ROS's ``Time()``).
    ``serial`` tells entries apart as ROS's object identity does (the functions
    here number the entries they create 1, 2, ... per :class:`ServerGoals`).
    """

    goal_id: str
    stamp_ns: int
    status: GoalStatus
    text: str = ""
    has_goal: bool = True
    has_handle: bool = True
    destruction_time_ns: int = 0
    serial: int = 0

    def __post_init__(self) -> None:
        if not isinstance(self.goal_id, str):
            raise DdesTypeError(f"goal id must be a str, got {self.goal_id!r}")
        check_ns(self.stamp_ns, "goal stamp_ns")
        try:
            object.__setattr__(self, "status", GoalStatus(self.status))
        except ValueError:
            raise DdesValueError(
                f"goal status {self.status!r} is not a GoalStatus (0..9)"
            ) from None
        check_ns(self.destruction_time_ns, "destruction_time_ns")

    @property
    def is_placeholder(self) -> bool:
        """True for the RECALLING entry a cancel for an unknown id leaves behind."""
        return not self.has_goal


@dataclass(frozen=True)
class ServerGoals:
    """The server's bookkeeping: the status list in order, ``last_cancel_ns``,
    ``status_list_timeout_ns`` (default 5 s) and ``created``, the number of
    entries ever created (the last serial handed out)."""

    trackers: tuple[GoalTracker, ...] = ()
    last_cancel_ns: int = 0
    status_list_timeout_ns: int = STATUS_LIST_TIMEOUT_NS
    created: int = 0

    def __post_init__(self) -> None:
        object.__setattr__(self, "trackers", tuple(self.trackers))
        check_ns(self.last_cancel_ns, "last_cancel_ns")
        check_ns(self.status_list_timeout_ns, "status_list_timeout_ns", instant=False)

    @classmethod
    def create(cls, status_list_timeout_ns: int = STATUS_LIST_TIMEOUT_NS) -> ServerGoals:
        """An empty status list with the given ``status_list_timeout_ns``."""
        return cls((), 0, status_list_timeout_ns, 0)

    def find(self, goal_id: str) -> GoalTracker | None:
        """The first entry with ``goal_id`` (as ROS's list scans find it), or None."""
        for t in self.trackers:
            if t.goal_id == goal_id:
                return t
        return None

    @property
    def goal_ids(self) -> tuple[str, ...]:
        """The ids of the entries, in list order."""
        return tuple(t.goal_id for t in self.trackers)


class PublicationTopic(str, Enum):
    """The server topic a :class:`Publication` goes to."""

    STATUS = "status"
    RESULT = "result"


@dataclass(frozen=True)
class Publication:
    """One message the server publishes: a status array or a result.

    ``stamp_ns`` is its ``header.stamp``; ``statuses`` is the status array's
    list, or the one status of a result.
    """

    topic: PublicationTopic
    stamp_ns: int
    statuses: tuple[GoalTracker, ...]


_D = TypeVar("_D")
_new = object.__new__
_set = object.__setattr__


def _made(cls: type[_D], fields: dict[str, Any]) -> _D:
    """``cls(**fields)`` for a frozen dataclass given *every* field (in order), already checked:
    what its ``__init__`` stores, without running it (nor ``__post_init__``).  ``fields`` (a
    new dict) becomes the instance's ``__dict__``.  The hot path's constructor."""
    obj: _D = _new(cls)
    _set(obj, "__dict__", fields)
    return obj


def _evolve(t: GoalTracker, changes: dict[str, Any]) -> GoalTracker:
    """``dataclasses.replace(t, **changes)`` for changes already checked (a GoalStatus member,
    a str text, int nanoseconds >= 0, a bool)."""
    if type(t) is not GoalTracker:
        return replace(t, **changes)
    return _made(GoalTracker, {**t.__dict__, **changes})


def _tracker(goal_id: str, stamp_ns: int, status: GoalStatus, serial: int, *,
             has_goal: bool = True, has_handle: bool = True,
             destruction_time_ns: int = 0) -> GoalTracker:
    """A new :class:`GoalTracker` from checked values (``goal_id`` a str, int ns >= 0)."""
    return _made(GoalTracker, {"goal_id": goal_id, "stamp_ns": stamp_ns, "status": status,
                               "text": "", "has_goal": has_goal, "has_handle": has_handle,
                               "destruction_time_ns": destruction_time_ns, "serial": serial})


def is_expired(tracker: GoalTracker, now_ns: int, status_list_timeout_ns: int) -> bool:
    """ROS's pruning test: ``destruction_time != 0 and destruction_time + timeout < now``."""
    t = tracker.destruction_time_ns
    return t != 0 and t + status_list_timeout_ns < now_ns


def cancel_matches(request: CancelRequest, tracker: GoalTracker) -> bool:
    """Whether ``request`` cancels ``tracker`` (the three tests of ``internal_cancel_callback``)."""
    everything = request.id == "" and request.stamp_ns == 0
    this_one = request.id == tracker.goal_id
    before_stamp = request.stamp_ns != 0 and tracker.stamp_ns <= request.stamp_ns
    return everything or this_one or before_stamp


class _Book:
    """A mutable working copy for one call: entries are boxes, so a pruned entry still
    seen by a loop over an earlier copy keeps being updated, as ROS's objects are."""

    __slots__ = ("boxes", "now_ns", "timeout_ns", "last_cancel_ns", "created", "publications",
                 "removed", "errors")

    def __init__(self, goals: ServerGoals, now_ns: int) -> None:
        self.boxes: list[list[GoalTracker]] = [[t] for t in goals.trackers]
        self.now_ns = now_ns
        self.timeout_ns = goals.status_list_timeout_ns
        self.last_cancel_ns = goals.last_cancel_ns
        self.created = goals.created
        self.publications: list[Publication] = []
        self.removed: list[GoalTracker] = []
        self.errors: list[str] = []  # what rospy logs with logerr, in order

    def publish_status(self) -> None:
        now_ns, timeout_ns = self.now_ns, self.timeout_ns
        kept = []
        for box in self.boxes:
            t = box[0].destruction_time_ns  # is_expired(), inline
            if t != 0 and t + timeout_ns < now_ns:
                self.removed.append(box[0])
            else:
                kept.append(box)
        self.boxes = kept
        entries = tuple([box[0] for box in kept])
        self.publications.append(_made(Publication, {
            "topic": _STATUS_TOPIC, "stamp_ns": now_ns, "statuses": entries}))

    def publish_result(self, tracker: GoalTracker) -> None:
        self.publications.append(_made(Publication, {
            "topic": _RESULT_TOPIC, "stamp_ns": self.now_ns, "statuses": (tracker,)}))
        self.publish_status()

    def goals(self, template: ServerGoals) -> ServerGoals:
        return _made(ServerGoals, {
            "trackers": tuple([b[0] for b in self.boxes]), "last_cancel_ns": self.last_cancel_ns,
            "status_list_timeout_ns": template.status_list_timeout_ns, "created": self.created})

    def serial(self) -> int:
        self.created += 1
        return self.created

    def apply(self, box: list[GoalTracker], event: ServerEvent, text: str) -> ServerTransition:
        """A ``ServerGoalHandle`` call on the entry in ``box`` (publishing as ROS does)."""
        t = box[0]
        if not t.has_goal:
            self.errors += [UNINITIALIZED_GOAL_ID_TEXT] * 2
            error = None if event is ServerEvent.CANCEL_REQUEST else UNINITIALIZED_HANDLE_TEXT
            if error is not None:
                self.errors.append(error)
            return ServerTransition(t.status, event, t.status, False, error)
        tr = server_transition(t.status, event)
        if not tr.legal:
            if tr.error is not None:
                self.errors.append(tr.error)
            return tr
        if event is ServerEvent.CANCEL_REQUEST:
            box[0] = _evolve(t, {"status": tr.after})
            self.publish_status()
        elif tr.after in TERMINAL_STATUSES:
            box[0] = _evolve(t, {"status": tr.after, "text": text,
                                 "destruction_time_ns": self.now_ns})
            self.publish_result(box[0])
        else:
            box[0] = _evolve(t, {"status": tr.after, "text": text})
            self.publish_status()
        return tr


class GoalArrival(str, Enum):
    """What the server did with a goal message."""

    NEW = "new"  # tracked as PENDING; the user's goal callback must run
    CANCELED_BY_STAMP = "canceled_by_stamp"  # stamp <= last_cancel: set_canceled at once
    DUPLICATE = "duplicate"  # id already tracked: ignored
    DUPLICATE_RECALLED = "duplicate_recalled"  # id tracked as RECALLING: now RECALLED


@dataclass(frozen=True)
class GoalOutcome:
    """The result of :func:`receive_goal`; ``tracker`` is the goal's entry afterwards."""

    goals: ServerGoals
    arrival: GoalArrival
    tracker: GoalTracker
    publications: tuple[Publication, ...] = ()
    transition: ServerTransition | None = None
    errors: tuple[str, ...] = ()

    @property
    def call_goal_callback(self) -> bool:
        """True iff the user's goal callback must run (only for a NEW goal)."""
        return self.arrival is _NEW


@dataclass(frozen=True)
class CancelOutcome:
    """The result of :func:`receive_cancel`.

    ``matched`` lists the ids of every entry the request matched (in list
    order); ``cancel_requested`` those that moved to RECALLING/PREEMPTING,
    whose user cancel callback must run, in order.  ``placeholder`` is the new
    RECALLING placeholder, if any.  ``transitions`` holds the cancel request
    of every matched entry; ``errors`` what rospy logs (a matched placeholder
    logs :data:`UNINITIALIZED_GOAL_ID_TEXT` twice).
    """

    goals: ServerGoals
    request: CancelRequest
    matched: tuple[str, ...] = ()
    cancel_requested: tuple[str, ...] = ()
    placeholder: GoalTracker | None = None
    publications: tuple[Publication, ...] = ()
    transitions: tuple[ServerTransition, ...] = ()
    errors: tuple[str, ...] = ()


@dataclass(frozen=True)
class EventOutcome:
    """The result of :func:`apply_goal_event`; ``tracker`` is the goal afterwards.

    ``errors`` is what rospy logs: the transition's error, and for a
    placeholder also :data:`UNINITIALIZED_GOAL_ID_TEXT` twice before it.
    """

    goals: ServerGoals
    transition: ServerTransition
    tracker: GoalTracker
    publications: tuple[Publication, ...] = ()
    errors: tuple[str, ...] = ()


@dataclass(frozen=True)
class StatusOutcome:
    """The result of :func:`publish_status`: the pruned list, the array, the entries dropped."""

    goals: ServerGoals
    publication: Publication
    removed: tuple[GoalTracker, ...] = ()


def receive_goal(
    goals: ServerGoals,
    goal_id: str,
    stamp_ns: int,
    now_ns: int,
    ids: GoalIdGenerator,
) -> GoalOutcome:
    """A goal message (``goal_id.id``, ``goal_id.stamp``) arrives (``internal_goal_callback``).

    * An id already in the list is a duplicate: ignored, except that a
      RECALLING entry becomes RECALLED (an empty result is published); an
      entry without a handle (a placeholder) gets ``destruction_time = now``.
    * Otherwise the goal is tracked as PENDING.  An empty id is replaced by
      ``ids.generate_id(now_ns)`` (whose stamp is now); a zero stamp becomes now.
    * The goal is cancelled at once when its stamp is nonzero and
      ``<= last_cancel``.  As in rospy the stamp tested is the one tracked for
      a given id (a zero stamp already replaced by now), but the message's
      own stamp when the id was empty and had to be generated.
    """
    if not isinstance(goal_id, str):
        raise DdesTypeError(f"goal id must be a str, got {goal_id!r}")
    if type(stamp_ns) is not int or stamp_ns < 0:
        check_ns(stamp_ns, "goal stamp_ns")
    if type(now_ns) is not int or now_ns < 0:
        check_ns(now_ns, "now_ns")
    book = _Book(goals, now_ns)
    for box in list(book.boxes):
        t = box[0]
        if t.goal_id != goal_id:
            continue
        arrival = GoalArrival.DUPLICATE
        if t.status is GoalStatus.RECALLING:
            box[0] = t = _evolve(t, {"status": GoalStatus.RECALLED})
            arrival = GoalArrival.DUPLICATE_RECALLED
            book.publish_result(t)
        if not t.has_handle:
            box[0] = _evolve(t, {"destruction_time_ns": now_ns})
        return GoalOutcome(book.goals(goals), arrival, box[0], tuple(book.publications))
    if goal_id == "":
        generated = ids.generate_id(now_ns)
        tracked_id, tracked_stamp, tested_stamp = generated.id, generated.stamp_ns, stamp_ns
    else:
        tracked_stamp = stamp_ns if stamp_ns != 0 else now_ns
        tracked_id, tested_stamp = goal_id, tracked_stamp
    if goal_id == "":  # a generator's id: checked by GoalTracker
        box = [GoalTracker(tracked_id, tracked_stamp, GoalStatus.PENDING, serial=book.serial())]
    else:
        box = [_tracker(tracked_id, tracked_stamp, _PENDING, book.serial())]
    book.boxes.append(box)
    if tested_stamp != 0 and tested_stamp <= book.last_cancel_ns:
        tr = book.apply(box, ServerEvent.CANCEL, CANCELED_BY_STAMP_TEXT)
        return GoalOutcome(
            book.goals(goals), GoalArrival.CANCELED_BY_STAMP, box[0], tuple(book.publications), tr
        )
    return _made(GoalOutcome, {"goals": book.goals(goals), "arrival": _NEW,
                               "tracker": box[0], "publications": (), "transition": None,
                               "errors": ()})


def receive_cancel(goals: ServerGoals, request: CancelRequest, now_ns: int) -> CancelOutcome:
    """A cancel request arrives (``internal_cancel_callback``); see the module docstring."""
    if not isinstance(request, CancelRequest):
        raise DdesTypeError(
            f"cancel request must be a CancelRequest, got {request!r}; "
            "use CancelRequest(id, stamp_ns) or CancelRequest.all()"
        )
    check_ns(now_ns, "now_ns")
    book = _Book(goals, now_ns)
    found = False
    matched: list[str] = []
    requested: list[str] = []
    transitions: list[ServerTransition] = []
    for box in list(book.boxes):
        t = box[0]
        if not cancel_matches(request, t):
            continue
        matched.append(t.goal_id)
        if request.id == t.goal_id:
            found = True
        if not t.has_handle:
            box[0] = _evolve(t, {"has_handle": True, "destruction_time_ns": now_ns})
        tr = book.apply(box, ServerEvent.CANCEL_REQUEST, "")
        transitions.append(tr)
        if tr.legal:
            requested.append(box[0].goal_id)
    placeholder = None
    if request.id != "" and not found:
        placeholder = GoalTracker(
            request.id, request.stamp_ns, GoalStatus.RECALLING,
            has_goal=False, has_handle=False, destruction_time_ns=now_ns, serial=book.serial(),
        )
        book.boxes.append([placeholder])
    book.last_cancel_ns = max(book.last_cancel_ns, request.stamp_ns)
    return CancelOutcome(
        book.goals(goals), request, tuple(matched), tuple(requested), placeholder,
        tuple(book.publications), tuple(transitions), tuple(book.errors),
    )


def apply_goal_event(
    goals: ServerGoals,
    goal: str | GoalTracker,
    event: ServerEvent | str,
    now_ns: int,
    text: str = "",
) -> EventOutcome:
    """A ``ServerGoalHandle`` call (``set_accepted``, ``set_succeeded``, ...) on one goal.

    ``goal`` is an id (the first entry with it is used) or a tracker (the
    entry with its ``serial``).  A tracker no longer in the list (pruned) is
    still updated, as ROS's handle keeps its StatusTracker: the result is
    published, and the status array without it.  ``text`` is the status text the
    call sets (a cancel request keeps the old text).  An illegal call changes
    nothing and publishes nothing; ``transition.error`` holds ROS's log text.
    """
    if type(now_ns) is not int or now_ns < 0:
        check_ns(now_ns, "now_ns")
    if not isinstance(text, str):
        raise DdesTypeError(f"status text must be a str, got {text!r}")
    if isinstance(event, str) and not isinstance(event, ServerEvent):
        try:
            event = ServerEvent(event)
        except ValueError:
            names = ", ".join(e.value for e in ServerEvent)
            raise DdesValueError(f"unknown server goal event {event!r}; use one of: {names}") from None
    if type(goal) is GoalTracker and type(event) is ServerEvent and goal.has_goal:
        fast = _apply_to_tracker(goals, goal, event, now_ns, text)
        if fast is not None:
            return fast
    book = _Book(goals, now_ns)
    if isinstance(goal, GoalTracker):
        serial = goal.serial
        box = [goal]
        for b in book.boxes:
            if b[0].serial == serial:
                box = b
                break
    elif isinstance(goal, str):
        found = next((b for b in book.boxes if b[0].goal_id == goal), None)
        if found is None:
            known = ", ".join(repr(i) for i in goals.goal_ids) or "none"
            raise DdesKeyError(
                f"no goal with id {goal!r} in the status list (known: {known}); "
                "pass the GoalTracker to act on a goal that has expired from the list"
            )
        box = found
    else:
        raise DdesTypeError(f"goal must be a goal id (str) or a GoalTracker, got {goal!r}")
    tr = book.apply(box, event if type(event) is ServerEvent else ServerEvent(event), text)
    return _made(EventOutcome, {"goals": book.goals(goals), "transition": tr, "tracker": box[0],
                                "publications": tuple(book.publications),
                                "errors": tuple(book.errors)})


def _apply_to_tracker(goals: ServerGoals, goal: GoalTracker, event: ServerEvent, now_ns: int,
                      text: str) -> EventOutcome | None:
    """:func:`apply_goal_event` on a tracker, for the hot path: what ``_Book.apply`` does,
    without a working copy of the list (None: a placeholder entry, left to the general path).

    The entry acted on is the list's entry with the tracker's serial, else the tracker itself
    (pruned: it is updated, its result published, the array published without it)."""
    trackers = goals.trackers
    serial = goal.serial
    index = -1
    for i in range(len(trackers)):
        if trackers[i].serial == serial:
            index = i
            break
    t = trackers[index] if index >= 0 else goal
    if not t.has_goal:
        return None
    tr = server_transition(t.status, event)
    if not tr.legal:
        return _made(EventOutcome, {
            "goals": _made(ServerGoals, {**goals.__dict__}), "transition": tr, "tracker": t,
            "publications": (), "errors": () if tr.error is None else (tr.error,)})
    after = tr.after
    pubs: list[Publication] = []
    if event is _CANCEL_REQUEST:
        new = _evolve(t, {"status": after})
    elif after in TERMINAL_STATUSES:
        new = _evolve(t, {"status": after, "text": text, "destruction_time_ns": now_ns})
        pubs.append(_made(Publication, {
            "topic": _RESULT_TOPIC, "stamp_ns": now_ns, "statuses": (new,)}))
    else:
        new = _evolve(t, {"status": after, "text": text})
    timeout_ns = goals.status_list_timeout_ns
    kept = []
    for i in range(len(trackers)):  # the new entry in its place, then ROS's pruning
        x = new if i == index else trackers[i]
        d = x.destruction_time_ns
        if d == 0 or d + timeout_ns >= now_ns:
            kept.append(x)
    entries = tuple(kept)
    pubs.append(_made(Publication, {
        "topic": _STATUS_TOPIC, "stamp_ns": now_ns, "statuses": entries}))
    return _made(EventOutcome, {
        "goals": _made(ServerGoals, {
            "trackers": entries, "last_cancel_ns": goals.last_cancel_ns,
            "status_list_timeout_ns": timeout_ns, "created": goals.created}),
        "transition": tr, "tracker": new, "publications": tuple(pubs), "errors": ()})


def publish_status(goals: ServerGoals, now_ns: int) -> StatusOutcome:
    """The status array at ``now_ns`` (``ActionServer.publish_status``), pruning expired entries."""
    book = _Book(goals, check_ns(now_ns, "now_ns"))
    book.publish_status()
    return StatusOutcome(book.goals(goals), book.publications[0], tuple(book.removed))


# Enum members as plain globals for the hot paths (a member read through its class is slower).
_STATUS_TOPIC, _RESULT_TOPIC = PublicationTopic.STATUS, PublicationTopic.RESULT
_CANCEL_REQUEST = ServerEvent.CANCEL_REQUEST
_PENDING = GoalStatus.PENDING
_NEW = GoalArrival.NEW
