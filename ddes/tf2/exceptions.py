"""tf2's exceptions (``tf2.TransformException`` and its five subclasses), in the ddes error tree.

As in tf2_py, each is a ``TransformException``; ``except tf2_ros.LookupException`` written for
rospy works unchanged.  ``TransformException`` is a :class:`ddes.errors.DdesError`, so
``except DdesError`` catches them too.
"""

from __future__ import annotations

from ddes.errors import DdesError

__all__ = [
    "ConnectivityException",
    "ExtrapolationException",
    "InvalidArgumentException",
    "LookupException",
    "TimeoutException",
    "TransformException",
]


class TransformException(DdesError):
    """Base of tf2's errors (``tf2.TransformException``)."""


class ConnectivityException(TransformException):
    """The two frames are not part of one tree, or no common time exists."""


class LookupException(TransformException):
    """A frame does not exist (or the tree contains a loop)."""


class ExtrapolationException(TransformException):
    """The lookup time lies outside the cached data of a link."""


class InvalidArgumentException(TransformException):
    """A frame id is empty or starts with '/'."""


class TimeoutException(TransformException):
    """A wait for a transform ran out of (simulated) time."""
