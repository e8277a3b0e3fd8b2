"""Packages on a package path, as rospack/rospkg find them.

A *package* is a folder holding a ``package.xml`` or any of the folders
``msg/``, ``srv/``, ``action/`` (so a plain folder of message definitions
counts).  The package path is a list of folders searched in order; each
folder is either a package itself or is searched recursively for packages
(not descending into a package).  The first package of a name wins, as with
``ROS_PACKAGE_PATH``.

The path is: the folders given explicitly, then ddes's bundled packages.
The environment is never read behind the caller's back: only
:meth:`RosPack.from_environment` (or an explicit ``use_env=True``) adds the
folders of ``DDES_PACKAGE_PATH`` (``os.pathsep``-separated), after the
explicit ones.  ddes does not read ``ROS_PACKAGE_PATH``, so a machine's real
ROS install never changes a simulation.
"""

from __future__ import annotations

import os
from collections.abc import Iterable, Mapping
from pathlib import Path

from ddes.errors import DdesError

__all__ = ["BUNDLED_PATH", "PACKAGE_PATH_VAR", "PackageNotFound", "RosPack", "env_package_path",
           "is_package"]

#: Folder of the packages that ship with ddes.
BUNDLED_PATH = Path(__file__).resolve().parent / "packages"

#: The environment variable read by the ``from_environment`` constructors.
PACKAGE_PATH_VAR = "DDES_PACKAGE_PATH"

_MARKERS = ("package.xml", "msg", "srv", "action")


class PackageNotFound(DdesError):
    """No package of that name on the package path (rospkg.ResourceNotFound)."""


def env_package_path(environ: Mapping[str, str]) -> list[Path]:
    """The folders of ``DDES_PACKAGE_PATH`` in ``environ`` (``os.pathsep``-separated)."""
    return [Path(p) for p in environ.get(PACKAGE_PATH_VAR, "").split(os.pathsep) if p]


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
                    index.setdefault(folder.name, folder)
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
                f"package '{name}' not found; searched: {searched}. Pass its parent folder "
                "on the package path (RosPack(paths), World(package_path=[...]), or "
                "DDES_PACKAGE_PATH read by RosPack.from_environment())"
            ) from None

    def __contains__(self, name: str) -> bool:
        if self._index is None:
            self._index = self._scan()
        return name in self._index
