"""Node types: Python callables that ``rosrun`` and launch files start by package and name.

A package's node types live in ``<package>/nodes.py`` as a dict
``NODES = {"talker": NodeType(main, name="talker"), ...}``.  ``main(node)``
receives the started :class:`~ddes.graph.node.Node`:

* a plain function sets up publishers, subscribers, timers, services and
  returns; the node then spins until it is killed (rospy.spin()).
* a generator function is the node's main loop (``yield rate.sleep()``);
  when it returns, the node shuts down, as a script that reaches its end.
  It may return an int exit code (recorded as ``node.exit`` in the trace).

A package's rospy scripts (``scripts/talker.py`` or ``nodes/talker.py`` of a
catkin package) are node types too (``rosrun PKG talker.py``): they run
unchanged through :mod:`ddes.compat.scripts`, ``import rospy`` resolving to
:mod:`ddes.compat.rospy` for that script only.

``NodeType.name`` is the name the code would pass to ``init_node``; ``rosrun``
``__name:=`` and launch ``name=`` override it.  ``log_style`` selects how
its log lines print (``"rospy"`` or ``"roscpp"``), so a C++ tutorial node prints
``[ INFO] [...]`` as roscpp does.  ``node_options(argv)``, when given, returns
the other ``init_node`` options the program's command line asks for
(``disable_rosout``, ``use_sim_time``, ``log_level``): ``rostopic pub`` calls
``init_node(..., disable_rosout=True, disable_rostime=not --use-rostime)``.

What a node program writes to standard output or error outside its logger
(``rosbag play``'s ``Hit space to toggle paused``) goes through
:func:`print_line`; the directory it was started in (relative file names,
``rosbag record -O x``) is :func:`node_cwd`.
"""

from __future__ import annotations

import hashlib
import importlib.util
import sys
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from types import GeneratorType
from typing import TYPE_CHECKING, Any, Union

from ddes.errors import DdesError
from ddes.graph.rosout import ERROR, INFO

if TYPE_CHECKING:
    import simpy
    from simpy.events import ProcessGenerator

    from ddes.graph.node import Node
    from ddes.graph.world import World
    from ddes.rospack import RosPack

__all__ = ["NODE_OPTION_NAMES", "SCRIPT_FOLDERS", "NodeExitedError", "NodeMain", "NodeOptionsFn",
           "NodeType", "NodeTypeNotFound",
           "find_script", "list_scripts", "load_node_types", "node_cwd", "print_line",
           "start_node"]

#: A node type's ``main(node)``: a plain function (set up, then spin) or a generator function
#: (the main loop; it may return an int exit code).
NodeMain = Callable[["Node"], Union["ProcessGenerator", None]]
#: A node type's ``node_options(argv)``: the ``init_node`` options its command line (without the
#: ROS arguments) asks for, among :data:`NODE_OPTION_NAMES`.
NodeOptionsFn = Callable[[list[str]], Mapping[str, Any]]
#: The node options a :class:`NodeType`'s ``node_options`` may set.
NODE_OPTION_NAMES = frozenset({"disable_rosout", "use_sim_time", "log_level"})


class NodeTypeNotFound(DdesError):
    """No node type of that name in the package (rosrun's "Couldn't find executable")."""


@dataclass(frozen=True)
class NodeType:
    """A runnable node: its main function and the name it registers by default."""

    main: NodeMain
    name: str
    anonymous: bool = False
    log_style: str = "rospy"
    doc: str = ""
    node_options: NodeOptionsFn | None = None


def load_node_types(package_dir: Path) -> dict[str, NodeType]:
    """The ``NODES`` dict of ``package_dir/nodes.py`` (empty if there is none)."""
    path = Path(package_dir) / "nodes.py"
    if not path.is_file():
        return {}
    # a stable module name (not hash(), which varies with PYTHONHASHSEED)
    mod_name = "_ddes_nodes_" + hashlib.sha256(str(path.resolve()).encode()).hexdigest()[:16]
    spec = importlib.util.spec_from_file_location(mod_name, path)
    if spec is None or spec.loader is None:  # pragma: no cover - a .py file always has a loader
        raise DdesError(f"cannot load node types from {path}")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    nodes = getattr(module, "NODES", None)
    if not isinstance(nodes, dict):
        raise DdesError(f"{path} must define NODES = {{'type': NodeType(main, name=...)}}")
    return dict(nodes)


def start_node(
    world: World,
    package: str,
    node_type: str,
    *,
    rospack: RosPack | None = None,
    name: str | None = None,
    namespace: str = "/",
    argv: Sequence[str] = (),
    remappings: dict[str, str] | None = None,
    cwd: str | None = None,
) -> Node:
    """Start ``package/node_type`` in ``world`` (``rosrun package node_type argv...``).

    ``cwd`` is the directory the program runs in (the console's after ``roscd``): relative file
    names the node opens start there (:func:`node_cwd`); None is the process's own.
    """
    rospack = rospack or world.rospack
    types = load_node_types(rospack.get_path(package))
    try:
        nt = types[node_type]
    except KeyError:
        script = find_script(rospack.get_path(package), node_type, package)
        if script is not None:
            from ddes.roscpp.executables import is_native

            if is_native(script):  # a compiled node (catkin_make): a process in lockstep
                return _start_native(world, package, script, name=name, namespace=namespace,
                                     argv=argv, remappings=remappings, cwd=cwd)
            return _start_script(world, package, script, name=name, namespace=namespace,
                                 argv=argv, remappings=remappings, cwd=cwd)
        known = ", ".join(sorted(types) + [p.name for p in list_scripts(
            rospack.get_path(package))]) or "none"
        raise NodeTypeNotFound(
            f"Couldn't find executable named {node_type} below {rospack.get_path(package)} "
            f"(node types of {package}: {known})"
        ) from None
    options: dict[str, Any] = {}
    if nt.node_options is not None:
        from ddes.graph.names import parse_node_args

        options = dict(nt.node_options(parse_node_args(list(argv)).args))
        unknown = sorted(set(options) - NODE_OPTION_NAMES)
        if unknown:
            raise DdesError(f"node_options of {package}/{node_type} set {', '.join(unknown)}; "
                            f"they may set only {', '.join(sorted(NODE_OPTION_NAMES))}")
    node = world.create_node(name or nt.name, namespace=namespace, argv=list(argv),
                             remappings=remappings, anonymous=nt.anonymous and name is None,
                             log_style=nt.log_style, **options)
    if cwd is not None:
        world.extension(_CWD_KEY, _new_cwd_table)[node] = cwd
    result = nt.main(node)
    if type(result) is GeneratorType:
        proc = node.process(result)

        def finished(ev: simpy.Event) -> None:
            if ev.ok:
                code = ev.value if isinstance(ev.value, int) else 0
                world.record("node.exit", node.name, code=code)
                node.shutdown("main loop returned")
                return
            exc = ev.value
            if world.strict or not isinstance(exc, Exception):
                return  # the world's failure policy raises it out of run()
            node.report_crash(exc)
            ev.defused = True  # logged and recorded; the world keeps running

        proc.callbacks.append(finished)
    return node


#: The folders of a catkin package that hold its Python node scripts, searched in this order.
SCRIPT_FOLDERS = ("scripts", "nodes")


class NodeExitedError(DdesError):
    """A script node ended before ``rospy.init_node`` (a usage error, ``sys.exit``): no node."""


def list_scripts(package_dir: Path) -> list[Path]:
    """The Python scripts of a catkin package (``scripts/`` and ``nodes/``), sorted by name."""
    found: list[Path] = []
    for folder in SCRIPT_FOLDERS:
        base = Path(package_dir) / folder
        if base.is_dir():
            found += sorted(p for p in base.iterdir() if p.is_file() and p.suffix in ("", ".py")
                            and not p.name.startswith((".", "_")))
    return found


#: Most directory entries a search of one package looks at (a package is a few hundred files;
#: the bound keeps a link loop or a huge tree from stalling rosrun).
MAX_SEARCH_ENTRIES = 20_000


class AmbiguousNodeType(DdesError):
    """Several executables of that name below the package (roslaunch's "multiple files
    named")."""


def find_executables(package_dir: Path, name: str) -> list[Path]:
    """Every executable file named ``name`` below ``package_dir``, as rosrun and roslaunch
    find a node (``roslib.packages.find_node``: the whole package tree, links followed, hidden
    folders skipped, readable and executable by its owner), in sorted order."""
    import os
    import stat

    found: list[Path] = []
    seen = 0
    visited: set[tuple[int, int]] = set()
    stack = [str(package_dir)]
    while stack:
        here = stack.pop()
        try:
            st = os.stat(here)
        except OSError:
            continue
        if (st.st_dev, st.st_ino) in visited:  # a link loop
            continue
        visited.add((st.st_dev, st.st_ino))
        try:
            entries = sorted(os.scandir(here), key=lambda e: e.name)
        except OSError:
            continue
        subdirs = []
        for e in entries:
            seen += 1
            if seen > MAX_SEARCH_ENTRIES:
                raise DdesError(f"{package_dir} holds more than {MAX_SEARCH_ENTRIES} entries: "
                                f"too many to search for {name}; give the script's path")
            try:
                if e.is_dir():
                    if not e.name.startswith("."):
                        subdirs.append(e.path)
                    continue
                if e.name == name:
                    mode = e.stat().st_mode
                    if stat.S_ISREG(mode) and mode & (stat.S_IRUSR | stat.S_IXUSR) == (
                            stat.S_IRUSR | stat.S_IXUSR):
                        found.append(Path(e.path))
            except OSError:
                continue
        stack.extend(reversed(subdirs))
    return sorted(found)


def find_script(package_dir: Path, node_type: str, package: str = "") -> Path | None:
    """The script ``node_type`` of a package, as rosrun finds it: ``scripts/<node_type>`` or
    ``nodes/<node_type>`` (executable or not: a zip drops the bit), else the one executable file
    of that name anywhere below the package (rospy_tutorials keeps its scripts in
    ``001_talker_listener/`` …, actionlib its test nodes in ``test/``).  Several raise
    :class:`AmbiguousNodeType` with roslaunch's text."""
    for folder in SCRIPT_FOLDERS:
        path = Path(package_dir) / folder / node_type
        if path.is_file():
            return path
    if "/" in node_type or node_type in ("", ".", ".."):
        return None
    from ddes.roscpp.executables import libexec_folders

    # catkin's devel space first (catkin_find --libexec), then the package's own folder
    matches = [m for folder in libexec_folders(package or _name_of(Path(package_dir)),
                                               Path(package_dir))
               for m in find_executables(folder, node_type)]
    matches += find_executables(Path(package_dir), node_type)
    if len(matches) > 1:
        listed = "".join(f"\n- {m}" for m in matches)
        raise AmbiguousNodeType(f"multiple files named [{node_type}] in package "
                                f"[{package or Path(package_dir).name}]:{listed}\n"
                                "Please specify full path instead")
    return matches[0] if matches else None


def _start_script(world: World, package: str, script: Path, *, name: str | None,
                  namespace: str, argv: Sequence[str], remappings: dict[str, str] | None,
                  cwd: str | None) -> Node:
    """Run a rospy script as a node (:mod:`ddes.compat.scripts`); its node once it has one."""
    from ddes.compat.scripts import ScriptContext, run_script
    from ddes.graph.blocking import current_node

    args = list(argv)
    if name is not None and not any(a.startswith("__name:=") for a in args):
        args.append(f"__name:={name}")  # roslaunch passes a launch name= this way

    started: list[ScriptContext] = []

    def out(text: str, stderr: bool) -> None:
        node = current_node()  # the script's code prints on its own greenlet
        if node is None and started:  # or in a hook the kernel runs (on_shutdown): its node
            node = started[0].node
        if node is None:
            stream = sys.stderr if stderr else sys.stdout
            stream.write(text + "\n")
            return
        print_line(node, text, stderr=stderr)

    done, context = run_script(world, script, args, namespace=namespace, remappings=remappings,
                               print_line=out)
    started.append(context)
    node = context.node
    if node is None:
        code = done.value if done.triggered and done.ok else 1
        raise NodeExitedError(f"{package}/{script.name} exited with code {code} before "
                              "rospy.init_node: there is no node (check its arguments)")
    if cwd is not None:
        world.extension(_CWD_KEY, _new_cwd_table)[node] = cwd
    return node


def _name_of(package_dir: Path) -> str:
    from ddes.rospack import _package_name

    return _package_name(package_dir)


def _start_native(world: World, package: str, program: Path, *, name: str | None,
                  namespace: str, argv: Sequence[str], remappings: dict[str, str] | None,
                  cwd: str | None) -> Node:
    """Run a compiled node (a C++ program built against ddes's roscpp) as an external node
    (:mod:`ddes.roscpp.host`); its node once it called ``ros::init``."""
    from ddes.roscpp.executables import start_executable

    started: list[Node] = []

    def out(text: str, stderr: bool) -> None:
        if started:
            print_line(started[0], text, stderr=stderr)
        else:
            (sys.stderr if stderr else sys.stdout).write(text + "\n")

    host, node = start_executable(world, program, argv, name=name, namespace=namespace,
                                  remappings=remappings, cwd=cwd, print_line=out)
    if node is None:
        code = host.exit_code if host.exit_code is not None else 1
        raise NodeExitedError(f"{package}/{program.name} exited with code {code} before "
                              "ros::init: there is no node (check its arguments)")
    started.append(node)
    if cwd is not None:
        world.extension(_CWD_KEY, _new_cwd_table)[node] = cwd
    return node


_CWD_KEY = "nodes.cwd"


def _new_cwd_table(_world: object) -> dict[Node, str]:
    return {}


def node_cwd(node: Node) -> str | None:
    """The directory ``node``'s program was started in (``start_node(cwd=...)``), or None (the
    process's working directory)."""
    table = node.world.extensions.get(_CWD_KEY)
    return table.get(node) if isinstance(table, dict) else None


def print_line(node: Node, text: str, *, stderr: bool = False) -> None:
    """A line the program of ``node`` prints on standard output (or error), not through its logger.

    It reaches the world's console (``world.log_output``) as the node's own output: a launch
    node without ``output="screen"`` shows only its standard error, as roslaunch sends standard
    output to the log file; ``rosrun --quiet`` likewise.  Standard output counts as INFO and
    standard error as ERROR for that choice.  With no console (``log_output`` None or True) the
    line goes to the process's own standard output (or error), as the program's print would;
    ``log_output = False`` prints nothing.
    """
    sink = node.world.log_output
    if sink is False:
        return
    if sink is None or sink is True:
        stream = sys.stderr if stderr else sys.stdout
        stream.write(text + "\n")
        stream.flush()
        return
    level = ERROR if stderr else INFO
    # A LogRouter (ddes.launch.runtime, a layer above) routes by node: ask it for this node's
    # level directly instead of letting it guess the node from the latest trace event.
    levels = getattr(sink, "levels", None)
    printer = getattr(sink, "out", None)
    if isinstance(levels, dict) and node.name in levels and callable(printer):
        if level >= levels[node.name]:
            printer(text)
        return
    sink(text, level)
