"""Running a :class:`~ddes.launch.plan.LaunchPlan` on a world: roslaunch's runner, on simulated time.

:class:`LaunchRunner` does what ``roslaunch.launch.ROSLaunchRunner`` does,
in the same order: the ``<rosparam>`` delete/dump commands, ``clear_params``,
every parameter, then the nodes (``ddes.nodes.start_node`` with name,
namespace, args, remappings).  It prints what roslaunch prints (the
SUMMARY, ``process[talker-1]: started with pid [N]``, ``[talker-1]
process has finished cleanly``, ``[talker-1] restarting process``, the
REQUIRED banner, ``[x] killing on exit`` ...), watches the processes and:

* ``respawn="true"``: restarts a node ``respawn_delay`` simulated seconds
  after it exits (its main loop returned or raised, it was killed, it died at
  start); a shutdown while it waits prints ``[x-3] killing on exit`` for it,
  as roslaunch's process monitor still holds it;
* ``required="true"``: shuts the whole launch down when the node exits;
* ``output="screen"``: the node's log lines print; otherwise only its
  warnings and errors do (roslaunch sends stdout to a log file and keeps
  stderr on the screen; rospy and roscpp log WARN and above to stderr).

:func:`start_core` is ``roscore``: the parameters roscore sets and a
``/rosout`` node that aggregates ``/rosout`` onto ``/rosout_agg``.
:class:`LogRouter` is the world's ``log_output`` that decides, per node,
which log lines reach the screen.

Deviations: no log files (so no ``log file:`` lines), synthetic pids, and
the ``process[master]`` / ``rosout`` lines only when the runner starts the
core itself (``ddes roslaunch`` from the shell).
"""

from __future__ import annotations

import contextlib
import hashlib
import uuid
from collections.abc import Callable, Iterator
from dataclasses import replace
from typing import TYPE_CHECKING

import simpy
import yaml

from ddes.errors import DdesError, ROSLaunchException
from ddes.graph.rosout import DEBUG, WARN

if TYPE_CHECKING:
    from ddes.graph.node import Node
    from ddes.graph.world import World
    from ddes.launch.plan import LaunchPlan, NodeSpec
    from ddes.rospack import RosPack
    from ddes.time.units import DurationLike

__all__ = ["CORE_PARAMS", "LaunchRunner", "LogRouter", "Process", "core_running", "node_pid",
           "node_uri", "run_id", "start_core"]

#: The parameters roscore/roslaunch set (``rosversion -d`` and ``rosversion ros``).
CORE_PARAMS: dict[str, str] = {"/rosdistro": "noetic\n", "/rosversion": "1.16.0\n"}

Print = Callable[[str], None]


def _digest(name: str) -> int:
    return int.from_bytes(hashlib.sha256(name.encode("utf-8")).digest()[:8], "big")


def node_uri(name: str) -> str:
    """The XML-RPC URI ROS tools show for node ``name``.

    ddes nodes live in one process and have no URI or pid, so both are
    synthetic: derived from the node's name alone, stable across runs and
    machines (``http://localhost:PORT/``).
    """
    return f"http://localhost:{32768 + _digest(name) % 28000}/"


def node_pid(name: str) -> int:
    """The process id shown for node ``name`` (synthetic and stable, see :func:`node_uri`)."""
    return 1000 + (_digest(name) >> 20) % 30000


def core_running(world: World) -> bool:
    """True when the world has a ``/rosout`` node (a roscore)."""
    return "/rosout" in world.nodes


def start_core(world: World) -> Node:
    """Start roscore's part of the graph (idempotent); returns the ``/rosout`` node.

    Sets ``/rosdistro``, ``/rosversion`` and ``/run_id`` (a UUID drawn from
    the world's seed), and starts ``/rosout``: it subscribes to ``/rosout``
    and republishes every log message on ``/rosout_agg``, as the C++
    ``rosout`` node does.
    """
    existing = world.nodes.get("/rosout")
    if existing is not None:
        return existing
    from ddes.msg import get_message_class

    params = world.master.params
    for key, value in CORE_PARAMS.items():
        params.set_param(key, value)
    params.set_param("/run_id", run_id(world))
    log_cls = get_message_class("rosgraph_msgs/Log")
    node = world.create_node("rosout", disable_rosout=True, log_style="roscpp")
    agg = node.advertise("/rosout_agg", log_cls, queue_size=0)
    node.subscribe("/rosout", log_cls, agg.publish, queue_size=100)
    return node


def run_id(world: World) -> str:
    """The ``/run_id`` of the world: a UUID from the world's seed (stable across runs)."""
    rng = world.rng_for("run_id")
    return str(uuid.UUID(int=rng.getrandbits(128), version=1))


class LogRouter:
    """``world.log_output`` that prints a log line if its node's level allows it.

    ``levels`` maps node names to the lowest level printed; other nodes use
    ``default_level``.  The node a line comes from is the source of the
    world's latest trace event (the node's ``log``/``/rosout`` publish
    event, recorded just before the line is printed); with the trace
    disabled every line uses ``default_level``.
    """

    def __init__(self, world: World, out: Print, default_level: int = DEBUG) -> None:
        self.world = world
        self.out = out
        self.default_level = default_level
        self.levels: dict[str, int] = {}
        self._pending: int | None = None

    def install(self) -> LogRouter:
        """Make this router the world's log output."""
        self.world.log_output = self
        return self

    def __call__(self, line: str, level: int) -> None:
        trace = self.world.trace
        level_min = self.default_level
        if trace.enabled and len(trace):
            source = trace[-1].source
            found = self.levels.get(source)
            if found is not None:
                level_min = found
            elif self._pending is not None:
                level_min = self._pending
        elif self._pending is not None:
            level_min = self._pending
        if level >= level_min:
            self.out(line)

    @contextlib.contextmanager
    def starting(self, level: int) -> Iterator[None]:
        """While a node is being started (its name not yet known), print at ``level``."""
        saved = self._pending
        self._pending = level
        try:
            yield
        finally:
            self._pending = saved


class Process:
    """One ``<node>`` of a running launch: roslaunch's process ``name-N``."""

    def __init__(self, spec: NodeSpec, label: str) -> None:
        self.spec = spec
        self.label = label
        self.node: Node | None = None
        self.alive = False
        self.starts = 0
        #: Dead and waiting ``respawn_delay`` to restart: still roslaunch's process (its
        #: process monitor keeps it registered), so a shutdown "kills" it too.
        self.respawning = False


class LaunchRunner:
    """Run a launch plan on a world (see the module docstring).

    ``out`` receives roslaunch's own lines; node log lines go through
    ``router`` (installed as the world's log output if not already).
    ``finished`` fires when the launch has shut down.
    """

    def __init__(self, world: World, plan: LaunchPlan, *, rospack: RosPack | None = None,
                 out: Print = print, router: LogRouter | None = None) -> None:
        self.world = world
        self.plan = plan
        self.rospack = rospack or world.rospack
        self.out = out
        if router is None:
            current = world.log_output
            router = current if isinstance(current, LogRouter) else LogRouter(world, out).install()
        self.router = router
        self.processes: list[Process] = []
        self.finished: simpy.Event = world.env.event()
        self._count = 0
        self._shutting_down = False

    @property
    def done(self) -> bool:
        """True once the launch has shut down."""
        return bool(self.finished.triggered)

    # -- start ---------------------------------------------------------------------------------
    def _next_label(self, name: str) -> str:
        """roslaunch's process name: ``ns_join(namespace, name)`` less its leading slash, and a
        counter (``foo/param_talker-2``)."""
        self._count += 1
        return f"{name}-{self._count}"

    def summary(self) -> str:
        """roslaunch's SUMMARY block (with the parameters roslaunch adds itself)."""
        shown = replace(self.plan, params={**self.plan.params, **CORE_PARAMS})
        return "\n" + shown.to_text()

    def validate(self) -> None:
        """Check that every node's package and node type exist, before anything starts.

        roslaunch prints "cannot launch node of type" and starts the rest;
        ddes refuses the launch instead (naming the ``<node>``'s file and
        line), so a typo never leaves a half-started launch behind.
        """
        from ddes.nodes import find_script, load_node_types

        for spec in self.plan.nodes:
            where = f"{spec.source}: " if spec.source else ""
            try:
                folder = self.rospack.get_path(spec.pkg)
                types = load_node_types(folder)
            except DdesError as exc:
                raise ROSLaunchException(
                    f"{where}cannot launch node of type [{spec.pkg}/{spec.type}]: {exc}") from None
            try:
                script = None if spec.type in types else find_script(folder, spec.type, spec.pkg)
            except DdesError as exc:  # several executables of that name (roslaunch's text)
                raise ROSLaunchException(f"{where}{exc}") from None
            if spec.type not in types and script is None:
                known = ", ".join(sorted(types)) or "none"
                raise ROSLaunchException(
                    f"{where}cannot launch node of type [{spec.pkg}/{spec.type}]: Couldn't find "
                    f"executable named {spec.type} below {folder} (node types of {spec.pkg}: "
                    f"{known})")

    def start(self, *, print_summary: bool = True) -> None:
        """Set up the parameter server and start every node (roslaunch's ``launch()``)."""
        self.validate()
        for warning in self.plan.warnings:
            self.out(f"WARNING: {warning}")
        if print_summary:
            self.out(self.summary())
        world = self.world
        launched = not core_running(world)
        if launched:
            self.out("auto-starting new master")
            self.out(f"process[master]: started with pid [{node_pid('master')}]")
        self.out("ROS_MASTER_URI=http://localhost:11311")
        self.out("")  # roslaunch sets the terminal title here: an escape code and a newline
        if launched:
            start_core(world)
            self.out(f"setting /run_id to {world.master.params.get_param('/run_id')}")
            label = self._next_label("rosout")
            self.out(f"process[{label}]: started with pid [{node_pid('/rosout')}]")
            self.out("started core service [/rosout]")
        self._setup_params()
        if not self.plan.nodes:
            self.out("No processes to monitor")
            self._stop_monitor()
            self.finished.succeed(0)
            return
        self.launch_nodes()

    def launch_nodes(self) -> None:
        """Start every node of the plan, in order (rostest's ``launch()`` calls this after
        :meth:`setup_params`, with no core and a test process of its own)."""
        for spec in self.plan.nodes:
            proc = Process(spec, self._next_label(spec.full_name[1:]))
            self.processes.append(proc)
            self._launch(proc)

    def add_process(self, spec: NodeSpec) -> Process:
        """Register a process started by someone else (rostest's test node): it gets the next
        ``name-N`` label and counts as alive until :meth:`process_exited`."""
        proc = Process(spec, self._next_label(spec.full_name[1:]))
        proc.alive = True
        self.processes.append(proc)
        return proc

    def process_exited(self, proc: Process, code: int) -> None:
        """A process of :meth:`add_process` ended with exit ``code`` (roslaunch's monitor)."""
        self._exited(proc, code)

    def setup_params(self) -> None:
        """roslaunch's ``_setup``: rosparam commands, ``clear_params``, then every parameter."""
        self._setup_params()

    def _setup_params(self) -> None:
        params = self.world.master.params
        for cmd in self.plan.rosparam_commands:
            if cmd.command == "delete":
                if params.has_param(cmd.param):
                    params.delete_param(cmd.param)
                else:
                    self.out(f"ERROR: parameter [{cmd.param}] is not set")
            elif cmd.command == "dump" and cmd.file:
                value = params.get_param(cmd.param) if params.has_param(cmd.param) else {}
                with open(cmd.file, "w", encoding="utf-8") as f:
                    yaml.dump(value, f)
        for ns in self.plan.clear_params:
            if params.has_param(ns):
                params.delete_param(ns)
        for key, value in self.plan.params.items():
            params.set_param(key, value)

    def _launch(self, proc: Process) -> None:
        """Start (or restart) the node of ``proc``."""
        from ddes.nodes import start_node

        spec = proc.spec
        argv = list(spec.args) + [f"{src}:={dst}" for src, dst in spec.remappings]
        level = DEBUG if spec.output == "screen" else WARN
        self.router.levels[spec.full_name] = level
        self.out(f"process[{proc.label}]: started with pid [{node_pid(spec.full_name)}]")
        try:
            with self.router.starting(level):
                node = start_node(self.world, spec.pkg, spec.type, rospack=self.rospack,
                                  name=spec.name, namespace=spec.namespace, argv=argv)
        except Exception as exc:  # noqa: BLE001 - the node's own start-up code failed
            # the script died at start-up: Python prints the error, roslaunch the exit
            left = self.world.nodes.get(spec.full_name)
            if left is not None:
                left.shutdown("process died")
            self.out(f"{type(exc).__name__}: {exc}")
            proc.alive = True
            self._exited(proc, 1)
            return
        self.router.levels[node.name] = level
        proc.node = node
        proc.alive = True
        proc.starts += 1

        def died(reason: str, p: Process = proc, n: Node = node) -> None:
            if p.node is n:
                self._exited(p, self._exit_code(n))

        node.on_shutdown(died)

    # -- the process monitor ----------------------------------------------------------------------
    def _exit_code(self, node: Node) -> int:
        now = self.world.now
        for ev in reversed(self.world.trace.filter(kind="node.exit", source=node.name)):
            if ev.t == now:
                return int(ev.details.get("code", 0) or 0)
            break
        return 0

    def _exited(self, proc: Process, code: int) -> None:
        """A process ended (its node shut down, or its start-up failed with ``code``)."""
        if not proc.alive:
            return
        proc.alive = False
        if self._shutting_down:
            return
        spec = proc.spec
        if code:
            cmd = " ".join([f"{spec.pkg}/{spec.type}", *spec.args, f"__name:={spec.name}"])
            desc = (f"process has died [pid {node_pid(spec.full_name)}, exit code {code}, "
                    f"cmd {cmd}].")
        else:
            desc = "process has finished cleanly"
        if spec.required:
            self.out("=" * 80 + f"REQUIRED process [{proc.label}] has died!\n{desc}\n"
                     "Initiating shutdown!\n" + "=" * 80)
            self._schedule(0, self.shutdown)
            return
        self.out(f"[{proc.label}] {desc}")
        if spec.respawn:
            delay = max(0.0, float(spec.respawn_delay))
            proc.respawning = True
            self._schedule(delay, lambda: self._respawn(proc))
            return
        if not any(p.alive for p in self.processes) and not any(
                p.spec.respawn for p in self.processes):
            self.out("all processes on machine have died, roslaunch will exit")
            self._schedule(0, self.shutdown)

    def _schedule(self, delay: DurationLike, fn: Callable[[], None]) -> None:
        ev = self.world.timeout(delay)
        ev.callbacks.append(lambda _ev: fn())

    def _respawn(self, proc: Process) -> None:
        if self._shutting_down or self.done or proc.alive:
            return
        proc.respawning = False
        self.out(f"[{proc.label}] restarting process")
        self._launch(proc)

    # -- shutdown ---------------------------------------------------------------------------------
    def _stop_monitor(self) -> None:
        self.out("shutting down processing monitor...")
        self.out("... shutting down processing monitor complete")

    def shutdown(self) -> None:
        """Stop the launch (Ctrl+C in roslaunch): kill the live nodes, newest first."""
        if self._shutting_down or self.done:
            return
        self._shutting_down = True
        self._kill_live()
        self._stop_monitor()
        self.out("done")
        self.finished.succeed(0)

    def _kill_live(self) -> None:
        for proc in reversed(self.processes):
            if proc.respawning:  # roslaunch's monitor still holds it: "killed" too, no restart
                self.out(f"[{proc.label}] killing on exit")
                proc.respawning = False
            elif proc.alive:
                self.out(f"[{proc.label}] killing on exit")
                proc.alive = False
                if proc.node is not None:
                    proc.node.shutdown("roslaunch shutdown")

    stop = shutdown

    def teardown(self) -> None:
        """rostest's tear-down (``runner.stop()``): the process monitor shuts down and kills the
        live nodes, newest first, in that order of lines; no ``done``."""
        if self._shutting_down or self.done:
            return
        self._shutting_down = True
        self.out("shutting down processing monitor...")
        self._kill_live()
        self.out("... shutting down processing monitor complete")
        self.finished.succeed(0)

    def nodes(self) -> list[Node]:
        """The live nodes of this launch, in start order."""
        return [p.node for p in self.processes if p.alive and p.node is not None]
