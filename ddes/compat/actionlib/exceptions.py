"""``actionlib.exceptions``: ``ActionException``, ddes's :class:`~ddes.errors.ROSActionException`
(what ddes's servers and clients raise for a misused action, as actionlib raises its own)."""

from __future__ import annotations

from ddes.errors import ROSActionException as ActionException

__all__ = ["ActionException"]
