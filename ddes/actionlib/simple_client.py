"""SimpleActionClient: one goal at a time, three simple states (rospy ``SimpleActionClient``).

``send_goal(goal, done_cb, active_cb, feedback_cb)`` stops tracking the
previous goal (it does not cancel it) and follows the new one:

* ``active_cb()`` on the first ACTIVE or PREEMPTING comm state;
* ``feedback_cb(feedback)`` for the tracked goal's feedback only;
* ``done_cb(terminal_state, result)`` **before** the simple state becomes
  DONE, so whoever waits on :meth:`wait_for_result` resumes only after
  ``done_cb`` returned (the order of ros/actionlib#190).

Each callback may be a generator (``yield node.sleep(0.5)``): it runs as part
of the client's subscriber callback and holds the node's spinner until it
ends, as a slow callback holds rospy's thread; a generator ``done_cb`` has
returned when it ends, so the simple state becomes DONE only then.

The blocking calls are events to ``yield``, on the node's ROS time:
``ok = yield client.wait_for_server(timeout)``,
``finished = yield client.wait_for_result(timeout)`` and
``state = yield client.send_goal_and_wait(goal, execute_timeout, preempt_timeout)``.
A zero timeout means for ever, as in ROS.  rospy's ``wait_for_result`` wakes
every 0.1 s to re-check; here the event fires exactly when the state becomes
DONE or the deadline passes, whichever is first.
"""

from __future__ import annotations

from collections.abc import Callable, Generator
from typing import TYPE_CHECKING, Any

from ddes.actionlib._common import CallbackGenerator, misuse, no_node, run_user_callbacks
from ddes.actionlib.client import ActionClient, ClientGoalHandle
from ddes.actionlib.states import (
    CommState,
    GoalStatus,
    SimpleCallback,
    SimpleGoalState,
    SimpleUpdate,
    simple_get_state,
    simple_transition,
)
from ddes.msg.message import Message
from ddes.time.rospy_calls import REQUIRED, is_node_like
from ddes.time.units import DurationLike, TimeLike, duration_to_ns

if TYPE_CHECKING:
    import simpy

    from ddes.graph.node import Node

__all__ = ["SimpleActionClient"]

#: ``done_cb(terminal_state, result)``: the goal finished (result None if none came).
DoneCallback = Callable[[int, "Message | None"], object]
#: ``active_cb()``: the goal became active.
ActiveCallback = Callable[[], object]
#: ``feedback_cb(feedback)``: feedback (a ``FooFeedback``) for the goal.
SimpleFeedbackCallback = Callable[[Message], object]


class SimpleActionClient:
    """``SimpleActionClient(node, ns, ActionSpec)``."""

    def __init__(self, node: Node, ns: str,
                 ActionSpec: type[Message] | str = REQUIRED) -> None:  # noqa: N803 - rospy's
        if not is_node_like(node):  # rospy's SimpleActionClient(ns, ActionSpec)
            no_node("SimpleActionClient", "client", node,
                    [a for a in (ns, ActionSpec) if a is not REQUIRED], {})
        self.node = node
        self.action_client = ActionClient(node, ns, ActionSpec)
        self.simple_state = SimpleGoalState.DONE
        self.gh: ClientGoalHandle | None = None
        self.done_cb: DoneCallback | None = None
        self.active_cb: ActiveCallback | None = None
        self.feedback_cb: SimpleFeedbackCallback | None = None
        self._done_waiters: list[simpy.Event] = []
        #: Errors logged by the simple-state machine (``Received comm state ...``).
        self.simple_errors = 0

    @property
    def ns(self) -> str:
        """The resolved action namespace."""
        return self.action_client.ns

    # -- goals ----------------------------------------------------------------------------
    def wait_for_server(self, timeout: DurationLike = 0) -> simpy.Event:
        """Event: True once the server is connected (see ``ActionClient.wait_for_server``)."""
        return self.action_client.wait_for_server(timeout)

    def send_goal(self, goal: Message, done_cb: DoneCallback | None = None,
                  active_cb: ActiveCallback | None = None,
                  feedback_cb: SimpleFeedbackCallback | None = None) -> None:
        """Send ``goal``, forgetting (not cancelling) the previous one."""
        self.stop_tracking_goal()
        self.done_cb = done_cb
        self.active_cb = active_cb
        self.feedback_cb = feedback_cb
        self.simple_state = SimpleGoalState.PENDING
        try:
            self.gh = self.action_client._send_goal(goal, None, self._handle_feedback,
                                                    self._handle_transition)
        except Exception:
            self.simple_state = SimpleGoalState.DONE
            raise
        self._record_simple(SimpleGoalState.DONE, SimpleGoalState.PENDING)

    def send_goal_and_wait(self, goal: Message, execute_timeout: DurationLike = 0,
                           preempt_timeout: DurationLike = 0) -> simpy.Event:
        """Event whose value is :meth:`get_state` after sending ``goal`` and waiting.

        If the result does not arrive within ``execute_timeout`` the goal is
        cancelled and the client waits up to ``preempt_timeout`` more.
        """
        self.send_goal(goal)
        return self.node.process(self._send_and_wait(execute_timeout, preempt_timeout))

    def _send_and_wait(self, execute_timeout: DurationLike, preempt_timeout: DurationLike
                       ) -> Generator[simpy.Event, Any, int]:
        finished = yield self.wait_for_result(execute_timeout)
        if not finished:
            self.node.logdebug("Canceling goal")
            self.cancel_goal()
            yield self.wait_for_result(preempt_timeout)
        return self.get_state()

    def wait_for_result(self, timeout: DurationLike = 0) -> simpy.Event:
        """Event whose value is True iff the goal is DONE before ``timeout`` (seconds or a
        Duration of ROS time; 0: for ever)."""
        env = self.node.world.env
        if self.gh is None:
            misuse(self.node, self.ns, "Called wait_for_result when no goal exists")
            return env.timeout(0, False)
        return self.node.process(self._wait_for_result(duration_to_ns(timeout, "timeout")))

    def _wait_for_result(self, timeout_ns: int) -> Generator[simpy.Event, Any, bool]:
        node = self.node
        if self.simple_state == SimpleGoalState.DONE or node.is_shutdown():
            return self.simple_state == SimpleGoalState.DONE
        env = node.world.env
        done = env.event()
        self._done_waiters.append(done)
        events = [done, node.spin()]
        if timeout_ns > 0:
            clock = node.clock
            events.append(clock.wait_until(clock.now_ns() + timeout_ns))
        yield env.any_of(events)
        if not done.triggered and done in self._done_waiters:
            self._done_waiters.remove(done)  # woken by the deadline or a shutdown
        return self._is_done()

    def _is_done(self) -> bool:
        return self.simple_state == SimpleGoalState.DONE

    def get_result(self) -> Any:
        """The tracked goal's result (a ``FooResult`` message), or None (logged) without a goal.

        Typed ``Any``, not ``Message | None``: rospy-style callers read fields of it at once.
        """
        if self.gh is None:
            misuse(self.node, self.ns, "Called get_result when no goal is running")
            return None
        return self.gh.get_result()

    def get_state(self) -> int:
        """The goal's status: LOST without a goal, RECALLING→PENDING, PREEMPTING→ACTIVE."""
        if self.gh is None:
            return GoalStatus.LOST
        return simple_get_state(self.gh.get_goal_status())

    def get_goal_status_text(self) -> str:
        """The text of the goal's latest status."""
        if self.gh is None:
            misuse(self.node, self.ns, "Called get_goal_status_text when no goal is running")
            return "ERROR: Called get_goal_status_text when no goal is running"
        return self.gh.get_goal_status_text()

    def cancel_all_goals(self) -> None:
        """Cancel every goal of the server."""
        self.action_client.cancel_all_goals()

    def cancel_goals_at_and_before_time(self, time: TimeLike) -> None:
        """Cancel the server's goals stamped at or before ``time`` (a Time or seconds)."""
        self.action_client.cancel_goals_at_and_before_time(time)

    def cancel_goal(self) -> None:
        """Cancel the tracked goal (nothing without one)."""
        if self.gh is not None:
            self.gh.cancel()

    def stop_tracking_goal(self) -> None:
        """Forget the tracked goal (it keeps running on the server)."""
        if self.gh is not None:
            self.gh.stop_tracking()
        self.gh = None

    # -- callbacks from the comm-state machine --------------------------------------------
    def _record_simple(self, before: SimpleGoalState, after: SimpleGoalState) -> None:
        gid = None if self.gh is None else self.gh.get_goal_id()
        self.node.world.record("action.simple.transition", self.node.name, ns=self.ns, id=gid,
                               before=before.name, after=after.name)

    def _handle_transition(self, gh: ClientGoalHandle, comm: CommState
                           ) -> CallbackGenerator | None:
        """The goal entered the comm state ``comm``; the rest of the user's callback, if any."""
        if gh != self.gh:
            misuse(self.node, self.ns,
                   "Got a transition callback on a goal handle that we're not tracking")
            return None
        upd = simple_transition(self.simple_state, comm, self.ns)
        if upd.error is not None:
            self.simple_errors += 1
            misuse(self.node, self.ns, upd.error)
            return None
        if upd.callback is SimpleCallback.ACTIVE:
            self.simple_state = upd.after
            self._record_simple(upd.before, upd.after)
            return run_user_callbacks([(self.active_cb, ())])
        if upd.callback is SimpleCallback.DONE:
            rest = run_user_callbacks([(self.done_cb, (gh.get_goal_status(), gh.get_result()))])
            if rest is None:
                self._done(upd)
                return None
            return self._done_after(rest, upd)
        return None

    def _done_after(self, done_cb: CallbackGenerator, upd: SimpleUpdate) -> CallbackGenerator:
        yield from done_cb
        self._done(upd)

    def _done(self, upd: SimpleUpdate) -> None:
        """``done_cb`` has returned: the simple state is DONE, and its waiters wake."""
        self.simple_state = upd.after
        self._record_simple(upd.before, upd.after)
        waiters, self._done_waiters = self._done_waiters, []
        for ev in waiters:
            if not ev.triggered:
                ev.succeed()

    def _handle_feedback(self, gh: ClientGoalHandle, feedback: Message
                         ) -> CallbackGenerator | None:
        if self.gh is None:
            return None
        if gh != self.gh:
            misuse(self.node, self.ns,
                   "Got a feedback callback on a goal handle that we're not tracking. "
                   f"{self.gh.get_goal_id()} vs {gh.get_goal_id()}")
            return None
        return run_user_callbacks([(self.feedback_cb, (feedback,))])
