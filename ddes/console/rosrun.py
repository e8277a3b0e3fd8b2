"""Session tools: ``rosrun``, ``roslaunch``, ``sleep``, ``time``, ``jobs`` and ``kill``.

* ``rosrun [--quiet] PKG NODE [args...]`` starts a node type of a package
  (``<pkg>/nodes.py``, see :mod:`ddes.nodes`) with a rosrun command line
  (``chatter:=/talk``, ``_rate:=5``, ``__name:=t2``, ``__ns:=/r1``).  As in
  ROS it runs in the foreground until the node exits (``rosrun
  roscpp_tutorials add_two_ints_client 20 22`` prints its sum and returns);
  a node that never exits runs until Ctrl+C (interactive) or the script's
  ``--until``, and with a trailing ``&`` it runs in the background
  (``jobs`` lists it, ``kill %N`` or ``rosnode kill`` stops it).  Its log
  lines print as it logs (``--quiet``: only warnings and errors, as for a
  launch node without ``output="screen"``).
* ``roslaunch [--duration S] PKG FILE.launch [arg:=value ...]`` or
  ``roslaunch PATH [arg:=value ...]`` runs a launch file
  (:class:`ddes.launch.runtime.LaunchRunner`) in the foreground until every
  node has exited (or Ctrl+C / ``--until``), for S simulated seconds with
  ``--duration`` (then it shuts down as on Ctrl+C), or in the background
  with ``&``.
* ``sleep SECONDS`` lets the world run (everything due up to and including
  that instant happens); ``time`` prints the simulated time.
* ``jobs`` lists what runs in the background (bash's format); ``kill %N``
  stops job N.

Time stands still between commands: starting a node runs only what is due
at the current instant (its start-up, first publish, first log line).
"""

from __future__ import annotations

import io
import sys
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from typing import TYPE_CHECKING, TextIO

from ddes.console.toolkit import (
    HelpPrinted,
    Task,
    ToolParser,
    command_label,
    job_alive,
    job_stop,
    parse_duration,
    run_task,
    settle,
    take_background,
)
from ddes.errors import DdesError, ROSConsoleError
from ddes.graph.names import parse_node_args
from ddes.graph.rosout import DEBUG, WARN
from ddes.launch.runtime import LaunchRunner, LogRouter

if TYPE_CHECKING:
    from ddes.console.tooling import Job, ToolContext
    from ddes.graph.world import World

__all__ = ["TOOLS", "format_job", "jobs", "kill", "log_router", "roslaunch", "rosrun", "sleep",
           "time"]


def log_router(ctx: ToolContext) -> LogRouter:
    """The world's :class:`LogRouter` printing through ``ctx`` (installed on first use)."""
    world = ctx.world
    current = world.log_output
    if isinstance(current, LogRouter):
        return current
    return LogRouter(world, lambda line: ctx.print(line)).install()


def rosrun(ctx: ToolContext, argv: list[str]) -> int:
    """``rosrun [--quiet] PKG NODE [args...]``: start a node in the world (see module docstring)."""
    from ddes.nodes import NodeExitedError, start_node

    args, background = take_background(argv)
    label = command_label("rosrun", args)
    quiet = False
    while args and args[0] in ("-q", "--quiet", "-h", "--help"):
        if args[0] in ("-h", "--help"):
            ctx.print("Usage: rosrun [--quiet] PACKAGE EXECUTABLE [ARGS]\n"
                      "  rosrun will locate PACKAGE and try to find\n"
                      "  an executable named EXECUTABLE in the PACKAGE tree.\n"
                      "  If it finds it, it will run it with ARGS.\n"
                      "  ddes: --quiet prints only the node's warnings and errors.")
            return 0
        quiet = True
        args.pop(0)
    if len(args) < 2:
        raise ROSConsoleError("rosrun needs a package and a node type: "
                              "rosrun [--quiet] PACKAGE EXECUTABLE [ARGS]")
    pkg, node_type, rest = args[0], args[1], args[2:]
    world = ctx.world
    router = log_router(ctx)
    level = WARN if quiet else DEBUG
    # rospy turns anonymous off when __name:= is given (init_node); start_node does so with name=
    name = parse_node_args(rest).name or None
    before = set(world.nodes)
    try:
        with router.starting(level), _script_streams(ctx):
            try:
                node = start_node(world, pkg, node_type, rospack=ctx.rospack, argv=rest,
                                  name=name, cwd=ctx.cwd)
            except NodeExitedError:
                settle(world)  # the script's end is handled now: its traceback prints here
                raise
    except DdesError:
        raise
    except Exception as exc:  # noqa: BLE001 - the node's own start-up code failed
        for left in [n for n in world.nodes.values() if n.name not in before]:
            left.shutdown("process died")
        raise ROSConsoleError(f"{pkg}/{node_type} died at start-up: {type(exc).__name__}: "
                              f"{exc}") from None
    router.levels[node.name] = level
    task = Task(world, label)
    task.own(node)
    if node.is_shutdown():  # it ended while starting (a usage message, then exit 1)
        task.finish(_exit_code(world, node.name))
    else:
        node.on_shutdown(lambda _reason: task.finish(_exit_code(world, node.name)))
    if background:  # "[1] rosrun ..." first, as a shell prints "[1] PID" before the output
        code = run_task(ctx, task, background=True, duration=None)
        settle(world)
        return code
    settle(world)
    return run_task(ctx, task, background=False, duration=None,
                    waiting_for=f"{node.name} to exit",
                    hint=f"{node.name} runs until Ctrl+C in ROS; end the line with & to keep it "
                         "running in the background (rosrun ... &)")


class _Lines(io.TextIOBase):
    """A stream writing whole lines to ``emit`` with the real streams back in place (``emit``
    may be the real ``print``)."""

    def __init__(self, emit: Callable[[str], None], real: tuple[TextIO, TextIO]) -> None:
        super().__init__()
        self._emit = emit
        self._real = real
        self._pending = ""

    def write(self, text: str) -> int:
        self._pending += text
        *lines, self._pending = self._pending.split("\n")
        for line in lines:
            self._send(line)
        return len(text)

    def _send(self, line: str) -> None:
        swapped = sys.stdout, sys.stderr
        sys.stdout, sys.stderr = self._real
        try:
            self._emit(line)
        finally:
            sys.stdout, sys.stderr = swapped

    def close_lines(self) -> None:
        if self._pending:
            self._send(self._pending)
            self._pending = ""


@contextmanager
def _script_streams(ctx: ToolContext) -> Iterator[None]:
    """While a node starts, what its script writes to the process's streams (its prints and its
    traceback before ``rospy.init_node``: it has no node to print through yet) is the command's
    output and errors, as rosrun shows a script's own output."""
    real = sys.stdout, sys.stderr
    out, err = _Lines(ctx.print, real), _Lines(ctx.eprint, real)
    sys.stdout, sys.stderr = out, err  # type: ignore[assignment]
    try:
        yield
    finally:
        sys.stdout, sys.stderr = real
        out.close_lines()
        err.close_lines()


def _exit_code(world: World, name: str) -> int:
    """The exit code a node that ends now leaves (its main's return value, 1 if it died), as
    rosrun returns its process's."""
    now = world.now
    for ev in reversed(world.trace.filter(kind="node.exit", source=name)):
        if ev.t == now:
            return int(ev.details.get("code", 0) or 0)
        break
    return 0


def roslaunch(ctx: ToolContext, argv: list[str]) -> int:
    """``roslaunch [--duration S] PKG FILE.launch | PATH [arg:=value ...]`` (see module docstring)."""
    from ddes.launch import load_launch, resolve_launch_args

    args, background = take_background(argv)
    parser = ToolParser(ctx, "usage: %prog [options] [package] <filename> [arg_name:=value...]",
                        "roslaunch")
    parser.add_option("--duration", dest="duration", default=None, metavar="SECONDS",
                      help="ddes: run SECONDS of simulated time, then shut down as on Ctrl+C")
    parser.add_option("--nodes", dest="node_list", default=False, action="store_true",
                      help="Print list of node names in launch file")
    parser.add_option("--args", dest="node_args", default=None, metavar="NODE_NAME",
                      help="Print command-line arguments for node")
    parser.add_option("--files", dest="file_list", default=False, action="store_true",
                      help="Print files this launch file includes")
    try:
        options, rest = parser.parse_args(args)
    except HelpPrinted:
        return 0
    duration = parse_duration(options.duration)
    world = ctx.world
    path, launch_args = resolve_launch_args([*(ctx.resolve_path(w) if ":=" not in w and ("/" in w or w.endswith((".launch", ".xml"))) else w for w in rest[:1]), *rest[1:]], ctx.rospack)  # a relative launch file path starts at the console's directory (roscd, cd)
    plan = load_launch(path, launch_args, ctx.rospack, anon_seed=world.rng_for("roslaunch"))
    if options.node_list:
        ctx.print("\n".join(n.full_name for n in plan.nodes))
        return 0
    if options.file_list:
        ctx.print("\n".join(plan.files))
        return 0
    if options.node_args:
        spec = plan.node(options.node_args)
        ctx.print(" ".join([f"{spec.pkg}/{spec.type}", *spec.args,
                            *(f"{a}:={b}" for a, b in spec.remappings),
                            f"__name:={spec.name}"]))
        return 0
    runner = LaunchRunner(world, plan, rospack=ctx.rospack, out=lambda line: ctx.print(line),
                          router=log_router(ctx))
    task = Task(world, command_label("roslaunch", args))
    task.on_stop(runner.shutdown)
    runner.finished.callbacks.append(lambda _ev: task.finish(0))
    if background:  # "[1] roslaunch ..." first, as a shell prints "[1] PID" before the output
        code = run_task(ctx, task, background=True, duration=duration)
        runner.start()
        settle(world)
        return code
    runner.start()
    settle(world)
    return run_task(ctx, task, background=False, duration=duration,
                    waiting_for="every node of the launch to exit",
                    hint="a launch runs until Ctrl+C in ROS; give --duration SECONDS, or end "
                         "the line with & to keep it running in the background")


def sleep(ctx: ToolContext, argv: list[str]) -> int:
    """``sleep SECONDS``: let the world run that long (inclusive of the last instant)."""
    if len(argv) != 1:
        raise ROSConsoleError("sleep needs one argument: the simulated seconds to let pass")
    try:
        seconds = float(argv[0].rstrip("s"))
    except ValueError:
        raise ROSConsoleError(f"sleep: invalid time interval '{argv[0]}' (give seconds, "
                              "e.g. sleep 1.5)") from None
    if not seconds >= 0:
        raise ROSConsoleError(f"sleep: invalid time interval '{argv[0]}' (must be >= 0)")
    ctx.advance(seconds)
    settle(ctx.world)
    return 0


def time(ctx: ToolContext, argv: list[str]) -> int:
    """``time``: print the simulated time (seconds, to the nanosecond)."""
    if argv:
        raise ROSConsoleError("time takes no arguments; it prints the simulated time")
    ctx.print(f"simulated time: {format_time(ctx.world)} s")
    return 0


def format_time(world: World) -> str:
    """The world's time as ``secs.nanoseconds`` (``12.300000000``)."""
    t = world.time()
    return f"{t.secs}.{t.nsecs:09d}"


def format_job(job: Job, state: str) -> str:
    """A ``jobs`` line in bash's layout: ``[1]  Running                 rostopic echo /t &``."""
    return f"[{job.id}]  {state:<24}{job.name}"


def jobs(ctx: ToolContext, argv: list[str]) -> int:
    """``jobs``: list running background jobs, and those finished since the last listing."""
    if argv:
        raise ROSConsoleError("jobs takes no arguments")
    for job in ctx.jobs:
        if job_alive(job):
            ctx.print(format_job(job, "Running") + " &")
        elif not _reported(job):
            ctx.print(format_job(job, "Done"))
            _mark_reported(job)
    return 0


def _reported(job: Job) -> bool:
    proc = job.process
    return bool(proc.reported if isinstance(proc, Task) else getattr(job, "_ddes_reported", False))


def _mark_reported(job: Job) -> None:
    """Remember that ``jobs`` (or ``kill``) told the user this job ended (bash forgets it then)."""
    if isinstance(job.process, Task):
        job.process.reported = True
    else:
        setattr(job, "_ddes_reported", True)  # noqa: B010 - Job has no field for it


def kill(ctx: ToolContext, argv: list[str]) -> int:
    """``kill %N [%M ...]``: stop background jobs (see ``jobs``)."""
    if not argv:
        raise ROSConsoleError("kill: usage: kill %N (the job numbers 'jobs' lists)")
    for arg in argv:
        if not arg.startswith("%") or not arg[1:].isdigit():
            raise ROSConsoleError(f"kill: {arg}: give a job as %N (see 'jobs'); nodes are "
                                  "stopped with 'rosnode kill /name'")
        number = int(arg[1:])
        job = next((j for j in ctx.jobs if j.id == number), None)
        if job is None or not job_alive(job):
            raise ROSConsoleError(f"kill: {arg}: no such job")
        job_stop(job)
        _mark_reported(job)
        ctx.print(format_job(job, "Terminated"))
    return 0


TOOLS = {"jobs": jobs, "kill": kill, "roslaunch": roslaunch, "rosrun": rosrun, "sleep": sleep,
         "time": time}
