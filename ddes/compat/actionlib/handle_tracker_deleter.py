"""``actionlib.handle_tracker_deleter``: ``HandleTrackerDeleter(action_server, status_tracker)``.

Called (with any argument) it sets the tracker's ``handle_destruction_time`` to the node's time,
under the server's ``lock``, as actionlib's does when the last handle of a goal goes.  ddes's
server does not need it (its core sets the destruction time when a goal ends, and expires the
entry from there, as docs/actionlib.md says); it is here for the scripts that use it.
"""

from __future__ import annotations

from typing import Any

from ddes.compat import rospy
from ddes.compat.actionlib._lazy import install_to_string

__all__ = ["HandleTrackerDeleter", "rospy"]

_script_imported = install_to_string


class HandleTrackerDeleter:
    """actionlib's ``HandleTrackerDeleter(action_server, status_tracker)``."""

    def __init__(self, action_server: Any, status_tracker: Any) -> None:
        self.action_server = action_server
        self.status_tracker = status_tracker

    def __call__(self, ptr: object) -> None:
        if self.action_server:
            with self.action_server.lock:
                self.status_tracker.handle_destruction_time = rospy.Time.now()
