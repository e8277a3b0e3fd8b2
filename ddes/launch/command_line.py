"""The ``roslaunch`` command line: ``roslaunch PKG FILE.launch a:=1`` or ``roslaunch PATH``.

:func:`resolve_launch_args` mirrors ``roslaunch.rlutil.resolve_launch_arguments``
plus ``rosgraph.names.load_mappings``: it finds the launch file and collects
the ``name:=value`` args that :func:`~ddes.launch.load_launch` takes.
"""

from __future__ import annotations

import os
from collections.abc import Sequence
from pathlib import Path

from ddes.errors import ROSInitException, ROSLaunchException
from ddes.graph.names import is_legal_remap, load_mappings
from ddes.launch.substitution import PackageFinder
from ddes.rospack import PackageNotFound, RosPack

__all__ = ["resolve_launch_args"]


def resolve_launch_args(
    argv: Sequence[str], rospack: PackageFinder | None = None
) -> tuple[str, dict[str, str]]:
    """Split ``roslaunch`` arguments (without the program name) into (file, args).

    Accepts ``PKG FILE.launch [arg:=value ...]`` (the file is searched for
    by name anywhere in the package, as ``roslib.packages.find_resource``)
    and ``PATH [arg:=value ...]``, with roslaunch's error wording.
    """
    try:
        args = load_mappings(argv)
    except ROSInitException as exc:
        raise ROSLaunchException(str(exc)) from None
    words = [a for a in argv if not is_legal_remap(a)]
    if not words:
        raise ROSLaunchException(
            "no launch file given: use 'roslaunch PKG FILE.launch [arg:=value ...]' or "
            "'roslaunch PATH [arg:=value ...]'"
        )
    finder = rospack if rospack is not None else RosPack()
    if len(words) >= 2:
        try:
            matches = _find_resource(Path(finder.get_path(words[0])), words[1])
        except PackageNotFound:
            matches = []
        if len(matches) > 1:
            listing = "".join(f"\n- {m}" for m in matches)
            raise ROSLaunchException(
                f"multiple files named [{words[1]}] in package [{words[0]}]:{listing}\n"
                "Please specify full path instead"
            )
        if matches:
            return _only_path(matches[0], words[2:]), args
    if os.path.isfile(words[0]):
        return _only_path(words[0], words[1:]), args
    if len(words) >= 2:
        raise ROSLaunchException(
            f"[{words[1]}] is neither a launch file in package [{words[0]}] nor is "
            f"[{words[0]}] a launch file name"
        )
    raise ROSLaunchException(f"[{words[0]}] is not a launch file name")


def _only_path(path: str, extra: Sequence[str]) -> str:
    if extra:
        raise ROSLaunchException(
            f"unexpected arguments {list(extra)} after the launch file; ddes loads one launch "
            "file at a time and args are written name:=value"
        )
    return path


def _find_resource(pkg_dir: Path, name: str) -> list[str]:
    """Files called ``name`` under ``pkg_dir`` (hidden folders skipped), in a stable order."""
    found: list[str] = []
    for folder, dirs, files in os.walk(pkg_dir, followlinks=True):
        dirs[:] = sorted(d for d in dirs if not d.startswith("."))
        if name in files:
            found.append(os.path.abspath(os.path.join(folder, name)))
    return found
