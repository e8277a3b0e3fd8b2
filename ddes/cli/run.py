"""``ddes run`` and ``ddes roslaunch``: run a scenario or a launch file from the shell prompt.

* ``ddes run SCENARIO [--until T] [--seed N] [arg:=value ...]``: SCENARIO
  is a launch file (``*.launch``/``*.xml``) or a Python file defining
  ``def scenario(world): ...`` (it creates nodes, links, processes; the
  world is then run), or rospy scripts (files importing rospy) run as nodes of one world
  (``ddes run talker.py listener.py --until 5``; the words after a script are
  its arguments), or compiled roscpp nodes built with ``ddes catkin_make`` (``ddes run
  devel/lib/roscpp_tutorials/talker devel/lib/roscpp_tutorials/listener --until 1``), in
  lockstep with the world, mixed with scripts.  Log lines print as ROS prints them, with
  simulated timestamps; at the end the simulated time, the number of trace events
  and the trace digest (same scenario + same seed = same digest).
* ``ddes roslaunch PKG FILE.launch | PATH [--until T] [--seed N]
  [arg:=value ...]``: what ``roslaunch`` prints (it starts a master and
  ``/rosout`` first, as roslaunch does without a running roscore), the
  nodes' log lines (``output="screen"``; warnings and errors always), and
  at ``T`` simulated seconds the shutdown roslaunch does on Ctrl+C.

Both stop early when the launch ends by itself (a ``required`` node died,
every node exited).
"""

from __future__ import annotations

import argparse
import importlib.util
import os
import re
import sys
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import TYPE_CHECKING

from ddes.errors import DdesError, ROSConsoleError
from ddes.time.units import ns_to_sec

if TYPE_CHECKING:
    from ddes.graph.world import World

__all__ = ["is_rospy_script", "register", "run_launch", "run_scenario", "run_scripts"]

_DEFAULT_UNTIL = 10.0


def _split_options(words: Sequence[str], until: float, seed: int,
                   flags: dict[str, bool] | None = None) -> tuple[list[str], float, int]:
    """Take ``--until``/``--seed`` (and the keys of ``flags``) out of the words, wherever they are."""
    rest: list[str] = []
    it = iter(words)
    for w in it:
        key, eq, value = w.partition("=")
        if flags is not None and w in flags:
            flags[w] = True
        elif key in ("--until", "--seed"):
            if not eq:
                value = next(it, "")
            try:
                if key == "--until":
                    until = float(value)
                else:
                    seed = int(value)
            except ValueError:
                raise ROSConsoleError(f"{key} needs a number, got {value!r}") from None
        else:
            rest.append(w)
    if not until >= 0:
        raise ROSConsoleError(f"--until must be >= 0 simulated seconds, got {until}")
    return rest, until, seed


def _print_line(text: str) -> None:
    sys.stdout.write(text + "\n")


def run_launch(argv: Sequence[str], *, until: float, seed: int = 0,
               out: Callable[[str], None] = _print_line) -> World:
    """Run a launch file (``PKG FILE`` or ``PATH`` plus ``arg:=value``) for ``until`` seconds.

    Returns the world (for its trace and digest).
    """
    from ddes.launch import load_launch, resolve_launch_args
    from ddes.launch.runtime import LaunchRunner, LogRouter
    from ddes.rospack import command_package_path
    from ddes.world import World as FacadeWorld

    world = FacadeWorld(seed=seed, package_path=command_package_path(os.environ, os.getcwd()))
    rospack = world.rospack
    path, args = resolve_launch_args(list(argv), rospack)
    plan = load_launch(path, args, rospack, anon_seed=world.rng_for("roslaunch"))
    router = LogRouter(world, out).install()
    runner = LaunchRunner(world, plan, rospack=rospack, out=out, router=router)
    runner.start()
    deadline = world.timeout(until)
    world.env.run(until=world.env.any_of([runner.finished, deadline]))
    if not runner.done:
        runner.shutdown()
    return world


def run_scenario(path: str | Path, *, until: float, seed: int = 0,
                 out: Callable[[str], None] = _print_line) -> World:
    """Run a Python scenario file (``def scenario(world)``) for ``until`` simulated seconds."""
    from ddes.rospack import command_package_path
    from ddes.world import World as FacadeWorld

    file = Path(path)
    if not file.is_file():
        raise ROSConsoleError(f"scenario file not found: {path}")
    spec = importlib.util.spec_from_file_location(f"_ddes_scenario_{file.stem}", file)
    if spec is None or spec.loader is None:
        raise ROSConsoleError(f"cannot load {path} as a Python module")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    scenario = getattr(module, "scenario", None)
    if not callable(scenario):
        raise ROSConsoleError(f"{path} must define 'def scenario(world): ...' (it sets up the "
                              "world's nodes; ddes run then runs the world)")
    world = FacadeWorld(seed=seed, package_path=command_package_path(os.environ, os.getcwd()))
    world.log_output = lambda line, level: out(line)
    scenario(world)
    world.run(until=until)
    return world


def is_rospy_script(path: str | Path) -> bool:
    """True for a Python file that imports rospy and defines no ``scenario(world)``."""
    file = Path(path)
    if file.suffix != ".py" or not file.is_file():
        return False
    text = file.read_text(encoding="utf-8", errors="replace")
    return "def scenario(" not in text and re.search(r"^\s*(import|from)\s+rospy\b", text,
                                                     re.M) is not None


def _is_program(word: str) -> bool:
    """A compiled program (a regular ELF file: a FIFO is never opened)."""
    from ddes.roscpp.executables import is_native

    return Path(word).is_file() and is_native(word)


def run_scripts(words: Sequence[str], *, until: float, seed: int = 0,
                out: Callable[[str], None] = _print_line) -> World:
    """Run rospy scripts as nodes of one world (``talker.py listener.py``) for ``until`` seconds.

    Each ``*.py`` word starts a script; the words after it, up to the next script, are its
    arguments (``add_two_ints_client.py 3 4``, ``talker.py chatter:=/talk``).
    """
    from ddes.compat.scripts import run_script
    from ddes.roscpp.executables import start_executable
    from ddes.roscpp.host import close_all
    from ddes.rospack import command_package_path
    from ddes.world import World as FacadeWorld

    commands: list[tuple[Path, list[str]]] = []
    for word in words:
        if word.endswith(".py"):
            if not Path(word).is_file():
                raise ROSConsoleError(f"script not found: {word}")
            commands.append((Path(word), []))
        elif _is_program(word):  # a compiled roscpp node (devel/lib/...)
            commands.append((Path(word), []))
        elif commands:
            commands[-1][1].append(word)
        else:
            raise ROSConsoleError(f"{word!r} comes before any script: ddes run a.py [args] b.py "
                                  "(or a compiled node: ddes run devel/lib/PKG/NODE [args])")
    world = FacadeWorld(seed=seed, package_path=command_package_path(os.environ, os.getcwd()))
    world.log_output = lambda line, level: out(line)
    try:
        for path, args in commands:
            if path.suffix == ".py":
                run_script(world, path, args, print_line=lambda text, _stderr: out(text))
            else:  # in lockstep with the world (ddes.roscpp.host), as rosrun starts it
                start_executable(world, path.resolve(), args, name=None, namespace="/",
                                 remappings=None, cwd=None,
                                 print_line=lambda text, _stderr: out(text))
        world.run(until=until)
    finally:
        close_all(world)
    return world


def _summary(world: World, out: Callable[[str], None]) -> None:
    out(f"simulated {ns_to_sec(world.now):.3f} s; {len(world.trace)} trace events")
    out(f"trace digest: {world.digest()}")


def _guard(fn: Callable[[], None]) -> int:
    try:
        fn()
    except (DdesError, BrokenPipeError):  # main() reports these (a closed pipe: quietly, 141)
        raise
    except Exception as exc:  # noqa: BLE001 - a node's own code failed while the world ran
        print(f"ERROR: {type(exc).__name__} raised while the world ran: {exc}", file=sys.stderr)
        return 1
    return 0


def _main_run(args: argparse.Namespace) -> int:
    words, until, seed = _split_options(args.args, args.until, args.seed)
    scenario = args.scenario
    if scenario.endswith((".launch", ".xml")):
        return _guard(lambda: _summary(run_launch([scenario, *words], until=until, seed=seed),
                                       _print_line))
    if is_rospy_script(scenario) or _is_program(scenario):
        return _guard(lambda: _summary(run_scripts([scenario, *words], until=until, seed=seed),
                                       _print_line))
    if words:
        raise ROSConsoleError(f"unexpected arguments {words}: arg:=value goes with launch files")
    return _guard(lambda: _summary(run_scenario(scenario, until=until, seed=seed), _print_line))


def _main_roslaunch(args: argparse.Namespace) -> int:
    flags = {"--digest": bool(args.digest)}
    words, until, seed = _split_options(args.args, args.until, args.seed, flags)

    def go() -> None:
        world = run_launch(words, until=until, seed=seed)
        if flags["--digest"]:
            _summary(world, _print_line)

    return _guard(go)


def register(sub: argparse._SubParsersAction[argparse.ArgumentParser]) -> None:
    """Add ``ddes run`` and ``ddes roslaunch`` to the ``ddes`` command."""
    p = sub.add_parser("run", help="run a scenario (launch file or Python) and print its digest",
                       description="Run a launch file, or a Python file defining "
                                   "'def scenario(world)', on simulated time.")
    p.add_argument("scenario", help="a .launch file, a .py file defining scenario(world), or "
                                    "rospy scripts (talker.py listener.py) with their arguments")
    p.add_argument("--until", type=float, default=_DEFAULT_UNTIL,
                   help=f"simulated seconds to run (default {_DEFAULT_UNTIL:g})")
    p.add_argument("--seed", type=int, default=0, help="world seed (default 0)")
    p.add_argument("args", nargs=argparse.REMAINDER, help="arg:=value for a launch file")
    p.set_defaults(func=_main_run)
    q = sub.add_parser("roslaunch", help="run a launch file on simulated time",
                       description="roslaunch PKG FILE.launch | PATH [arg:=value ...], on "
                                   "simulated time, shut down after --until seconds.")
    q.add_argument("--until", type=float, default=_DEFAULT_UNTIL,
                   help=f"simulated seconds to run (default {_DEFAULT_UNTIL:g})")
    q.add_argument("--seed", type=int, default=0, help="world seed (default 0)")
    q.add_argument("--digest", action="store_true", help="print the trace digest at the end")
    q.add_argument("args", nargs=argparse.REMAINDER,
                   help="PKG FILE.launch or PATH, then arg:=value ...")
    q.set_defaults(func=_main_roslaunch)
