"""``actionlib.server_goal_handle``: ``ServerGoalHandle``, one goal as an action server's user
sees it.

It is :class:`ddes.actionlib.ServerGoalHandle` (the same transitions, texts and publications)
with actionlib's constructor ``ServerGoalHandle(status_tracker=None, action_server=None,
handle_tracker=None)`` and attributes (``status_tracker``, ``action_server``,
``handle_tracker``, ``goal``, ``get_default_result()``).  ``ServerGoalHandle()`` is a handle
without a goal, as a SimpleActionServer holds before its first one: its calls log actionlib's
errors ("Attempt to set status on an uninitialized ServerGoalHandle"...) on the running node and
do nothing, and ``get_goal()`` is None.  The handles a server gives its goal callback are made
by the server.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from ddes.actionlib.cancel import UNINITIALIZED_GOAL_ID_TEXT, UNINITIALIZED_HANDLE_TEXT
from ddes.actionlib.server import ServerGoalHandle as _ServerGoalHandle
from ddes.compat import rospy
from ddes.compat.actionlib._lazy import install_to_string, message_class, module_getattr

if TYPE_CHECKING:
    from ddes.actionlib.cancel import GoalTracker
    from ddes.actionlib.server import ActionServer
    from ddes.actionlib.states import ServerTransition
    from ddes.msg.message import Message

#: The names answered when read (:mod:`ddes.compat.actionlib._lazy`).
_LAZY = ("actionlib_msgs",)
__all__ = ["ServerGoalHandle", "rospy", *_LAZY]

_lazy_attr = module_getattr(__name__, _LAZY)


def __getattr__(name: str) -> Any:
    return _lazy_attr(name)

_script_imported = install_to_string


class ServerGoalHandle(_ServerGoalHandle):
    """actionlib's ``ServerGoalHandle(status_tracker=None, action_server=None,
    handle_tracker=None)`` over ddes's handle."""

    __slots__ = ("handle_tracker",)

    def __init__(self, status_tracker: Any = None, action_server: Any = None,
                 handle_tracker: Any = None) -> None:
        tracker: GoalTracker | None = None
        goal = getattr(status_tracker, "goal", None) if status_tracker else None
        if status_tracker and action_server is not None and goal is not None:
            goals = getattr(action_server, "_goals", None)  # a ddes server: its core's entry
            if goals is not None:
                tracker = goals.find(status_tracker.status.goal_id.id)
        super().__init__(action_server, tracker, goal)
        self.handle_tracker = handle_tracker

    @classmethod
    def _made(cls, server: ActionServer | None, tracker: GoalTracker | None,
              goal: Message | None) -> ServerGoalHandle:
        """The handle the server makes for one of its goals."""
        h = cls.__new__(cls)
        _ServerGoalHandle.__init__(h, server, tracker, goal)  # type: ignore[arg-type]
        h.handle_tracker = None
        return h

    @classmethod
    def uninitialized(cls, server: ActionServer) -> ServerGoalHandle:
        return cls._made(server, None, None)

    # -- actionlib's attributes ----------------------------------------------------------
    @property
    def action_server(self) -> Any:
        """The server of the goal (None for ``ServerGoalHandle()``)."""
        return self._server

    @property
    def status_tracker(self) -> Any:
        """The goal's entry of the status list, as an actionlib ``StatusTracker`` (a copy made
        now: ddes's server keeps the entry in its core; None without a goal)."""
        if self._server is None or self._tracker is None:
            return None
        from ddes.compat.actionlib.action_server import status_tracker_of

        return status_tracker_of(self._server, self._tracker)

    def get_default_result(self) -> Any:
        """A default-constructed ``FooResult`` of the server's action."""
        if self._server is None:
            raise AttributeError("'NoneType' object has no attribute 'ActionResultType'")
        return self._server.ActionResultType()

    # -- a handle without a server: actionlib's errors, on the running node ---------------
    def get_goal_id(self) -> Message:
        if self._server is None:
            rospy.logerr(UNINITIALIZED_GOAL_ID_TEXT)
            return message_class("actionlib_msgs/GoalID")()  # type: ignore[no-any-return]
        return super().get_goal_id()

    def get_goal_status(self) -> Message:
        if self._server is None:
            rospy.logerr("Attempt to get goal status on an uninitialized ServerGoalHandle")
            return message_class("actionlib_msgs/GoalStatus")()  # type: ignore[no-any-return]
        return super().get_goal_status()

    def _serverless(self, text: str | None = UNINITIALIZED_HANDLE_TEXT, *,
                    result: object = True) -> None:
        if not result:  # actionlib first makes the default result: of no server
            self.get_default_result()
        self.get_goal_id()  # actionlib's debug line reads the id twice first
        self.get_goal_id()
        if text is not None:
            rospy.logerr(text)

    def set_accepted(self, text: str = "") -> ServerTransition | None:
        if self._server is None:
            return self._serverless()
        return super().set_accepted(text)

    def set_rejected(self, result: Message | None = None,
                     text: str = "") -> ServerTransition | None:
        if self._server is None:
            return self._serverless(result=result)
        return super().set_rejected(result, text)

    def set_canceled(self, result: Message | None = None,
                     text: str = "") -> ServerTransition | None:
        if self._server is None:
            return self._serverless(result=result)
        return super().set_canceled(result, text)

    def set_succeeded(self, result: Message | None = None,
                      text: str = "") -> ServerTransition | None:
        if self._server is None:
            return self._serverless(result=result)
        return super().set_succeeded(result, text)

    def set_aborted(self, result: Message | None = None,
                    text: str = "") -> ServerTransition | None:
        if self._server is None:
            return self._serverless(result=result)
        return super().set_aborted(result, text)

    def set_cancel_requested(self) -> bool:
        if self._server is None:
            self._serverless(None)
            return False
        return super().set_cancel_requested()

    def publish_feedback(self, feedback: Message) -> None:
        if self._server is None:
            return self._serverless(
                "Attempt to publish feedback on an uninitialized ServerGoalHandle")
        return super().publish_feedback(feedback)
