"""``roscore``: the master, the parameter server and ``/rosout``, as roscore prints them.

The console is a roscore already: ``ddes console`` (``Console()``) starts
``/rosout`` and roscore's parameters (:func:`ddes.launch.runtime.start_core`)
before the first prompt.  So ``roscore`` there does what a second
``roscore`` does in ROS: it prints roslaunch's ``ros_comm version`` line
and SUMMARY, then, on stderr::

    RLException: roscore cannot run as another roscore/master is already running.
    Please kill other roscore/master processes before relaunching.
    The ROS_MASTER_URI is http://localhost:11311/

followed by ddes's own line (:data:`ALREADY_RUNNING_NOTE`: the console is the roscore, type the
next command here), and exits 1.  In a console started without the core (``ddes console
--no-core``, ``Console(core=False)``) it starts the core and prints
roscore's start-up (``auto-starting new master``, ``process[master]: started
with pid [...]``, ``ROS_MASTER_URI=http://localhost:11311/``, ``setting
/run_id to ...``, ``process[rosout-1]: started with pid [...]``, ``started
core service [/rosout]``), with the synthetic pids of
:func:`ddes.launch.runtime.node_pid` and the ``/run_id`` drawn from the
world's seed.  roscore then runs until Ctrl+C; in the console the prompt
returns at once and the core keeps running (a later ``roscore`` says it is
already running).

As ``ddes roslaunch``, it prints no log-file lines (``... logging to``, the
log-directory disk check, ``The traceback for the exception was written to
the log file``), no ``started roslaunch server`` line (ddes has no roslaunch
server), no terminal-title or colour escape codes; the title set after
``ROS_MASTER_URI`` leaves its empty line.  The master's host is
``localhost`` (roscore prints the machine's host name unless
``ROS_HOSTNAME`` is set).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from ddes.console.toolkit import HelpPrinted, ToolParser, settle
from ddes.errors import ROSConsoleError
from ddes.launch.runtime import CORE_PARAMS, core_running, node_pid, start_core

if TYPE_CHECKING:
    from ddes.console.tooling import ToolContext

__all__ = ["ALREADY_RUNNING_NOTE", "MASTER_URI", "TOOLS", "roscore"]

#: The master's URI as roscore prints it (``http://HOST:11311/``).
MASTER_URI = "http://localhost:11311/"

#: ddes's line after roscore's refusal: why a newcomer needs no roscore here.
ALREADY_RUNNING_NOTE = ("[ddes] this console is the roscore: the master, the parameter server "
                        "and /rosout already run here, until you exit the console; type the next "
                        "command (rosrun, rostopic, ...) at this prompt, no other terminal is "
                        "needed")


def _summary() -> str:
    """roslaunch's SUMMARY of roscore's (empty) launch, with the parameters it sets."""
    from ddes.launch.plan import LaunchPlan

    return "\n" + LaunchPlan(params=dict(CORE_PARAMS)).to_text()


def roscore(ctx: ToolContext, argv: list[str]) -> int:
    """``roscore [options]`` (see the module docstring)."""
    parser = ToolParser(ctx, "usage: %prog [options]", "roscore")
    parser.add_option("-p", "--port", dest="port", default=None, metavar="PORT",
                      help="master port. Only valid if master is launched")
    parser.add_option("-v", action="store_true", dest="verbose", default=False,
                      help="verbose printing")
    parser.add_option("-w", "--numworkers", dest="num_workers", default=None, type="int",
                      metavar="NUM_WORKERS", help="override number of worker threads")
    parser.add_option("-t", "--timeout", dest="timeout", metavar="TIMEOUT",
                      help="override the socket connection timeout (in seconds).")
    parser.add_option("--master-logger-level", dest="master_logger_level", default=False,
                      help="set rosmaster.master logger level ('debug', 'info', 'warn', "
                           "'error', 'fatal')")
    parser.add_option("--sigint-timeout", dest="sigint_timeout", type="float",
                      metavar="SIGINT_TIMEOUT",
                      help="the SIGINT timeout used when killing the core (in seconds).")
    parser.add_option("--sigterm-timeout", dest="sigterm_timeout", type="float",
                      metavar="SIGTERM_TIMEOUT",
                      help="the SIGTERM timeout used when killing core if SIGINT does not stop "
                           "the core (in seconds).")
    try:
        options, args = parser.parse_args(argv)
    except HelpPrinted:
        return 0
    if args:
        parser.error("roscore does not take arguments")
    if options.port not in (None, "11311"):
        raise ROSConsoleError(
            f"roscore -p {options.port}: the console has one master, at {MASTER_URI}; ddes "
            "cannot start a second one on another port")
    world = ctx.world
    ctx.print(f"ros_comm version {CORE_PARAMS['/rosversion']}")
    ctx.print(_summary())
    if core_running(world):
        ctx.eprint("RLException: roscore cannot run as another roscore/master is already "
                   "running. \nPlease kill other roscore/master processes before relaunching.\n"
                   f"The ROS_MASTER_URI is {MASTER_URI}")
        ctx.eprint(ALREADY_RUNNING_NOTE)
        return 1
    ctx.print("auto-starting new master")
    ctx.print(f"process[master]: started with pid [{node_pid('master')}]")
    ctx.print(f"ROS_MASTER_URI={MASTER_URI}")
    ctx.print("")  # roscore sets the terminal title here: an escape code and a newline
    start_core(world)
    ctx.print(f"setting /run_id to {world.master.params.get_param('/run_id')}")
    ctx.print(f"process[rosout-1]: started with pid [{node_pid('/rosout')}]")
    ctx.print("started core service [/rosout]")
    settle(world)
    return 0


TOOLS = {"roscore": roscore}
