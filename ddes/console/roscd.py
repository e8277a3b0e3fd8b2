"""``roscd``, ``pwd``, ``cd`` and ``ls``: the console's working directory.

The console keeps its own working directory, ``ctx.cwd`` (the process's
directory is never changed: the console is also used from Python, by
notebooks and graders).  ``roscd`` moves it as rosbash's ``roscd`` does; the
tools that open files (``rosparam load``/``dump``, ``roslaunch PATH``,
``rosbag``) resolve relative paths from it with ``ctx.resolve_path``.

* ``roscd PKG[/SUBDIR]`` goes to the package's folder (``rospack find``) or
  a folder below it; ``roscd: No such package/stack 'x'`` for an unknown
  package.  Without an argument rosbash goes to ``$ROS_WORKSPACE`` or to the
  catkin workspace on ``CMAKE_PREFIX_PATH``; ddes has neither (it reads no
  ``ROS_*`` variable, so a machine's ROS set-up never changes a session) and
  prints rosbash's message for that case.
* ``pwd`` prints the working directory; ``cd [DIR]`` changes it (bash's
  logical ``cd``: ``..`` removes the last component of the path as
  written; no argument is the home directory); ``ls [DIR...]`` lists a
  folder's names one per line, sorted by code point (``ls`` of a pipe in
  the C locale; no options).

A failed ``cd`` (and so a failed ``roscd PKG/SUBDIR``) prints bash's
``bash: cd: DIR: No such file or directory`` and exits 1 (rosbash's
``roscd`` returns 0 after it: ddes stops a script there instead).
"""

from __future__ import annotations

import os
from typing import TYPE_CHECKING

from ddes.errors import ROSConsoleError
from ddes.rospack import PackageNotFound

if TYPE_CHECKING:
    from ddes.console.tooling import ToolContext

__all__ = ["NO_WORKSPACE", "TOOLS", "cd", "ls", "pwd", "roscd"]

#: What rosbash's ``roscd`` prints without an argument when no workspace is known.
NO_WORKSPACE = ("Neither ROS_WORKSPACE is set nor a catkin workspace is listed in "
                "CMAKE_PREFIX_PATH.  Please set ROS_WORKSPACE or source a catkin workspace to "
                "use roscd with no arguments.")

_ROSCD_USAGE = "usage: roscd package\n\nJump to target package."


def _here(ctx: ToolContext) -> str:
    """The console's working directory (the process's until ``cd``/``roscd`` set one)."""
    return ctx.cwd if ctx.cwd is not None else os.getcwd()


def _change(ctx: ToolContext, target: str, shown: str) -> int:
    """bash's ``cd -L``: go to ``target`` (absolute, or relative to the working directory)."""
    path = os.path.normpath(os.path.join(_here(ctx), os.path.expanduser(target)))
    if path.startswith("//"):
        path = "/" + path.lstrip("/")
    if not os.path.exists(path):
        ctx.eprint(f"bash: cd: {shown}: No such file or directory")
        return 1
    if not os.path.isdir(path):
        ctx.eprint(f"bash: cd: {shown}: Not a directory")
        return 1
    if not os.access(path, os.X_OK):
        ctx.eprint(f"bash: cd: {shown}: Permission denied")
        return 1
    ctx.cwd = path
    return 0


def roscd(ctx: ToolContext, argv: list[str]) -> int:
    """``roscd [PKG[/SUBDIR]]`` (see the module docstring)."""
    if (argv and argv[0] == "--help") or len(argv) > 1:
        ctx.print(_ROSCD_USAGE)
        return 0
    if not argv or not argv[0]:
        ctx.print(NO_WORKSPACE)
        return 1
    arg = argv[0]
    rospack = ctx.rospack
    assert rospack is not None
    name, slash, rest = arg.partition("/")
    try:
        folder = str(rospack.get_path(name)) if name else ""
    except PackageNotFound:
        folder = ""
    if not folder:
        ctx.print(f"roscd: No such package/stack '{arg}'")
        return 1
    target = folder + "/" + rest if slash else folder
    return _change(ctx, target, target)


def pwd(ctx: ToolContext, argv: list[str]) -> int:
    """``pwd``: the console's working directory."""
    if argv:
        raise ROSConsoleError("pwd takes no arguments in the ddes console")
    ctx.print(_here(ctx))
    return 0


def cd(ctx: ToolContext, argv: list[str]) -> int:
    """``cd [DIR]``: change the console's working directory (no argument: the home folder)."""
    if len(argv) > 1:
        ctx.eprint("bash: cd: too many arguments")
        return 1
    if not argv:
        return _change(ctx, os.path.expanduser("~"), "~")
    if argv[0] == "-":
        raise ROSConsoleError("cd - is not offered by the ddes console; give the folder")
    return _change(ctx, argv[0], argv[0])


def ls(ctx: ToolContext, argv: list[str]) -> int:
    """``ls [DIR|FILE...]``: names one per line, sorted (folders listed after files, as ls)."""
    if any(a.startswith("-") and a != "-" for a in argv):
        raise ROSConsoleError("ls takes no options in the ddes console (it lists names, one per "
                              "line)")
    targets = argv or ["."]
    code = 0
    files: list[str] = []
    folders: list[str] = []
    for arg in targets:
        path = ctx.resolve_path(arg)
        if os.path.isdir(path):
            folders.append(arg)
        elif os.path.lexists(path):
            files.append(arg)
        else:
            ctx.eprint(f"ls: cannot access '{arg}': No such file or directory")
            code = 2
    for name in sorted(files):
        ctx.print(name)
    for index, arg in enumerate(sorted(folders)):
        try:
            names = sorted(n for n in os.listdir(ctx.resolve_path(arg)) if not n.startswith("."))
        except OSError as exc:
            ctx.eprint(f"ls: cannot open directory '{arg}': {exc.strerror}")
            code = 2
            continue
        if len(targets) > 1:
            if files or index:
                ctx.print("")
            ctx.print(f"{arg}:")
        for name in names:
            ctx.print(name)
    return code


TOOLS = {"cd": cd, "ls": ls, "pwd": pwd, "roscd": roscd}
