"""The console: a simulated ``roscore`` with the ROS tools, as a library.

:class:`Console` runs command lines (``rosrun``, ``roslaunch``, ``rostopic``,
``rosnode``, ``rosparam``, ``rosservice``, ``rossrv``, ``rosmsg``, ``rosbag``,
``sleep``, ``jobs``, ``kill``) on a world and returns what the ROS tools
print, so notebooks, tests and the grader use the same tools students type.
The ``ddes console`` command (:mod:`ddes.cli.console`) is a thin entry point
on top.  See docs/console.md.
"""

from ddes.console.shell import BUILTINS, Console, interact, run_script
from ddes.console.tooling import CommandResult, ToolContext

__all__ = ["BUILTINS", "CommandResult", "Console", "ToolContext", "interact", "run_script"]
