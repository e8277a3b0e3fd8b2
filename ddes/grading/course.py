"""What the course's exercises share: hidden scenarios, the student's launch file, artefacts.

* **Hidden scenarios**: an exercise's ``scenarios(seed, public)`` draws each hidden scenario's
  parameters (pillar, start pose, parameter overrides) from ``random.Random(seed)`` of that
  scenario (:func:`hidden_random`); :func:`ddes.grading.scenarios.select_scenarios` replaces the
  seed by ``HMAC-SHA256(course secret, exercise/student/attempt/index)`` when the grade has a
  key, so the checks are open source and the parameters are not.
* **The student's launch file** is read by :mod:`ddes.launch` in the grader (nothing of the
  submission runs there): :func:`start_launch` sets its parameters on the trusted parameter
  server, starts the bundled node types it names in the trusted world (the simulator is built
  here, with the scenario's world and start pose, so its ground truth is the grader's), and
  returns the student's ``<node>`` entries as scripts for the sandboxed child, with their name,
  namespace, remappings and private parameters on the command line (``__name:=``, ``__ns:=``,
  ``from:=to``, ``_param:=value``: parameters cross into the child that way, since the child has
  a parameter server of its own).  ``rviz`` nodes are recorded, not started: their ``-d`` file is
  an artefact.
* **Artefacts**: RViz configs read with the bounded YAML loader (``ddes.graph.yamlsafe.load_yaml``) (:func:`rviz_displays`), Python
  source parsed with :mod:`ast` (never imported).
"""

from __future__ import annotations

import ast
import math
import random
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

import yaml

from ddes.errors import DdesError
from ddes.grading.exercise import Exercise, Facts, Scenario
from ddes.graph.yamlsafe import load_yaml

if TYPE_CHECKING:
    from ddes.graph.world import World
    from ddes.launch.plan import LaunchPlan, NodeSpec
    from ddes.sim import Simulator

__all__ = ["CourseExercise", "LaunchNotes", "find_package",
           "notes", "parse_source", "rviz_displays", "rviz_file", "start_launch"]

CREDIT = "after ETH Zurich, Programming for Robotics, exercise {n}"


def hidden_random(exercise: str, seed: int) -> random.Random:
    """The generator of a hidden scenario's parameters (its seed is the keyed hash's when the
    grade has a key)."""
    return random.Random(f"{exercise}/{seed}")


# -- the student's launch file ------------------------------------------------------------------

@dataclass
class LaunchNotes:
    """What :func:`start_launch` found and started (criteria read it through :func:`notes`)."""

    launch: str = ""
    plan: LaunchPlan | None = None
    error: str = ""
    student_nodes: list[NodeSpec] = field(default_factory=list)
    scripts: list[tuple[str, list[str]]] = field(default_factory=list)
    trusted_nodes: list[NodeSpec] = field(default_factory=list)
    rviz_args: list[list[str]] = field(default_factory=list)
    problems: list[str] = field(default_factory=list)
    sim: Simulator | None = None
    sim_params: dict[str, Any] = field(default_factory=dict)
    extra: dict[str, Any] = field(default_factory=dict)


def notes(world: World) -> LaunchNotes:
    """The launch notes of a scenario's trusted world (empty ones when nothing was launched)."""
    found = getattr(world, "_ddes_course_notes", None)
    return found if isinstance(found, LaunchNotes) else LaunchNotes()


def find_package(root: Path, name: str) -> Path | None:
    """The folder of package ``name`` inside the submission (its ``package.xml`` names it)."""
    from ddes.rospack import RosPack

    try:
        path = RosPack([root]).get_path(name)
    except DdesError:
        return None
    path = Path(path).resolve()
    return path if root.resolve() in path.parents or path == root.resolve() else None


def declared_packages(submission: Path) -> list[tuple[str, str]]:
    """``(folder relative to the submission, the name its package.xml declares)`` of every
    package.xml of the submission (read as text with a bounded parser, sorted by folder)."""
    import xml.etree.ElementTree as ET

    found = []
    root = submission.resolve()
    for xml in sorted(root.rglob("package.xml"))[:64]:
        if xml.is_symlink() or not xml.is_file() or xml.stat().st_size > 1 << 20:
            continue
        text = xml.read_text(encoding="utf-8", errors="replace")
        if "<!DOCTYPE" in text or "<!ENTITY" in text:
            continue
        try:
            name = (ET.fromstring(text).findtext("name") or "").strip()
        except ET.ParseError:
            continue
        found.append((str(xml.parent.relative_to(root)), name))
    return found


def package_hint(submission: Path, name: str) -> str:
    """Why package ``name`` is not found in the submission, as a student can act on it: a
    folder of that name declaring another package, or the packages it does have."""
    declared = declared_packages(submission)
    for folder, declares in declared:
        if Path(folder).name == name and declares != name:
            return (f"the folder {folder}/ declares package {declares!r} in its package.xml, not "
                    f"{name!r}: ROS finds a package by the <name> of its package.xml, so make "
                    "the two the same")
    if declared:
        return ("your submission's packages are " + ", ".join(
            f"{d!r} ({f}/)" for f, d in declared[:8]) + f"; none is named {name!r}")
    return f"your submission has no package.xml at all (a package {name!r} needs one)"


def _student_text(text: str, submission: Path) -> str:
    """A launch error as a student reads it: a missing package explained from their own files,
    without the grading machine's search path or ddes's API."""
    import re

    m = re.search(r"package '([^']+)' not found", text)
    if m is None:
        return text.replace(str(submission.resolve()) + "/", "").replace(str(submission) + "/", "")
    where = text[:m.start()].rstrip(": ")
    cut = where.rfind("$(find")
    where = where[:cut].rstrip(": ") if cut > 0 else where
    said = f"$(find {m.group(1)}): {package_hint(submission, m.group(1))}"
    return f"{where}: {said}" if where else said


def _middle(text: str, limit: int = 480) -> str:
    """``text`` of at most ``limit`` characters, its middle cut out: a launch error quotes the
    start tag (a value of 400,000 characters, say) before it says what is wrong and what to do,
    and a report line keeps its start only."""
    if len(text) <= limit:
        return text
    head = limit // 3
    return f"{text[:head]} … {text[-(limit - head - 3):]}"


def _arg_value(value: Any) -> str:
    """A parameter value as rospy's ``_param:=value`` reads it back (YAML)."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, (int, float)):
        return repr(value)
    if isinstance(value, str):
        try:
            same = load_yaml(value) == value
        except (yaml.YAMLError, DdesError):
            same = False
        return value if same and value else yaml.safe_dump(value, default_flow_style=True).strip()
    return yaml.safe_dump(value, default_flow_style=True).strip().replace("\n", " ")


def _private_params(plan: LaunchPlan, spec: NodeSpec) -> dict[str, Any]:
    prefix = spec.full_name + "/"
    return {k[len(prefix):]: v for k, v in plan.params.items() if k.startswith(prefix)}


def start_launch(world: World, scenario: Scenario, submission: Path, launch: str, *,
                 overrides: dict[str, dict[str, Any]] | None = None,
                 sim_overrides: dict[str, Any] | None = None,
                 remaps: dict[str, dict[str, str]] | None = None,
                 namespaces: dict[str, str] | None = None) -> list[tuple[str, list[str]]]:
    """Read the student's ``launch`` (relative to the submission) and start it on ``world``.

    ``overrides`` maps a node *type* to private parameters set after the student's (a hidden
    YAML loaded last); ``sim_overrides`` replaces the simulator's parameters (world file, start
    pose); ``remaps`` maps a node type to extra remappings; ``namespaces`` maps a node type to
    the namespace its node is started in instead of the launch file's (as a ``<group ns=...>``
    around the ``<include>`` of the student's launch file would: its private parameters follow
    it, a name spelled absolute does not).  Returns the scripts for the child.
    """
    from ddes.launch import load_launch
    from ddes.rospack import RosPack

    out = LaunchNotes(launch=launch)
    world._ddes_course_notes = out  # type: ignore[attr-defined]
    path = (submission / launch)
    if not path.is_file():
        out.error = f"the launch file {launch} is missing"
        return []
    rospack = RosPack([submission])
    try:
        plan = load_launch(path, {}, rospack, environ={})
    except (DdesError, ValueError, OSError, KeyError) as exc:
        out.error = f"{launch} does not load: {_middle(_student_text(str(exc), submission))}"
        return []
    out.plan = plan
    params = world.master.params
    for key, value in plan.params.items():
        params.set_param(key, value)
    for spec in plan.nodes:
        pkg_dir = find_package(submission, spec.pkg)
        if pkg_dir is not None:
            _student_node(out, plan, spec, pkg_dir, submission, overrides or {}, remaps or {},
                          (namespaces or {}).get(spec.type))
        elif spec.pkg == "rviz":
            out.rviz_args.append(list(spec.args))
        elif spec.pkg == "ddes_sim" and spec.type == "simulator":
            _simulator(world, out, plan, spec, sim_overrides or {}, remaps or {})
        else:
            out.trusted_nodes.append(spec)
            try:
                from ddes.nodes import start_node

                start_node(world, spec.pkg, spec.type, rospack=rospack, name=spec.name,
                           namespace=spec.namespace,
                           argv=[*spec.args, *(f"{a}:={b}" for a, b in spec.remappings)])
            except Exception as exc:  # noqa: BLE001 - a node the launch names that cannot start
                text = _middle(_student_text(str(exc), submission))
                out.problems.append(f"{spec.pkg}/{spec.type} ({spec.full_name}) did not start: "
                                    + (text if "$(find" in text else
                                       f"{type(exc).__name__}: {text}"))
    return out.scripts


def _student_node(out: LaunchNotes, plan: LaunchPlan, spec: NodeSpec, pkg_dir: Path,
                  submission: Path, overrides: dict[str, dict[str, Any]],
                  remaps: dict[str, dict[str, str]], namespace: str | None = None) -> None:
    from ddes.nodes import find_script

    script = find_script(pkg_dir, spec.type)
    if script is None:
        out.problems.append(f"{spec.pkg}/{spec.type}: no scripts/{spec.type} in the package")
        return
    out.student_nodes.append(spec)
    private = _private_params(plan, spec)
    private.update(overrides.get(spec.type, {}))
    args = [*spec.args, f"__name:={spec.name}"]
    ns = spec.namespace if namespace is None else namespace
    if ns != "/":
        args.append(f"__ns:={ns.rstrip('/')}")
    maps = [*spec.remappings, *remaps.get(spec.type, {}).items()]
    args += [f"{a}:={b}" for a, b in maps]
    args += [f"_{k}:={_arg_value(v)}" for k, v in private.items() if not isinstance(v, dict)]
    out.scripts.append((str(script.resolve().relative_to(submission.resolve())), args))


def _simulator(world: World, out: LaunchNotes, plan: LaunchPlan, spec: NodeSpec,
               sim_overrides: dict[str, Any], remaps: dict[str, dict[str, str]]) -> None:
    from ddes.sim import Simulator, WorldSpec

    p = _private_params(plan, spec)
    p.update(sim_overrides)
    out.sim_params = p

    def flag(name: str, default: bool) -> bool:
        v = p.get(name, default)
        return v.lower() in ("true", "1") if isinstance(v, str) else bool(v)

    try:
        if "world_yaml" in p:
            spec_w = WorldSpec.from_yaml(str(p["world_yaml"]), "hidden.yaml")
        else:
            spec_w = WorldSpec.load(str(p.get("world_file") or p.get("world", "empty")))
        maps = [*spec.remappings, *remaps.get("simulator", {}).items()]
        node = world.create_node(spec.full_name, remappings=dict(maps))
        out.sim = Simulator(world, spec_w, x=float(p.get("x", 0.0)), y=float(p.get("y", 0.0)),
                            yaw=float(p.get("yaw", 0.0)), noise=flag("noise", True), node=node,
                            laser=flag("laser_enabled", True))
    except (DdesError, ValueError, OSError, TypeError) as exc:
        out.problems.append(f"the simulator did not start: {exc}")


@dataclass(frozen=True)
class CourseExercise(Exercise):
    """An exercise whose student nodes come from the submission's launch file."""

    #: The launch file the grader reads, relative to the submission.
    launch: str = ""
    #: ``(world, scenario) -> (overrides, sim_overrides, remaps)`` of a scenario.
    setup: Any = None

    def student_scripts(self, world: World, scenario: Scenario,
                        submission: Path) -> list[tuple[str, list[str]]]:
        overrides, sim_overrides, remaps = (self.setup(world, scenario) if self.setup
                                            else ({}, {}, {}))
        namespaces = scenario.params.get("node_namespaces")
        scripts = start_launch(world, scenario, submission, self.launch, overrides=overrides,
                               sim_overrides=sim_overrides, remaps=remaps,
                               namespaces=namespaces if isinstance(namespaces, dict) else None)
        after = scenario.params.get("after_launch")
        if callable(after):
            after(world, scenario)
        return scripts


# -- artefacts ----------------------------------------------------------------------------------

def rviz_file(facts: Facts) -> tuple[str | None, str]:
    """The RViz config the launch starts rviz with (``-d FILE``), relative to the submission, or
    None and why."""
    n = notes(facts.world)
    if not n.rviz_args:
        return None, "the launch file starts no rviz node"
    for args in n.rviz_args:
        for i, a in enumerate(args):
            if a in ("-d", "--display-config") and i + 1 < len(args):
                target = Path(args[i + 1]).resolve()
                root = facts.submission.resolve()
                if root in target.parents and target.is_file():
                    return str(target.relative_to(root)), ""
                return None, f"rviz -d {args[i + 1]}: not a file of the submission"
    return None, "the rviz node has no -d CONFIG argument"


def rviz_displays(facts: Facts) -> tuple[dict[str, Any] | None, list[dict[str, Any]], str]:
    """``(Global Options, displays, why)`` of the launch's RViz config (displays flattened out of
    groups), read with the bounded YAML loader."""
    rel, why = rviz_file(facts)
    if rel is None:
        return None, [], why
    text = facts.read_text(rel) or ""
    try:
        data = load_yaml(text)
    except (yaml.YAMLError, DdesError) as exc:  # malformed, or past the loader's bounds
        return None, [], f"{rel} is not YAML: {str(exc)[:120]}"
    manager = data.get("Visualization Manager") if isinstance(data, dict) else None
    if not isinstance(manager, dict):
        return None, [], f"{rel} has no 'Visualization Manager'"
    glob = manager.get("Global Options")
    flat: list[dict[str, Any]] = []

    def walk(items: Any) -> None:
        for d in items if isinstance(items, list) else []:
            if isinstance(d, dict):
                flat.append(d)
                walk(d.get("Displays"))

    walk(manager.get("Displays"))
    return glob if isinstance(glob, dict) else {}, flat, ""


def parse_source(facts: Facts, rel: str) -> ast.Module | None:
    """A Python file of the submission parsed with :mod:`ast` (never imported), or None."""
    text = facts.read_text(rel)
    if text is None:
        return None
    try:
        return ast.parse(text, rel)
    except (SyntaxError, ValueError, RecursionError, MemoryError):  # too deep to parse
        return None


def min_valid_range(scan: Any) -> tuple[float, int]:
    """The smallest range with ``range_min <= r <= range_max`` and its index (inf, -1 if none)."""
    best, index = math.inf, -1
    lo, hi = scan.range_min, scan.range_max
    for i, r in enumerate(scan.ranges):
        if lo <= r <= hi and r < best:
            best, index = r, i
    return best, index

