"""World-bound ROS tools, shared by the console, scripts and the Python API.

A *tool* is a function ``tool(ctx, argv) -> int`` (an exit code) that writes
its output with ``ctx.print``/``ctx.eprint`` and acts on ``ctx.world``.
ROS's tools block until Ctrl+C or until something happens in the graph; on a
simulated clock they instead let time pass explicitly:

* ``ctx.run_until(event, timeout=...)`` runs the world until ``event`` has
  been processed (``timeout`` in simulated seconds; ``None`` = until the
  event, raising ROSConsoleError if the world runs out of events first);
* ``ctx.advance(seconds)`` runs the world for a span;
* ``ctx.background(name, process)`` leaves a process running in the world
  (a ``rostopic pub -r`` or ``rosbag record`` that goes on while the user
  types), listed by the console's ``jobs``.

Tool modules are listed in :data:`TOOL_MODULES`; each defines ``TOOLS``, a
dict from command name (``"rostopic"``) to its tool function.  Errors are
raised as :class:`~ddes.errors.DdesError` subclasses (the console prints a
one-line ``ERROR: ...`` and keeps running) or reported with ``ctx.eprint``
and a non-zero exit code, as the ROS tool would.

``run_command(world, "rostopic list")`` runs one command line and returns its
output; it is what notebooks and autograders call.
"""

from __future__ import annotations

import importlib
import os
import shlex
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, Protocol, Union

from ddes.errors import DdesError, ROSConsoleError
from ddes.time.units import duration_to_ns

if TYPE_CHECKING:
    import simpy

    from ddes.console.toolkit import Task
    from ddes.graph.node import Node
    from ddes.graph.world import World
    from ddes.rospack import RosPack

__all__ = ["TOOL_MODULES", "CommandResult", "ToolContext", "Tool", "find_tool", "run_command",
           "run_command_result", "sim_time_notice", "tool_names"]

#: Modules defining world-bound tools (``TOOLS = {"name": fn}``); one line per module.
TOOL_MODULES: tuple[str, ...] = (
    "ddes.console.catkin",
    "ddes.console.rosbag",
    "ddes.console.roscd",
    "ddes.console.roscore",
    "ddes.console.rosmsg",
    "ddes.console.rosnode",
    "ddes.console.rosparam",
    "ddes.console.rospack",
    "ddes.console.rosrun",
    "ddes.console.rosservice",
    "ddes.console.rostest",
    "ddes.console.rostopic",
    "ddes.console.viz",
)

Tool = Callable[["ToolContext", list[str]], int]


class Stoppable(Protocol):
    """Something with ``stop()`` (a Player, a Recorder, a LaunchRunner)."""

    def stop(self) -> None: ...


#: What a background job runs: a console Task, a SimPy process, a node, or something stoppable.
JobProcess = Union["Task", "simpy.Process", "Node", Stoppable]


@dataclass
class Job:
    """A background process started by a tool (listed by the console's ``jobs``)."""

    id: int
    name: str
    process: JobProcess
    started_ns: int


@dataclass
class ToolContext:
    """What a tool runs against: the world, the package path, and output sinks."""

    world: World
    rospack: RosPack | None = None
    out: Callable[[str], None] = print
    err: Callable[[str], None] = print
    jobs: list[Job] = field(default_factory=list)
    #: The console's working directory (``roscd`` changes it); None: the process's own.
    cwd: str | None = None
    #: Real-time factor of foreground commands (interactive console: 1.0 by default);
    #: None runs them as fast as possible (scripts, Python).
    rtf: float | None = None
    #: A script's simulated time limit (``ddes console --until S``), kernel nanoseconds:
    #: foreground commands that ROS runs until Ctrl+C stop there; None: no limit.
    until_ns: int | None = None
    #: While an interactive command runs: true once Ctrl+C was pressed (set for the whole
    #: command, so a Ctrl+C pressed before its paced run starts is not lost); None otherwise.
    interrupted: Callable[[], bool] | None = None
    #: The command printed :func:`sim_time_notice` already (it prints once per command; the
    #: console and :func:`run_command_result` clear it before each command).
    time_noted: bool = False

    def __post_init__(self) -> None:
        if self.rospack is None:
            self.rospack = self.world.rospack

    def resolve_path(self, path: str) -> str:
        """``path`` as the tools open it: relative paths start at :attr:`cwd` (``roscd``)."""
        expanded = os.path.expanduser(path)
        if self.cwd is None or os.path.isabs(expanded):
            return expanded
        return os.path.join(self.cwd, expanded)

    def print(self, text: str = "") -> None:
        """Write a line to the tool's standard output."""
        self.out(text)

    def eprint(self, text: str) -> None:
        """Write a line to the tool's standard error."""
        self.err(text)

    def note_waiting(self) -> None:
        """The command is about to let the world run: print :func:`sim_time_notice` if
        simulated time stands still (once per command)."""
        if self.time_noted:
            return
        notice = sim_time_notice(self.world)
        if notice is not None:
            self.time_noted = True
            self.eprint(notice)

    def run_until(self, event: simpy.Event, timeout: float | None = None) -> Any:
        """Run the world until ``event`` is processed; return its value.

        With ``timeout`` (simulated seconds) the world stops at the deadline
        and :class:`ROSConsoleError` is raised if the event has not happened.
        A failed event re-raises its exception.
        """
        world = self.world
        if not event.processed:
            self.note_waiting()
        if timeout is not None:
            limit = world.env.timeout(max(0, duration_to_ns(timeout, "timeout")))
            world.run(world.env.any_of([event, limit]))
        else:
            if not event.triggered or not event.processed:
                try:
                    world.run(event)
                except RuntimeError as exc:  # SimPy: no scheduled events left
                    raise ROSConsoleError(
                        f"the world has nothing left to do and the command is still waiting ({exc})"
                    ) from None
        if not event.triggered:
            raise ROSConsoleError(f"timed out after {timeout} simulated seconds")
        if not event.ok:
            raise event.value  # type: ignore[misc]
        return event.value

    def advance(self, seconds: float) -> None:
        """Let ``seconds`` of simulated time pass."""
        if seconds < 0:
            raise ROSConsoleError(f"cannot advance by a negative time ({seconds})")
        if seconds > 0:
            self.note_waiting()
        self.world.run_for(seconds)

    def background(self, name: str, process: JobProcess) -> Job:
        """Keep ``process`` running in the world; returns its job record."""
        job = Job(len(self.jobs) + 1, name, process, self.world.now)
        self.jobs.append(job)
        return job


def sim_time_notice(world: World) -> str | None:
    """ddes's one-line notice when simulated time stands still, or None.

    It stands still when ``/use_sim_time`` is true and nothing publishes ``/clock`` (a
    ``rosbag play`` without ``--clock`` advertises ``/clock`` but never publishes on it): every
    node on simulated time then reads the last ``/clock`` value (0 before the first) and its
    sleeps, rates and timers wait for ever, silently, as in ROS.
    """
    master = world.master
    if not master.params.get_param("/use_sim_time", False):  # as a node reads it
        return None
    entry = master.topics.get("/clock")
    publishers = list(entry.publishers) if entry is not None else []
    silent: list[object] = []
    if publishers:
        from ddes.rosbag.player import silent_clock_publishers

        silent = [p for p in silent_clock_publishers(world) if any(p is q for q in publishers)]
        if len(silent) < len(publishers):
            return None
    stamps = [n.clock.now_ns() for n in world.nodes.values() if n.use_sim_time]
    at = max(stamps, default=0)
    shown = "0" if at == 0 else f"{at // 1_000_000_000}.{at % 1_000_000_000:09d}, the last /clock"
    hint = ("rosbag play publishes it only with --clock" if silent else
            "start rosbag play --clock, or a node publishing /clock")
    return (f"[ddes] /use_sim_time is true and nothing publishes /clock: simulated time stands "
            f"still at {shown} ({hint})")


@dataclass
class CommandResult:
    """The outcome of one command line."""

    code: int
    out: str
    err: str


def _tools() -> dict[str, Tool]:
    table: dict[str, Tool] = {}
    for name in TOOL_MODULES:
        table.update(importlib.import_module(name).TOOLS)
    return table


def tool_names() -> list[str]:
    """The names of all world-bound tools, sorted."""
    return sorted(_tools())


def find_tool(name: str) -> Tool:
    """The tool called ``name`` (``"rostopic"``); ROSConsoleError if unknown."""
    table = _tools()
    try:
        return table[name]
    except KeyError:
        raise ROSConsoleError(
            f"unknown command '{name}'; known commands: {', '.join(sorted(table))}"
        ) from None


def run_command_result(ctx: ToolContext, line: str) -> CommandResult:
    """Run one command line against ``ctx``; capture what it prints."""
    out: list[str] = []
    err: list[str] = []
    saved = ctx.out, ctx.err
    ctx.out, ctx.err = out.append, err.append
    ctx.time_noted = False
    try:
        argv = shlex.split(line, comments=True)
        if not argv:
            return CommandResult(0, "", "")
        try:
            code = find_tool(argv[0])(ctx, argv[1:])
        except DdesError as exc:
            err.append(f"ERROR: {exc}")
            code = 1
    except ValueError as exc:  # shlex: unbalanced quotes
        err.append(f"ERROR: cannot parse the command line: {exc}")
        code = 1
    finally:
        ctx.out, ctx.err = saved
    return CommandResult(code, "".join(x + "\n" for x in out), "".join(x + "\n" for x in err))


def run_command(world: World, line: str, ctx: ToolContext | None = None) -> str:
    """Run one command on ``world`` and return its output (for notebooks and graders).

    A failing command raises :class:`ROSConsoleError` carrying its error text.
    """
    ctx = ctx or ToolContext(world)
    result = run_command_result(ctx, line)
    if result.code != 0:
        raise ROSConsoleError(result.err.strip() or f"'{line}' exited with {result.code}")
    return result.out
