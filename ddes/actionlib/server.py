"""ActionServer and ServerGoalHandle on the five action topics (rospy ``actionlib.ActionServer``).

The server owns five topics under its namespace ``ns``:

============  =========================  ==========  =====================================
topic         type                       direction   notes
============  =========================  ==========  =====================================
``goal``      ``FooActionGoal``          subscribed  queue ``actionlib_server_sub_queue_size``
``cancel``    ``actionlib_msgs/GoalID``  subscribed  (default -1: unbounded)
``status``    ``GoalStatusArray``        published   **latched**; queue
``feedback``  ``FooActionFeedback``      published   ``actionlib_server_pub_queue_size``
``result``    ``FooActionResult``        published   (default 50)
============  =========================  ==========  =====================================

Every decision is taken by the pure core (:mod:`ddes.actionlib.cancel`:
``receive_goal``, ``receive_cancel``, ``apply_goal_event``,
``publish_status``); this module only turns its publications into messages
and runs the user's callbacks.  So the status array is published on every
transition (a result first, then the array, for a terminal one), by a node
Timer at ``actionlib_status_frequency`` (default 5 Hz, ROS time), and
finished goals stay in it ``<ns>/status_list_timeout`` (default 5 s).

An illegal call on a goal handle (``set_succeeded`` on a goal already
SUCCEEDED, ...) changes nothing, logs ROS's error text, records an
``action.server.illegal`` trace event and counts it in
:attr:`ActionServer.illegal_transitions`: never silent, never a crash.

Differences from rospy, on purpose: ``auto_start`` defaults to False (ROS
defaults to True and then warns that it races; ddes keeps the warning when you
pass True); goals and cancels reaching a server that is not started are
ignored, as in ROS, but recorded as ``action.misuse``; goal ids count per node
(ROS: per process).
"""

from __future__ import annotations

from collections.abc import Callable
from functools import cached_property
from typing import TYPE_CHECKING

from ddes.actionlib._common import (
    ActionTypes,
    CallbackGenerator,
    NodeGoalIds,
    UserCall,
    check_message,
    misuse,
    no_node,
    queue_size_param,
    run_user_callbacks,
)
from ddes.actionlib.cancel import (
    UNINITIALIZED_HANDLE_TEXT,
    CancelRequest,
    GoalArrival,
    GoalTracker,
    Publication,
    PublicationTopic,
    ServerGoals,
    apply_goal_event,
    publish_status,
    receive_cancel,
    receive_goal,
)
from ddes.actionlib.goal_id import GoalIdStyle
from ddes.actionlib.states import TERMINAL_STATUSES, GoalStatus, ServerEvent, ServerTransition
from ddes.errors import DdesTypeError, ROSActionException
from ddes.graph.rosout import WARN
from ddes.msg.message import Message
from ddes.time.rospy_calls import REQUIRED, is_node_like
from ddes.time.rostime import Duration, Time
from ddes.time.units import duration_to_ns, time_to_ns

if TYPE_CHECKING:
    from ddes.graph.node import Node
    from ddes.graph.timer import Timer, TimerEvent
    from ddes.graph.topics import Publisher, Subscriber

__all__ = ["AUTO_START_WARNING", "ActionServer", "ServerGoalHandle"]

#: rospy's warning for ``auto_start=True``.
AUTO_START_WARNING = (
    "You've passed in true for auto_start to the python action server, you should always pass "
    "in false to avoid race conditions."
)
_DEPRECATED_FREQUENCY = (
    "You're using the deprecated status_frequency parameter, please switch to "
    "actionlib_status_frequency.")

#: ``goal_cb(gh)`` / ``cancel_cb(gh)``: a plain function, or a generator that takes time.
GoalHandleCallback = Callable[["ServerGoalHandle"], object]


class ServerGoalHandle:
    """One goal as the server's user sees it (rospy ``ServerGoalHandle``).

    Handles are made by the server; two handles are equal when their goal
    ids are.  A handle without a goal (``ServerGoalHandle.uninitialized``,
    what SimpleActionServer holds before its first goal) logs ROS's
    "uninitialized" error on every call, as rospy does.
    """

    __slots__ = ("_server", "_tracker", "goal")

    def __init__(self, server: ActionServer, tracker: GoalTracker | None,
                 goal: Message | None) -> None:
        self._server = server
        self._tracker = tracker
        #: The ``FooActionGoal`` message (header, goal_id, goal), or None.
        self.goal = goal

    @classmethod
    def uninitialized(cls, server: ActionServer) -> ServerGoalHandle:
        """A handle without a goal (rospy ``ServerGoalHandle()``)."""
        return cls(server, None, None)

    # -- state ----------------------------------------------------------------------------
    @property
    def tracker(self) -> GoalTracker | None:
        """The goal's current entry of the status list (kept after it is pruned)."""
        return self._tracker

    def get_goal(self) -> Message | None:
        """The user's goal (``FooGoal``), or None for an uninitialized handle."""
        return None if self.goal is None else self.goal.goal

    def get_goal_id(self) -> Message:
        """The ``actionlib_msgs/GoalID`` of the goal (an empty one, logged, if uninitialized)."""
        GoalID = self._server._GoalID
        t = self._tracker
        if self.goal is None or t is None:
            misuse(self._server.node, self._server.ns,
                   "Attempt to get a goal id on an uninitialized ServerGoalHandle")
            return GoalID()
        return GoalID(stamp=Time.from_nsec(t.stamp_ns), id=t.goal_id)

    def get_goal_status(self) -> Message:
        """The goal's ``actionlib_msgs/GoalStatus`` (an empty one, logged, if uninitialized)."""
        t = self._tracker
        if self.goal is None or t is None:
            misuse(self._server.node, self._server.ns,
                   "Attempt to get goal status on an uninitialized ServerGoalHandle")
            return self._server._GoalStatus()
        return self._server._status_msg(t)

    @property
    def status(self) -> GoalStatus | None:
        """The goal's status as a :class:`GoalStatus` (None if uninitialized); no logging."""
        return None if self._tracker is None or self.goal is None else self._tracker.status

    # -- transitions ----------------------------------------------------------------------
    def set_accepted(self, text: str = "") -> ServerTransition | None:
        """PENDING → ACTIVE or RECALLING → PREEMPTING."""
        return self._server._event(self, _ACCEPT, None, text)

    def set_rejected(self, result: Message | None = None,
                     text: str = "") -> ServerTransition | None:
        """PENDING or RECALLING → REJECTED (publishes the result)."""
        return self._server._event(self, _REJECT, result, text)

    def set_canceled(self, result: Message | None = None,
                     text: str = "") -> ServerTransition | None:
        """PENDING/RECALLING → RECALLED, ACTIVE/PREEMPTING → PREEMPTED (publishes the result)."""
        return self._server._event(self, _CANCEL, result, text)

    def set_succeeded(self, result: Message | None = None,
                      text: str = "") -> ServerTransition | None:
        """ACTIVE or PREEMPTING → SUCCEEDED (publishes the result)."""
        return self._server._event(self, _SUCCEED, result, text)

    def set_aborted(self, result: Message | None = None,
                    text: str = "") -> ServerTransition | None:
        """ACTIVE or PREEMPTING → ABORTED (publishes the result)."""
        return self._server._event(self, _ABORT, result, text)

    def set_cancel_requested(self) -> bool:
        """PENDING → RECALLING or ACTIVE → PREEMPTING; True iff it moved (ROS's private helper)."""
        tr = self._server._event(self, ServerEvent.CANCEL_REQUEST, None, "")
        return tr is not None and tr.legal

    def publish_feedback(self, feedback: Message) -> None:
        """Publish ``feedback`` (a ``FooFeedback``) for this goal, whatever its state, as ROS does."""
        self._server._feedback(self, feedback)

    # -- identity -------------------------------------------------------------------------
    def _id(self) -> str | None:
        return None if self.goal is None or self._tracker is None else self._tracker.goal_id

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, ServerGoalHandle):
            return NotImplemented
        mine, theirs = self._id(), other._id()
        return mine is not None and theirs is not None and mine == theirs

    def __ne__(self, other: object) -> bool:
        result = self.__eq__(other)
        return result if result is NotImplemented else not result

    def __hash__(self) -> int:
        return hash(self._id())

    def __repr__(self) -> str:
        t = self._tracker
        if self.goal is None or t is None:
            return "<ServerGoalHandle uninitialized>"
        return f"<ServerGoalHandle {t.goal_id} {t.status.name}>"


class ActionServer:
    """``ActionServer(node, ns, ActionSpec, goal_cb, cancel_cb=None, auto_start=False)``.

    ``goal_cb(gh)`` runs for every new goal, ``cancel_cb(gh)`` for every goal
    a cancel request moves to RECALLING or PREEMPTING.  Callbacks run through
    the node's callback queue; a callback that is a generator takes simulated
    time, holding the node's spinner as a slow ROS callback does.
    """

    def __init__(
        self,
        node: Node,
        ns: str,
        ActionSpec: type[Message] | str,  # noqa: N803 - rospy's parameter name
        goal_cb: GoalHandleCallback = REQUIRED,
        cancel_cb: GoalHandleCallback | None = None,
        auto_start: bool = False,
    ) -> None:
        if not is_node_like(node):
            # rospy's ActionServer(ns, ActionSpec, goal_cb, cancel_cb, auto_start): shifted left
            args: list[object] = [a for a in (ns, ActionSpec) if a is not REQUIRED]
            kwargs: dict[str, object] = {}
            if goal_cb is not REQUIRED:  # by position: rospy's cancel_cb
                kwargs["cancel_cb"] = goal_cb
            if cancel_cb is not None:  # by position: rospy's auto_start
                kwargs["auto_start"] = cancel_cb
            elif auto_start:
                kwargs["auto_start"] = auto_start
            no_node("ActionServer", "server", node, args, kwargs,
                    start=kwargs.get("auto_start") is not True)
        node.check_alive("create an action server")
        if not isinstance(ns, str) or not ns:
            raise DdesTypeError(f"action namespace must be a non-empty string, got {ns!r}")
        if not callable(goal_cb):
            raise DdesTypeError(
                f"goal_cb must be callable (it receives a ServerGoalHandle), got {goal_cb!r}")
        if cancel_cb is not None and not callable(cancel_cb):
            raise DdesTypeError(f"cancel_cb must be callable or None, got {cancel_cb!r}")
        from ddes.msg import get_message_class

        self.node = node
        self.types = ActionTypes.of(ActionSpec)
        self.ActionSpec = self.types.spec
        self.ActionGoal = self.types.action_goal
        self.ActionResult = self.types.action_result
        self.ActionResultType = self.types.result
        self.ActionFeedback = self.types.action_feedback
        self._GoalID = get_message_class("actionlib_msgs/GoalID")
        self._GoalStatus = get_message_class("actionlib_msgs/GoalStatus")
        self._GoalStatusArray = get_message_class("actionlib_msgs/GoalStatusArray")
        #: The resolved action namespace (``/fibonacci``).
        self.ns = node.resolve_name(ns)
        self.goal_callback: GoalHandleCallback = goal_cb
        self.cancel_callback: GoalHandleCallback | None = cancel_cb
        self.auto_start = bool(auto_start)
        self.started = False
        self._stopped = False
        self._ids = NodeGoalIds(node, GoalIdStyle.SERVER)
        self._goals = ServerGoals.create()
        self._handles: dict[int, ServerGoalHandle] = {}
        #: Illegal goal-handle calls so far (each also an ``action.server.illegal`` event).
        self.illegal_transitions = 0
        self.status_frequency = 5.0
        self.goal_sub: Subscriber[type[Message]] | None = None
        self.cancel_sub: Subscriber[type[Message]] | None = None
        self.status_pub: Publisher[type[Message]] | None = None
        self.result_pub: Publisher[type[Message]] | None = None
        self.feedback_pub: Publisher[type[Message]] | None = None
        self.status_timer: Timer | None = None
        node.add_entity(self)
        if self.auto_start:
            misuse(node, self.ns, AUTO_START_WARNING, level=WARN)
            self.start()

    # -- configuration --------------------------------------------------------------------
    def register_goal_callback(self, cb: GoalHandleCallback) -> None:
        """Replace the goal callback."""
        self.goal_callback = cb

    def register_cancel_callback(self, cb: GoalHandleCallback | None) -> None:
        """Replace the cancel callback."""
        self.cancel_callback = cb

    @property
    def status_list(self) -> tuple[GoalTracker, ...]:
        """The status list as the pure core holds it, in order."""
        return self._goals.trackers

    @property
    def last_cancel_ns(self) -> int:
        """The latest cancel stamp seen (int ns)."""
        return self._goals.last_cancel_ns

    @property
    def last_cancel(self) -> Time:
        """The latest cancel stamp seen (rospy's ``last_cancel``, a Time)."""
        return Time.from_nsec(self._goals.last_cancel_ns)

    @property
    def status_list_timeout_ns(self) -> int:
        """How long finished goals stay in the status list (int ns)."""
        return self._goals.status_list_timeout_ns

    @property
    def status_list_timeout(self) -> Duration:
        """How long finished goals stay in the status list (rospy's attribute, a Duration)."""
        return Duration.from_nsec(self._goals.status_list_timeout_ns)

    # -- lifecycle ------------------------------------------------------------------------
    def start(self) -> None:
        """Create the topics and the status timer, then publish the status (rospy ``start``)."""
        self.node.check_alive("start an action server")
        if self.started:
            misuse(self.node, self.ns, f"action server {self.ns} is already started; "
                   "start() was ignored", level=WARN)
            return
        self._initialize()
        self.started = True
        self._stopped = False
        self.node.world.record("action.server.start", self.node.name, ns=self.ns,
                               type=self.types.name, status_frequency=self.status_frequency,
                               status_list_timeout=self._goals.status_list_timeout_ns)
        self.publish_status()

    def _initialize(self) -> None:
        node, ns = self.node, self.ns
        pub_q = queue_size_param(node, "actionlib_server_pub_queue_size", 50)
        sub_q = queue_size_param(node, "actionlib_server_sub_queue_size", -1)
        self.status_pub = node.advertise(ns + "/status", self._GoalStatusArray, latch=True,
                                         queue_size=pub_q)
        self.result_pub = node.advertise(ns + "/result", self.ActionResult, queue_size=pub_q)
        self.feedback_pub = node.advertise(ns + "/feedback", self.ActionFeedback, queue_size=pub_q)
        self.goal_sub = node.subscribe(ns + "/goal", self.ActionGoal, self._internal_goal_callback,
                                       queue_size=sub_q)
        self.cancel_sub = node.subscribe(ns + "/cancel", self._GoalID,
                                         self._internal_cancel_callback, queue_size=sub_q)
        deprecated = ns + "/status_frequency"
        if node.has_param(deprecated):
            freq = node.get_param(deprecated, 5.0)
            misuse(node, ns, _DEPRECATED_FREQUENCY, level=WARN)
        else:
            key = node.search_param("actionlib_status_frequency")
            freq = 5.0 if key is None else node.get_param(key, 5.0)
        if isinstance(freq, bool) or not isinstance(freq, (int, float)):
            misuse(node, ns, f"actionlib_status_frequency must be a number, got {freq!r}; "
                   "using 5.0", level=WARN)
            freq = 5.0
        self.status_frequency = float(freq)
        timeout = node.get_param(ns + "/status_list_timeout", 5.0)
        if isinstance(timeout, bool) or not isinstance(timeout, (int, float)):
            misuse(node, ns, f"{ns}/status_list_timeout must be a number of seconds, got "
                   f"{timeout!r}; using 5.0", level=WARN)
            timeout = 5.0
        self._goals = ServerGoals(self._goals.trackers, self._goals.last_cancel_ns,
                                  duration_to_ns(float(timeout), "status_list_timeout"),
                                  self._goals.created)
        if self.status_frequency > 0.0:
            self.status_timer = node.create_timer(1.0 / self.status_frequency,
                                                  self._publish_status_async)

    def stop(self) -> None:
        """Stop the server: its topics and timer go away (rospy ``stop``)."""
        if not self.started:
            return
        self.started = False
        self._stopped = True
        for ent in (self.status_timer, self.goal_sub, self.cancel_sub, self.status_pub,
                    self.feedback_pub, self.result_pub):
            if ent is not None:
                ent.shutdown()
        self.status_timer = None
        self.node.world.record("action.server.stop", self.node.name, ns=self.ns)

    def shutdown(self) -> None:
        """The node is shutting down."""
        self.stop()
        self.node.remove_entity(self)

    # -- publishing -----------------------------------------------------------------------
    def _now_ns(self) -> int:
        return self.node.clock.now_ns()

    def _status_msg(self, t: GoalTracker) -> Message:
        """A new ``actionlib_msgs/GoalStatus`` of ``t`` (see :meth:`_status_entry`)."""
        return self._GoalStatus(self._GoalID(Time._from_ns(t.stamp_ns), t.goal_id), int(t.status),
                                t.text)

    def _can_publish(self, what: str) -> bool:
        if self.node.is_shutdown():
            return False  # rospy: ``if not rospy.is_shutdown(): publish``
        if not self.started:
            if self._stopped:
                raise ROSActionException(
                    f"publish() to an unregistered() handle: cannot {what} for {self.ns}, the "
                    "action server was stopped; call start() again or finish goals before stop()")
            raise ROSActionException(
                f"cannot {what} for {self.ns}: the action server is not started; call start()")
        return True

    def publish_status(self) -> None:
        """Publish the status array now, pruning expired entries (rospy ``publish_status``)."""
        if not self.started:
            misuse(self.node, self.ns, f"publish_status() on {self.ns} ignored: the action "
                   "server is not started; call start()", level=WARN)
            return
        out = publish_status(self._goals, self._now_ns())
        self._commit(out.goals, (out.publication,), None)

    def _publish_status_async(self, _event: TimerEvent) -> None:
        if self.started:
            out = publish_status(self._goals, self._now_ns())
            self._commit(out.goals, (out.publication,), None)

    def _commit(self, goals: ServerGoals, pubs: tuple[Publication, ...],
                result: Message | None) -> None:
        """Adopt the core's new state, sync the handles, forward its publications in order."""
        self._goals = goals
        handles = self._handles
        trackers = goals.trackers
        get = handles.get
        for t in trackers:  # their serials are distinct: one per entry the core ever created
            h = get(t.serial)
            if h is not None:
                h._tracker = t
        if len(trackers) != len(handles) or len(self._entries) > 2 * len(trackers) + 16:
            self._forget(trackers)  # handles (and status messages) of entries no longer listed
        if not pubs or self.node.is_shutdown():
            return
        # Each message is built whole (no default fields made, then replaced); the entries of
        # the status array are the trackers' shared GoalStatus messages (see _status_entry).
        entry = self._status_entry
        for p in pubs:
            stamp = Time._from_ns(p.stamp_ns)
            if p.topic is _STATUS_TOPIC:
                arr = self._GoalStatusArray(self._headers[0](0, stamp, ""),
                                            [entry(t) for t in p.statuses])
                assert self.status_pub is not None
                self.status_pub.publish(arr)
            else:
                ar = self.ActionResult(
                    header=self._headers[1](0, stamp, ""), status=entry(p.statuses[0]),
                    result=self.ActionResultType() if result is None else result)
                assert self.result_pub is not None
                self.result_pub.publish(ar)

    # -- goal handle calls ----------------------------------------------------------------
    def _event(self, gh: ServerGoalHandle, event: ServerEvent, result: Message | None,
               text: str) -> ServerTransition | None:
        node = self.node
        t = gh._tracker
        if gh.goal is None or t is None:
            self._uninitialized_debug_line(gh)
            if event is not ServerEvent.CANCEL_REQUEST:
                misuse(node, self.ns, UNINITIALIZED_HANDLE_TEXT, method=event.ros_method)
            return None
        if not isinstance(text, str):
            raise DdesTypeError(f"{event.ros_method}: text must be a str, got {text!r}")
        if result is not None and type(result) is not self.ActionResultType:  # else it is one
            check_message(result, self.ActionResultType, f"{event.ros_method}: the result",
                          f"pass a {self.ActionResultType.__name__}() or None")
        self._can_publish(event.ros_method)
        out = apply_goal_event(self._goals, t, event, self._now_ns(), text)
        tr, gh._tracker = out.transition, out.tracker
        if tr.legal:
            world = node.world
            world.trace.append_row((world.env.now_ns, "action.server.transition", node.name,
                                    _TRANSITION_KEYS, self.ns, t.goal_id, event.ros_method,
                                    _STATUS_NAMES[tr.before], _STATUS_NAMES[tr.after], text))
        elif tr.error is not None:
            self._illegal(t.goal_id, tr)
        self._commit(out.goals, out.publications, result)
        return tr

    @staticmethod
    def _uninitialized_debug_line(gh: ServerGoalHandle) -> None:
        """rospy's handle methods start with ``logdebug("... id: %s, stamp: %.2f",
        self.get_goal_id().id, self.get_goal_id().stamp.to_sec())``: on a handle without a
        goal, those two calls each log "Attempt to get a goal id ..." first, as here."""
        gh.get_goal_id()
        gh.get_goal_id()

    def _illegal(self, goal_id: str, tr: ServerTransition) -> None:
        self.illegal_transitions += 1
        node = self.node
        node.world.record("action.server.illegal", node.name, ns=self.ns, id=goal_id,
                          event=tr.event.ros_method, state=tr.before.name, error=tr.error)
        node.logerr(tr.error)

    def _feedback(self, gh: ServerGoalHandle, feedback: Message) -> None:
        node = self.node
        t = gh._tracker
        if gh.goal is None or t is None:
            self._uninitialized_debug_line(gh)
            misuse(node, self.ns, "Attempt to publish feedback on an uninitialized ServerGoalHandle")
            return
        if type(feedback) is not self.types.feedback:  # (an instance of the class passes)
            check_message(feedback, self.types.feedback, "publish_feedback: the feedback",
                          f"pass a {self.types.feedback.__name__}()")
        if not self._can_publish("publish feedback"):
            return
        if t.status in TERMINAL_STATUSES:
            node.world.record("action.misuse", node.name, ns=self.ns, level="WARN",
                              text=f"feedback for goal {t.goal_id} published after its terminal "
                                   f"state {t.status.name} (ROS publishes it too)")
        af = self.ActionFeedback(  # built whole, its status the tracker's shared GoalStatus
            header=self._headers[2](0, Time._from_ns(self._now_ns()), ""),
            status=self._status_entry(t), feedback=feedback)
        node.world.trace.append_row((node.world.env.now_ns, "action.server.feedback", node.name,
                                     _FEEDBACK_KEYS, self.ns, t.goal_id, _STATUS_NAMES[t.status]))
        assert self.feedback_pub is not None
        self.feedback_pub.publish(af)

    def _handle(self, tracker: GoalTracker, goal: Message) -> ServerGoalHandle:
        h = self._handles.get(tracker.serial)
        if h is None:
            h = self._handles[tracker.serial] = ServerGoalHandle(self, tracker, goal)
        return h

    # -- incoming messages ----------------------------------------------------------------
    def _internal_goal_callback(self, goal: Message) -> CallbackGenerator | None:
        node = self.node
        if not self.started:
            misuse(node, self.ns, f"goal {goal.goal_id.id!r} ignored: the action server {self.ns} "
                   "is not started (call start())", level=WARN)
            return None
        out = receive_goal(self._goals, goal.goal_id.id,
                           time_to_ns(goal.goal_id.stamp, "goal stamp"), self._now_ns(), self._ids)
        t, trace, env = out.tracker, node.world.trace, node.world.env
        trace.append_row((env.now_ns, "action.server.goal", node.name, _GOAL_KEYS, self.ns,
                          t.goal_id, t.stamp_ns, out.arrival.value))
        if out.arrival is _NEW or out.arrival is _CANCELED_BY_STAMP:
            gh = self._handle(t, goal)
        tr = out.transition
        if tr is not None and tr.legal:
            trace.append_row((env.now_ns, "action.server.transition", node.name, _TRANSITION_KEYS,
                              self.ns, t.goal_id, tr.event.ros_method, _STATUS_NAMES[tr.before],
                              _STATUS_NAMES[tr.after], t.text))
        elif out.arrival is GoalArrival.DUPLICATE_RECALLED:
            node.world.record("action.server.transition", node.name, ns=self.ns, id=t.goal_id,
                              event="goal_after_cancel", before=GoalStatus.RECALLING.name,
                              after=GoalStatus.RECALLED.name, text=t.text)
        self._commit(out.goals, out.publications, None)
        if out.call_goal_callback:
            return run_user_callbacks([(self.goal_callback, (gh,))])
        return None

    def _internal_cancel_callback(self, goal_id: Message) -> CallbackGenerator | None:
        node = self.node
        if not self.started:
            misuse(node, self.ns, f"cancel request {goal_id.id!r} ignored: the action server "
                   f"{self.ns} is not started (call start())", level=WARN)
            return None
        request = CancelRequest(goal_id.id, time_to_ns(goal_id.stamp, "cancel stamp"))
        before = {t.goal_id: t for t in self._goals.trackers}
        out = receive_cancel(self._goals, request, self._now_ns())
        node.world.record("action.server.cancel", node.name, ns=self.ns, id=request.id,
                          stamp=request.stamp_ns, matched=list(out.matched),
                          requested=list(out.cancel_requested),
                          placeholder=out.placeholder is not None)
        for tr, gid in zip([x for x in out.transitions if x.legal], out.cancel_requested):
            node.world.record("action.server.transition", node.name, ns=self.ns, id=gid,
                              event=tr.event.ros_method, before=tr.before.name,
                              after=tr.after.name, text=before[gid].text if gid in before else "")
        self._commit(out.goals, out.publications, None)
        calls: list[UserCall] = []
        for gid in out.cancel_requested:
            h = next((h for h in self._handles.values() if h._id() == gid), None)
            if h is not None:
                calls.append((self.cancel_callback, (h,)))
        return run_user_callbacks(calls)

    # -- the hot path's members (here, after every logging call: a log's line is traced) ----
    @cached_property
    def _headers(self) -> tuple[type[Message], type[Message], type[Message]]:
        """The header classes (std_msgs/Header) of the status array, the result, the feedback."""
        return (type(self._GoalStatusArray().header), type(self.ActionResult().header),
                type(self.ActionFeedback().header))

    @cached_property
    def _entries(self) -> dict[int, tuple[GoalTracker, Message]]:
        """serial -> (tracker, its GoalStatus message), for the messages this server publishes."""
        return {}

    def _status_entry(self, t: GoalTracker) -> Message:
        """``_status_msg(t)`` for a message this server publishes: made once per tracker (a
        tracker never changes) and shared; a published message is only serialized."""
        hit = self._entries.get(t.serial)
        if hit is not None and hit[0] is t:
            return hit[1]
        msg = self._status_msg(t)
        self._entries[t.serial] = (t, msg)
        return msg

    def _forget(self, trackers: tuple[GoalTracker, ...]) -> None:
        """Drop the handles, and the cached status messages, of entries not in ``trackers``."""
        live = {t.serial for t in trackers}
        handles = self._handles
        if len(live) != len(handles):
            for serial in [s for s in handles if s not in live]:
                del handles[serial]
        entries = self._entries
        if len(entries) > 2 * len(trackers) + 16:
            self._entries = {s: e for s, e in entries.items() if s in live}


# Defined last, so that every logging call above keeps its line: a log's file and line are in
# the trace (and in /rosout's bytes), so moving one would change the run's digest.
_STATUS_NAMES = tuple(s.name for s in GoalStatus)  # indexed by the status value
assert [s.value for s in GoalStatus] == list(range(len(_STATUS_NAMES)))

# Keys of this module's hot trace rows (``Trace.append_row``: the details dict is built when read).
_GOAL_KEYS = ("ns", "id", "stamp", "arrival")
_TRANSITION_KEYS = ("ns", "id", "event", "before", "after", "text")
_FEEDBACK_KEYS = ("ns", "id", "status")

# Enum members as plain globals for the hot lines (a member read through its class is slower).
_ACCEPT, _REJECT, _CANCEL = ServerEvent.ACCEPT, ServerEvent.REJECT, ServerEvent.CANCEL
_SUCCEED, _ABORT = ServerEvent.SUCCEED, ServerEvent.ABORT
_STATUS_TOPIC = PublicationTopic.STATUS
_NEW, _CANCELED_BY_STAMP = GoalArrival.NEW, GoalArrival.CANCELED_BY_STAMP
