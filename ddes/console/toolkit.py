"""Shared machinery of the world-bound ROS tools (rostopic, rosnode, rosparam, rosrun...).

* :class:`ToolParser`: ``optparse`` as the ROS tools use it, but a usage
  error raises :class:`~ddes.errors.ROSConsoleError` (one line, the console
  keeps running) and ``-h`` prints through the tool context.
* :class:`Task` and :func:`run_task`: how a command that ROS runs until
  Ctrl+C (``rostopic echo``, ``hz``, ``pub -r``, a launch, ``rosnode ping``)
  runs on simulated time: until its count is reached, for ``--duration S``
  simulated seconds, or in the background of the world (a trailing ``&`` or
  ``--background``; listed by ``jobs``, stopped by ``kill %N``).
* :func:`script_resolve_name`: rosgraph's name resolution for command-line tools.
* :func:`node_uri` and :func:`node_pid` (re-exported from
  :mod:`ddes.launch.runtime`): the synthetic, stable XML-RPC URI and pid
  that ROS tools print for a node.
"""

from __future__ import annotations

import optparse
import shlex
from collections.abc import Callable, Sequence
from typing import TYPE_CHECKING, NoReturn

import simpy

from ddes.errors import ROSConsoleError
from ddes.graph.names import resolve_name
from ddes.launch.runtime import node_pid, node_uri

if TYPE_CHECKING:
    from _typeshed import SupportsWrite

    from ddes.console.tooling import Job, ToolContext
    from ddes.graph.node import Node
    from ddes.graph.world import World

__all__ = [
    "DEFAULT_WAIT_LIMIT",
    "HelpPrinted",
    "Task",
    "ToolParser",
    "add_run_options",
    "command_label",
    "job_alive",
    "job_stop",
    "node_pid",
    "node_uri",
    "parse_count",
    "parse_duration",
    "run_task",
    "script_resolve_name",
    "settle",
    "take_background",
]

#: How long (simulated seconds) a foreground command waits for its count
#: (``rostopic echo -n 3``) before giving up; ``--duration`` overrides it.
DEFAULT_WAIT_LIMIT = 600.0


class HelpPrinted(Exception):
    """Raised by :class:`ToolParser` after ``-h``: the tool returns 0 at once."""


class ToolParser(optparse.OptionParser):
    """An ``OptionParser`` that reports through the tool context instead of exiting."""

    def __init__(self, ctx: ToolContext, usage: str, prog: str) -> None:
        super().__init__(usage=usage, prog=prog, add_help_option=True)
        self.ctx = ctx

    def error(self, msg: str) -> NoReturn:
        usage = (self.usage or "").replace("%prog", self.prog or "").strip()
        if usage.lower().startswith("usage: "):
            usage = usage[7:]
        raise ROSConsoleError(f"{msg} (usage: {usage})")

    def exit(self, status: int = 0, msg: str | None = None) -> NoReturn:
        if msg:
            raise ROSConsoleError(msg.strip())
        raise HelpPrinted()

    def print_help(self, file: SupportsWrite[str] | None = None) -> None:
        self.ctx.print(self.format_help().rstrip("\n"))

    def print_usage(self, file: SupportsWrite[str] | None = None) -> None:
        self.ctx.print(self.get_usage().rstrip("\n"))


def take_background(argv: Sequence[str]) -> tuple[list[str], bool]:
    """Strip a trailing ``&`` (or ``--background``) from ``argv``; report whether it was there."""
    args = list(argv)
    background = False
    if args and args[-1] == "&":
        args.pop()
        background = True
    if "--background" in args:
        args.remove("--background")
        background = True
    return args, background


def add_run_options(parser: ToolParser, count: str | None = None) -> None:
    """Add ``--duration S`` (and ``-n COUNT`` when ``count`` describes it) to ``parser``."""
    parser.add_option("--duration", dest="duration", default=None, metavar="SECONDS",
                      help="ddes: stop after SECONDS of simulated time (ROS runs until Ctrl+C)")
    if count is not None:
        parser.add_option("-n", dest="count", default=None, metavar="COUNT", help=count)


def parse_duration(value: str | None) -> float | None:
    """The ``--duration`` value as seconds (None when absent); a clear error otherwise."""
    if value is None:
        return None
    try:
        seconds = float(value)
    except ValueError:
        raise ROSConsoleError(f"--duration must be a number of seconds, got {value!r}") from None
    if not seconds >= 0:
        raise ROSConsoleError(f"--duration must be >= 0 seconds, got {value!r}")
    return seconds


def parse_count(value: str | None, what: str = "COUNT") -> int | None:
    """A ``-n COUNT`` value (None when absent)."""
    if value is None:
        return None
    try:
        n = int(value)
    except ValueError:
        raise ROSConsoleError(f"{what} must be an integer, got {value!r}") from None
    if n <= 0:
        raise ROSConsoleError(f"{what} must be at least 1, got {value!r}")
    return n


def script_resolve_name(script: str, name: str) -> str:
    """Resolve ``name`` as a command-line tool does (``rosgraph.names.script_resolve_name``).

    Relative names go into the global namespace, ``~name`` under ``/script``.
    """
    if not name:
        return "/"
    return resolve_name(name, "/" + script)


def settle(world: World) -> None:
    """Process every event due at the current instant (nodes just started run their start-up)."""
    env = world.env
    now = env.now
    for _ in range(1_000_000):
        if env.peek() != now:
            return
        env.step()
    raise ROSConsoleError("the world keeps scheduling events at the same instant (a zero-time loop?)")


class Task:
    """Something a command keeps running in the world: its nodes and how it ends.

    ``finished`` fires when the task ends, by itself (:meth:`finish`, e.g.
    ``rostopic echo -n 3`` got its messages) or when stopped (:meth:`stop`:
    ``kill %N``, the end of ``--duration``).  The nodes it owns are shut down
    either way; ``on_stop`` hooks run first (to print a summary).
    """

    def __init__(self, world: World, label: str) -> None:
        self.world = world
        self.label = label
        self.nodes: list[Node] = []
        self.finished: simpy.Event = world.env.event()
        self.code = 0
        self.reported = False
        self._finishing = False
        self._on_stop: list[Callable[[], None]] = []

    @property
    def done(self) -> bool:
        """True once the task has ended."""
        return bool(self.finished.triggered)

    def own(self, node: Node) -> Node:
        """Shut ``node`` down when the task ends."""
        self.nodes.append(node)
        return node

    def on_stop(self, hook: Callable[[], None]) -> None:
        """Call ``hook()`` when the task is stopped from outside (before its nodes go)."""
        self._on_stop.append(hook)

    def finish(self, code: int = 0) -> None:
        """End the task (its own decision); its nodes shut down."""
        if self.done or self._finishing:
            return
        self._finishing = True
        self.code = code
        for node in reversed(self.nodes):
            node.shutdown("task finished")
        self.finished.succeed(code)

    def stop(self) -> None:
        """Stop the task from outside (``kill %N``, end of ``--duration``)."""
        if self.done or self._finishing:
            return
        for hook in list(self._on_stop):
            hook()
        self.finish(self.code)


def job_alive(job: Job) -> bool:
    """Whether a background job still runs (a :class:`Task`, a SimPy process or a node)."""
    p = job.process
    if isinstance(p, Task):
        return not p.done
    if isinstance(p, simpy.Process):
        return bool(p.is_alive)
    is_shutdown = getattr(p, "is_shutdown", None)
    if callable(is_shutdown):
        return not is_shutdown()
    done = getattr(p, "done", None)
    if isinstance(done, bool):
        return not done
    return True


def job_stop(job: Job) -> None:
    """Stop a background job (``kill %N``)."""
    p = job.process
    stop = getattr(p, "stop", None)
    if callable(stop):
        stop()
    elif isinstance(p, simpy.Process):
        if p.is_alive:
            p.callbacks.append(_defuse)
            p.interrupt("killed")
    elif callable(shutdown := getattr(p, "shutdown", None)):
        shutdown("killed")
    else:
        raise ROSConsoleError(f"job [{job.id}] ({job.name}) cannot be stopped")


def _defuse(ev: simpy.Event) -> None:
    if not ev.ok and isinstance(ev.value, simpy.Interrupt):
        ev.defused = True


def run_task(ctx: ToolContext, task: Task, *, background: bool, duration: float | None,
             waiting_for: str | None = None) -> int:
    """Run ``task`` in the foreground (until it ends or ``duration``) or leave it in the background.

    ``waiting_for`` describes the count a foreground run waits for (for the
    message when :data:`DEFAULT_WAIT_LIMIT` passes without it); ``None``
    means the task has no end of its own, so a bound is required.
    """
    if background:
        job = ctx.background(task.label, task)
        ctx.print(f"[{job.id}] {task.label}")
        return 0
    world = ctx.world
    if duration is None and waiting_for is None:
        task.stop()
        cmd = task.label.split()[0:2]
        raise ROSConsoleError(
            f"'{' '.join(cmd)}' runs until Ctrl+C in ROS; in ddes give --duration SECONDS "
            f"(simulated), or end the line with & to keep it running in the background"
        )
    limit = duration if duration is not None else DEFAULT_WAIT_LIMIT
    deadline = world.timeout(limit)
    try:
        ctx.run_until(world.env.any_of([task.finished, deadline]))
    except BaseException:
        task.stop()
        raise
    if task.done:
        return task.code
    task.stop()
    if duration is None:
        raise ROSConsoleError(
            f"{task.label}: still waiting for {waiting_for} after {limit:g} simulated seconds; "
            f"give --duration SECONDS to wait longer"
        )
    return task.code


def command_label(tool: str, argv: Sequence[str]) -> str:
    """The command line of a tool invocation, as ``jobs`` shows it."""
    return shlex.join([tool, *argv])
