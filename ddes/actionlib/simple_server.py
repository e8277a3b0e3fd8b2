"""SimpleActionServer: one goal at a time on top of ActionServer (rospy ``SimpleActionServer``).

Two ways to use it, as in ROS:

* **execute callback**: ``SimpleActionServer(node, "fib", FibonacciAction,
  execute_cb=run)``.  ``run(goal)`` runs as a *process* on simulated time
  (ROS: its own thread).  Write it as a generator to take time::

      def run(goal):
          for i in range(goal.order):
              if server.is_preempt_requested():
                  server.set_preempted()
                  return
              server.publish_feedback(feedback)
              yield node.sleep(1.0)
          server.set_succeeded(result)

  If it returns with the goal still active the server warns ("...did not set
  the goal to a terminal status...") and sets it ABORTED with the text
  ``"No terminal state was set."``; if it raises, ABORTED with
  ``"Exception in execute callback: <error>"``, ROS's texts.
* **goal/preempt callbacks**: no execute callback; ``register_goal_callback``
  and ``register_preempt_callback``, then ``accept_new_goal()`` from the goal
  callback (or later) and ``set_succeeded`` etc. when done.

The single-goal policy is rospy's: a goal stamped at or after both the
current and the pending next goal becomes the next goal (a pending next goal
it replaces is cancelled: RECALLED), and an active current goal gets a
preempt request (the preempt callback runs); an older goal is cancelled at
once (RECALLED).  ``accept_new_goal()`` cancels a still-active current goal
(PREEMPTED), makes the next goal current, copies its preempt flag, and
accepts it.

rospy's execute loop waits on a condition with a 0.1 s timeout: a goal that
arrives while the callback runs is picked up 0.1 s (kernel time) after the
callback returns, one that arrives while the loop waits is picked up at once.
ddes keeps exactly that timing.
"""

from __future__ import annotations

from collections.abc import Callable
from types import GeneratorType
from typing import TYPE_CHECKING, Any

from ddes.actionlib._common import (
    CallbackGenerator,
    UserCall,
    misuse,
    no_node,
    run_user_callbacks,
)
from ddes.actionlib.server import AUTO_START_WARNING, ActionServer, ServerGoalHandle
from ddes.actionlib.states import GoalStatus
from ddes.errors import DdesTypeError, ROSActionException
from ddes.graph.failures import user_traceback
from ddes.graph.rosout import WARN
from ddes.msg.message import Message
from ddes.time.rospy_calls import REQUIRED, is_node_like

if TYPE_CHECKING:
    import simpy

    from ddes.graph.node import Node

__all__ = [
    "NO_TERMINAL_STATE_TEXT",
    "NO_TERMINAL_STATE_WARNING",
    "SimpleActionServer",
]

#: ``execute_cb(goal)``: a plain function, or a generator that takes simulated time.
ExecuteCallback = Callable[[Message], object]
#: ``goal_cb()`` / ``preempt_cb()``: a plain function, or a generator.
SimpleServerCallback = Callable[[], object]

#: The status text of a goal the execute callback left active.
NO_TERMINAL_STATE_TEXT = "No terminal state was set."
#: rospy's warning when the execute callback leaves the goal active.
NO_TERMINAL_STATE_WARNING = (
    "Your executeCallback did not set the goal to a terminal status.  This is a bug in your "
    "ActionServer implementation. Fix your code!  For now, the ActionServer will set this goal "
    "to aborted"
)
_REPLACED_TEXT = ("This goal was canceled because another goal was received by the simple "
                  "action server")
_ACCEPTED_TEXT = "This goal has been accepted by the simple action server"
_KERNEL_WAIT_NS = 100_000_000  # the execute loop's condition wait: 0.1 s (wall, the kernel clock)


def _stamp_ns(gh: ServerGoalHandle) -> int:
    t = gh.tracker
    return 0 if t is None else t.stamp_ns


class SimpleActionServer:
    """``SimpleActionServer(node, name, ActionSpec, execute_cb=None, auto_start=True)``."""

    def __init__(self, node: Node, name: str,
                 ActionSpec: type[Message] | str = REQUIRED,  # noqa: N803 - rospy's name
                 execute_cb: ExecuteCallback | None = None, auto_start: bool = True) -> None:
        if not is_node_like(node):
            # rospy's SimpleActionServer(name, ActionSpec, execute_cb, auto_start): shifted left
            r_cb: object = execute_cb
            r_auto: object = auto_start
            if ActionSpec is not REQUIRED:  # given by position: rospy's execute_cb, auto_start
                r_cb, r_auto = ActionSpec, (auto_start if execute_cb is None else execute_cb)
            kwargs: dict[str, object] = {}
            if r_cb is not None:
                kwargs["execute_cb"] = r_cb
            if r_auto is not True:
                kwargs["auto_start"] = r_auto
            no_node("SimpleActionServer", "server", node, [name], kwargs)
        if execute_cb is not None and not callable(execute_cb):
            raise DdesTypeError(f"execute_cb must be callable or None, got {execute_cb!r}")
        self.node = node
        self.new_goal = False
        self.preempt_request = False
        self.new_goal_preempt_request = False
        self.execute_callback = execute_cb
        self.goal_callback: SimpleServerCallback | None = None
        self.preempt_callback: SimpleServerCallback | None = None
        self.need_to_terminate = False
        self.action_server = ActionServer(node, name, ActionSpec, self._internal_goal_callback,
                                          self._internal_preempt_callback, auto_start=False)
        self.current_goal = ServerGoalHandle.uninitialized(self.action_server)
        self.next_goal = ServerGoalHandle.uninitialized(self.action_server)
        self._wake: simpy.Event | None = None
        self.execute_process: simpy.Process | None = None
        if execute_cb is not None:
            self.execute_process = node.process(self._execute_loop())
        if auto_start:
            misuse(node, self.action_server.ns, AUTO_START_WARNING, level=WARN)
            self.action_server.start()

    @property
    def ns(self) -> str:
        """The resolved action namespace."""
        return self.action_server.ns

    # -- the user's API -------------------------------------------------------------------
    def start(self) -> None:
        """Start the underlying ActionServer."""
        self.action_server.start()

    def shutdown(self) -> None:
        """Stop the execute loop and the action server (roscpp ``shutdown``)."""
        self.need_to_terminate = True
        self._notify()
        self.action_server.stop()

    def accept_new_goal(self) -> Any:
        """Make the next goal current and accept it; returns its ``FooGoal`` (None, logged, if none).

        Typed ``Any``, not ``Message | None``: rospy-style callers read fields of it at once.
        """
        if not self.new_goal or self.next_goal.get_goal() is None:
            misuse(self.node, self.ns,
                   "Attempting to accept the next goal when a new goal is not available")
            return None
        if (self.is_active() and self.current_goal.get_goal() is not None
                and self.current_goal != self.next_goal):
            self.current_goal.set_canceled(None, _REPLACED_TEXT)
        self.current_goal = self.next_goal
        self.new_goal = False
        self.preempt_request = self.new_goal_preempt_request
        self.new_goal_preempt_request = False
        self.current_goal.set_accepted(_ACCEPTED_TEXT)
        return self.current_goal.get_goal()

    def is_new_goal_available(self) -> bool:
        """True while a next goal waits for ``accept_new_goal``."""
        return self.new_goal

    def is_preempt_requested(self) -> bool:
        """True once the current goal was asked to stop (cancel or newer goal)."""
        return self.preempt_request

    def is_active(self) -> bool:
        """True while the current goal is ACTIVE or PREEMPTING."""
        return self.current_goal.status in (GoalStatus.ACTIVE, GoalStatus.PREEMPTING)

    def get_default_result(self) -> Message:
        """A default-constructed ``FooResult``."""
        return self.action_server.ActionResultType()

    def set_succeeded(self, result: Message | None = None, text: str = "") -> None:
        """The current goal SUCCEEDED (result None: a default result)."""
        self.current_goal.set_succeeded(result if result is not None else
                                        self.get_default_result(), text)

    def set_aborted(self, result: Message | None = None, text: str = "") -> None:
        """The current goal ABORTED."""
        self.current_goal.set_aborted(result if result is not None else
                                      self.get_default_result(), text)

    def set_preempted(self, result: Message | None = None, text: str = "") -> None:
        """The current goal PREEMPTED (``set_canceled``; RECALLED if it was never accepted)."""
        self.current_goal.set_canceled(result if result is not None else
                                       self.get_default_result(), text)

    def publish_feedback(self, feedback: Message) -> None:
        """Feedback for the current goal."""
        self.current_goal.publish_feedback(feedback)

    def register_goal_callback(self, cb: SimpleServerCallback) -> None:
        """The goal callback (refused, with ROS's warning, when an execute callback exists)."""
        if self.execute_callback is not None:
            misuse(self.node, self.ns, "Cannot call SimpleActionServer.register_goal_callback() "
                   "because an executeCallback exists. Not going to register it.", level=WARN)
        else:
            self.goal_callback = cb

    def register_preempt_callback(self, cb: SimpleServerCallback) -> None:
        """The preempt callback."""
        self.preempt_callback = cb

    # -- from the ActionServer ------------------------------------------------------------
    def _notify(self) -> None:
        wake = self._wake
        if wake is not None and not wake.triggered:
            wake.succeed()

    def _preempt_requested(self, gh: ServerGoalHandle, why: str) -> None:
        self.preempt_request = True
        t = gh.tracker
        self.node.world.record("action.simple.preempt_request", self.node.name, ns=self.ns,
                               id=None if t is None else t.goal_id, reason=why)

    def _internal_goal_callback(self, goal: ServerGoalHandle) -> CallbackGenerator | None:
        cur, nxt = self.current_goal, self.next_goal
        stamp_ns = _stamp_ns(goal)
        if ((cur.get_goal() is None or stamp_ns >= _stamp_ns(cur))
                and (nxt.get_goal() is None or stamp_ns >= _stamp_ns(nxt))):
            if nxt.get_goal() is not None and (cur.get_goal() is None or nxt != cur):
                nxt.set_canceled(None, _REPLACED_TEXT)
            self.next_goal = goal
            self.new_goal = True
            self.new_goal_preempt_request = False
            calls: list[UserCall] = []
            if self.is_active():
                self._preempt_requested(cur, "new goal")
                calls.append((self.preempt_callback, ()))
            calls.append((self.goal_callback, ()))
            try:
                gen = run_user_callbacks(calls)
            except Exception as exc:  # noqa: BLE001 - rospy catches and logs it here
                misuse(self.node, self.ns,
                       f"SimpleActionServer.internal_goal_callback - exception {exc}")
                return None
            if gen is None:
                self._notify()
                return None
            return self._finish_goal_callbacks(gen)
        goal.set_canceled(None, _REPLACED_TEXT)
        return None

    def _finish_goal_callbacks(self, gen: CallbackGenerator) -> CallbackGenerator:
        try:
            yield from gen
        except Exception as exc:  # noqa: BLE001 - rospy catches and logs it here
            misuse(self.node, self.ns,
                   f"SimpleActionServer.internal_goal_callback - exception {exc}")
            return
        self._notify()

    def _internal_preempt_callback(self, preempt: ServerGoalHandle) -> CallbackGenerator | None:
        if preempt == self.current_goal:
            self._preempt_requested(preempt, "cancel")
            return run_user_callbacks([(self.preempt_callback, ())])
        if preempt == self.next_goal:
            self.new_goal_preempt_request = True
            t = preempt.tracker
            self.node.world.record("action.simple.preempt_request", self.node.name, ns=self.ns,
                                   id=None if t is None else t.goal_id, reason="cancel next goal")
        return None

    # -- the execute loop -----------------------------------------------------------------
    def _execute_loop(self) -> CallbackGenerator:
        node = self.node
        env = node.world.env
        while not node.is_shutdown() and not self.need_to_terminate:
            if self.is_active():
                misuse(node, self.ns, "Should never reach this code with an active goal")
                return
            waits: list[simpy.Event] = []
            if self.is_new_goal_available():
                goal = self.accept_new_goal()
                if goal is not None:  # always: a new goal comes with its goal message
                    yield from self._run_execute(goal)
                waits.append(env.timeout(_KERNEL_WAIT_NS))
            if node.is_shutdown() or self.need_to_terminate:
                return
            self._wake = env.event()
            yield env.any_of([self._wake, node.spin(), *waits])

    def _run_execute(self, goal: Message) -> CallbackGenerator:
        node = self.node
        assert self.execute_callback is not None
        gid = self.current_goal.tracker.goal_id if self.current_goal.tracker else None
        node.world.record("action.simple.execute", node.name, ns=self.ns, id=gid, phase="start")
        try:
            result = self.execute_callback(goal)
            if type(result) is GeneratorType:
                yield from result
            if self.is_active():
                misuse(node, self.ns, NO_TERMINAL_STATE_WARNING, level=WARN)
                self._abort(NO_TERMINAL_STATE_TEXT)
        except Exception as ex:  # noqa: BLE001 - rospy aborts the goal and carries on
            # rospy appends traceback.format_exc(); ddes the user's frames by base name, so
            # the log (and a digest) is the same wherever the code is installed
            misuse(node, self.ns, f"Exception in your execute callback: {ex}\n{user_traceback(ex)}\n")
            self._abort(f"Exception in execute callback: {ex}")
        node.world.record("action.simple.execute", node.name, ns=self.ns, id=gid, phase="end")

    def _abort(self, text: str) -> None:
        try:
            self.set_aborted(None, text)
        except ROSActionException as exc:  # the server was stopped under the callback
            misuse(self.node, self.ns, f"could not abort the goal: {exc}")
