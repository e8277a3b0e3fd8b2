"""``catkin_make`` and ``catkin build`` in the console: build a catkin workspace's C++ nodes
against ddes's roscpp (:mod:`ddes.roscpp.catkin`, docs/roscpp.md "Building with catkin").

They run in the console's working directory (``cd``/``roscd`` move it) with the process's
environment; their output (CMake's and make's included) is the tool's output.  The build takes
wall time, not simulated time: the world does not move while it runs.  Afterwards ``rosrun``
and ``roslaunch`` find the new executables in ``devel/lib/<package>``.
"""

from __future__ import annotations

import os
from typing import TYPE_CHECKING

from ddes.roscpp.catkin import catkin_make as _catkin_make
from ddes.roscpp.catkin import catkin_tool as _catkin_tool

if TYPE_CHECKING:
    from ddes.console.tooling import ToolContext

__all__ = ["TOOLS", "catkin", "catkin_make"]


def _cwd(ctx: ToolContext) -> str:
    return ctx.cwd if ctx.cwd is not None else os.getcwd()


def catkin_make(ctx: ToolContext, argv: list[str]) -> int:
    """``catkin_make [-j N] [--pkg P ...] [-DVAR=VALUE ...] [--force-cmake] [targets]``."""
    code = _catkin_make(argv, cwd=_cwd(ctx), out=ctx.print, err=ctx.eprint)
    _refresh(ctx)
    return code


def catkin(ctx: ToolContext, argv: list[str]) -> int:
    """``catkin build [PKG ...]``, ``catkin clean``, ``catkin init`` (catkin_tools' verbs)."""
    code = _catkin_tool(argv, cwd=_cwd(ctx), out=ctx.print, err=ctx.eprint)
    _refresh(ctx)
    return code


def _refresh(ctx: ToolContext) -> None:
    """New packages or executables are seen by the next rosrun/roslaunch."""
    rospack = ctx.rospack
    if rospack is not None:
        rospack.refresh()


TOOLS = {"catkin_make": catkin_make, "catkin": catkin}
