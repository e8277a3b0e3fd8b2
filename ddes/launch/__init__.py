"""roslaunch XML, loaded into a plain launch plan (nothing is started here).

:func:`load_launch` reads a launch file (or XML text) with its command-line
args and returns a :class:`LaunchPlan`: the parameters to set before any
node starts, the parameter namespaces to clear, ``<rosparam>`` delete/dump
commands, and one :class:`NodeSpec` per ``<node>`` with its namespace,
args, remappings, private parameters and settings, all resolved.
:func:`resolve_launch_args` turns ``roslaunch PKG FILE.launch a:=1`` style
arguments into a path and an args dict.  The graph runs the plan.

The behaviour follows Noetic's ``roslaunch`` (``xmlloader.py``,
``loader.py``, ``substitution_args.py``); ``docs/launch.md`` lists what is
supported, ignored or rejected.
"""

from ddes.launch.command_line import resolve_launch_args
from ddes.launch.loader import load_launch
from ddes.launch.plan import LaunchPlan, NodeSpec, RosparamCommand
from ddes.launch.substitution import SubstitutionContext, resolve_args
from ddes.launch.values import convert_value

__all__ = [
    "LaunchPlan",
    "NodeSpec",
    "RosparamCommand",
    "SubstitutionContext",
    "convert_value",
    "load_launch",
    "resolve_args",
    "resolve_launch_args",
]
