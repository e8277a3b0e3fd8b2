"""The callback runner: every callback of a node goes through its one queue.

Subscriber callbacks, periodic and one-shot timers, service handlers, action
server and client callbacks and dynamic_reconfigure callbacks are all run by
:meth:`CallbackQueue.run`, the one place that calls user code, decides
between a plain function and a generator, and reports a failure.

A *plain* callback finishes at once.  A *generator* callback takes simulated
time: it runs as a kernel process and holds its thread of the spinner until
it returns.  Which callbacks may run together is the node's spinner policy:

``"single"`` (default; roscpp ``ros::spin()``, the course's model)
    One callback at a time per node, FIFO.  While a generator callback
    holds the spinner, the others wait in the queue (so a full subscriber
    queue drops its oldest message).
``N`` (an int >= 1; roscpp ``AsyncSpinner(N)`` / ``MultiThreadedSpinner``)
    Up to N callbacks at once.
``"rospy"`` (rospy's threading model)
    A thread per subscription, per timer and per service connection,
    concurrent with each other and with the node's main process.
``"manual"`` (roscpp ``ros::spinOnce()`` loops)
    Callbacks wait until the node's own loop calls ``yield node.spin_once()``.

In every policy the callbacks of one *owner* — a subscription, a timer, a
service connection — never overlap: roscpp's subscription queues and
rospy's per-subscription lock both serialise them.

An owner is any object with a boolean attribute ``cb_active``, which the
runner sets while one of its callbacks runs.  An owner with a
``callback_failed()`` method is told when one of its callbacks raised, before
the failure is reported (a rospy Timer stops then: its thread died).
"""

from __future__ import annotations

import sys
import traceback
from collections import deque
from collections.abc import Callable, Generator
from types import GeneratorType
from typing import TYPE_CHECKING, Any, Protocol

import simpy

from ddes.errors import DdesValueError
from ddes.graph.blocking import run_callback, run_callback1
from ddes.graph.failures import user_traceback

if TYPE_CHECKING:
    from simpy.events import ProcessGenerator

    from ddes.graph.node import Node

__all__ = ["POLICIES", "CallbackOwner", "CallbackQueue", "GreenCallbackQueue", "SpinnerPolicy",
           "make_green"]

#: The named policies (an int is a thread count).
POLICIES = ("single", "manual", "rospy")

SpinnerPolicy = str | int
#: A callback: a plain function, or a generator function whose generator yields kernel
#: events (it takes simulated time); the runner only tells the two apart by the result.
Callback = Callable[..., object]
_Entry = tuple[Callback, tuple[object, ...], "CallbackOwner | None", "Callable[[], object] | None"]


class CallbackOwner(Protocol):
    """An entity whose callbacks run one at a time (a subscription, a timer...)."""

    cb_active: bool


def _tell_owner(owner: CallbackOwner | None) -> None:
    """Tell ``owner`` (if it wants to know) that its callback raised."""
    failed = getattr(owner, "callback_failed", None)
    if failed is not None:
        failed()


def parse_policy(policy: SpinnerPolicy) -> tuple[int, bool]:
    """``(threads, manual)`` of a spinner policy; a typed error names a bad one."""
    if policy == "single":
        return 1, False
    if policy == "manual":
        return 1, True
    if policy == "rospy":
        return sys.maxsize, False
    if isinstance(policy, int) and not isinstance(policy, bool) and policy >= 1:
        return policy, False
    raise DdesValueError(
        f"spinner must be 'single', 'manual', 'rospy' or a number of threads >= 1, got {policy!r}")


class CallbackQueue:
    """A node's callback queue and spinner (see the module docstring)."""

    __slots__ = ("node", "policy", "threads", "manual", "running", "free", "closed", "_q", "_env",
                 "green_pool")

    #: A blocking node's queue only (:class:`GreenCallbackQueue`): the world's idle callback
    #: tasks, set by :func:`make_green`.
    green_pool: list[Any]

    def __init__(self, node: Node, policy: SpinnerPolicy = "single") -> None:
        self.threads, self.manual = parse_policy(policy)
        self.node = node
        #: The spinner policy this queue was made with.
        self.policy = policy
        #: Generator callbacks running now.
        self.running = 0
        #: True when a new callback may run at once: no thread is busy past
        #: the policy's limit, nothing waits, the queue is not manual or closed.
        self.free = not self.manual
        self.closed = False
        self._q: deque[_Entry] = deque()
        self._env = node.world.env

    def __len__(self) -> int:
        """Callbacks waiting in the queue."""
        return len(self._q)

    def _update_free(self) -> None:
        self.free = not (self.manual or self.closed or self.running >= self.threads or self._q)

    # -- entry points ---------------------------------------------------------------------
    def invoke(self, fn: Callback, args: tuple[object, ...] = (), owner: CallbackOwner | None = None,
               on_done: Callable[[], object] | None = None) -> None:
        """Run ``fn(*args)`` now if the spinner is free for ``owner``, else queue it.

        ``on_done()`` is called when the callback finished (at once for a
        plain function, at the generator's end for a generator).
        """
        if self.free and (owner is None or not owner.cb_active):
            self.run(fn, args, owner, on_done)
        else:
            self.enqueue(fn, args, owner, on_done)

    def can_run(self, owner: CallbackOwner | None) -> bool:
        """True if a callback of ``owner`` would run at once."""
        return self.free and (owner is None or not owner.cb_active)

    def enqueue(self, fn: Callback, args: tuple[object, ...] = (), owner: CallbackOwner | None = None,
                on_done: Callable[[], object] | None = None) -> None:
        """Queue ``fn(*args)``; it runs when the policy allows (FIFO per owner)."""
        if self.closed:
            return
        self._q.append((fn, args, owner, on_done))
        self.free = False
        if not self.manual:
            self._drain()

    def run(self, fn: Callback, args: tuple[object, ...] = (), owner: CallbackOwner | None = None,
            on_done: Callable[[], object] | None = None) -> None:
        """Run one callback now: the one place user callbacks are called."""
        try:
            result = fn(*args)
        except Exception as exc:  # noqa: BLE001 - reported, then the world's policy decides
            self._failed(fn, exc, on_done, owner)
            return
        if result is not None and type(result) is GeneratorType:
            self._adopt(fn, result, owner, on_done)
        elif on_done is not None:
            on_done()

    def run1(self, fn: Callback, arg: object, owner: CallbackOwner | None = None,
             on_done: Callable[[], object] | None = None) -> bool:
        """:meth:`run` for the common one-argument callback (a message, a TimerEvent).

        The same steps as :meth:`run`, without packing the argument into a tuple
        (deliveries and timer fires are the kernel's hottest path).  Returns True
        when the callback has finished (``on_done`` is *not* called then: the
        caller finishes at once), False when it failed or goes on as a generator
        (``on_done`` is called when it ends, as with :meth:`run`).
        """
        try:
            result = fn(arg)
        except Exception as exc:  # noqa: BLE001 - reported, then the world's policy decides
            self._failed(fn, exc, on_done, owner)
            return False
        if result is not None and type(result) is GeneratorType:
            self._adopt(fn, result, owner, on_done)
            return False
        return True

    def _failed(self, fn: Callback, exc: Exception, on_done: Callable[[], object] | None,
                owner: CallbackOwner | None) -> None:
        _tell_owner(owner)
        if on_done is not None:
            on_done()
        self.report_error(fn, exc)

    # -- generators ---------------------------------------------------------------------------
    def hold(self, owner: CallbackOwner | None) -> None:
        """A callback goes on past its call (a generator, a blocked task): it holds a thread."""
        self.running += 1
        if self.running >= self.threads:
            self.free = False
        if owner is not None:
            owner.cb_active = True

    def _adopt(self, fn: Callback, gen: ProcessGenerator, owner: CallbackOwner | None,
               on_done: Callable[[], object] | None) -> None:
        """A generator callback: it holds a thread of the spinner until it ends."""
        self.running += 1
        if self.running >= self.threads:
            self.free = False
        if owner is not None:
            owner.cb_active = True
        proc = self._env.process(self._run_generator(fn, gen, owner))
        proc.callbacks.append(lambda _p: self._finished(owner, on_done))

    def _run_generator(self, fn: Callback, gen: ProcessGenerator,
                       owner: CallbackOwner | None = None) -> ProcessGenerator:
        try:
            return (yield from gen)
        except Exception as exc:  # noqa: BLE001
            _tell_owner(owner)
            self.report_error(fn, exc)
            return None

    def _finished(self, owner: CallbackOwner | None, on_done: Callable[[], object] | None) -> None:
        self.running -= 1
        if owner is not None:
            owner.cb_active = False
        if on_done is not None:
            on_done()
        if self._q and not self.manual:
            self._drain()
        else:
            self._update_free()

    def _drain(self) -> None:
        q = self._q
        while q and self.running < self.threads and not self.manual and not self.closed:
            index = next((k for k, entry in enumerate(q)
                          if entry[2] is None or not entry[2].cb_active), -1)
            if index < 0:
                break  # every queued callback belongs to an owner still running
            fn, args, owner, on_done = q[index]
            del q[index]
            self.run(fn, args, owner, on_done)
        self._update_free()

    # -- manual spinning -------------------------------------------------------------------
    def set_manual(self, manual: bool) -> None:
        """Switch between manual spinning (callbacks wait for :meth:`spin_once`) and running
        them as they come, as a roscpp node does when its main enters ``ros::spin()`` or starts
        an ``AsyncSpinner`` (and stops it again).  What waits runs now, in order."""
        self.manual = bool(manual)
        if not self.manual and self._q:
            self._drain()
        else:
            self._update_free()

    def spin_once(self) -> simpy.Process:
        """Run the callbacks queued now, one at a time (roscpp ``spinOnce``)."""
        return self._env.process(self._spin_once())

    def _spin_once(self) -> Generator[simpy.Event, object, int]:
        n = len(self._q)
        done = 0
        for _ in range(n):
            if not self._q or self.closed:
                break
            fn, args, owner, on_done = self._q.popleft()
            try:
                result = fn(*args)
            except Exception as exc:  # noqa: BLE001
                _tell_owner(owner)
                if on_done is not None:
                    on_done()
                self.report_error(fn, exc)
                continue
            if type(result) is GeneratorType:
                yield self._env.process(self._run_generator(fn, result, owner))
            if on_done is not None:
                on_done()
            done += 1
        self._update_free()
        return done

    # -- errors and shutdown -----------------------------------------------------------------
    def report_error(self, fn: Callback, exc: BaseException) -> None:
        """A callback raised: rospy's "bad callback" log, or (strict) stop the run with it.

        See :mod:`ddes.graph.failures`.
        """
        node = self.node
        world = node.world
        name = getattr(fn, "__qualname__", repr(fn))
        world.record("callback.exception", node.name, callback=name,
                     error=f"{type(exc).__name__}: {exc}")
        world.callback_errors.append((node.name, name, exc, traceback.format_exc()))
        if world.strict:
            world.note_failure(exc)
            raise exc
        node.logerr("bad callback: %s\n%s", name, user_traceback(exc))

    def close(self) -> None:
        """The node shut down: queued callbacks are dropped, nothing new runs."""
        self.closed = True
        self.free = False
        self._q.clear()


class GreenCallbackQueue(CallbackQueue):
    """The queue of a node whose code blocks (:mod:`ddes.graph.blocking`, rospy scripts).

    The same queue, policy and rules; only the call differs: each callback runs on a task
    of its own, so it may block (``rospy.sleep``, ``proxy(req)``), holding its thread of the
    spinner while it waits, as a generator callback does.  A node's queue becomes one with
    :func:`make_green`, so yield-style nodes keep :meth:`CallbackQueue.run` untouched.
    """

    __slots__ = ()

    # The calls themselves are ddes.graph.blocking's (one Python call less per message).
    run = run_callback
    run1 = run_callback1


def make_green(queue: CallbackQueue, pool: list[Any]) -> None:
    """Run ``queue``'s callbacks on tasks from now on (its node's code blocks).

    ``pool`` is the world's list of idle callback tasks (:mod:`ddes.graph.blocking`).
    """
    queue.green_pool = pool
    queue.__class__ = GreenCallbackQueue
