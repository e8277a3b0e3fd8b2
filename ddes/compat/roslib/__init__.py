"""``roslib`` of ROS Noetic for rospy scripts: ``import roslib; roslib.load_manifest("pkg")``.

Follows Noetic's ``roslib`` (ros/ros, ``core/roslib/src/roslib``) in the parts scripts use:

* :func:`load_manifest`: under catkin (every Noetic package) it only checks that the package
  exists and returns None, changing nothing (Noetic's ``_generate_python_path`` short-circuits
  for a catkin package); an unknown package raises rospkg's ``ResourceNotFound``
  (:class:`ddes.compat.roslib.packages.ResourceNotFound`), whose text is the name then one
  ``ROS path [i]=...`` line per folder of the package path;
* :mod:`ddes.compat.roslib.packages`: ``get_pkg_dir``, ``find_resource``, ``find_node`` and the
  exceptions ``ROSPkgException``, ``InvalidROSPkgException``, ``MultipleNodesException``;
* :mod:`ddes.compat.roslib.message`: ``get_message_class``, ``get_service_class`` and the
  message base names (``Message``, ``Time``, ``Duration`` ...);
* :mod:`ddes.compat.roslib.scriptutil` (deprecated in Noetic): ``script_resolve_name``
  (``get_master``/``get_param_server`` raise: ddes has no XML-RPC).

Packages are those of the running world (``world.rospack``: its package path, then ddes's
bundled packages, never ``ROS_PACKAGE_PATH``); message types its registry's
(``world.messages``).  Code outside any script sees the bundled packages and types.

Deliberate deviations: every package counts as a catkin package, so ``load_manifest`` never
changes ``sys.path`` (Noetic's does for a rosbuild package, which ddes cannot have); it keeps
no "bootstrapped" list.  ``set_interactive``/``is_interactive`` (a process-wide flag in Noetic)
and the rosbuild-era submodules (``manifest``, ``stacks``, ``rosenv`` ...) are not provided.
"""

from __future__ import annotations

from ddes.compat.roslib import message, packages
from ddes.compat.roslib.packages import ResourceNotFound, _rospack

__all__ = ["load_manifest", "message", "packages"]

__version__ = "1.7.0"


def load_manifest(package_name: str, bootstrap_version: str = "0.7") -> None:
    """Noetic's ``roslib.load_manifest`` under catkin: nothing to do for an existing package
    (:class:`~ddes.compat.roslib.packages.ResourceNotFound` for an unknown one)."""
    rospack = _rospack()
    if package_name not in rospack:
        raise ResourceNotFound(package_name, [str(p) for p in rospack.paths])
