"""Compiled node executables: told from scripts, found where catkin puts them, started as
external nodes (:class:`~ddes.roscpp.host.ExternalNode`).

rosrun and roslaunch find a package's executables in its catkin devel space
(``<workspace>/devel/lib/<package>/``, what ``catkin_find --libexec`` lists) and anywhere below
its source folder; :func:`libexec_folders` gives the first.  :func:`is_native` tells a compiled
program (an ELF file) from a script ddes runs in-process.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from pathlib import Path
from typing import TYPE_CHECKING

from ddes.roscpp.host import ExternalNode
from ddes.rospack import workspace_of

if TYPE_CHECKING:
    from ddes.graph.node import Node
    from ddes.graph.world import World

__all__ = ["ELF_MAGIC", "is_native", "libexec_folders", "start_executable"]

ELF_MAGIC = b"\x7fELF"


def is_native(path: str | Path) -> bool:
    """True for a compiled program (an ELF file), which runs as an external node."""
    try:
        with open(path, "rb") as f:
            return f.read(4) == ELF_MAGIC
    except OSError:
        return False


def libexec_folders(package: str, package_dir: Path) -> list[Path]:
    """Where catkin puts ``package``'s executables: ``devel/lib/<package>`` of the workspace
    its source folder is in (none when it is in no workspace or has not been built)."""
    ws = workspace_of(package_dir)
    if ws is None:
        return []
    folder = ws / "devel" / "lib" / package
    return [folder] if folder.is_dir() else []


def start_executable(world: World, path: Path, argv: Sequence[str], *, name: str | None,
                     namespace: str, remappings: dict[str, str] | None, cwd: str | None,
                     print_line: Callable[[str, bool], None] | None = None) -> tuple[
                         ExternalNode, Node | None]:
    """Start the compiled node ``path`` with ``argv``: the host and, once the program called
    ``ros::init``, its node (None when it ended first, e.g. a usage message)."""
    host = ExternalNode(world, [str(path), *argv], name=name, namespace=namespace,
                        remappings=remappings, cwd=cwd, print_line=print_line)
    node = host.start()
    return host, node
