"""Blocking calls on simulated time: node code on greenlets, switched by the kernel.

rospy code blocks: ``rate.sleep()``, ``rospy.sleep(0.5)``, ``proxy(req)``,
``rospy.spin()``.  ddes's own API makes every such call an event to
``yield``.  This module lets ordinary blocking code run too, on a
:class:`GreenTask` (a ``greenlet``: a second Python stack that runs until it
switches away):

* :func:`spawn` starts a node's main function on a task, at once, in the
  caller's instant.  It runs until its first blocking call.
* A blocking call is :func:`wait` on the SimPy event it waits for: the task
  appends its ``resume`` to the event's callbacks and switches back to the
  greenlet that last resumed it (the kernel's, or the code that started it).
  When the kernel processes the event, the callback switches into the task,
  which goes on with the event's value (or raises its exception).  Only the
  calling node's task stops; the order of everything stays the kernel's
  deterministic event order.
* Once a node has a task (:func:`attach`), its callback queue is a
  :class:`~ddes.graph.callbacks.GreenCallbackQueue`: each callback runs on a
  task of its own (:func:`run_callback`), so callbacks may block too; a
  callback that blocks holds its thread of the spinner, exactly as a
  generator callback does.  Generator callbacks of such a node still run as
  kernel processes: both styles live in one node and one world.
* When the node shuts down, the tasks blocked in it raise
  :class:`~ddes.errors.ROSInterruptException` ("ROS shutdown request", rospy's
  text) at the instant of the shutdown, except a wait marked
  ``interruptible=False`` (``rospy.spin()``, which returns).

A blocking call outside a task raises a
:class:`~ddes.errors.BlockingCallError`: outside any node (rospy's "time is
not initialized. Have you called init_node()?"), in yield-style code
(``yield`` the event instead), or from a thread the user started.

There is no module-level state: a task knows its world and node; the
current one is the running greenlet.
"""

from __future__ import annotations

import threading
from collections.abc import Callable
from types import GeneratorType
from typing import TYPE_CHECKING, Any

import simpy
from greenlet import getcurrent, greenlet

from ddes.errors import (
    BlockingCallError,
    BlockingInYieldCodeError,
    BlockingOutsideNodeError,
    ROSInterruptException,
)
from ddes.graph.failures import NODE_OF_PROCESS
from ddes.kernel.events import post

if TYPE_CHECKING:
    from ddes.graph.callbacks import Callback, CallbackOwner, CallbackQueue
    from ddes.graph.node import Node
    from ddes.graph.world import World

__all__ = ["INIT_TEXT", "GreenTask", "attach", "current_node", "current_task", "is_blocking_node",
           "run_callback", "run_callback1", "spawn", "wait", "wait_ns"]

#: rospy's text for ROS time read before ``init_node`` (``rospy.rostime.get_rostime``).
INIT_TEXT = "time is not initialized. Have you called init_node()?"

#: What a task's switch back to its resumer carries when it blocked (not finished).
_BLOCKED: Any = object()

#: The per-world list of nodes whose code runs on tasks (a kernel extension slot).
_NODES_KEY = "graph.blocking.nodes"


class GreenTask(greenlet):  # type: ignore[misc]  # greenlet ships no stubs for subclassing
    """A greenlet running one node's code: its main function or one callback.

    ``node`` is None for a main that has not called ``init_node`` yet; a
    script's start-up values (``context``: name, argv, remappings ...) wait
    there for it.
    """

    # Slots: a greenlet's own attributes live in a dict, several times slower to read and
    # write, and these are touched on every blocking call and every callback.
    __slots__ = ("world", "node", "context", "waiting", "blocked", "on_end", "_interrupt",
                 "_interruptible", "_wake")

    def __init__(self, world: World, node: Node | None, run: Callable[..., object],
                 context: object = None) -> None:
        super().__init__(run)
        self.world = world
        self.node = node
        #: What the code's start-up needs (the compat layer's script context), or None.
        self.context = context
        #: The event this task is blocked on (None while it runs or before it first blocks).
        self.waiting: simpy.Event | None = None
        #: True once the task blocked at least once (its start returned before it ended).
        self.blocked = False
        #: Called once when the task has ended after blocking (a callback frees its spinner).
        self.on_end: Callable[[], object] | None = None
        self._interrupt: BaseException | None = None
        self._interruptible = True
        #: ``resume`` bound once: :func:`wait` appends it to the callbacks of each event it waits on.
        self._wake = self.resume

    def resume(self, event: simpy.Event) -> None:
        """The event this task waits on fired (a kernel callback): run the task on from there."""
        if self.waiting is not event or self.dead:
            return  # woken earlier (an interrupt); the event no longer concerns it
        self.waiting = None
        me = getcurrent()
        # reading is cheaper than setting (a cycle check); greenlet has no stubs
        if self.parent is not me:  # type: ignore[has-type]
            self.parent = me  # type: ignore[misc]  # greenlet's own attribute
        if self.on_end is None:  # a main, or a callback that never blocked before: nothing to end
            self.switch(event)
            return
        ended = True
        try:
            ended = self.switch(event) is not _BLOCKED
        finally:
            if ended and self.on_end is not None:
                end, self.on_end = self.on_end, None
                end()

    def interrupt(self, exc: BaseException) -> None:
        """Wake the blocked task with ``exc`` raised from its blocking call (at the next step)."""
        if self.waiting is None or not self._interruptible or self.dead:
            return
        self._interrupt = exc
        wake = self.world.env.event()
        waiting = self.waiting
        wake.callbacks.append(lambda _ev: self.resume(waiting))
        wake.succeed()

    def __repr__(self) -> str:
        who = self.node.name if self.node is not None else "(no node yet)"
        return f"<GreenTask of {who}>"


def current_task() -> GreenTask | None:
    """The task running now, or None (kernel code, yield-style code, another thread)."""
    g = getcurrent()
    return g if isinstance(g, GreenTask) else None


def current_node() -> Node | None:
    """The node whose task is running now (None outside a task or before ``init_node``)."""
    g = getcurrent()
    return g.node if isinstance(g, GreenTask) else None


def _not_here(env: simpy.Environment, what: str) -> BlockingCallError:
    """The error for a blocking call ``what`` made outside a task."""
    if threading.current_thread() is not threading.main_thread():
        return BlockingOutsideNodeError(
            f"{what} was called from a thread ddes did not start "
            f"({threading.current_thread().name}): ddes runs every node on the kernel's thread, "
            "so a thread of your own cannot block on simulated time. Do the work in the node's "
            "main or in a callback (rospy.Timer for periodic work) instead of a threading.Thread.")
    if getattr(env, "active_process", None) is not None:
        return BlockingInYieldCodeError(
            f"{what} blocks, but it was called inside yield-style code (a node process or a "
            "generator callback run by the kernel), which cannot block. Either yield the event "
            "there (yield rate.sleep(), yield node.sleep(0.5), resp = yield proxy(req)), or "
            "write the function without yield as plain blocking code: the main and the "
            "callbacks of a node started with `from ddes.compat import rospy` (a rospy script) "
            "run on greenlets and may block.")
    return BlockingOutsideNodeError(
        f"{what}: {INIT_TEXT} {what} blocks only inside a node's code: the main of a rospy "
        "script node after rospy.init_node(...) (`from ddes.compat import rospy`, started by "
        "rosrun/roslaunch or ddes.graph.blocking.spawn) or one of its callbacks. In yield-style "
        "code (node.process(main()), a plain or generator callback) write "
        "`yield node.sleep(0.5)` / `yield rate.sleep()` instead.")


def wait(event: simpy.Event, what: str = "a blocking call", *,
         interruptible: bool = True) -> Any:
    """Block the running task until the kernel processes ``event``; its value (or its error).

    ``what`` names the call in the error raised outside a task (``"rospy.sleep()"``).
    An ``interruptible`` wait raises :class:`ROSInterruptException` when the node shuts down
    meanwhile.
    """
    task = getcurrent()
    if not isinstance(task, GreenTask):
        raise _not_here(event.env, what)
    callbacks = event.callbacks
    if callbacks is None:  # processed already: no need to block
        return _outcome(event)
    callbacks.append(task._wake)
    task.waiting = event
    task.blocked = True
    task._interruptible = interruptible
    task.parent.switch(_BLOCKED)  # back here from resume(), which cleared task.waiting
    if task._interrupt is not None:
        exc, task._interrupt = task._interrupt, None
        raise exc
    if event._ok:
        return event._value
    return _outcome(event)


def wait_ns(env: simpy.Environment, delay: int, what: str = "a blocking call", *,
            interruptible: bool = True) -> None:
    """Block the running task for ``delay`` ns (>= 0) of kernel time: ``wait(env.timeout(delay))``.

    The same event at the same place in the kernel's queue (:func:`ddes.kernel.events.post`
    is exactly a timeout with one callback), made without SimPy's Timeout constructor: the
    path of every ``rate.sleep()`` in a rospy loop.  ``interruptible`` as :func:`wait`.
    """
    task = getcurrent()
    if not isinstance(task, GreenTask):
        raise _not_here(env, what)
    task.waiting = post(env, delay, None, task._wake)
    task.blocked = True
    task._interruptible = interruptible
    task.parent.switch(_BLOCKED)  # back here from resume(), which cleared task.waiting
    if task._interrupt is not None:
        exc, task._interrupt = task._interrupt, None
        raise exc


def _outcome(event: simpy.Event) -> Any:
    """The value of a processed event, or its exception raised (and defused: it was handled)."""
    if event.ok:
        return event.value
    event.defused = True
    exc = event.value
    if not isinstance(exc, BaseException):  # pragma: no cover - SimPy fails with exceptions only
        raise TypeError(f"event failed with {exc!r}")
    raise exc


# -- nodes ----------------------------------------------------------------------------------
def _blocking_nodes(world: World) -> dict[Node, list[GreenTask]]:
    return world.extension(_NODES_KEY, _new_table)


def _new_table(_world: object) -> dict[Node, list[GreenTask]]:
    return {}


def is_blocking_node(node: Node) -> bool:
    """True when ``node``'s code runs on tasks (its callbacks may block)."""
    table = node.world.extensions.get(_NODES_KEY)
    return isinstance(table, dict) and node in table


def attach(task: GreenTask, node: Node) -> None:
    """``node`` is the task's node from now on (``init_node``): its callbacks run on tasks."""
    from ddes.graph.callbacks import make_green

    task.node = node
    _track(node).append(task)
    make_green(node.callbacks, _pool_of(node.world))


def _track(node: Node) -> list[GreenTask]:
    table = _blocking_nodes(node.world)
    tasks = table.get(node)
    if tasks is None:
        tasks = table[node] = []

        def interrupt_all(_reason: str) -> None:
            for t in list(tasks):
                t.interrupt(ROSInterruptException("ROS shutdown request"))

        node.on_shutdown(interrupt_all)
    return tasks


def _forget(task: GreenTask) -> None:
    node = task.node
    if node is None:
        return
    tasks = _blocking_nodes(node.world).get(node)
    if tasks is not None and task in tasks:
        tasks.remove(task)


def spawn(world: World, main: Callable[..., object], args: tuple[object, ...] = (), *,
          node: Node | None = None, context: object = None) -> simpy.Event:
    """Run ``main(*args)`` on a new task now, until it first blocks; an event of its end.

    With ``node``, the task belongs to it (:func:`attach`); without, the code
    attaches itself (``rospy.init_node``).  The returned event succeeds with
    ``main``'s return value (``sys.exit(n)`` gives ``n``) or fails with its
    exception; like a node's process, a failure nobody handles is the node's
    crash (``node.report_crash``), or in a strict world ends the run.
    """
    done = world.env.event()

    def body() -> None:
        task = getcurrent()
        try:
            value = main(*args)
        except SystemExit as stop:
            value = stop.code if isinstance(stop.code, int) else (0 if stop.code is None else 1)
        except ROSInterruptException:
            value = None  # rospy scripts end this way when their node shuts down
        except Exception as exc:  # noqa: BLE001 - the done event carries it to the world's policy
            _finish(task, done)
            done.fail(exc)
            return
        _finish(task, done)
        done.succeed(value)

    task = GreenTask(world, None, body, context)
    if node is not None:
        attach(task, node)
    task.parent = getcurrent()
    task.switch()
    return done


def _finish(task: GreenTask, done: simpy.Event) -> None:
    if task.node is not None:
        setattr(done, NODE_OF_PROCESS, task.node)
    _forget(task)


# -- callbacks ------------------------------------------------------------------------------
#: The per-world pool of idle callback tasks (a kernel extension slot).  Starting a greenlet
#: costs far more than switching to one (CPython allocates its frame stack), so callback tasks
#: are reused: an idle one waits at the end of its loop for the next callback.
_POOL_KEY = "graph.blocking.pool"


def _new_pool(_world: object) -> list[GreenTask]:
    return []


def _worker(job: tuple[Any, ...]) -> None:
    """A callback task's loop: run a callback, go back to the pool, wait for the next one.

    The plain path (the callback returns without raising and without a generator) is inline:
    it is what every message delivered to a rospy subscriber runs.
    """
    task = getcurrent()
    pool = _pool_of(task.world)
    while True:
        queue, fn, args, owner, on_done, many = job
        try:
            result = fn(*args) if many else fn(args)
        except ROSInterruptException:
            if not queue.node.is_shutdown():
                raise
            finished = False  # woken by the node's shutdown: the callback just ends
        except Exception as exc:  # noqa: BLE001 - reported, then the world's policy decides
            _callback_failed(task, queue, fn, exc, owner, on_done)
            finished = False
        else:
            finished = result is None or type(result) is not GeneratorType \
                or _callback_generator(task, queue, fn, result, owner, on_done)
        if task.blocked:
            _forget(task)
        task.node = None
        pool.append(task)
        job = task.parent.switch(finished)


def _pool_of(world: World) -> list[GreenTask]:
    """The world's idle callback tasks (``GreenCallbackQueue.green_pool`` holds the same list)."""
    return world.extension(_POOL_KEY, _new_pool)


def _callback_failed(task: GreenTask, queue: CallbackQueue, fn: Callback, exc: Exception,
                     owner: CallbackOwner | None, on_done: Callable[[], object] | None) -> None:
    """A callback on ``task`` raised: "bad callback" (or the world's policy), its owner freed."""
    if task.blocked:
        failed = getattr(owner, "callback_failed", None)
        if failed is not None:
            failed()
        queue.report_error(fn, exc)
    else:
        queue._failed(fn, exc, on_done, owner)


def _callback_generator(task: GreenTask, queue: CallbackQueue, fn: Callback, gen: Any,
                        owner: CallbackOwner | None, on_done: Callable[[], object] | None
                        ) -> bool:
    """A callback on ``task`` returned a generator: it runs on as yield-style code (False)."""
    if task.blocked:  # blocked, then returned a generator: it runs on its own
        queue.node.world.env.process(queue._run_generator(fn, gen, owner))
    else:
        queue._adopt(fn, gen, owner, on_done)
    return False


def run_callback(queue: CallbackQueue, fn: Callback, args: tuple[object, ...] = (),
                 owner: CallbackOwner | None = None,
                 on_done: Callable[[], object] | None = None) -> None:
    """Run one callback of a blocking node on a task (``GreenCallbackQueue.run``).

    ``on_done`` is called when it ends.  A callback that blocks holds its thread of the
    spinner (and its owner) until it ends, as a generator callback does; a generator result
    is adopted as in yield style.
    """
    node = queue.node
    pool = queue.green_pool
    task = pool.pop() if pool else GreenTask(node.world, None, _worker)
    task.node = node
    task.blocked = False
    task.on_end = None
    me = getcurrent()
    if task.parent is not me:
        task.parent = me
    finished = task.switch((queue, fn, args, owner, on_done, True))
    if finished is _BLOCKED:
        _block(queue, task, owner, on_done)
    elif finished and on_done is not None:
        on_done()


def run_callback1(queue: CallbackQueue, fn: Callback, arg: object,
                  owner: CallbackOwner | None = None,
                  on_done: Callable[[], object] | None = None) -> bool:
    """:func:`run_callback` for one argument (``GreenCallbackQueue.run1``: a message, a timer).

    Returns True when the callback finished without blocking (``run1``'s contract: the
    caller finishes, ``on_done`` is not called); otherwise ``on_done`` is called when it
    ends, and False is returned.  This is the path of every message a rospy subscriber gets.
    """
    pool = queue.green_pool
    task = pool.pop() if pool else GreenTask(queue.node.world, None, _worker)
    task.node = queue.node
    task.blocked = False
    task.on_end = None
    me = getcurrent()
    if task.parent is not me:
        task.parent = me
    finished = task.switch((queue, fn, arg, owner, on_done, False))
    if finished is _BLOCKED:
        _block(queue, task, owner, on_done)
        return False
    return finished  # type: ignore[no-any-return]  # the worker's bool


def _block(queue: CallbackQueue, task: GreenTask, owner: CallbackOwner | None,
           on_done: Callable[[], object] | None) -> None:
    """The callback on ``task`` blocked: it holds its spinner thread until it ends."""
    _track(queue.node).append(task)  # a blocked callback is woken when its node shuts down
    queue.hold(owner)
    task.on_end = lambda: queue._finished(owner, on_done)
