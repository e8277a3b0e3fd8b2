"""tf2_ros.Buffer on simulated time: tf2's BufferCore plus waits that are events.

``Buffer(cache_time=None, debug=False)`` is a :class:`ddes.tf2.BufferCore` (every tf2 rule, text
and exception is the core's) with tf2_ros's Python API (``buffer.py``, ``buffer_interface.py``):

* with ``timeout`` None or zero, ``lookup_transform``/``can_transform``/``transform`` answer at
  once, as tf2_ros does: the Buffer needs no world (a notebook, a test, a bag read offline);
* ``yield buffer.wait_for_transform(target, source, time, timeout)`` in yield-style code is an
  event that succeeds in the very instant a ``set_transform``/``set_transform_static`` makes the
  transform available (tf2_ros polls every ``timeout * 0.01``), and fails with
  :class:`TimeoutException` when ``timeout`` has passed on the node's ROS clock;
* in blocking code (a rospy script: :mod:`ddes.compat.tf2_ros`, or :mod:`ddes.graph.blocking`)
  ``lookup_transform(..., timeout=Duration(1))`` blocks the calling node until the transform is
  available or the timeout has passed, then answers as tf2_ros does: the transform, or the core's
  exception (``LookupException``, ``ExtrapolationException``...).

The node a wait runs on is the Buffer's (``Buffer(node=...)``, or the node of the first
:class:`~ddes.tf2_ros.TransformListener` made on it), else the node of the running rospy code.
"""

from __future__ import annotations

import logging
import sys
from typing import TYPE_CHECKING, Any

from ddes.errors import DdesValueError
from ddes.graph.blocking import current_node, current_task, wait
from ddes.graph.rosout import ERROR, WARN
from ddes.tf2 import BufferCore, TimeoutException
from ddes.tf2_ros.geometry import TypeException, transform_function
from ddes.time.rostime import Duration
from ddes.time.sleep import duration_sleep
from ddes.time.units import duration_to_ns

if TYPE_CHECKING:
    import simpy

    from ddes.graph.node import Node
    from ddes.tf2.cache import TimeCache

__all__ = ["DEFAULT_CAN_TRANSFORM_POLLING_SCALE", "Buffer", "TimeoutException", "TypeException",
           "console_bridge_text"]

#: tf2_ros's polling scale (``timeout * 0.01``); kept for code that reads it.  ddes does not poll:
#: a wait ends in the instant the transform arrives.
DEFAULT_CAN_TRANSFORM_POLLING_SCALE = 0.01


class _Waiter:
    __slots__ = ("args", "event", "full")

    def __init__(self, event: simpy.Event, full: bool, args: tuple[Any, ...]) -> None:
        self.event = event
        self.full = full
        self.args = args


class Buffer(BufferCore):
    """``tf2_ros.Buffer(cache_time=None, debug=False)``: a BufferCore with ROS-side waits.

    ``node`` (a ddes extension) binds the Buffer to a node for its waits; ``debug=True`` with a
    node advertises ``~tf2_frames`` (tf2_msgs/FrameGraph, ``all_frames_as_yaml``), as tf2_ros
    does with its default ``debug=True`` (ddes's default is False: a Buffer need not have a node).
    """

    def __init__(self, cache_time: Any = None, debug: bool = False, *,
                 node: Node | None = None) -> None:
        if cache_time is not None:
            BufferCore.__init__(self, cache_time)
        else:
            BufferCore.__init__(self)
        self.CAN_TRANSFORM_POLLING_SCALE = DEFAULT_CAN_TRANSFORM_POLLING_SCALE
        self._waiters: list[_Waiter] = []
        self._node: Node | None = None
        self._debug = debug
        self.frame_server: Any = None
        if node is not None:
            self.attach(node)

    # -- the node ------------------------------------------------------------------------------
    @property
    def node(self) -> Node | None:
        """The node this Buffer waits on (None: a plain data structure)."""
        return self._node

    def attach(self, node: Node) -> None:
        """Bind the Buffer to ``node`` (its waits run on its clock); a second node is refused."""
        if self._node is node:
            return
        if self._node is not None:
            raise DdesValueError(
                f"this Buffer belongs to node {self._node.name}; node {node.name} cannot use it "
                "as well: make a Buffer (and a TransformListener) per node, as in ROS")
        self._node = node
        if self._debug:
            self._advertise_frames(node)

    def _advertise_frames(self, node: Node) -> None:
        from ddes.msg import get_service_class
        from ddes.services import Service

        if node.world.master.lookup_service(node.resolve_name("~tf2_frames")) is not None:
            return  # tf2_ros checks the master first: one ~tf2_frames per node
        frame_graph = get_service_class("tf2_msgs/FrameGraph")
        self.frame_server = Service(node, "~tf2_frames", frame_graph,
                                    lambda _req: frame_graph._response_class(
                                        self.all_frames_as_yaml()))

    def _wait_node(self, what: str) -> Node:
        node = self._node or current_node()
        if node is None:
            raise DdesValueError(
                f"{what} waits on simulated time, but this Buffer has no node: make it with "
                "Buffer(node=node) or give it a TransformListener(node, buffer), or call it from "
                "a rospy script's code; with timeout=None (or 0) it answers at once")
        return node

    def _log(self, level: int, text: str) -> None:
        """tf2's warnings and errors on the Buffer's node (/rosout and its console line, at the
        node's simulated time), as a roscpp node with rosconsole_bridge shows them; without a
        node, on standard error in console_bridge's words, as tf2_ros writes them (see
        docs/tf.md, "tf2's warnings")."""
        node = self._node
        if node is None:
            _to_stderr(console_bridge_text(level, text))
            return
        # depth 2: the BufferCore method that logged is the line's file/function/line
        node.log.log(ERROR if level >= logging.ERROR else WARN, text, (), depth=2)

    # -- insertion wakes the waiters ----------------------------------------------------------
    def set_transform(self, transform: Any, authority: str) -> None:  # type: ignore[override]
        """tf2's setTransform; a wait this insertion satisfies succeeds now.  Returns None, as
        tf2_ros's does (a refused transform is logged; :class:`BufferCore` returns tf2's bool)."""
        BufferCore.set_transform(self, transform, authority)
        if self._waiters:
            self._wake()

    def set_transform_static(self, transform: Any,  # type: ignore[override]
                             authority: str) -> None:
        """tf2's setTransform for a static transform; a wait it satisfies succeeds now.  Returns
        None, as tf2_ros's does."""
        BufferCore.set_transform_static(self, transform, authority)
        if self._waiters:
            self._wake()

    def _insert_fast(self, slot: tuple[int, int, TimeCache], stamp: int, tx: float, ty: float,
                     tz: float, qx: float, qy: float, qz: float, qw: float,
                     authority: str) -> bool:
        """BufferCore's unchecked-path insertion (the one ``_set_transform_fast`` and the
        listener's steady-stream path both end in); a wait it satisfies succeeds now."""
        done = BufferCore._insert_fast(self, slot, stamp, tx, ty, tz, qx, qy, qz, qw, authority)
        if done and self._waiters:
            self._wake()
        return done

    def _check(self, w: _Waiter) -> tuple[bool, str]:
        if w.full:
            return self.can_transform_full_core(*w.args)  # type: ignore[no-any-return]
        return self.can_transform_core(*w.args)  # type: ignore[no-any-return]

    def _wake(self) -> None:
        for w in list(self._waiters):
            if w.event.triggered:
                self._waiters.remove(w)
            elif self._check(w)[0]:
                self._waiters.remove(w)
                w.event.succeed(True)

    # -- waits as events -----------------------------------------------------------------------
    def wait_for_transform(self, target_frame: str, source_frame: str, time: Any,
                           timeout: Any = None) -> simpy.Event:
        """An event: True once ``can_transform`` holds, or TimeoutException after ``timeout``.

        ``timeout`` None or 0 decides now (the event succeeds or fails in this instant).
        """
        return self._wait(False, (target_frame, source_frame, time), timeout,
                          "buffer.wait_for_transform()")

    def wait_for_transform_full(self, target_frame: str, target_time: Any, source_frame: str,
                                source_time: Any, fixed_frame: str,
                                timeout: Any = None) -> simpy.Event:
        """:meth:`wait_for_transform` for the advanced API (``can_transform_full``)."""
        return self._wait(True, (target_frame, target_time, source_frame, source_time,
                                 fixed_frame), timeout, "buffer.wait_for_transform_full()")

    def _wait(self, full: bool, args: tuple[Any, ...], timeout: Any, what: str) -> simpy.Event:
        node = self._wait_node(what)
        if self._node is None:
            self.attach(node)
        env = node.world.env
        ev = env.event()
        w = _Waiter(ev, full, args)
        ok, text = self._check(w)
        if ok:
            ev.succeed(True)
            return ev
        t_ns = 0 if timeout is None else duration_to_ns(timeout, "timeout")
        if t_ns <= 0:
            ev.fail(TimeoutException(text or _timeout_text(args, 0)))
            return ev
        self._waiters.append(w)
        timer = duration_sleep(node.clock, Duration(0, t_ns))

        def expire(_ev: simpy.Event) -> None:
            if ev.triggered:
                return
            if w in self._waiters:
                self._waiters.remove(w)
            ok_now, text_now = self._check(w)
            if ok_now:  # tf2_ros checks once more when the time is up
                ev.succeed(True)
            else:
                ev.fail(TimeoutException(text_now or _timeout_text(args, t_ns)))

        timer.callbacks.append(expire)
        return ev

    def _block(self, full: bool, args: tuple[Any, ...], timeout: Any, what: str) -> bool:
        """Block the running rospy code until the transform can be done or ``timeout`` passed."""
        if timeout is None or duration_to_ns(timeout, "timeout") <= 0:
            return bool(self._check(_Waiter(None, full, args))[0])  # type: ignore[arg-type]
        ev = self._wait(full, args, timeout, what)
        try:
            return bool(wait(ev, what))
        except TimeoutException:
            return False

    # -- tf2_ros's API ----------------------------------------------------------------------------
    def can_transform(self, target_frame: str, source_frame: str, time: Any,
                      timeout: Any = None, return_debug_tuple: bool = False) -> Any:
        """tf2_ros ``can_transform``: True/False (or ``(bool, text)``); a timeout blocks."""
        args = (target_frame, source_frame, time)
        if timeout is not None and duration_to_ns(timeout, "timeout") > 0:
            self._block(False, args, timeout, "buffer.can_transform()")
        core = self.can_transform_core(*args)
        return core if return_debug_tuple else core[0]

    def can_transform_full(self, target_frame: str, target_time: Any, source_frame: str,
                           source_time: Any, fixed_frame: str, timeout: Any = None,
                           return_debug_tuple: bool = False) -> Any:
        """tf2_ros ``can_transform_full`` (a timeout blocks)."""
        args = (target_frame, target_time, source_frame, source_time, fixed_frame)
        if timeout is not None and duration_to_ns(timeout, "timeout") > 0:
            self._block(True, args, timeout, "buffer.can_transform_full()")
        core = self.can_transform_full_core(*args)
        return core if return_debug_tuple else core[0]

    def lookup_transform(self, target_frame: str, source_frame: str, time: Any,
                         timeout: Any = None) -> Any:
        """tf2_ros ``lookup_transform``: the TransformStamped, or the core's exception.

        With a timeout it first blocks (rospy code only) until ``can_transform`` or the timeout.
        """
        if timeout is not None and duration_to_ns(timeout, "timeout") > 0:
            self._block(False, (target_frame, source_frame, time), timeout,
                        "buffer.lookup_transform()")
        return self.lookup_transform_core(target_frame, source_frame, time)

    def lookup_transform_full(self, target_frame: str, target_time: Any, source_frame: str,
                              source_time: Any, fixed_frame: str, timeout: Any = None) -> Any:
        """tf2_ros ``lookup_transform_full`` (a timeout blocks, as ``lookup_transform``)."""
        args = (target_frame, target_time, source_frame, source_time, fixed_frame)
        if timeout is not None and duration_to_ns(timeout, "timeout") > 0:
            self._block(True, args, timeout, "buffer.lookup_transform_full()")
        return self.lookup_transform_full_core(*args)

    def transform(self, object_stamped: Any, target_frame: str, timeout: Any = None,
                  new_type: Any = None) -> Any:
        """tf2_ros ``transform``: ``object_stamped`` (PointStamped, PoseStamped, Vector3Stamped)
        in ``target_frame``, at its header's stamp, with tf2_geometry_msgs's math."""
        do_transform = transform_function(object_stamped)  # tf2_ros: the type first
        _check_new_type(object_stamped, new_type)
        t = self.lookup_transform(target_frame, object_stamped.header.frame_id,
                                  object_stamped.header.stamp, timeout)
        return do_transform(object_stamped, t)

    def transform_full(self, object_stamped: Any, target_frame: str, target_time: Any,
                       fixed_frame: str, timeout: Any = None, new_type: Any = None) -> Any:
        """tf2_ros ``transform_full`` (advanced API: a target time and a fixed frame)."""
        do_transform = transform_function(object_stamped)
        _check_new_type(object_stamped, new_type)
        t = self.lookup_transform_full(target_frame, target_time, object_stamped.header.frame_id,
                                       object_stamped.header.stamp, fixed_frame, timeout)
        return do_transform(object_stamped, t)

    def clear(self) -> None:
        """tf2's clear (the waits go on: a transform sent after the clear still ends them)."""
        BufferCore.clear(self)


def _check_new_type(object_stamped: Any, new_type: Any) -> None:
    if new_type is not None and new_type is not type(object_stamped):
        raise TypeException(
            f"Type {new_type} if not loaded or supported (ddes converts to no other type: "
            "leave new_type None)")


def _timeout_text(args: tuple[Any, ...], t_ns: int) -> str:
    frames = (args[0], args[1]) if len(args) == 3 else (args[0], args[2])
    return (f"Timed out after {t_ns / 1e9:.9f} s waiting for the transform from frame "
            f"[{frames[1]}] to frame [{frames[0]}]")


# -- tf2's lines on standard error, as console_bridge's default handler writes them ---------------

#: The line of tf2 0.7.6's ``buffer_core.cpp`` that logs each of tf2's warnings and errors (by
#: the start of its text), which console_bridge prints after it.
_CPP_LINES = (("TF_OLD_DATA", 278), ("TF_REPEATED_DATA", 278), ("TF_SELF_TRANSFORM", 221),
              ("TF_NO_CHILD_FRAME_ID", 227), ("TF_NO_FRAME_ID", 233), ("TF_NAN_INPUT", 240),
              ("TF_DENORMALIZED_QUATERNION", 255))


def console_bridge_text(level: int, text: str) -> str:
    """tf2's line ``text`` as console_bridge's default output handler writes it to standard
    error (no handler registered: every rospy process): ``Warning: `` or ``Error:   `` before
    it, ``at line N in ./tf2/src/buffer_core.cpp`` on the next line."""
    line = next((n for start, n in _CPP_LINES if text.startswith(start)), 0)
    if not line and text.startswith("Invalid argument"):  # BufferCore::warnIfInvalid
        line = 126 if text.endswith("cannot be empty") else 134
    head = "Error:   " if level >= logging.ERROR else "Warning: "
    return f"{head}{text}\n         at line {line} in ./tf2/src/buffer_core.cpp\n"


def _to_stderr(text: str) -> None:
    """``text`` on standard error: the running script's (its ``print_line``), else the process's."""
    task = current_task()
    printer = getattr(getattr(task, "context", None), "print_line", None)
    if printer is not None:
        printer(text.rstrip("\n"), True)
    else:
        sys.stderr.write(text)
