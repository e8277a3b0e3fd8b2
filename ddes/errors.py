"""One error tree for all of ddes.

Every error ddes raises derives from :class:`DdesError`.  Where ROS has a
name for an error, ddes uses it (``ROSException``, ``ServiceException``,
``ROSBagException`` ...).  Where rospy/genpy raise a builtin exception
(``TypeError`` for a negative ``Time``, ``ValueError`` for a zero
``wait_for_service`` timeout, ``KeyError`` for a missing parameter), the ddes
error also derives from that builtin, so ``except TypeError`` written for
rospy keeps working.

Deliberate deviation: rospy's ``ROSInterruptException`` is also a
``KeyboardInterrupt``.  Raising a ``KeyboardInterrupt`` inside a simulation
would stop pytest and Jupyter kernels, so ddes's is not.
"""

from __future__ import annotations

import io

__all__ = [
    "BadYieldError",
    "BagNotFoundError",
    "BagReadOnlyError",
    "BlockingCallError",
    "BlockingInYieldCodeError",
    "BlockingOutsideNodeError",
    "DdesAttributeError",
    "DdesError",
    "DdesKeyError",
    "DdesTypeError",
    "DdesValueError",
    "DeadlockError",
    "DeserializationError",
    "DigestError",
    "DynamicReconfigureCallbackException",
    "GradingError",
    "InvalidMsgSpec",
    "MissingNodeError",
    "MsgNotFound",
    "NoGlobalFunctionError",
    "NodeShutdownError",
    "ProtocolError",
    "ROSActionException",
    "ROSBagEncryptNotSupportedException",
    "ROSBagException",
    "ROSBagFormatException",
    "ROSBagUnindexedException",
    "ROSConsoleError",
    "ROSException",
    "ROSInitException",
    "ROSInterruptException",
    "ROSLaunchException",
    "ROSMessageException",
    "ROSNameException",
    "ROSParamException",
    "ROSSerializationException",
    "ROSServiceException",
    "ROSTimeMovedBackwardsException",
    "ROSTopicException",
    "ResourceLimitError",
    "RospyCallError",
    "RunawayError",
    "ServiceException",
    "ServiceTimeout",
    "SubmissionError",
    "UnsafeExpressionError",
    "WorldError",
]


class DdesError(Exception):
    """Base class of every error raised by ddes."""


class DdesTypeError(DdesError, TypeError):
    """A value of the wrong type (a ``TypeError`` too, as in genpy/rospy)."""


class DdesValueError(DdesError, ValueError):
    """A value out of range or malformed (a ``ValueError`` too)."""


class DdesAttributeError(DdesError, AttributeError):
    """An unknown attribute, e.g. a message field (an ``AttributeError`` too, as genpy)."""


class DdesKeyError(DdesError, KeyError):
    """A missing key, e.g. a parameter (a ``KeyError`` too, as rospy raises)."""

    def __str__(self) -> str:  # KeyError quotes its argument; keep messages readable
        return str(self.args[0]) if self.args else ""


class WorldError(DdesError):
    """Misuse of the simulation kernel (running backwards, foreign events...)."""


# --- rospy's tree (rospy/exceptions.py) -------------------------------------


class RunawayError(WorldError):
    """User code ran past a budget: a callback that never yields, or a zero-time livelock.

    The message names the node, the callback and the simulated time, and the
    budget that stopped it (``World(wall_budget=..., instant_budget=...)``).
    """


class ForgottenYieldError(RunawayError):
    """A loop called a blocking call (``rate.sleep()``) again and again without yielding its
    event, so simulated time never moved: the ``yield`` in front of it is missing."""


class BadYieldError(DdesTypeError):
    """A process or generator callback yielded something that is not an event (``yield 5``)."""


class DigestError(WorldError):
    """A digest was asked of a trace that does not hold every event (recording off or filtered)."""


class ResourceLimitError(DdesValueError):
    """An input is larger, deeper or costlier than ddes allows (a bomb, or a mistake).

    The message names the limit, the value that crossed it, and how to raise it
    when the input is genuine.
    """


class UnsafeExpressionError(DdesValueError):
    """An expression uses something outside ddes's safe expression subset (see docs/reliability.md)."""


class ROSException(DdesError):
    """Base exception class for ROS clients (rospy.ROSException)."""


class ROSSerializationException(ROSException):
    """A message field could not be serialized (wrong type or value)."""


class ROSInitException(ROSException):
    """Initialisation is missing or wrong (e.g. time read before init)."""


class ROSInterruptException(ROSException):
    """The operation was interrupted by shutdown (not a KeyboardInterrupt in ddes)."""


class ROSTimeMovedBackwardsException(ROSInterruptException):
    """ROS time jumped backwards during a sleep (rospy semantics).

    ``time`` holds the size of the jump in seconds, as rospy's does.
    """

    def __init__(self, time: float) -> None:
        # args must be (time,): SimPy re-creates exceptions from their args.
        super().__init__(time)
        self.time = time

    def __str__(self) -> str:
        return f"ROS time moved backwards by {self.time}s"


class NodeShutdownError(ROSException):
    """A node (or one of its entities) was used after ``shutdown()``."""


class RospyCallError(ROSInitException):
    """A rospy-shaped call that ddes spells differently (ddes has no global node).

    rospy keeps one node per process (``rospy.init_node``); a ddes world holds
    many, so every ROS call takes its node (or world) first.  The message
    shows the ddes call to write instead.
    """


class MissingNodeError(RospyCallError, DdesTypeError):
    """A ddes call made the rospy way, without its node first: ``ddes.Rate(10)``.

    Also a ``TypeError``, as the missing argument would be.
    """


class NoGlobalFunctionError(RospyCallError, DdesAttributeError):
    """A rospy module function ddes has as a node or world method: ``ddes.init_node``.

    Also an ``AttributeError``, so ``hasattr(ddes, "init_node")`` stays False.
    """


class BlockingCallError(ROSInitException):
    """A blocking call (``rate.sleep()``, ``rospy.sleep()``, ``proxy(req)`` ...) where nothing can
    block: only a node's code running on a greenlet (ddes.graph.blocking) can."""


class BlockingOutsideNodeError(BlockingCallError):
    """A blocking call outside any node (before ``init_node``, at import time, in a thread of
    one's own); rospy's "time is not initialized. Have you called init_node()?"."""


class BlockingInYieldCodeError(BlockingCallError):
    """A blocking call inside yield-style code (a node process or a generator callback):
    ``yield`` the event there, or write the code as plain blocking rospy."""


class DeadlockError(BlockingCallError):
    """A wait that can never end: a lock waiting, through its owners, on itself (the nodes
    involved are named), or a wait outside any node that nothing could end."""


class ROSNameException(DdesValueError):
    """An illegal graph resource name (rosgraph.names semantics)."""


class ROSParamException(ROSException):
    """A parameter server operation that ROS rejects (other than a missing key)."""


class ROSTopicException(ROSException):
    """Errors of topics and the rostopic tool (type mismatch, unknown topic...)."""


# --- services -----------------------------------------------------------------


class ServiceException(DdesError):
    """A service call failed (rospy.ServiceException).

    As in rospy it is *not* a subclass of ROSException.
    """


class ServiceTimeout(ServiceException):
    """A service call timed out (a ddes extension: ROS 1 calls have no timeout)."""


class ROSServiceException(ROSException):
    """Errors of the rosservice tool (unknown service, bad arguments)."""


# --- messages (genmsg / genpy) ------------------------------------------------


class InvalidMsgSpec(DdesError):
    """A malformed .msg/.srv/.action definition (genmsg.InvalidMsgSpec)."""


class MsgNotFound(DdesError):
    """No definition for a message or service type on the search path."""


class ROSMessageException(DdesError):
    """Filling or converting a message failed (genpy.MessageException)."""


class DeserializationError(ROSMessageException):
    """Wire bytes are truncated or corrupt (genpy.DeserializationError)."""


# --- actions, bags, launch, console ----------------------------------------------


class ROSActionException(ROSException):
    """Misuse of actionlib (e.g. a goal of the wrong type)."""


class ROSBagException(DdesError):
    """Base class of bag errors (rosbag.ROSBagException)."""


class ROSBagFormatException(ROSBagException):
    """A bag file is malformed or corrupt."""


class ROSBagUnindexedException(ROSBagException):
    """A bag file has no index (rosbag reindex fixes it)."""


class ROSBagEncryptNotSupportedException(ROSBagException):
    """The bag uses an encryption ddes does not support."""


class BagNotFoundError(DdesError, FileNotFoundError):
    """rosbag.Bag(path) of a file that does not exist (rosbag's FileNotFoundError)."""


class BagReadOnlyError(DdesValueError, io.UnsupportedOperation):
    """A write to a bag opened for reading (rosbag's io.UnsupportedOperation)."""


class ROSLaunchException(DdesError):
    """A launch file is malformed or cannot be resolved."""


class ROSConsoleError(DdesError):
    """A console command failed; the console prints it and keeps running."""


class DynamicReconfigureCallbackException(DdesError):
    """A dynamic_reconfigure callback returned None."""


class GradingError(DdesError):
    """The autograder cannot grade: an unknown exercise, a bad option (ddes.grading)."""


class SubmissionError(GradingError):
    """A submission cannot be read: a zip entry that escapes, a bomb, a notebook that is not JSON."""


class ProtocolError(GradingError):
    """A frame from the sandboxed child breaks the grading protocol (forged, oversized, cut)."""
