"""``actionlib.action_server``: ``ActionServer``, the goal-handle action server of a script.

``ActionServer(ns, ActionSpec, goal_cb, cancel_cb=nop_cb, auto_start=True)`` is
:class:`ddes.actionlib.ActionServer` on the node of the running script, with actionlib's
defaults and attributes besides ddes's:

* the goal callback gets a :class:`~ddes.compat.actionlib.server_goal_handle.ServerGoalHandle`;
* ``status_list`` is the status list as actionlib's StatusTrackers, read from ddes's core
  when read (so changing a tracker's fields changes nothing); ``del server.status_list[i]``
  removes the goal from the list, as actionlib's test server does to lose a goal: the next
  status array no longer lists it and its clients see it LOST;
* ``lock`` is an RLock (:mod:`ddes.compat.threads`) the script may take; ddes's server does not
  take it (its callbacks never interleave), so holding it does not hold back the status array;
* ``id_generator`` is a :class:`~ddes.compat.actionlib.goal_id_generator.GoalIDGenerator`.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator, MutableSequence
from dataclasses import replace
from typing import TYPE_CHECKING, Any, overload

from ddes.actionlib.server import ActionServer as _ActionServer
from ddes.compat import rospy
from ddes.compat import threads as _threads
from ddes.compat.actionlib._lazy import install_to_string, module_getattr
from ddes.compat.actionlib.exceptions import ActionException
from ddes.compat.actionlib.goal_id_generator import GoalIDGenerator
from ddes.compat.actionlib.handle_tracker_deleter import HandleTrackerDeleter
from ddes.compat.actionlib.server_goal_handle import ServerGoalHandle
from ddes.compat.actionlib.status_tracker import StatusTracker
from ddes.compat.rospy import _node
from ddes.errors import DdesError
from ddes.time.rostime import Time

if TYPE_CHECKING:
    from ddes.actionlib.cancel import GoalTracker
    from ddes.msg.message import Message

#: The names answered when read (:mod:`ddes.compat.actionlib._lazy`).
_LAZY = ("GoalID", "GoalStatus", "GoalStatusArray")
__all__ = ["ActionException", "ActionServer", "GoalIDGenerator", "HandleTrackerDeleter",
           "ServerGoalHandle", "StatusTracker", "nop_cb", "rospy", "threading", *_LAZY]

threading = _threads.module()

_lazy_attr = module_getattr(__name__, _LAZY)


def __getattr__(name: str) -> Any:
    return _lazy_attr(name)

_script_imported = install_to_string


def nop_cb(goal_handle: Any) -> None:
    """actionlib's default cancel callback: does nothing."""


def status_tracker_of(server: _ActionServer, t: GoalTracker) -> StatusTracker:
    """An actionlib ``StatusTracker`` of the core's entry ``t`` (a copy, made now)."""
    st = StatusTracker(server._GoalID(Time._from_ns(t.stamp_ns), t.goal_id), int(t.status))
    st.status.text = t.text
    h = server._handles.get(t.serial)
    st.goal = h.goal if h is not None and t.has_goal else None
    st.handle_destruction_time = Time._from_ns(t.destruction_time_ns)
    return st


class _StatusList(MutableSequence[StatusTracker]):
    """``server.status_list``: the core's status list, read as StatusTrackers; ``del`` removes
    an entry from the core."""

    def __init__(self, server: _ActionServer) -> None:
        self._server = server

    def _trackers(self) -> tuple[GoalTracker, ...]:
        return self._server._goals.trackers

    def __len__(self) -> int:
        return len(self._trackers())

    @overload
    def __getitem__(self, i: int) -> StatusTracker: ...
    @overload
    def __getitem__(self, i: slice) -> list[StatusTracker]: ...
    def __getitem__(self, i: int | slice) -> StatusTracker | list[StatusTracker]:
        if isinstance(i, slice):
            return [status_tracker_of(self._server, t) for t in self._trackers()[i]]
        return status_tracker_of(self._server, self._trackers()[i])

    def __iter__(self) -> Iterator[StatusTracker]:
        for t in self._trackers():
            yield status_tracker_of(self._server, t)

    def __delitem__(self, i: int | slice) -> None:
        server = self._server
        trackers = list(server._goals.trackers)
        gone = trackers[i] if isinstance(i, slice) else [trackers[i]]
        del trackers[i]
        server._goals = replace(server._goals, trackers=tuple(trackers))
        node = server.node
        for t in gone:
            node.world.record("action.server.status_list_del", node.name, ns=server.ns,
                              id=t.goal_id, status=t.status.name)

    def _refuse(self) -> DdesError:
        return DdesError(
            "ddes's action server keeps its status list in its core: a script may read "
            "server.status_list and remove entries (del server.status_list[i]), not add or "
            "replace them; let the server's goals and goal handles change it")

    @overload
    def __setitem__(self, i: int, value: StatusTracker) -> None: ...
    @overload
    def __setitem__(self, i: slice, value: Any) -> None: ...
    def __setitem__(self, i: int | slice, value: Any) -> None:
        raise self._refuse()

    def insert(self, index: int, value: StatusTracker) -> None:
        raise self._refuse()

    def __repr__(self) -> str:
        return f"<status list of {self._server.ns}: {len(self)} goals>"


class ActionServer(_ActionServer):
    """actionlib's ``ActionServer(ns, ActionSpec, goal_cb, cancel_cb=nop_cb, auto_start=True)``."""

    lock: Any
    id_generator: GoalIDGenerator

    def __init__(self, ns: str, ActionSpec: Any,  # noqa: N803 - actionlib's name
                 goal_cb: Callable[..., object], cancel_cb: Callable[..., object] | None = nop_cb,
                 auto_start: bool = True) -> None:
        self._script_fields()
        super().__init__(_node(), ns, ActionSpec, goal_cb, cancel_cb, auto_start=auto_start)

    def _script_fields(self) -> None:
        self.lock = _threads.RLock()
        self.id_generator = GoalIDGenerator()

    @classmethod
    def _adopt(cls, server: _ActionServer) -> ActionServer:
        """Make ddes's ``server`` (a SimpleActionServer's) this class, with its attributes."""
        server.__class__ = cls
        assert isinstance(server, ActionServer)
        server._script_fields()
        return server

    @property
    def status_list(self) -> _StatusList:  # type: ignore[override]
        """The status list as actionlib's StatusTrackers (read from ddes's core)."""
        return _StatusList(self)

    def _handle(self, tracker: GoalTracker, goal: Message) -> ServerGoalHandle:
        h = self._handles.get(tracker.serial)
        if h is None:
            h = self._handles[tracker.serial] = ServerGoalHandle._made(self, tracker, goal)
        assert isinstance(h, ServerGoalHandle)
        return h
