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
from ddes.time.units import duration_to_ns

if TYPE_CHECKING:
    from _typeshed import SupportsWrite

    from ddes.console.tooling import Job, ToolContext
    from ddes.graph.node import Node
    from ddes.graph.world import World

__all__ = [
    "DEFAULT_WAIT_LIMIT",
    "EXIT_INTERRUPTED",
    "HelpPrinted",
    "Task",
    "ToolParser",
    "add_run_options",
    "command_label",
    "job_alive",
    "job_stop",
    "open_ended",
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
    world.settle()


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


#: Exit code of a foreground command stopped by Ctrl+C (128 + SIGINT, as a shell reports it).
EXIT_INTERRUPTED = 130


def open_ended(ctx: ToolContext) -> bool:
    """Whether a foreground command without a count or duration can run here: interactively
    (until Ctrl+C) or in a script with a time limit (``--until``)."""
    return ctx.rtf is not None or ctx.until_ns is not None


def run_task(ctx: ToolContext, task: Task, *, background: bool, duration: float | None,
             waiting_for: str | None = None, hint: str | None = None) -> int:
    """Run ``task`` in the foreground, or leave it in the background; returns its exit code.

    * Background (``&``): the task goes on while the user types; with
      ``duration`` it stops itself that many simulated seconds later.
    * Foreground, interactive (``ctx.rtf`` set): simulated time is paced at
      ``ctx.rtf`` against the wall clock until the task ends, ``duration``
      passes, or Ctrl+C (exit 130; the task stops as in ROS).
    * Foreground, script or Python: until the task ends or ``duration``
      passes; ``ctx.until_ns`` (``ddes console --until``) caps both.
      ``waiting_for`` describes how the task ends by itself (a count, a node
      exiting): without a duration or a script limit it may take
      :data:`DEFAULT_WAIT_LIMIT` seconds, then it is an error.  ``None``
      means it never ends by itself (``rostopic echo`` without ``-n``): with
      no bound at all it is refused at once, saying what to add; ``hint``
      replaces the default advice in that refusal.
    """
    world = ctx.world
    if background:
        job = ctx.background(task.label, task)
        if duration is not None:
            world.post_ns(duration_to_ns(duration, "--duration"), None,
                          lambda _ev: task.stop())
        ctx.print(f"[{job.id}] {task.label}")
        return 0
    deadline: int | None = None
    if duration is not None:
        deadline = world.now + duration_to_ns(duration, "--duration")
    if ctx.until_ns is not None:
        deadline = ctx.until_ns if deadline is None else min(deadline, ctx.until_ns)
    default_limit = False
    if deadline is None and ctx.rtf is None:
        if waiting_for is None:
            task.stop()
            cmd = " ".join(task.label.split()[0:2])
            raise ROSConsoleError(
                f"'{cmd}' runs until Ctrl+C in ROS and would never end here: "
                + (hint or "give --duration SECONDS (simulated)")
                + ", end the line with & to keep it running in the background, or give the "
                "script a time limit (ddes console --until SECONDS)"
            )
        deadline = world.now + duration_to_ns(DEFAULT_WAIT_LIMIT, "limit")
        default_limit = True
    try:
        if not task.done:
            ends = [task.finished]
            if deadline is not None:
                ends.append(world.env.timeout(max(0, deadline - world.now)))
            until = world.env.any_of(ends)
            if ctx.rtf is not None:
                if _run_paced(ctx, until) == "stopped":
                    task.stop()  # Ctrl+C: as ROS's SIGINT, the command's nodes shut down
                    settle(world)
                    return EXIT_INTERRUPTED
            else:
                ctx.run_until(until)
    except BaseException:
        task.stop()
        raise
    if task.done:
        return task.code
    task.stop()
    if default_limit:
        raise ROSConsoleError(
            f"{task.label}: still waiting for {waiting_for} after {DEFAULT_WAIT_LIMIT:g} "
            f"simulated seconds; " + (hint or "give --duration SECONDS to wait longer")
        )
    return task.code


def _run_paced(ctx: ToolContext, until: simpy.Event) -> str:
    """The interactive foreground: the world paced at ``ctx.rtf`` until ``until`` or Ctrl+C
    (see :func:`ddes.kernel.realtime.run_paced`); returns its result."""
    from ddes.kernel.realtime import InterruptFlag, run_paced

    assert ctx.rtf is not None
    if not until.processed:
        ctx.note_waiting()
    if ctx.interrupted is not None:  # the console's flag, up since the command started
        return run_paced(ctx.world, until, rtf=ctx.rtf, stopped=ctx.interrupted)
    with InterruptFlag() as interrupted:
        return run_paced(ctx.world, until, rtf=ctx.rtf, stopped=interrupted)


def command_label(tool: str, argv: Sequence[str]) -> str:
    """The command line of a tool invocation, as ``jobs`` shows it."""
    return shlex.join([tool, *argv])
