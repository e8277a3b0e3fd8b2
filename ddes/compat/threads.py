"""``threading`` as a rospy script sees it: locks, conditions, events and threads on greenlets.

rospy runs callbacks on threads, so rospy code guards shared state with
``threading.Lock``.  In ddes every node's code runs on greenlets of the one
kernel thread; a real ``Lock`` held across a blocking call would freeze the
whole process.  In a script, ``import threading`` gives this module instead
(:mod:`ddes.compat.scripts`): ``Lock``, ``RLock``, ``Condition``, ``Event``
and ``Semaphore`` whose waits block only the waiting greenlet, handed over
first come first served (deterministic), with ``timeout`` in simulated
seconds; ``Thread(target=...).start()`` runs the target on a new greenlet of
the same node (``join`` blocks until it ends).  A wait that can never end —
a lock waiting, through its owners, on itself — raises
:class:`~ddes.errors.DeadlockError` naming the nodes involved, instead of
freezing.  Everything else is the real ``threading`` module.
"""

from __future__ import annotations

import threading as _threading
import types
from collections import deque
from collections.abc import Callable
from typing import Any

import simpy

from ddes.errors import DdesValueError, DeadlockError
from ddes.graph.blocking import GreenTask, current_task, spawn, wait
from ddes.time.units import duration_to_ns

__all__ = ["Condition", "Event", "Lock", "RLock", "Semaphore", "Thread", "module"]


def _who(task: GreenTask | None) -> str:
    if task is None:
        return "code outside any node"
    return task.node.name if task.node is not None else "a script before init_node"


def _block(what: str, event: simpy.Event, timeout: float | None) -> bool:
    """Block the running task on ``event`` (at most ``timeout`` simulated seconds); fired?"""
    task = current_task()
    if timeout is None or timeout < 0 or task is None:
        wait(event, what)
        return True
    env = task.world.env
    deadline = env.timeout(duration_to_ns(timeout, "timeout"))
    wait(env.any_of([event, deadline]), what)
    return event.triggered


class Lock:
    """threading.Lock: a waiter blocks only its own greenlet; FIFO hand-over."""

    def __init__(self) -> None:
        self._owner: GreenTask | None = None
        self._locked = False
        self._waiters: deque[tuple[GreenTask | None, simpy.Event]] = deque()

    def _check_deadlock(self, me: GreenTask | None) -> None:
        chain = [me]
        lock: Lock | None = self
        while lock is not None and lock._locked:
            owner = lock._owner
            if owner is me:
                names = " -> ".join(_who(t) for t in chain + [me])
                raise DeadlockError(
                    f"deadlock: {names} waits for a lock it holds through this chain, so it "
                    "would wait for ever (a real process would freeze here). Release the lock "
                    "before waiting, take locks in one order everywhere, or use an RLock for "
                    "re-entry.")
            chain.append(owner)
            lock = getattr(owner, "ddes_waiting_lock", None)

    def acquire(self, blocking: bool = True, timeout: float = -1) -> bool:
        me = current_task()
        if not self._locked:
            self._locked, self._owner = True, me
            return True
        if not blocking:
            return False
        if timeout < 0:  # a wait with a timeout ends anyway
            self._check_deadlock(me)
        if me is None:
            raise DeadlockError("a Lock held by a node was acquired outside any node: it can "
                                "never be released while this code waits")
        granted = me.world.env.event()
        entry = (me, granted)
        self._waiters.append(entry)
        me.ddes_waiting_lock = self
        try:
            got = _block("lock.acquire()", granted, None if timeout < 0 else timeout)
        finally:
            me.ddes_waiting_lock = None
        if not got:
            self._waiters.remove(entry)
        return got

    def release(self) -> None:
        if not self._locked:
            raise RuntimeError("release unlocked lock")
        if self._waiters:
            task, granted = self._waiters.popleft()
            self._owner = task  # handed over: it stays locked
            granted.succeed()
        else:
            self._locked, self._owner = False, None

    def locked(self) -> bool:
        return self._locked

    def __enter__(self) -> bool:
        return self.acquire()

    def __exit__(self, *exc: object) -> None:
        self.release()


class RLock(Lock):
    """threading.RLock: its owner may acquire it again."""

    def __init__(self) -> None:
        super().__init__()
        self._count = 0

    def acquire(self, blocking: bool = True, timeout: float = -1) -> bool:
        if self._locked and self._owner is current_task():
            self._count += 1
            return True
        got = super().acquire(blocking, timeout)
        if got:
            self._count = 1
        return got

    def release(self) -> None:
        if not self._locked or self._owner is not current_task():
            raise RuntimeError("cannot release un-acquired lock")
        self._count -= 1
        if self._count == 0:
            super().release()
            if self._locked:
                self._count = 1  # handed over to the next waiter


class Condition:
    """threading.Condition(lock=None): ``wait`` releases the lock while it blocks."""

    def __init__(self, lock: Lock | None = None) -> None:
        self._lock = lock if lock is not None else RLock()
        self._waiters: deque[simpy.Event] = deque()

    def __enter__(self) -> bool:
        return self._lock.acquire()

    def __exit__(self, *exc: object) -> None:
        self._lock.release()

    def acquire(self, blocking: bool = True, timeout: float = -1) -> bool:
        return self._lock.acquire(blocking, timeout)

    def release(self) -> None:
        self._lock.release()

    def wait(self, timeout: float | None = None) -> bool:
        me = current_task()
        if me is None:
            raise DeadlockError("Condition.wait() outside any node: nothing can notify it")
        woken = me.world.env.event()
        self._waiters.append(woken)
        count = self._lock._count if isinstance(self._lock, RLock) else 1
        for _ in range(count):
            self._lock.release()
        try:
            got = _block("condition.wait()", woken, timeout)
        finally:
            if woken in self._waiters:
                self._waiters.remove(woken)
            for _ in range(count):
                self._lock.acquire()
        return got

    def wait_for(self, predicate: Callable[[], bool], timeout: float | None = None) -> bool:
        result = predicate()
        while not result:
            if not self.wait(timeout) and timeout is not None:
                return bool(predicate())
            result = predicate()
        return bool(result)

    def notify(self, n: int = 1) -> None:
        for _ in range(min(n, len(self._waiters))):
            self._waiters.popleft().succeed()

    def notify_all(self) -> None:
        self.notify(len(self._waiters))


class Semaphore:
    """threading.Semaphore(value=1)."""

    def __init__(self, value: int = 1) -> None:
        if value < 0:
            raise DdesValueError("semaphore initial value must be >= 0")
        self._value = value
        self._cond = Condition(Lock())

    def acquire(self, blocking: bool = True, timeout: float | None = None) -> bool:
        with self._cond:
            if not blocking and self._value == 0:
                return False
            if not self._cond.wait_for(lambda: self._value > 0, timeout):
                return False
            self._value -= 1
            return True

    def release(self, n: int = 1) -> None:
        with self._cond:
            self._value += n
            self._cond.notify(n)

    def __enter__(self) -> bool:
        return self.acquire()

    def __exit__(self, *exc: object) -> None:
        self.release()


class Event:
    """threading.Event: ``wait`` blocks only the waiting greenlet."""

    def __init__(self) -> None:
        self._flag = False
        self._waiters: list[simpy.Event] = []

    def is_set(self) -> bool:
        return self._flag

    isSet = is_set  # noqa: N815 - threading's old name

    def set(self) -> None:
        self._flag = True
        waiters, self._waiters = self._waiters, []
        for w in waiters:
            w.succeed()

    def clear(self) -> None:
        self._flag = False

    def wait(self, timeout: float | None = None) -> bool:
        if self._flag:
            return True
        me = current_task()
        if me is None:
            raise DeadlockError("Event.wait() outside any node: nothing can set it meanwhile")
        woken = me.world.env.event()
        self._waiters.append(woken)
        _block("event.wait()", woken, timeout)
        if woken in self._waiters:
            self._waiters.remove(woken)
        return self._flag


class Thread:
    """threading.Thread: ``start()`` runs the target on a new greenlet of the same node."""

    def __init__(self, group: None = None, target: Callable[..., object] | None = None,
                 name: str | None = None, args: tuple[Any, ...] = (),
                 kwargs: dict[str, Any] | None = None, *, daemon: bool | None = None) -> None:
        self._target = target
        self._args = args
        self._kwargs = dict(kwargs or {})
        self._auto_name = name is None
        self.name = name or "Thread"
        self.daemon = bool(daemon)
        self._done: simpy.Event | None = None

    def run(self) -> None:
        if self._target is not None:
            self._target(*self._args, **self._kwargs)

    def _bootstrap(self) -> None:
        """``run()``, and what threading does when it raises: the traceback on standard error
        ("Exception in thread NAME:"), the thread ends, the node and its other threads go on
        (``threading.excepthook``; SystemExit ends the thread silently)."""
        try:
            self.run()
        except SystemExit:
            pass
        except Exception as exc:  # noqa: BLE001 - a thread's error ends only the thread
            import sys
            import traceback

            text = "".join(traceback.format_exception(type(exc), exc, exc.__traceback__))
            print(f"Exception in thread {self.name}:\n{text}", end="", file=sys.stderr,
                  flush=True)

    def start(self) -> None:
        me = current_task()
        if me is None or me.node is None:
            raise DeadlockError("Thread.start() outside a node's code: ddes runs a thread on a "
                                "greenlet of the node that starts it (call it after init_node)")
        if self._done is not None:
            raise RuntimeError("threads can only be started once")
        if self._auto_name:  # threading's "Thread-N (target)", N counted per node
            counts = me.world.extension("threads.count", _new_counts)
            n = counts[me.node] = counts.get(me.node, 0) + 1
            target = getattr(self._target, "__name__", "")
            self.name = f"Thread-{n}" + (f" ({target})" if target else "")
        self._done = spawn(me.world, self._bootstrap, node=me.node)

    def join(self, timeout: float | None = None) -> None:
        if self._done is None:
            raise RuntimeError("cannot join thread before it is started")
        _block("thread.join()", self._done, timeout)

    def is_alive(self) -> bool:
        return self._done is not None and not self._done.triggered


def _new_counts(_world: object) -> dict[Any, int]:
    return {}


def module() -> types.ModuleType:
    """The ``threading`` module of a script: these classes, the real module for the rest."""
    mod = _ThreadingView("threading")
    for name in ("Condition", "Event", "Lock", "RLock", "Semaphore", "Thread"):
        setattr(mod, name, globals()[name])
    setattr(mod, "BoundedSemaphore", Semaphore)  # noqa: B010 - a module attribute
    return mod


class _ThreadingView(types.ModuleType):
    def __getattr__(self, name: str) -> Any:
        return getattr(_threading, name)
