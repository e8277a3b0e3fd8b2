"""Building a catkin workspace against ddes's roscpp: ``ddes catkin_make`` and ``catkin build``.

``catkin_make`` here does what ROS's does, with ddes's catkin in place of ROS's: it configures
the build space with the system's CMake, on ddes's top-level CMakeLists.txt
(``cmake/toplevel``: every package under ``src/`` found by its ``package.xml``, ordered by
dependencies, added as a subdirectory) and ddes's catkin configuration (``cmake/catkinConfig.cmake``,
found through ``CMAKE_PREFIX_PATH``), then runs make.  Executables land in
``devel/lib/<pkg>/``, a package's message headers in ``devel/include/<pkg>/``, the headers of
ddes's message packages in ``build/ddes_gencpp/include``, ddes's roscpp library
(``cpp/``) is built once per machine (below); ``devel/setup.bash`` puts the workspace's ``src/``
on ``DDES_PACKAGE_PATH`` and ``ROS_PACKAGE_PATH``.  Output is catkin_make's: its
``Base path:`` ... ``Install space:`` lines, its ``#### Running command:`` banners, CMake's and
make's own output, ``Invoking "make -j2 -l2" failed`` and exit code 1 on a failure.

Bounds: a whole run has a wall-time limit (``--timeout``, default :data:`DEFAULT_TIMEOUT_S`):
past it the build's processes are stopped; make runs at most as many jobs as the machine has
CPUs (``-j`` asks for fewer, never more; ``MAKEFLAGS`` jobs are dropped).  The wall clock
(``time.monotonic``) is read only here, for that limit and the times ``catkin build`` prints: a
build is a tool run outside any world, and nothing it times enters a trace.

``catkin build`` (catkin_tools' command) builds the same single build space, package by
package, with catkin_tools' ``Starting >>>``/``Finished <<<`` lines and summary.

ddes's roscpp library is compiled once per machine (per library sources, compiler and flags)
into a cache, ``$DDES_CACHE_DIR/roscpp`` (default ``~/.cache/ddes/roscpp``), when a package first
asks for it; ``DDES_ROSCPP_CACHE=0`` (or ``-DDDES_ROSCPP_SOURCE_DIR=`` another library) builds it
in each build space instead.

The CMake side calls back into this module (``python -m ddes.roscpp.catkin scan|genmsg|library``):
``scan`` lists and orders the packages and writes the component configurations, ``genmsg``
writes a package's own message headers, ``library`` builds ddes's roscpp for the cache.  See docs/roscpp.md, "Building with catkin".
"""

from __future__ import annotations

import argparse
import os
import re
import selectors
import shlex
import shutil
import signal
import subprocess
import sys
import time
from collections import deque
from collections.abc import Callable, Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING
from xml.parsers import expat

from ddes._version import __version__
from ddes.errors import DdesError

if TYPE_CHECKING:
    from ddes.msg.registry import MessageRegistry

__all__ = [
    "ALWAYS_GENERATED", "CMAKE_DIR", "DEFAULT_TIMEOUT_S", "LIBRARY_COMPONENTS", "LIBRARY_SOURCE_DIR",
    "NOOP_COMPONENTS", "TOPLEVEL_DIR", "CatkinError", "WorkspacePackage", "bounded_make_args",
    "build_library", "catkin_build", "catkin_clean", "catkin_make", "catkin_tool",
    "dependency_closure", "find_packages", "genmsg", "library_cache_dir", "library_sources_key",
    "main", "scan", "topological_order",
]

Write = Callable[[str], None]

_HERE = Path(__file__).resolve().parent
#: ddes's catkin configuration (catkinConfig.cmake, ddes_catkin.cmake): on CMAKE_PREFIX_PATH.
CMAKE_DIR = _HERE / "cmake"
#: The workspace's top-level CMakeLists.txt (catkin's toplevel.cmake).
TOPLEVEL_DIR = CMAKE_DIR / "toplevel"
#: ddes's roscpp library: headers in include/, sources in src/, its own CMakeLists.txt.
LIBRARY_SOURCE_DIR = _HERE / "cpp"
#: A build's wall-time limit, seconds.
DEFAULT_TIMEOUT_S = 600.0

#: Components that are ddes's roscpp library, with the message packages their headers use (and
#: real ROS puts beside them: ``#include <std_msgs/String.h>`` works with roscpp alone).
LIBRARY_COMPONENTS: dict[str, tuple[str, ...]] = {
    "roscpp": ("std_msgs", "rosgraph_msgs"),
    "rostime": (),
    "rosconsole": (),
    "roscpp_serialization": (),
    "roscpp_traits": (),
    "cpp_common": (),
    "actionlib": ("actionlib_msgs", "std_msgs"),
    "tf2": ("geometry_msgs", "tf2_msgs", "std_msgs"),
    "tf2_ros": ("geometry_msgs", "tf2_msgs", "std_msgs"),
    "tf": ("geometry_msgs", "tf2_msgs", "sensor_msgs", "std_msgs"),
}
#: Components accepted with nothing to add for C++ code.
NOOP_COMPONENTS: tuple[str, ...] = (
    "catkin", "rospy", "message_generation", "message_runtime", "genmsg", "gencpp", "genpy",
    "rostest", "roslaunch", "rosunit",
)
#: Message packages whose headers every configure writes (roscpp's own).
ALWAYS_GENERATED: tuple[str, ...] = ("std_msgs", "rosgraph_msgs")

_IGNORE_MARKERS = ("CATKIN_IGNORE", "COLCON_IGNORE", "AMENT_IGNORE")
_BUILD_DEPEND_TAGS = ("build_depend", "buildtool_depend", "depend", "test_depend")
_RUN_DEPEND_TAGS = ("run_depend", "exec_depend", "build_export_depend", "buildtool_export_depend",
                    "depend")
_ALL_DEPEND_TAGS = tuple(dict.fromkeys(_BUILD_DEPEND_TAGS + _RUN_DEPEND_TAGS + ("doc_depend",)))
_MAX_MANIFEST_BYTES = 1 << 20
_BUILT_BY = ".built_by"
_WORKSPACE_MARKER = ".catkin_workspace"


class CatkinError(DdesError):
    """A workspace ddes's catkin cannot build (bad package.xml, a dependency cycle, ...)."""


# -- packages ------------------------------------------------------------------------------------
@dataclass(frozen=True)
class WorkspacePackage:
    """A package of the source space, as its ``package.xml`` describes it."""

    name: str
    path: Path
    relpath: str
    depends: Mapping[str, tuple[str, ...]] = field(default_factory=dict)
    metapackage: bool = False
    build_type: str = "catkin"

    @property
    def manifest(self) -> Path:
        return self.path / "package.xml"

    def names(self, tags: Iterable[str]) -> list[str]:
        """The dependencies under ``tags``, each once, in tag order."""
        out: dict[str, None] = {}
        for tag in tags:
            out.update(dict.fromkeys(self.depends.get(tag, ())))
        out.pop(self.name, None)
        return list(out)

    @property
    def all_depends(self) -> list[str]:
        return self.names(_ALL_DEPEND_TAGS)


def _condition_holds(condition: str) -> bool:
    """A package.xml format 3 ``condition`` for ROS 1 (``$ROS_VERSION == 1``); unknown: true."""
    values = {"ROS_VERSION": "1", "ROS_PYTHON_VERSION": "3", "ROS_DISTRO": "noetic"}
    m = re.fullmatch(r"\s*\$(\w+)\s*(==|!=)\s*(\w+)\s*", condition)
    if not m or m.group(1) not in values:
        return True
    same = values[m.group(1)] == m.group(3)
    return same if m.group(2) == "==" else not same


def _read_manifest(path: Path, folder: Path, source: Path) -> WorkspacePackage:
    where = f"package.xml '{path}'"
    try:
        data = path.read_bytes()[: _MAX_MANIFEST_BYTES + 1]
    except OSError as exc:
        raise CatkinError(f"cannot read {where}: {exc.strerror or exc}") from None
    if len(data) > _MAX_MANIFEST_BYTES:
        raise CatkinError(f"{where} is larger than {_MAX_MANIFEST_BYTES} bytes")
    parser = expat.ParserCreate()
    stack: list[str] = []
    text: list[str] = []
    fields: dict[str, list[str]] = {}
    export: list[tuple[str, str]] = []
    skip = [0]

    def doctype(doc: str, *_: object) -> None:
        raise CatkinError(f"{where}: <!DOCTYPE {doc}> is not allowed; remove it")

    def start(tag: str, attrs: dict[str, str]) -> None:
        stack.append(tag)
        if len(stack) == 2 and not _condition_holds(attrs.get("condition", "")):
            skip[0] = len(stack)
        if len(stack) in (2, 3):
            text.clear()

    def end(tag: str) -> None:
        depth = len(stack)
        if depth == 2 and not skip[0]:
            fields.setdefault(tag, []).append("".join(text).strip())
        elif depth == 3 and stack[1] == "export" and not skip[0]:
            export.append((tag, "".join(text).strip()))
        if skip[0] == depth:
            skip[0] = 0
        stack.pop()

    def chars(data: str) -> None:
        text.append(data)

    parser.StartDoctypeDeclHandler = doctype
    parser.StartElementHandler = start
    parser.EndElementHandler = end
    parser.CharacterDataHandler = chars
    try:
        parser.Parse(data, True)
    except expat.ExpatError as exc:
        raise CatkinError(f"error parsing {where}: {expat.ErrorString(exc.code)} "
                          f"(line {exc.lineno}, column {exc.offset}); fix the XML") from None
    names = fields.get("name") or [""]
    name = names[0]
    if not name:
        raise CatkinError(f"{where} has no <name>: add <name>{folder.name}</name>")
    if not re.fullmatch(r"[A-Za-z][A-Za-z0-9_]*", name):
        raise CatkinError(f"{where}: the package name '{name}' is not a valid catkin package "
                          "name (letters, digits and underscores, starting with a letter)")
    depends = {tag: tuple(v for v in fields.get(tag, ()) if v) for tag in _ALL_DEPEND_TAGS}
    build_type = next((t for tag, t in export if tag == "build_type"), "") or "catkin"
    return WorkspacePackage(
        name=name, path=folder, relpath=folder.relative_to(source).as_posix(),
        depends=depends, metapackage=any(tag == "metapackage" for tag, _ in export),
        build_type=build_type)


def find_packages(source: str | os.PathLike[str]) -> list[WorkspacePackage]:
    """The packages under the source space ``source``, sorted by folder.

    A package is a folder with a ``package.xml``; the search does not go into a package, nor into
    hidden folders or folders holding ``CATKIN_IGNORE`` (``COLCON_IGNORE``, ``AMENT_IGNORE``).
    Two packages of one name raise :class:`CatkinError`.
    """
    root = Path(source).absolute()
    found: list[WorkspacePackage] = []
    seen_real: set[str] = set()
    stack = [root]
    while stack:
        folder = stack.pop()
        real = os.path.realpath(folder)
        if real in seen_real:
            continue
        seen_real.add(real)
        if any((folder / m).exists() for m in _IGNORE_MARKERS):
            continue
        if (folder / "package.xml").is_file() and folder != root:
            found.append(_read_manifest(folder / "package.xml", folder, root))
            continue
        try:
            children = sorted(p for p in folder.iterdir() if p.is_dir()
                              and not p.name.startswith("."))
        except OSError:
            continue
        stack.extend(reversed(children))
    found.sort(key=lambda p: p.relpath)
    by_name: dict[str, WorkspacePackage] = {}
    for pkg in found:
        if pkg.name in by_name:
            raise CatkinError(f'Multiple packages found with the same name "{pkg.name}":\n'
                              f"- {by_name[pkg.name].relpath}\n- {pkg.relpath}\n"
                              "rename one (its package.xml <name> and project()) or put a "
                              "CATKIN_IGNORE file into one of the folders")
        by_name[pkg.name] = pkg
    return found


def _order_depends(pkg: WorkspacePackage, by_name: Mapping[str, WorkspacePackage]) -> set[str]:
    """Workspace packages ``pkg`` must come after: its build dependencies and, recursively, what
    those export to their dependents (catkin_pkg's order)."""
    out: set[str] = set()
    todo = [d for d in pkg.names(_BUILD_DEPEND_TAGS + _RUN_DEPEND_TAGS) if d in by_name]
    while todo:
        dep = todo.pop()
        if dep in out or dep == pkg.name:
            continue
        out.add(dep)
        todo.extend(d for d in by_name[dep].names(_RUN_DEPEND_TAGS) if d in by_name)
    return out


def topological_order(packages: Sequence[WorkspacePackage]) -> list[WorkspacePackage]:
    """``packages`` ordered so each comes after the workspace packages it depends on; among
    those ready at once, by name.  A cycle raises :class:`CatkinError` naming it."""
    by_name = {p.name: p for p in packages}
    pending = {p.name: _order_depends(p, by_name) for p in packages}
    order: list[WorkspacePackage] = []
    while pending:
        ready = sorted(n for n, deps in pending.items() if not deps & pending.keys())
        if not ready:
            cycle = _a_cycle({n: deps & pending.keys() for n, deps in pending.items()})
            raise CatkinError("circular dependency between the packages "
                              f"{' -> '.join(cycle)}: remove one of these package.xml "
                              "dependencies")
        name = ready[0]
        order.append(by_name[name])
        del pending[name]
    return order


def _a_cycle(graph: Mapping[str, set[str]]) -> list[str]:
    start = sorted(graph)[0]
    path = [start]
    while True:
        nxt = sorted(graph[path[-1]])[0]
        if nxt in path:
            return path[path.index(nxt):] + [nxt]
        path.append(nxt)


def dependency_closure(packages: Sequence[WorkspacePackage], names: Iterable[str]) -> list[str]:
    """``names`` and the workspace packages they depend on, recursively (--only-pkg-with-deps)."""
    by_name = {p.name: p for p in packages}
    out: set[str] = set()
    todo = [n for n in names if n in by_name]
    while todo:
        name = todo.pop()
        if name not in out:
            out.add(name)
            todo.extend(d for d in by_name[name].all_depends if d in by_name)
    return sorted(out)


# -- the CMake side's helpers ----------------------------------------------------------------------
def _cmake_quote(text: str) -> str:
    return '"' + text.replace("\\", "\\\\").replace('"', '\\"').replace("$", "\\$") + '"'


def _cmake_list(items: Iterable[str]) -> str:
    return _cmake_quote(";".join(items))


def _write_if_changed(path: Path, text: str) -> bool:
    try:
        if path.read_text(encoding="utf-8") == text:
            return False
    except (OSError, UnicodeDecodeError):
        pass
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_name(f".{path.name}.{os.getpid()}.tmp")
    tmp.write_text(text, encoding="utf-8")
    os.replace(tmp, path)
    return True


def _message_packages(workspace_names: Iterable[str]) -> list[str]:
    """Packages with message, service or action types in ddes's registry (bundled and
    ``DDES_PACKAGE_PATH``), the workspace's own left out."""
    from ddes.msg.registry import MessageRegistry

    registry = MessageRegistry.from_environment()
    names: set[str] = set()
    for kind in ("msg", "srv", "action"):
        names.update(registry.list_packages(kind))
    return sorted(names - set(workspace_names))


def _split_cmake_list(value: str) -> list[str]:
    return [v for v in value.replace(",", ";").split(";") if v.strip()]


def scan(source: Path, build: Path, devel: Path, cmake_dir: Path, *,
         whitelist: Sequence[str] = (), blacklist: Sequence[str] = ()) -> str:
    """Write ``build/ddes_catkin/workspace.cmake`` (packages in order, components) and a
    ``<name>Config.cmake`` for every component, and the headers of the message packages the
    packages' ``package.xml`` files name.  Returns a line for CMake to show (or "")."""
    from ddes.msg.registry import MessageRegistry
    from ddes.roscpp.gencpp import write_headers

    packages = find_packages(source)
    notes: list[str] = []
    if whitelist:
        packages = [p for p in packages if p.name in whitelist]
    if blacklist:
        packages = [p for p in packages if p.name not in blacklist]
    for pkg in list(packages):
        if pkg.build_type != "catkin":
            notes.append(f"skipping '{pkg.name}': build_type {pkg.build_type} is not catkin")
            packages.remove(pkg)
        elif not (pkg.path / "CMakeLists.txt").is_file():
            if not pkg.metapackage:
                notes.append(f"skipping '{pkg.name}' ({pkg.relpath}): it has no CMakeLists.txt")
            packages.remove(pkg)
    ordered = topological_order(packages)
    ws_names = [p.name for p in ordered]
    all_ws_names = [p.name for p in find_packages(source)]
    msg_packages = _message_packages(all_ws_names)

    wanted: dict[str, None] = dict.fromkeys(p for p in ALWAYS_GENERATED if p in msg_packages)
    for pkg in ordered:
        for dep in pkg.all_depends:
            if dep in msg_packages:
                wanted[dep] = None
            wanted.update(dict.fromkeys(m for m in LIBRARY_COMPONENTS.get(dep, ())
                                        if m in msg_packages))
    gencpp_include = build / "ddes_gencpp" / "include"
    if wanted:
        write_headers(MessageRegistry.from_environment(), [], gencpp_include,
                      packages=list(wanted))

    generators = [_HERE / "gencpp.py", _HERE / "catkin.py"]
    lines = [
        "# Written by ddes (python -m ddes.roscpp.catkin scan) at every configure: do not edit.",
        f"set(DDES_VERSION {_cmake_quote(__version__)})",
        f"set(DDES_WS_PACKAGES {_cmake_list(ws_names)})",
        f"set(DDES_WS_MANIFESTS {_cmake_list(str(p.manifest) for p in ordered)})",
    ]
    for pkg in ordered:
        lines.append(f"set(DDES_WS_{pkg.name}_PATH {_cmake_quote(str(pkg.path))})")
        lines.append(f"set(DDES_WS_{pkg.name}_REL {_cmake_quote(pkg.relpath)})")
    lines += [
        f"set(DDES_LIBRARY_COMPONENTS {_cmake_list(LIBRARY_COMPONENTS)})",
        f"set(DDES_NOOP_COMPONENTS {_cmake_list(NOOP_COMPONENTS)})",
        f"set(DDES_MESSAGE_PACKAGES {_cmake_list(msg_packages)})",
        f"set(DDES_GENCPP_PREGENERATED {_cmake_list(wanted)})",
        f"set(DDES_GENERATOR_SOURCES {_cmake_list(str(p) for p in generators)})",
    ]
    for name, msgs in LIBRARY_COMPONENTS.items():
        lines.append(f"set(DDES_COMPONENT_{name}_MESSAGES "
                     f"{_cmake_list(m for m in msgs if m in msg_packages)})")
    catkin_dir = build / "ddes_catkin"
    _write_if_changed(catkin_dir / "workspace.cmake", "\n".join(lines) + "\n")

    # find_package(X) for every component X: a config that asks ddes's catkin.
    share = catkin_dir / "share"
    components = {*ws_names, *LIBRARY_COMPONENTS, *NOOP_COMPONENTS, *msg_packages} - {"catkin"}
    for name in sorted(components):
        config = (f"# Written by ddes: find_package({name}) in a workspace built by "
                  "`ddes catkin_make`.\n"
                  f"include({_cmake_quote(str(cmake_dir / 'ddes_catkin.cmake'))})\n"
                  f"_ddes_find_component({name})\n")
        version = ('set(PACKAGE_VERSION "0.0.0")\nset(PACKAGE_VERSION_COMPATIBLE TRUE)\n'
                   "set(PACKAGE_VERSION_EXACT FALSE)\n")
        _write_if_changed(share / name / "cmake" / f"{name}Config.cmake", config)
        _write_if_changed(share / name / "cmake" / f"{name}ConfigVersion.cmake", version)
    if share.is_dir():
        for old in share.iterdir():
            if old.name not in components:
                shutil.rmtree(old, ignore_errors=True)
    return "\n".join(f"ddes: {n}" for n in notes)


def _package_closure(registry: MessageRegistry, packages: Iterable[str]) -> set[str]:
    """``packages`` and every package their message types use, recursively."""
    from ddes.msg.gentools import all_dependencies

    out: set[str] = set()
    todo = list(packages)
    while todo:
        pkg = todo.pop()
        if pkg in out:
            continue
        out.add(pkg)
        try:
            names = registry.list_types(pkg, "msg")
        except DdesError:
            continue
        for name in names:
            for dep in all_dependencies(registry.get_msg_spec(name), registry.get_msg_spec):
                todo.append(dep.partition("/")[0])
    return out


def genmsg(package: str, source: Path, devel_include: Path, gencpp_include: Path,
           types: Sequence[str], dependencies: Sequence[str], stamp: Path | None = None) -> None:
    """Write the headers of workspace package ``package``'s ``types`` (``pkg/Name``) into
    ``devel_include/package/``; those of the message packages they use that are not in the
    workspace into ``gencpp_include``.  A type using a package that is neither ``package`` nor in
    ``dependencies`` (nor used by their messages) raises :class:`CatkinError`, as genmsg stops."""
    from ddes.msg.gentools import all_dependencies
    from ddes.msg.registry import MessageRegistry
    from ddes.roscpp.gencpp import generate_headers
    from ddes.rospack import RosPack

    registry = MessageRegistry.from_environment(paths=[source])
    workspace = RosPack([source], bundled=False)
    headers = generate_headers(registry, list(types))
    allowed = {package} | _package_closure(registry, dependencies)
    for name in types:
        specs = []
        try:
            srv = registry.get_srv_spec(name)
            specs += [srv.request, srv.response]
        except DdesError:
            pass
        try:
            specs.append(registry.get_msg_spec(name))
        except DdesError:
            pass
        try:
            action = registry.get_action_spec(name)
            specs += list(action.messages.values())
        except DdesError:
            pass
        for spec in specs:
            for dep in all_dependencies(spec, registry.get_msg_spec):
                dep_pkg = dep.partition("/")[0]
                if dep_pkg not in allowed:
                    raise CatkinError(
                        f"{name} uses {dep}, but '{dep_pkg}' is not in generate_messages("
                        f"DEPENDENCIES {' '.join(dependencies)}) of package '{package}': add "
                        f"{dep_pkg} there, to find_package(catkin REQUIRED COMPONENTS ...) and "
                        f"to package.xml (<depend>{dep_pkg}</depend>)")
    for header in headers:
        pkg = header.relpath.partition("/")[0]
        if pkg == package:
            _write_bytes_if_changed(devel_include / header.relpath, header.text)
        elif pkg not in workspace:
            _write_bytes_if_changed(gencpp_include / header.relpath, header.text)
    if stamp is not None:
        stamp.parent.mkdir(parents=True, exist_ok=True)
        stamp.write_text(" ".join(types) + "\n", encoding="utf-8")
        os.utime(stamp)


def _write_bytes_if_changed(path: Path, text: str) -> None:
    data = text.encode("utf-8")
    try:
        if path.read_bytes() == data:
            return
    except OSError:
        pass
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_name(f".{path.name}.{os.getpid()}.tmp")
    tmp.write_bytes(data)
    os.replace(tmp, path)


# -- running the tools -----------------------------------------------------------------------------
class _TimedOut(Exception):
    pass


@dataclass
class _Runner:
    """Runs the build's commands under one deadline, their output line by line to ``out``."""

    out: Write
    env: dict[str, str]
    deadline: float
    tail: deque[str] = field(default_factory=lambda: deque(maxlen=4000))

    def run(self, cmd: Sequence[str], cwd: Path, out: Write | None = None) -> int:
        """The command's exit code; raises :class:`_TimedOut` past the deadline."""
        show = self.out if out is None else out
        proc = subprocess.Popen(list(cmd), cwd=cwd, env=self.env, stdin=subprocess.DEVNULL,
                                stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                                start_new_session=True)
        assert proc.stdout is not None
        fd = proc.stdout.fileno()
        pending = b""
        sel = selectors.DefaultSelector()
        sel.register(fd, selectors.EVENT_READ)
        try:
            while True:
                left = self.deadline - time.monotonic()
                if left <= 0:
                    raise _TimedOut
                if not sel.select(timeout=min(left, 1.0)):
                    continue
                chunk = os.read(fd, 65536)
                if not chunk:
                    break
                pending += chunk
                *lines, pending = pending.split(b"\n")
                for raw in lines:
                    line = raw.decode("utf-8", "replace").rstrip("\r")
                    self.tail.append(line)
                    show(line)
            if pending:
                line = pending.decode("utf-8", "replace")
                self.tail.append(line)
                show(line)
            left = self.deadline - time.monotonic()
            try:
                return proc.wait(timeout=max(left, 0.01))
            except subprocess.TimeoutExpired:
                raise _TimedOut from None
        finally:
            sel.close()
            proc.stdout.close()
            if proc.poll() is None:
                _stop(proc)


def _stop(proc: subprocess.Popen[bytes]) -> None:
    """End ``proc`` and everything it started (its own session)."""
    for sig, wait in ((signal.SIGTERM, 3.0), (signal.SIGKILL, 5.0)):
        try:
            os.killpg(proc.pid, sig)
        except (ProcessLookupError, PermissionError):
            pass
        try:
            proc.wait(timeout=wait)
            return
        except subprocess.TimeoutExpired:
            continue


def _which(name: str, environ: Mapping[str, str]) -> str | None:
    found = shutil.which(name, path=environ.get("PATH", os.defpath))
    if found:
        return found
    local = Path(sys.executable).parent / name  # pip install cmake, into ddes's environment
    return str(local) if local.is_file() and os.access(local, os.X_OK) else None


def _cxx_compiler(environ: Mapping[str, str], build: Path) -> str | None:
    cached = _cache_value(build / "CMakeCache.txt", "CMAKE_CXX_COMPILER")
    if cached and Path(cached).is_file():
        return cached
    cxx = environ.get("CXX", "").strip()
    if cxx:
        first = shlex.split(cxx)[0] if cxx else ""
        return _which(first, environ) or (first if Path(first).is_file() else None)
    for name in ("c++", "g++", "clang++"):
        found = _which(name, environ)
        if found:
            return found
    return None


def _cache_value(cache: Path, key: str) -> str | None:
    try:
        text = cache.read_text(encoding="utf-8", errors="replace")
    except OSError:
        return None
    m = re.search(rf"^{re.escape(key)}:[A-Z]+=(.*)$", text, re.M)
    return m.group(1).strip() if m else None


def _cpu_count() -> int:
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except (AttributeError, OSError):
        return max(1, os.cpu_count() or 1)


_JOBS_RE = re.compile(r"^(?:-j|--jobs=?)(\d*)$")
_LOAD_RE = re.compile(r"^(?:-l|--load-average=?)([\d.]*)$")


def bounded_make_args(make_args: Sequence[str], cpus: int) -> tuple[list[str], list[str]]:
    """``make_args`` with one ``-jN`` (N at most ``cpus``; catkin_make's ``-jN -lN`` when none is
    given) and the notes to print when a request was lowered."""
    rest: list[str] = []
    jobs: int | None = None
    asked: str | None = None
    load: str | None = None
    args = list(make_args)
    i = 0
    while i < len(args):
        arg = args[i]
        mj = _JOBS_RE.match(arg)
        ml = _LOAD_RE.match(arg)
        if mj:
            value = mj.group(1)
            if not value and i + 1 < len(args) and args[i + 1].isdigit():
                value = args[i + 1]
                i += 1
            asked = arg if not value or arg.endswith(value) else f"{arg} {value}"
            jobs = int(value) if value else 0
        elif ml:
            value = ml.group(1)
            if not value and i + 1 < len(args) and re.fullmatch(r"[\d.]+", args[i + 1]):
                value = args[i + 1]
                i += 1
            load = value or str(cpus)
        else:
            rest.append(arg)
        i += 1
    notes: list[str] = []
    if jobs is None:
        return rest + [f"-j{cpus}", f"-l{load or cpus}"], notes
    if jobs == 0 or jobs > cpus:
        notes.append(f"ddes: make jobs bounded to this machine's {cpus} CPUs "
                     f"({asked or '-j'} asked for {'no limit' if jobs == 0 else jobs})")
        jobs = cpus
    out = rest + [f"-j{jobs}"]
    if load is not None:
        out.append(f"-l{load}")
    return out, notes


def _make_env(environ: Mapping[str, str]) -> dict[str, str]:
    env = dict(environ)
    flags = env.get("MAKEFLAGS", "")
    if flags:
        cleaned = re.sub(r"(?:^|\s)(?:-?j\s*\d*|--jobs(?:=\d+)?|--jobserver-(?:auth|fds)=\S*)"
                         r"(?=\s|$)", " ", flags).strip()
        if cleaned:
            env["MAKEFLAGS"] = cleaned
        else:
            env.pop("MAKEFLAGS")
    env.pop("MFLAGS", None)
    return env


# -- ddes's roscpp, built once per machine ---------------------------------------------------------
#: How many library builds (of different sources or compilers) the cache keeps.
_LIBRARY_CACHE_KEEP = 4

_WRAPPER_CMAKE = """\
# Written by ddes: ddes's roscpp library built once for this machine, for every workspace.
cmake_minimum_required(VERSION 3.16)
project(ddes_roscpp_prebuilt CXX)
set(CMAKE_POSITION_INDEPENDENT_CODE ON)
add_subdirectory({source} roscpp)
export(TARGETS ddes_roscpp FILE "${{CMAKE_BINARY_DIR}}/ddes_roscpp-targets.cmake")
"""


def library_cache_dir(environ: Mapping[str, str]) -> Path | None:
    """Where ddes keeps the library built for this machine (``$DDES_CACHE_DIR/roscpp``, else
    ``$XDG_CACHE_HOME/ddes/roscpp``, else ``~/.cache/ddes/roscpp``); None when
    ``DDES_ROSCPP_CACHE=0`` asks to build it in each build space instead."""
    if environ.get("DDES_ROSCPP_CACHE", "").strip().lower() in ("0", "off", "no", "false"):
        return None
    if environ.get("DDES_CACHE_DIR"):
        return Path(environ["DDES_CACHE_DIR"]) / "roscpp"
    base = environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    return Path(base) / "ddes" / "roscpp"


def library_sources_key() -> str:
    """A digest of ddes's roscpp sources (and ddes's version): when it changes, the library is
    built again and catkin_make configures the workspace again."""
    import hashlib

    digest = hashlib.sha256(f"ddes {__version__}\0".encode())
    for path in sorted(p for p in LIBRARY_SOURCE_DIR.rglob("*") if p.is_file()
                       and "__pycache__" not in p.parts):
        digest.update(path.relative_to(LIBRARY_SOURCE_DIR).as_posix().encode() + b"\0")
        digest.update(path.read_bytes() + b"\0")
    return digest.hexdigest()[:20]


def _library_key(defines: Sequence[str], compiler: str, cmake: str) -> str:
    import hashlib

    digest = hashlib.sha256(f"{library_sources_key()}\0{os.path.realpath(cmake)}\0".encode())
    try:
        st = os.stat(compiler)
        digest.update(f"{os.path.realpath(compiler)} {st.st_size} {st.st_mtime_ns}\0".encode())
    except OSError:
        digest.update(compiler.encode() + b"\0")
    for arg in defines:
        digest.update(arg.encode() + b"\0")
    return digest.hexdigest()[:20]


def build_library(cache: Path, cmake: str, compiler: str, defines: Sequence[str],
                  out: Write = print) -> Path:
    """Build ddes's roscpp for this machine under ``cache`` (once for given sources, compiler
    and ``defines``; a build making the same one at the same time is waited for) and return the
    file CMake's export() wrote for it.  The workspace's CMake runs this when a package first
    asks for roscpp; the commands stay in its process group, so catkin_make's time limit stops
    them too."""
    import fcntl

    if not (LIBRARY_SOURCE_DIR / "CMakeLists.txt").is_file():
        raise CatkinError(f"ddes's roscpp sources are missing ({LIBRARY_SOURCE_DIR}/"
                          "CMakeLists.txt): this ddes installation is incomplete; reinstall ddes")
    key = _library_key(defines, compiler, cmake)
    folder = cache / key
    targets = folder / "build" / "ddes_roscpp-targets.cmake"
    done = folder / "complete"
    if done.is_file() and targets.is_file():
        return targets
    cache.mkdir(parents=True, exist_ok=True)
    env = {k: v for k, v in os.environ.items() if k not in ("MAKEFLAGS", "MFLAGS", "MAKELEVEL")}
    with open(cache / f"{key}.lock", "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)  # the same library being built elsewhere: wait for it
        if done.is_file() and targets.is_file():
            return targets
        shutil.rmtree(folder, ignore_errors=True)
        (folder / "build").mkdir(parents=True)
        _write_if_changed(folder / "CMakeLists.txt",
                          _WRAPPER_CMAKE.format(source=_cmake_quote(str(LIBRARY_SOURCE_DIR))))
        out(f"ddes: building ddes's roscpp library once for this machine, in {folder}")
        steps = [[cmake, str(folder), f"-DCMAKE_CXX_COMPILER={compiler}", *defines,
                  "-G", "Unix Makefiles"],
                 [cmake, "--build", ".", "--target", "ddes_roscpp", "--parallel",
                  str(_cpu_count())]]
        for cmd in steps:
            out(f'ddes:   "{" ".join(cmd)}"')
            proc = subprocess.Popen(cmd, cwd=folder / "build", env=env, stdin=subprocess.DEVNULL,
                                    stdout=subprocess.PIPE, stderr=subprocess.STDOUT)
            assert proc.stdout is not None
            shown: list[str] = []
            for raw in proc.stdout:
                line = raw.decode("utf-8", "replace").rstrip("\n")
                shown.append(line)
                if line.startswith("["):  # make's progress, as it comes
                    out(f"ddes:   {line}")
            code = proc.wait()
            if code:
                for line in shown:
                    if not line.startswith("["):
                        out(f"ddes:   {line}")
                raise CatkinError(f"building ddes's roscpp library failed ({Path(cmd[0]).name} "
                                  f"exited with {code}; its output is above)")
        done.write_text(f"{LIBRARY_SOURCE_DIR}\n", encoding="utf-8")
    _prune_cache(cache, keep=folder)
    return targets


def _prune_cache(cache: Path, keep: Path) -> None:
    """Forget all but the newest few library builds."""
    builds = sorted((p for p in cache.iterdir() if p.is_dir() and (p / "complete").is_file()),
                    key=lambda p: (p / "complete").stat().st_mtime, reverse=True)
    for old in builds[_LIBRARY_CACHE_KEEP:]:
        if old != keep:
            shutil.rmtree(old, ignore_errors=True)
            (cache / f"{old.name}.lock").unlink(missing_ok=True)


# -- catkin_make -----------------------------------------------------------------------------------
def _split_sections(args: Sequence[str], markers: Sequence[str]) -> tuple[list[str], dict[str,
                                                                                     list[str]]]:
    """catkin's ``--cmake-args``/``--make-args``: each takes what follows it, up to the other."""
    rest: list[str] = []
    sections: dict[str, list[str]] = {m: [] for m in markers}
    current: list[str] | None = None
    for arg in args:
        if arg in sections:
            current = sections[arg]
        elif current is not None:
            current.append(arg)
        else:
            rest.append(arg)
    return rest, sections


def _catkin_make_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="catkin_make", add_help=True,
        description="Creates the catkin workspace layout and invokes cmake and make, with "
                    "ddes's catkin and roscpp (C++ nodes run on simulated time). Any argument "
                    'starting with "-D" is passed to cmake; -j/-l and every other argument '
                    "(targets) to make.")
    add = parser.add_argument
    add("-C", "--directory", default=os.curdir,
        help="The base path of the workspace (default '.')")
    add("--source", help="The path to the source space (default 'workspace_base/src')")
    add("--build", help="The path to the build space (default 'workspace_base/build')")
    add("--use-ninja", action="store_true", help="Use 'ninja' instead of 'make'")
    add("--use-nmake", action="store_true", help="Use 'nmake' instead of 'make'")
    add("--use-gmake", action="store_true", help="Use 'gmake' instead of 'make'")
    add("--force-cmake", action="store_true",
        help="Invoke 'cmake' even if it has been executed before")
    add("--no-color", action="store_true", help="Disables colored output (always off in ddes)")
    add("--pkg", nargs="+", help="Invoke 'make' on specific packages only")
    add("--only-pkg-with-deps", nargs="+",
        help="Whitelist only the specified packages and their dependencies by setting the "
             "CATKIN_WHITELIST_PACKAGES variable")
    add("--cmake-args", nargs="*", help="Arbitrary arguments which are passed to CMake")
    add("--make-args", nargs="*", help="Arbitrary arguments which are passed to make")
    add("--override-build-tool-check", action="store_true",
        help="use to override failure due to using different build tools on the same workspace")
    add("--timeout", type=float, default=DEFAULT_TIMEOUT_S, metavar="SECONDS",
        help=f"ddes: stop the build after SECONDS of wall time (default {DEFAULT_TIMEOUT_S:g})")
    return parser


@dataclass
class _Spaces:
    base: Path
    source: Path
    build: Path
    devel: Path
    install: Path


def _space(cwd: Path, base: Path, arg: str | None, default: str) -> Path:
    if arg is None:
        return base / default
    return Path(os.path.abspath(cwd / arg))


def _previous_tool(space: Path) -> str | None:
    try:
        return (space / _BUILT_BY).read_text(encoding="utf-8").strip()
    except OSError:
        return None


def _mark(space: Path, tool: str) -> None:
    space.mkdir(parents=True, exist_ok=True)
    _write_if_changed(space / _BUILT_BY, tool)


def _banner(out: Write, cmd: Sequence[str], cwd: Path) -> None:
    out("####")
    out(f'#### Running command: "{" ".join(cmd)}" in "{cwd}"')
    out("####")


def _setup_scripts(devel: Path, source: Path) -> None:
    """devel/setup.sh (.bash, .zsh): the workspace's src/ on DDES_PACKAGE_PATH and
    ROS_PACKAGE_PATH, devel/ on CMAKE_PREFIX_PATH, for a user who sources it."""
    src = shlex.quote(str(source))
    dev = shlex.quote(str(devel))
    sh = f"""#!/usr/bin/env sh
# Written by ddes catkin_make: this workspace's packages for ddes (and ROS's tools).
# Source it (". devel/setup.sh"); it puts {source}
# first on DDES_PACKAGE_PATH and ROS_PACKAGE_PATH and {devel} on CMAKE_PREFIX_PATH.
_ddes_prepend() {{
  # $1: variable name, $2: folder
  eval "_ddes_value=\\${{$1:-}}"
  case ":$_ddes_value:" in
    *":$2:"*) ;;
    *) if [ -n "$_ddes_value" ]; then eval "export $1=\\"\\$2:\\$_ddes_value\\""; \
else eval "export $1=\\"\\$2\\""; fi ;;
  esac
  unset _ddes_value
}}
_ddes_prepend DDES_PACKAGE_PATH {src}
_ddes_prepend ROS_PACKAGE_PATH {src}
_ddes_prepend CMAKE_PREFIX_PATH {dev}
unset -f _ddes_prepend
"""
    _write_if_changed(devel / "setup.sh", sh)
    for shell in ("bash", "zsh"):
        _write_if_changed(devel / f"setup.{shell}",
                          f"#!/usr/bin/env {shell}\n# Written by ddes catkin_make.\n"
                          f". {shlex.quote(str(devel / 'setup.sh'))}\n")
    for name in ("setup.sh", "setup.bash", "setup.zsh"):
        (devel / name).chmod(0o755)
    _write_if_changed(devel / ".catkin", str(source))


_MISSING_HEADER = re.compile(r"fatal error: ([A-Za-z_][\w]*)/([A-Za-z_]\w*)\.h: No such file")


def _hints(lines: Iterable[str], message_packages: Iterable[str],
           packages: Sequence[WorkspacePackage]) -> list[str]:
    """Advice for failures students meet: a message header of a package not asked for, ros.h
    not on the include path, roscpp not linked."""
    known = set(message_packages)
    ws = {p.name for p in packages}
    out: dict[str, None] = {}
    for line in lines:
        m = _MISSING_HEADER.search(line)
        if m:
            pkg, name = m.groups()
            if pkg == "ros":
                out["ddes: hint: ros/ros.h is not on the include path: add "
                    "include_directories(${catkin_INCLUDE_DIRS}) after find_package(catkin "
                    "REQUIRED COMPONENTS roscpp ...)"] = None
            elif pkg in known:
                out[f"ddes: hint: {pkg}/{name}.h is a message header of '{pkg}': add {pkg} to "
                    "find_package(catkin REQUIRED COMPONENTS ...) and <depend>"
                    f"{pkg}</depend> to package.xml"] = None
            elif pkg in ws:
                out[f"ddes: hint: {pkg}/{name}.h is generated from package '{pkg}''s "
                    f"definitions: is {name} in its add_message_files()/add_service_files() and "
                    "generate_messages() called; does the target depend on "
                    f"{pkg}_generate_messages_cpp (add_dependencies)?"] = None
        if "undefined reference to `ros::" in line:
            out["ddes: hint: roscpp is not linked: add target_link_libraries(<target> "
                "${catkin_LIBRARIES})"] = None
    return list(out)


def catkin_make(argv: Sequence[str], *, cwd: str | os.PathLike[str] | None = None,
                out: Write = print, err: Write | None = None,
                environ: Mapping[str, str] | None = None) -> int:
    """ROS's ``catkin_make ARGS`` with ddes's catkin; the exit code (0 built, 1 failed)."""
    err = err or (lambda line: print(line, file=sys.stderr))
    environ = dict(os.environ if environ is None else environ)
    rest, sections = _split_sections(list(argv), ("--cmake-args", "--make-args"))
    implicit_cmake = [a for a in rest if a.startswith(("-D", "-G"))]
    rest = [a for a in rest if a not in implicit_cmake]
    parser = _catkin_make_parser()
    try:
        args, unknown = parser.parse_known_args(rest)
    except SystemExit as exc:
        return int(exc.code or 0)
    cmake_args = implicit_cmake + sections["--cmake-args"]
    make_args = unknown + sections["--make-args"]
    try:
        return _catkin_make(args, cmake_args, make_args, Path(cwd or os.getcwd()), out, err,
                            environ)
    except CatkinError as exc:
        err(str(exc))
        return 1


def _resolve_spaces(args: argparse.Namespace, cwd: Path, cmake_args: list[str], out: Write,
                    err: Write) -> tuple[_Spaces, list[str]] | None:
    base = Path(os.path.abspath(cwd / args.directory))
    if not base.exists():
        err(f'The specified base path "{base}" does not exist')
        return None
    out(f"Base path: {base}")
    if (base / "package.xml").exists():
        err(f'The specified base path "{base}" contains a package but "catkin_make" must be '
            "invoked in the root of workspace")
        return None
    source = _space(cwd, base, args.source, "src")
    if not source.exists():
        err(f'The specified source space "{source}" does not exist')
        return None
    out(f"Source space: {source}")
    if os.path.realpath(base) != os.path.realpath(source) and (base / "CMakeLists.txt").exists():
        err(f'The specified base path "{base}" contains a CMakeLists.txt but "catkin_make" must '
            "be invoked in the root of workspace")
        return None
    build = _space(cwd, base, args.build, "build")
    out(f"Build space: {build}")
    cmake_args = list(cmake_args)
    devel_arg = install_arg = None
    for prefix in ("-DCATKIN_DEVEL_PREFIX=", "-DCMAKE_INSTALL_PREFIX="):
        given = [a for a in cmake_args if a.startswith(prefix)]
        if given:
            cmake_args = [a for a in cmake_args if a not in given]
            if prefix.startswith("-DCATKIN"):
                devel_arg = given[-1][len(prefix):]
            else:
                install_arg = given[-1][len(prefix):]
    devel = _space(cwd, base, devel_arg, "devel")
    install = _space(cwd, base, install_arg, "install")
    for label, space in (("build", build), ("devel", devel)):
        previous = _previous_tool(space)
        if previous is not None and previous != "catkin_make":
            if args.override_build_tool_check:
                out(f"Warning: {label} space at '{space}' was previously built by '{previous}', "
                    "but --override-build-tool-check was passed so continuing anyways.")
            else:
                err(f"The {label} space at '{space}' was previously built by '{previous}'. "
                    f"Please remove the {label} space or pick a different {label} space.")
                return None
        if label == "build":
            out(f"Devel space: {devel}")
    out(f"Install space: {install}")
    return _Spaces(base, source, build, devel, install), cmake_args


def _check_tools(environ: Mapping[str, str], build: Path, maker: str,
                 err: Write) -> tuple[str, str, str] | None:
    cmake = _which("cmake", environ)
    if cmake is None:
        err("cmake not found: install it (pip install cmake, or apt install cmake)")
        return None
    make = _which(maker, environ)
    if make is None:
        err(f"{maker} not found: install it (apt install {maker})")
        return None
    compiler = _cxx_compiler(environ, build)
    if compiler is None:
        err("no C++ compiler found: install g++ (apt install g++)")
        return None
    return cmake, make, compiler


def _shown(path: str, name: str, environ: Mapping[str, str]) -> str:
    """How a tool's command is shown: its bare name when PATH finds that one."""
    return name if shutil.which(name, path=environ.get("PATH", os.defpath)) == path else path


def _foreign_cache(build: Path) -> str | None:
    """The source folder a CMakeCache.txt in ``build`` was made for, if not ddes's top level."""
    cache = build / "CMakeCache.txt"
    home = _cache_value(cache, "CMAKE_HOME_DIRECTORY")
    if home is None or os.path.realpath(home) == os.path.realpath(TOPLEVEL_DIR):
        return None
    if _cache_value(cache, "DDES_PYTHON") is not None:
        # ddes's own build space from another ddes installation: configure afresh
        cache.unlink(missing_ok=True)
        shutil.rmtree(build / "CMakeFiles", ignore_errors=True)
        return None
    return home


def _configure_args(spaces: _Spaces, cmake_args: list[str], generator: str,
                    environ: Mapping[str, str]) -> list[str]:
    user_prefix = [a for a in cmake_args if a.startswith("-DCMAKE_PREFIX_PATH=")]
    cmake_args = [a for a in cmake_args if a not in user_prefix]
    prefix = [str(CMAKE_DIR)] + [a.split("=", 1)[1] for a in user_prefix[-1:]]
    return [
        str(TOPLEVEL_DIR), *cmake_args,
        f"-DCATKIN_DEVEL_PREFIX={spaces.devel}", f"-DCMAKE_INSTALL_PREFIX={spaces.install}",
        f"-DCATKIN_SOURCE_SPACE={spaces.source}", f"-DDDES_PYTHON={sys.executable}",
        f"-DDDES_VERSION={__version__}", f"-DCMAKE_PREFIX_PATH={';'.join(prefix)}",
        *_library_args(cmake_args, environ), "-G", generator,
    ]


def _library_args(cmake_args: Sequence[str], environ: Mapping[str, str]) -> list[str]:
    """Where the workspace's CMake finds (or builds) ddes's roscpp for this machine: nowhere
    for a library of the user's (-DDDES_ROSCPP_SOURCE_DIR) or with DDES_ROSCPP_CACHE=0."""
    cache = library_cache_dir(environ)
    if cache is None or any(a.startswith("-DDDES_ROSCPP_SOURCE_DIR=") for a in cmake_args) \
            or not (LIBRARY_SOURCE_DIR / "CMakeLists.txt").is_file():
        return ["-DDDES_ROSCPP_CACHE_DIR="]
    return [f"-DDDES_ROSCPP_CACHE_DIR={cache}", f"-DDDES_ROSCPP_SOURCES={library_sources_key()}"]


def _input_changed(packages: Sequence[WorkspacePackage], build: Path,
                   cmake_args: Sequence[str]) -> bool:
    """catkin_make's rule: CMake runs again when the package folders or arguments change."""
    now = os.pathsep.join(sorted(str(p.path) for p in packages)) + "\n" + " ".join(cmake_args)
    path = build / "catkin_make.cache"
    try:
        before = path.read_text(encoding="utf-8")
    except OSError:
        before = None
    _write_if_changed(path, now)
    return before != now


def _catkin_make(args: argparse.Namespace, cmake_args: list[str], make_args: list[str],
                 cwd: Path, out: Write, err: Write, environ: dict[str, str]) -> int:
    resolved = _resolve_spaces(args, cwd, cmake_args, out, err)
    if resolved is None:
        return 1
    spaces, cmake_args = resolved
    if args.use_nmake:
        err("catkin_make: --use-nmake is for Windows; ddes builds with make (or --use-ninja)")
        return 1
    maker = "ninja" if args.use_ninja else "gmake" if args.use_gmake else "make"
    tools = _check_tools(environ, spaces.build, maker, err)
    if tools is None:
        return 1
    cmake, make, compiler = tools
    foreign = _foreign_cache(spaces.build)
    if foreign is not None:
        err(f"The build space at '{spaces.build}' was configured by another catkin (for the "
            f"sources '{foreign}'), not by ddes: remove it and the devel space "
            f"(rm -rf {shlex.quote(str(spaces.build))} {shlex.quote(str(spaces.devel))}) and "
            "run catkin_make again")
        return 1
    spaces.build.mkdir(parents=True, exist_ok=True)
    _mark(spaces.build, "catkin_make")
    _mark(spaces.devel, "catkin_make")
    packages = find_packages(spaces.source)

    if args.only_pkg_with_deps:
        names = {p.name for p in packages}
        unknown = [n for n in args.only_pkg_with_deps if n not in names]
        if len(unknown) == len(args.only_pkg_with_deps):
            err(f'Packages "{", ".join(args.only_pkg_with_deps)}" not found in the workspace')
            return 1
        if unknown:
            err(f'Packages "{", ".join(sorted(unknown))}" not found in the workspace - ignoring '
                "them")
        keep = dependency_closure(packages, [n for n in args.only_pkg_with_deps if n in names])
        out(f"Whitelisted packages: {', '.join(keep)}")
        packages = [p for p in packages if p.name in keep]
        cmake_args.append(f"-DCATKIN_WHITELIST_PACKAGES={';'.join(keep)}")
    by_name = {p.name: p for p in packages}
    pkgs: list[str] = []
    if args.pkg:
        unknown = [n for n in args.pkg if n not in by_name]
        if len(unknown) == len(args.pkg):
            err(f'Packages "{", ".join(args.pkg)}" not found in the workspace')
            return 1
        if unknown:
            err(f'Packages "{", ".join(sorted(unknown))}" not found in the workspace - ignoring '
                "them")
        pkgs = [n for n in args.pkg if n in by_name]

    generator_given = any(a.startswith("-G") for a in cmake_args)
    if generator_given and args.use_ninja:
        err("Error: either specify a generator using '-G...' or '--use-[ninja|nmake]' but not "
            "both")
        return 1
    generator = "Ninja" if args.use_ninja else "Unix Makefiles"
    runner = _Runner(out=out, env=_make_env(environ),
                     deadline=time.monotonic() + max(args.timeout, 0.0))
    configure = _configure_args(spaces, cmake_args, generator, environ)
    if generator_given:
        configure = configure[:-2]
    force = _input_changed(packages, spaces.build, configure[1:])
    state_file = spaces.build / ("build.ninja" if args.use_ninja else "Makefile")
    shown_cmake = _shown(cmake, "cmake", environ)
    shown_make = _shown(make, maker, environ)
    try:
        if not state_file.exists() or args.force_cmake or force:
            cmd = [shown_cmake, *configure]
            _banner(out, cmd, spaces.build)
            if runner.run([cmake, *configure], spaces.build) != 0:
                err('Invoking "cmake" failed')
                return 1
        else:
            check = [shown_make, "build.ninja"] if args.use_ninja else \
                [shown_make, "cmake_check_build_system"]
            _banner(out, check, spaces.build)
            if runner.run([make, *check[1:]], spaces.build) != 0:
                err(f'Invoking "{" ".join(check)}" failed')
                return 1
        _write_if_changed(spaces.base / _WORKSPACE_MARKER,
                          "# This file currently only serves to mark the location of a catkin "
                          "workspace for tool integration\n")
        _setup_scripts(spaces.devel, spaces.source)
        margs, notes = bounded_make_args(make_args, _cpu_count())
        for note in notes:
            out(note)
        cmd = [shown_make, *margs]
        paths = [spaces.build / by_name[n].relpath for n in pkgs] or [spaces.build]
        for path in paths:
            _banner(out, cmd, path)
            if runner.run([make, *margs], path) != 0:
                for hint in _hints(runner.tail, _known_message_packages(spaces.build), packages):
                    out(hint)
                err(f'Invoking "{" ".join(cmd)}" failed')
                return 1
    except _TimedOut:
        err(f"catkin_make: stopped: the build ran past its time limit of {args.timeout:g} s "
            "(--timeout SECONDS sets it)")
        return 1
    return 0


def _known_message_packages(build: Path) -> list[str]:
    """The message packages the last configure listed (from its workspace.cmake)."""
    try:
        text = (build / "ddes_catkin" / "workspace.cmake").read_text(encoding="utf-8")
    except OSError:
        return []
    m = re.search(r'^set\(DDES_MESSAGE_PACKAGES "([^"]*)"\)', text, re.M)
    return m.group(1).split(";") if m else []


# -- catkin build (catkin_tools) -------------------------------------------------------------------
def _find_workspace(start: Path) -> Path | None:
    here = start.absolute()
    for marker in (".catkin_tools", _WORKSPACE_MARKER):
        for folder in [here, *here.parents]:
            if (folder / marker).exists() and (folder / "src").is_dir():
                return folder
    for folder in [here, *here.parents]:
        if (folder / "src").is_dir() and (folder / "src" / "CMakeLists.txt").exists():
            return folder
    return here if (here / "src").is_dir() else None


def _catkin_build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="catkin build",
        description="Build the packages of a catkin workspace (catkin_tools' command, with "
                    "ddes's catkin: one build space for the whole workspace, as catkin_make).")
    add = parser.add_argument
    add("packages", nargs="*", metavar="PKGNAME", help="packages to build (default: all)")
    add("-w", "--workspace", help="the workspace (default: found from the current folder)")
    add("--no-deps", action="store_true", help="build the given packages without dependencies")
    add("-j", "--jobs", type=int, help="maximum make jobs (at most the machine's CPUs)")
    add("--force-cmake", action="store_true", help="run cmake even if it has run before")
    add("-v", "--verbose", action="store_true", help="show every package's make output")
    add("--cmake-args", nargs="*", default=[], help="arguments for cmake")
    add("--make-args", nargs="*", default=[], help="arguments for make")
    add("--timeout", type=float, default=DEFAULT_TIMEOUT_S, metavar="SECONDS",
        help=f"ddes: stop after SECONDS of wall time (default {DEFAULT_TIMEOUT_S:g})")
    return parser


def catkin_build(argv: Sequence[str], *, cwd: str | os.PathLike[str] | None = None,
                 out: Write = print, err: Write | None = None,
                 environ: Mapping[str, str] | None = None) -> int:
    """catkin_tools' ``catkin build [PKG...]`` on ddes's catkin; the exit code."""
    err = err or (lambda line: print(line, file=sys.stderr))
    environ = dict(os.environ if environ is None else environ)
    rest, sections = _split_sections(list(argv), ("--cmake-args", "--make-args"))
    try:
        args = _catkin_build_parser().parse_args(rest)
    except SystemExit as exc:
        return int(exc.code or 0)
    args.cmake_args = sections["--cmake-args"]
    args.make_args = sections["--make-args"]
    here = Path(cwd or os.getcwd())
    base = Path(os.path.abspath(here / args.workspace)) if args.workspace else \
        _find_workspace(here)
    if base is None or not (base / "src").is_dir():
        err("[build] Error: Unable to find a catkin workspace (a folder holding src/) from "
            f"'{here}': run catkin build in the workspace, or give it with --workspace")
        return 1
    try:
        return _catkin_build(args, base, out, err, environ)
    except CatkinError as exc:
        err(f"[build] Error: {exc}")
        return 1


def _catkin_build(args: argparse.Namespace, base: Path, out: Write, err: Write,
                  environ: dict[str, str]) -> int:
    started = time.monotonic()
    spaces = _Spaces(base, base / "src", base / "build", base / "devel", base / "install")
    rule = "-" * 62

    def state(p: Path) -> str:
        return "[exists]" if p.exists() else "[missing]"

    out(rule)
    out(f"{'Profile:':<29}default")
    out(f"{'Extending:':<29}None (ddes's catkin and roscpp)")
    out(f"{'Workspace:':<29}{base}")
    out(rule)
    out(f"{'Build Space:':<20}{state(spaces.build):<10} {spaces.build}")
    out(f"{'Devel Space:':<20}{state(spaces.devel):<10} {spaces.devel}")
    out(f"{'Install Space:':<20}{'[unused]':<10} {spaces.install}")
    out(f"{'Source Space:':<20}{state(spaces.source):<10} {spaces.source}")
    out(rule)
    for space in (spaces.build, spaces.devel):
        previous = _previous_tool(space)
        if previous is not None and previous not in ("catkin_make", "catkin build (ddes)"):
            err(f"[build] Error: the space '{space}' was built by '{previous}': remove it "
                "(catkin clean) and build again")
            return 1
    tools = _check_tools(environ, spaces.build, "make", err)
    if tools is None:
        return 1
    cmake, make, compiler = tools
    foreign = _foreign_cache(spaces.build)
    if foreign is not None:
        err(f"[build] Error: the build space '{spaces.build}' was configured by another catkin "
            f"(for '{foreign}'): run catkin clean, then build again")
        return 1
    t0 = time.monotonic()
    packages = topological_order([p for p in find_packages(spaces.source)
                                  if (p.path / "CMakeLists.txt").is_file()
                                  and p.build_type == "catkin"])
    out(f"[build] Found '{len(packages)}' packages in {time.monotonic() - t0:.1f} seconds.")
    names = [p.name for p in packages]
    unknown = [n for n in args.packages if n not in names]
    if unknown:
        err(f"[build] Error: Given packages {unknown} are not in the workspace.")
        return 1
    if args.packages:
        keep = set(args.packages) if args.no_deps else \
            set(dependency_closure(packages, args.packages))
        todo = [p for p in packages if p.name in keep]
    else:
        todo = list(packages)
    spaces.build.mkdir(parents=True, exist_ok=True)
    _mark(spaces.build, "catkin_make")
    _mark(spaces.devel, "catkin_make")
    runner = _Runner(out=out, env=_make_env(environ),
                     deadline=time.monotonic() + max(args.timeout, 0.0))
    configure = _configure_args(spaces, list(args.cmake_args), "Unix Makefiles", environ)
    force = _input_changed(find_packages(spaces.source), spaces.build, configure[1:])
    margs, notes = bounded_make_args(
        [*args.make_args, *([f"-j{args.jobs}"] if args.jobs else [])], _cpu_count())
    for note in notes:
        out(note)
    succeeded: list[str] = []
    failed: list[str] = []
    warned: list[str] = []
    abandoned: list[str] = []
    try:
        if not (spaces.build / "Makefile").exists() or args.force_cmake or force:
            lines: list[str] = []
            out("Starting  >>> (workspace) cmake")
            code = runner.run([cmake, *configure], spaces.build, out=lines.append)
            if code != 0:
                out("Errors     << (workspace):cmake")
                for line in lines:
                    out(line)
                out(f"Failed     << (workspace):cmake  [ Exited with code {code} ]")
                failed.append("(workspace)")
                abandoned = [p.name for p in todo]
                todo = []
        _setup_scripts(spaces.devel, spaces.source)
        _write_if_changed(spaces.base / _WORKSPACE_MARKER,
                          "# This file currently only serves to mark the location of a catkin "
                          "workspace for tool integration\n")
        for index, pkg in enumerate(todo):
            out(f"Starting  >>> {pkg.name}")
            t_pkg = time.monotonic()
            lines = []
            code = runner.run([make, *margs], spaces.build / pkg.relpath, out=lines.append)
            took = time.monotonic() - t_pkg
            if code != 0:
                out(f"Errors     << {pkg.name}:make")
                for line in lines:
                    out(line)
                for hint in _hints(lines, _known_message_packages(spaces.build), packages):
                    out(hint)
                out(f"Failed     << {pkg.name}:make{'':<10}[ Exited with code {code} ]")
                failed.append(pkg.name)
                for later in todo[index + 1:]:
                    out(f"Abandoned <<< {later.name:<20}[ Unrelated job failed ]")
                    abandoned.append(later.name)
                break
            shown = lines if args.verbose else [ln for ln in lines if "warning:" in ln]
            if shown:
                if not args.verbose:
                    warned.append(pkg.name)
                    out(f"Warnings   << {pkg.name}:make")
                for line in shown:
                    out(line)
            out(f"Finished  <<< {pkg.name:<20}[ {took:.1f} seconds ]")
            succeeded.append(pkg.name)
    except _TimedOut:
        err(f"[build] Error: stopped: the build ran past its time limit of {args.timeout:g} s "
            "(--timeout SECONDS sets it)")
        return 1
    total = len(succeeded) + len([f for f in failed if f != "(workspace)"]) + len(abandoned)
    if not failed:
        out(f"[build] Summary: All {len(succeeded)} packages succeeded!")
    else:
        out(f"[build] Summary: {len(succeeded)} of {total} packages succeeded.")
    out("[build]   Ignored:   None.")
    out(f"[build]   Warnings:  {f'{len(warned)} packages succeeded with warnings.' if warned else 'None.'}")
    out(f"[build]   Abandoned: {f'{len(abandoned)} packages were abandoned.' if abandoned else 'None.'}")
    out(f"[build]   Failed:    {f'{len(failed)} packages failed.' if failed else 'None.'}")
    out(f"[build] Runtime: {time.monotonic() - started:.1f} seconds total.")
    return 1 if failed else 0


def catkin_clean(argv: Sequence[str], *, cwd: str | os.PathLike[str] | None = None,
                 out: Write = print, err: Write | None = None) -> int:
    """``catkin clean [-y]``: remove the build, devel and install spaces ddes built."""
    err = err or (lambda line: print(line, file=sys.stderr))
    parser = argparse.ArgumentParser(prog="catkin clean",
                                     description="Remove the workspace's build products.")
    parser.add_argument("-y", "--yes", action="store_true", help="do not ask (ddes never asks)")
    parser.add_argument("-w", "--workspace")
    try:
        args = parser.parse_args(list(argv))
    except SystemExit as exc:
        return int(exc.code or 0)
    here = Path(cwd or os.getcwd())
    base = Path(os.path.abspath(here / args.workspace)) if args.workspace else \
        _find_workspace(here)
    if base is None:
        err(f"[clean] Error: no catkin workspace at or above '{here}'")
        return 1
    removed = False
    for label, name in (("buildspace", "build"), ("develspace", "devel"),
                        ("installspace", "install"), ("logspace", "logs")):
        space = base / name
        if not space.is_dir():
            continue
        if name in ("build", "devel") and _previous_tool(space) is None:
            err(f"[clean] Error: '{space}' was not made by catkin (no {_BUILT_BY}); remove it "
                "yourself if it should go")
            return 1
        out(f"[clean] Removing {label}: {space}")
        shutil.rmtree(space)
        removed = True
    if not removed:
        out("[clean] Nothing to be cleaned for the workspace.")
    return 0


def catkin_tool(argv: Sequence[str], *, cwd: str | os.PathLike[str] | None = None,
                out: Write = print, err: Write | None = None,
                environ: Mapping[str, str] | None = None) -> int:
    """catkin_tools' ``catkin VERB ...``: build, clean, init."""
    err = err or (lambda line: print(line, file=sys.stderr))
    argv = list(argv)
    if not argv or argv[0] in ("-h", "--help"):
        out("usage: catkin [-h] VERB ...\n\ncatkin command (ddes): build, clean, init")
        return 0 if argv else 2
    verb, rest = argv[0], argv[1:]
    if verb == "build":
        return catkin_build(rest, cwd=cwd, out=out, err=err, environ=environ)
    if verb == "clean":
        return catkin_clean(rest, cwd=cwd, out=out, err=err)
    if verb == "init":
        base = Path(cwd or os.getcwd())
        (base / ".catkin_tools").mkdir(exist_ok=True)
        out(f"Initializing catkin workspace in `{base}`.")
        return 0
    err(f"catkin: error: '{verb}' is not a verb ddes's catkin offers (build, clean, init)")
    return 2


# -- python -m ddes.roscpp.catkin ------------------------------------------------------------------
def main(argv: Sequence[str] | None = None) -> int:
    """The CMake side's helpers (``scan``, ``genmsg``, ``library``) and the ``catkin_make`` and
    ``catkin`` commands."""
    argv = list(sys.argv[1:] if argv is None else argv)
    if argv and argv[0] == "catkin_make":
        return catkin_make(argv[1:])
    if argv and argv[0] == "catkin":
        return catkin_tool(argv[1:])
    parser = argparse.ArgumentParser(prog="python -m ddes.roscpp.catkin")
    sub = parser.add_subparsers(dest="verb", required=True)
    p = sub.add_parser("scan", help="list the workspace's packages for CMake")
    p.add_argument("--source", required=True)
    p.add_argument("--build", required=True)
    p.add_argument("--devel", required=True)
    p.add_argument("--cmake-dir", required=True)
    p.add_argument("--whitelist", default="")
    p.add_argument("--blacklist", default="")
    g = sub.add_parser("genmsg", help="write a workspace package's message headers")
    g.add_argument("--package", required=True)
    g.add_argument("--source", required=True)
    g.add_argument("--devel-include", required=True)
    g.add_argument("--gencpp-include", required=True)
    g.add_argument("--stamp")
    g.add_argument("--dependencies", nargs="*", default=[])
    g.add_argument("--types", nargs="*", default=[])
    b = sub.add_parser("library", help="build ddes's roscpp for this machine (once)")
    b.add_argument("--cache-dir", required=True)
    b.add_argument("--cmake", required=True)
    b.add_argument("--compiler", required=True)
    b.add_argument("--result", required=True, help="file to write the export file's path to")
    b.add_argument("--define", action="append", default=[], metavar="-DVAR=VALUE",
                   help="an argument for the library's CMake (--define=-DVAR=VALUE)")
    args = parser.parse_args(argv)
    try:
        if args.verb == "scan":
            note = scan(Path(args.source), Path(args.build), Path(args.devel),
                        Path(args.cmake_dir), whitelist=_split_cmake_list(args.whitelist),
                        blacklist=_split_cmake_list(args.blacklist))
            if note:
                print(note)
        elif args.verb == "library":
            targets = build_library(Path(args.cache_dir), args.cmake, args.compiler,
                                    args.define, out=lambda line: print(line, flush=True))
            Path(args.result).write_text(str(targets), encoding="utf-8")
        else:
            genmsg(args.package, Path(args.source), Path(args.devel_include),
                   Path(args.gencpp_include), args.types, args.dependencies,
                   Path(args.stamp) if args.stamp else None)
    except DdesError as exc:
        print(f"ddes catkin: {exc}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
