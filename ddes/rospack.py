"""Packages on a package path, as rospack/rospkg find them.

A *package* is a folder holding a ``package.xml`` or any of the folders
``msg/``, ``srv/``, ``action/`` (so a plain folder of message definitions
counts).  The package path is a list of folders searched in order; each
folder is either a package itself or is searched recursively for packages
(not descending into a package).  The first package of a name wins, as with
``ROS_PACKAGE_PATH``.

A package's name is its ``package.xml``'s ``<name>`` (as rospkg reads it; the folder
may be named otherwise), or the folder's name where there is no package.xml.

The path is: the folders given explicitly, then ddes's bundled packages.
The environment is never read behind the caller's back: only
:meth:`RosPack.from_environment` (or an explicit ``use_env=True``) adds the
folders of ``DDES_PACKAGE_PATH`` (``os.pathsep``-separated), after the
explicit ones.  ddes does not read ``ROS_PACKAGE_PATH``, so a machine's real
ROS install never changes a simulation.  The ``ddes`` command's path
(:func:`command_package_path`) adds what a ROS user's ``source devel/setup.bash`` would: the
catkin workspace it is started in (its ``src/``) and the folder it is started in when that holds
packages.
"""

from __future__ import annotations

import os
import stat
from collections.abc import Iterable, Mapping
from pathlib import Path
from xml.parsers import expat

from ddes.errors import DdesError, ResourceLimitError

__all__ = ["BUNDLED_PATH", "DEPEND_TAGS", "MAX_MANIFEST_BYTES", "PACKAGE_PATH_VAR",
           "InvalidManifest", "PackageNotFound", "RosPack", "command_package_path",
           "env_package_path", "is_package", "working_folder_paths", "workspace_of"]

#: Folder of the packages that ship with ddes.
BUNDLED_PATH = Path(__file__).resolve().parent / "packages"

#: The environment variable read by the ``from_environment`` constructors.
PACKAGE_PATH_VAR = "DDES_PACKAGE_PATH"

_MARKERS = ("package.xml", "msg", "srv", "action")

#: The ``package.xml`` elements rospack reads run-time dependencies from, in its order.
DEPEND_TAGS = ("run_depend", "exec_depend", "depend")

#: The largest ``package.xml`` ddes reads (a real one is a few KiB).
MAX_MANIFEST_BYTES = 1 << 20


class PackageNotFound(DdesError):
    """No package of that name on the package path (rospkg.ResourceNotFound)."""


class InvalidManifest(DdesError):
    """A ``package.xml`` that cannot be read: malformed XML, or a package depending on itself.

    ``rospack_text`` is what rospack prints for the problem (after ``[rospack] Error: ``).
    """

    def __init__(self, message: str, rospack_text: str | None = None) -> None:
        super().__init__(message)
        self.rospack_text = rospack_text or message


def env_package_path(environ: Mapping[str, str]) -> list[Path]:
    """The folders of ``DDES_PACKAGE_PATH`` in ``environ`` (``os.pathsep``-separated)."""
    return [Path(p) for p in environ.get(PACKAGE_PATH_VAR, "").split(os.pathsep) if p]


#: How far up from the working folder a catkin workspace is looked for, and the most entries
#: looked at below it for packages (a home folder is not searched).
WORKSPACE_UP = 32
LOOK_BELOW_ENTRIES = 2_000


def workspace_of(folder: Path) -> Path | None:
    """The catkin workspace ``folder`` is in (it or an ancestor holds ``src/`` beside
    ``devel/``, ``build/`` or ``.catkin_workspace``, or ``src/CMakeLists.txt``), or None."""
    here = Path(folder).absolute()
    for _ in range(WORKSPACE_UP):
        src = here / "src"
        if src.is_dir() and any((here / m).exists() for m in (
                "devel", "build", ".catkin_workspace", "src/CMakeLists.txt")):
            return here
        if here.parent == here:
            return None
        here = here.parent
    return None


def working_folder_paths(cwd: str | os.PathLike[str]) -> list[Path]:
    """The package folders a ROS user expects found from the folder a command starts in, as
    ``source devel/setup.bash`` finds them: the catkin workspace's ``src/`` (``cwd`` or an
    ancestor being the workspace, or inside it), and ``cwd`` itself when it is a package or
    holds packages one or two levels down (an exercise folder).  A large folder (a home) is not
    searched: only its first :data:`LOOK_BELOW_ENTRIES` entries are looked at."""
    here = Path(cwd).absolute()
    found: list[Path] = []
    ws = workspace_of(here)
    if ws is not None:
        found.append(ws / "src")
    if is_package(here) or _packages_below(here):
        if not any(here == p or p in here.parents for p in found):
            found.append(here)
    return found


def _packages_below(folder: Path) -> bool:
    seen = 0
    level = [folder]
    for _depth in range(2):
        nxt: list[Path] = []
        for base in level:
            try:
                entries = sorted(os.scandir(base), key=lambda e: e.name)
            except OSError:
                continue
            for e in entries:
                seen += 1
                if seen > LOOK_BELOW_ENTRIES:
                    return False
                if e.name.startswith(".") or not e.is_dir():
                    continue
                child = Path(e.path)
                if (child / "package.xml").is_file():
                    return True
                nxt.append(child)
        level = nxt
    return False


def command_package_path(environ: Mapping[str, str], cwd: str | os.PathLike[str]) -> list[Path]:
    """The package path of a ``ddes`` command: the folders of ``DDES_PACKAGE_PATH``, then those
    found from the working folder (:func:`working_folder_paths`).  ddes's bundled packages
    come after these in every :class:`RosPack`."""
    paths = env_package_path(environ)
    for p in working_folder_paths(cwd):
        if p not in paths:
            paths.append(p)
    return paths


def is_package(folder: Path) -> bool:
    """True if ``folder`` is a package (has package.xml, msg/, srv/ or action/)."""
    return any((folder / m).exists() for m in _MARKERS)


class RosPack:
    """Finds packages by name on a package path (``rospack find``).

    The path is ``paths`` then, unless ``bundled=False``, ddes's bundled
    packages.  ``use_env=True`` (default False) inserts the folders of
    ``DDES_PACKAGE_PATH`` after ``paths``, reading ``os.environ`` once, here;
    prefer :meth:`from_environment`, which says so at the call site.  The
    path is fixed at construction (``paths`` is a tuple).
    """

    def __init__(self, paths: Iterable[str | os.PathLike[str]] = (), *, use_env: bool = False,
                 bundled: bool = True) -> None:
        entries: list[Path] = [Path(p) for p in paths]
        if use_env:
            entries += env_package_path(os.environ)
        if bundled:
            entries.append(BUNDLED_PATH)
        self.paths: tuple[Path, ...] = tuple(entries)
        self._index: dict[str, Path] | None = None
        self._python: tuple[Path, ...] | None = None

    @classmethod
    def from_environment(cls, environ: Mapping[str, str] = os.environ, *,
                         paths: Iterable[str | os.PathLike[str]] = (),
                         bundled: bool = True) -> RosPack:
        """``paths``, then the folders of ``DDES_PACKAGE_PATH`` in ``environ``, then bundled.

        The only way ddes reads the package path from the environment: the
        variable is read once, by this call.
        """
        return cls([*paths, *env_package_path(environ)], bundled=bundled)

    def __repr__(self) -> str:
        return f"RosPack({[str(p) for p in self.paths]!r}, bundled=False)"

    def _scan(self) -> dict[str, Path]:
        index: dict[str, Path] = {}
        for root in self.paths:
            if not root.is_dir():
                continue
            stack = [root]
            while stack:
                folder = stack.pop()
                if is_package(folder):
                    index.setdefault(_package_name(folder), folder)
                    continue
                try:
                    children = sorted(p for p in folder.iterdir() if p.is_dir())
                except OSError:
                    continue
                stack.extend(reversed([c for c in children if not c.name.startswith(".")]))
        return index

    def refresh(self) -> None:
        """Forget the cached index (after adding packages on disk)."""
        self._index = None
        self._python = None

    def depends1(self, name: str) -> list[str]:
        """The direct dependencies of package ``name`` (``rospack depends1``), in rospack's order.

        The names of the ``<run_depend>``, then ``<exec_depend>``, then
        ``<depend>`` children of its ``package.xml`` (whitespace stripped,
        each name once); a package without ``package.xml`` (a folder of
        definitions) has none.  Names that are not on the path are kept:
        the caller decides (rospack skips those rosdep knows as system
        packages).  :class:`PackageNotFound` for an unknown ``name``,
        :class:`InvalidManifest` for a malformed file or a package that
        depends on itself, :class:`~ddes.errors.ResourceLimitError` for a
        ``package.xml`` over :data:`MAX_MANIFEST_BYTES`.
        """
        return _declared_depends(self.get_path(name) / "package.xml", name)

    def list(self) -> list[str]:
        """Names of all packages on the path, sorted."""
        if self._index is None:
            self._index = self._scan()
        return sorted(self._index)

    def get_path(self, name: str) -> Path:
        """The folder of package ``name`` (``$(find name)``)."""
        if self._index is None:
            self._index = self._scan()
        try:
            return self._index[name]
        except KeyError:
            searched = ", ".join(str(p) for p in self.paths) or "(empty path)"
            raise PackageNotFound(
                f"package '{name}' not found; searched: {searched}. Start ddes in the folder "
                "that holds the package (or in its catkin workspace), or put its parent folder "
                "on the package path: DDES_PACKAGE_PATH=/path/to/parent (in Python: "
                "RosPack(paths), World(package_path=[...]))"
            ) from None

    def python_folders(self) -> tuple[Path, ...]:
        """The Python folders a built workspace puts on a node's path (catkin_python_setup).

        A package on the path (the bundled ones aside) whose ``CMakeLists.txt`` calls
        ``catkin_python_setup()`` and which has a ``setup.py`` gets its modules installed into
        the devel space's ``dist-packages`` by ``catkin_make``, so any node imports them by
        name.  ddes builds nothing: it returns the package's folder of Python packages in the
        source tree instead, ``package_dir``'s root as the ``setup.py`` names it (read with
        :func:`_setup_package_root`, never run), ``src`` by default.  In package order; read
        once, until :meth:`refresh`.
        """
        if self._python is not None:
            return self._python
        if self._index is None:
            self._index = self._scan()
        folders = []
        for name in sorted(self._index):
            root = self._index[name]
            if root.is_relative_to(BUNDLED_PATH):
                continue
            if _calls_catkin_python_setup(root / "CMakeLists.txt") and (root / "setup.py").is_file():
                folder = root / _setup_package_root(root / "setup.py")
                if folder.is_dir() and folder not in folders:
                    folders.append(folder)
        self._python = tuple(folders)
        return self._python

    def __contains__(self, name: str) -> bool:
        if self._index is None:
            self._index = self._scan()
        return name in self._index


def _package_name(folder: Path) -> str:
    """A package's name as rospkg reads it: package.xml's ``<name>``; the folder's name for a
    folder without one (a plain folder of message definitions) or whose package.xml cannot be
    read (its errors are raised where the manifest is used: ``rospack depends``)."""
    manifest = folder / "package.xml"
    if not manifest.is_file():
        return folder.name
    try:
        texts = _top_level_texts(manifest, folder.name)
    except DdesError:
        return folder.name
    name = next((text.strip() for tag, text in texts if tag == "name"), "")
    return name or folder.name


def _declared_depends(manifest: Path, name: str) -> list[str]:
    """The run-time dependencies ``manifest`` (package ``name``'s package.xml) declares."""
    if not manifest.is_file():
        return []
    found: dict[str, list[str]] = {tag: [] for tag in DEPEND_TAGS}
    for tag, text in _top_level_texts(manifest, name):
        if tag in found:
            found[tag].append(text.strip())
    names: list[str] = []
    for tag in DEPEND_TAGS:
        for dep in found[tag]:
            if dep == name:
                raise InvalidManifest(
                    f"package '{name}' depends on itself ({manifest}: <{tag}>{dep}</{tag}>); "
                    "remove that element", f"package '{name}' depends on itself")
            if dep and dep not in names:
                names.append(dep)
    return names


def _top_level_texts(manifest: Path, name: str) -> list[tuple[str, str]]:
    """``(tag, text)`` of each child of the root element of ``manifest`` (a package.xml)."""
    where = f"manifest of package {name} at {manifest}"
    try:
        st = manifest.stat()
    except OSError as exc:
        raise InvalidManifest(f"cannot read the {where}: {exc.strerror or exc}") from None
    if not stat.S_ISREG(st.st_mode):
        raise InvalidManifest(f"the {where} is not a regular file")
    if st.st_size > MAX_MANIFEST_BYTES:
        raise ResourceLimitError(
            f"the {where} has {st.st_size} bytes, more than {MAX_MANIFEST_BYTES} (the most ddes "
            "reads of a package.xml); a package.xml lists a package's metadata only")
    with open(manifest, "rb") as f:
        data = f.read(MAX_MANIFEST_BYTES + 1)
    if len(data) > MAX_MANIFEST_BYTES:
        raise ResourceLimitError(f"the {where} grew past {MAX_MANIFEST_BYTES} bytes while read")
    parser = expat.ParserCreate()
    depth = [0]
    children: list[tuple[str, str]] = []
    text: list[str] = []

    def doctype(doc: str, *_: object) -> None:
        raise InvalidManifest(f"error parsing {where}: <!DOCTYPE {doc}> is not allowed (ddes "
                              "refuses DTDs and entities); remove it", f"error parsing {where}")

    def start(tag: str, _attrs: object) -> None:
        depth[0] += 1
        if depth[0] == 2:
            children.append((tag, ""))
            text.clear()

    def end(tag: str) -> None:
        if depth[0] == 2:
            children[-1] = (tag, "".join(text))
        depth[0] -= 1

    def chars(data: str) -> None:
        if depth[0] == 2:
            text.append(data)

    parser.StartDoctypeDeclHandler = doctype
    parser.StartElementHandler = start
    parser.EndElementHandler = end
    parser.CharacterDataHandler = chars
    try:
        parser.Parse(data, True)
    except expat.ExpatError as exc:
        raise InvalidManifest(
            f"error parsing {where}: {expat.ErrorString(exc.code)} (line {exc.lineno}, column "
            f"{exc.offset}); fix the XML", f"error parsing {where}") from None
    return children


def _calls_catkin_python_setup(cmakelists: Path) -> bool:
    """Whether a ``CMakeLists.txt`` calls ``catkin_python_setup()`` outside a comment (CMake's
    command names ignore case and take blanks before the parenthesis).  A file over
    :data:`MAX_MANIFEST_BYTES` is not read: no package's build file is that large."""
    try:
        if cmakelists.stat().st_size > MAX_MANIFEST_BYTES:
            return False
        text = cmakelists.read_text(encoding="utf-8", errors="replace")
    except OSError:
        return False
    return any("catkin_python_setup(" in "".join(line.split("#", 1)[0].split()).lower()
               for line in text.splitlines())


def _setup_package_root(setup_py: Path) -> str:
    """The folder of ``package_dir={'': ROOT}`` in a ``setup.py`` (``src`` when it is not a
    literal there): the file is parsed, never executed."""
    import ast

    try:
        if setup_py.stat().st_size > MAX_MANIFEST_BYTES:
            return "src"
        tree = ast.parse(setup_py.read_text(encoding="utf-8", errors="replace"))
    except (OSError, SyntaxError, ValueError, RecursionError, MemoryError):
        return "src"
    for node in ast.walk(tree):
        if isinstance(node, ast.keyword) and node.arg == "package_dir" \
                and isinstance(node.value, ast.Dict):
            for key, value in zip(node.value.keys, node.value.values, strict=True):
                if isinstance(key, ast.Constant) and key.value == "" \
                        and isinstance(value, ast.Constant) and isinstance(value.value, str) \
                        and value.value and not Path(value.value).is_absolute() \
                        and ".." not in Path(value.value).parts:
                    return value.value
    return "src"
