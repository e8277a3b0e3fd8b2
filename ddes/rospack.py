"""Packages on a package path, as rospack/rospkg find them.

A *package* is a folder holding a ``package.xml`` or any of the folders
``msg/``, ``srv/``, ``action/`` (so a plain folder of message definitions
counts).  The package path is a list of folders searched in order; each
folder is either a package itself or is searched recursively for packages
(not descending into a package).  The first package of a name wins, as with
``ROS_PACKAGE_PATH``.

The path is: the folders given explicitly, then those in the environment
variable ``DDES_PACKAGE_PATH`` (``os.pathsep``-separated), then ddes's
bundled packages.  ddes does not read ``ROS_PACKAGE_PATH``, so a machine's
real ROS install never changes a simulation.
"""

from __future__ import annotations

import os
from collections.abc import Iterable
from pathlib import Path

from ddes.errors import DdesError

__all__ = ["BUNDLED_PATH", "PackageNotFound", "RosPack", "is_package"]

#: Folder of the packages that ship with ddes.
BUNDLED_PATH = Path(__file__).resolve().parent / "packages"

_MARKERS = ("package.xml", "msg", "srv", "action")


class PackageNotFound(DdesError):
    """No package of that name on the package path (rospkg.ResourceNotFound)."""


def is_package(folder: Path) -> bool:
    """True if ``folder`` is a package (has package.xml, msg/, srv/ or action/)."""
    return any((folder / m).exists() for m in _MARKERS)


class RosPack:
    """Finds packages by name on a package path (``rospack find``)."""

    def __init__(self, paths: Iterable[str | os.PathLike[str]] = (), *, use_env: bool = True,
                 bundled: bool = True) -> None:
        entries: list[Path] = [Path(p) for p in paths]
        if use_env:
            env = os.environ.get("DDES_PACKAGE_PATH", "")
            entries += [Path(p) for p in env.split(os.pathsep) if p]
        if bundled:
            entries.append(BUNDLED_PATH)
        self.paths: list[Path] = entries
        self._index: dict[str, Path] | None = None

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
                f"package '{name}' not found; searched: {searched}. Add its parent folder "
                "to DDES_PACKAGE_PATH or pass it on the package path"
            ) from None

    def __contains__(self, name: str) -> bool:
        if self._index is None:
            self._index = self._scan()
        return name in self._index
