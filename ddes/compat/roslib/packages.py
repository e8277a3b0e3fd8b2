"""``roslib.packages`` of ROS Noetic: find packages and the files in them.

Follows Noetic's ``roslib/packages.py`` for what scripts use:

* :func:`get_pkg_dir` the folder of a package as a string (``rospack find``), or, when it is
  not found, ``InvalidROSPkgException`` with Noetic's text (``required=False``: None);
* :func:`find_resource` every file named ``resource_name`` inside a package (a walk that
  follows links and skips folders whose name starts with ``.``), absolute paths, each once;
  rospkg's ``ResourceNotFound`` for an unknown package; :func:`find_node` the same for an
  executable file (user-readable and user-executable);
* the exceptions ``ROSPkgException``, ``InvalidROSPkgException`` (a
  :class:`~ddes.rospack.PackageNotFound` too), ``MultipleNodesException`` and rospkg's
  ``ResourceNotFound`` (also :class:`~ddes.rospack.PackageNotFound`), all
  :class:`~ddes.errors.DdesError`.

Packages are found on the running world's package path (``world.rospack``; outside any
script, ddes's bundled packages).

Deliberate deviations:

* ``ros_root``/``ros_package_path`` of :func:`get_pkg_dir` and ``rospack`` of
  :func:`find_resource` are accepted and ignored: the world's path is the only path; the
  error text shows that path as ``ROS_PACKAGE_PATH[...]`` and ``ROS_ROOT[None]`` (Noetic's
  shows the environment variables, and, as Noetic under Python 3 does, rospack's message as a
  bytes literal ``b"..."``);
* :func:`find_resource` searches the package folder only (a catkin workspace's ``devel``
  ``libexec``/``share`` folders do not exist in ddes), and walks folders and files in sorted
  order, so its answer does not depend on the file system's listing order.
"""

from __future__ import annotations

import os
import stat
from collections.abc import Callable, Sequence
from typing import Any

from ddes.errors import DdesError
from ddes.graph.blocking import current_task
from ddes.rospack import PackageNotFound, RosPack

__all__ = ["InvalidROSPkgException", "MultipleNodesException", "ROSPkgException",
           "ResourceNotFound", "find_node", "find_resource", "get_pkg_dir"]

MANIFEST_FILE = "manifest.xml"
PACKAGE_FILE = "package.xml"


class ROSPkgException(DdesError):
    """Base class of package-related errors (roslib.packages.ROSPkgException)."""


class InvalidROSPkgException(ROSPkgException, PackageNotFound):
    """A ROS package does not exist (roslib.packages.InvalidROSPkgException)."""


class MultipleNodesException(ROSPkgException):
    """Several nodes of one name in one package (roslib.packages.MultipleNodesException)."""


class ResourceNotFound(PackageNotFound):
    """rospkg's ``ResourceNotFound``: the name, then one ``ROS path [i]=...`` line per folder
    of ``ros_paths``."""

    def __init__(self, msg: str, ros_paths: Sequence[str] | None = None) -> None:
        super().__init__(msg)
        self.ros_paths = list(ros_paths) if ros_paths else None

    def __str__(self) -> str:
        text = str(self.args[0])
        for i, path in enumerate(self.ros_paths or ()):
            text += f"\nROS path [{i}]={path}"
        return text


def _rospack() -> RosPack:
    """The packages of the world whose code runs now (ddes's bundled ones outside any)."""
    task = current_task()
    return task.world.rospack if task is not None else RosPack()


def _not_found(rospack: RosPack, pkg: str) -> ResourceNotFound:
    return ResourceNotFound(pkg, [str(p) for p in rospack.paths])


def get_pkg_dir(package: str, required: bool = True, ros_root: str | None = None,
                ros_package_path: str | None = None) -> str | None:
    """The folder of ``package``; None when it is unknown and not ``required``."""
    rospack = _rospack()
    if package in rospack:
        return os.path.normpath(str(rospack.get_path(package)))
    if not required:
        return None
    path = os.pathsep.join(str(p) for p in rospack.paths)
    raise InvalidROSPkgException(
        f"Cannot locate installation of package {package}: "
        f"b\"[rospack] Error: package '{package}' not found\". "
        f"ROS_ROOT[None] ROS_PACKAGE_PATH[{path}]")


def _files_named(folder: str, resource_name: str,
                 filter_fn: Callable[[str], bool] | None) -> list[str]:
    matches: list[str] = []
    for here, dirs, files in os.walk(folder, followlinks=True):
        dirs[:] = sorted(d for d in dirs if not d.startswith("."))
        if resource_name in files:
            path = os.path.join(here, resource_name)
            if filter_fn is None or filter_fn(path):
                matches.append(os.path.abspath(path))
    return matches


def find_resource(pkg: str, resource_name: str, filter_fn: Callable[[str], bool] | None = None,
                  rospack: Any = None) -> list[str]:
    """The paths of the files named ``resource_name`` in package ``pkg`` (those ``filter_fn``
    accepts, if given); ``ResourceNotFound`` for an unknown package."""
    packages = _rospack()
    if pkg not in packages:
        raise _not_found(packages, pkg)
    unique: list[str] = []
    for match in _files_named(str(packages.get_path(pkg)), resource_name, filter_fn):
        if match not in unique:
            unique.append(match)
    return unique


def _executable_filter(test_path: str) -> bool:
    flags = stat.S_IRUSR | stat.S_IXUSR
    return (os.stat(test_path).st_mode & flags) == flags


def find_node(pkg: str, node_type: str, rospack: Any = None) -> list[str]:
    """The executable files named ``node_type`` in package ``pkg``."""
    return find_resource(pkg, node_type, filter_fn=_executable_filter, rospack=rospack)
