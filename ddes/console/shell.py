"""``ddes console``: one shell for what ROS spreads over several terminals, on simulated time.

The console is a ``roscore``: a fresh :class:`~ddes.graph.world.World`
with the ``/rosout`` node and roscore's parameters
(:func:`ddes.launch.runtime.start_core`).  Every world-bound tool listed in
:data:`ddes.console.tooling.TOOL_MODULES` is a command (``rosrun``,
``rostopic``, ``rosnode``, ``rosparam``, ``roslaunch``, ``sleep``, ``time``,
``jobs``, ``kill`` and whatever later modules add), plus ``help``, ``rtf``,
``clear`` (the ANSI codes of ``clear`` on an xterm) and ``exit``.

Time stands still while you type.  A command that needs time lets the world
run: ``sleep 2``, ``rostopic echo -n 3 /chatter`` (until three messages
arrived), ``rostopic hz --duration 5 /chatter``.  Log lines of the nodes,
and the output of background jobs (``rostopic echo /chatter &``), print
while the world runs, in simulated-time order.

Three ways in:

* interactive (a TTY): ``cmd``/``readline`` with history and tab completion
  of commands, sub-commands, topic, service, node and parameter names,
  packages, node types, launch files and message types;
* a script (``--script FILE``, or lines on standard input): a transcript
  that echoes each command after ``$ `` then its output, identical run after
  run; the first failing command stops it with its exit code (``--keep-going``
  runs on and exits 1 if any failed);
* Python: ``Console().run("rostopic list")`` returns the text (notebooks,
  graders); :meth:`Console.execute` returns code, stdout and stderr apart.

Errors print one line, ``ERROR: ...``, and the console keeps running.

Hostile input: a command line longer than :data:`MAX_LINE` characters (64
KiB) is refused with ``ERROR: ...`` naming the limit, without echoing it
whole, and the console goes on.  Ctrl+C during a command stops that
foreground command only (its nodes shut down, a foreground recording is
written) and says so on a line of its own (:func:`interrupted_text`, written
over the ``^C`` a terminal echoes); background jobs go on.  After every command the open
recordings write their pending chunk to ``NAME.bag.active``, so a killed
console loses nothing it recorded; :meth:`Console.close` closes them (the
``ddes console`` command calls it when a script ends, on Ctrl+D, SIGINT and
SIGTERM).
"""

from __future__ import annotations

import cmd
import os
import shlex
import sys
from collections.abc import Callable, Iterable
from typing import TYPE_CHECKING, TextIO

from ddes.console.tooling import CommandResult, ToolContext, find_tool, tool_names
from ddes.errors import DdesError, ROSConsoleError
from ddes.graph.world import World as GraphWorld
from ddes.time.units import duration_to_ns, ns_to_sec

if TYPE_CHECKING:
    from ddes.graph.world import World
    from ddes.rospack import RosPack

__all__ = ["BUILTINS", "CLEAR_KEEP_SCROLLBACK", "CLEAR_SCREEN", "CONSOLE_RECORD_DATE", "MAX_LINE",
           "Console", "clear_sequence", "interact", "run_script"]

#: The longest command line the console runs (characters); longer ones are refused.
MAX_LINE = 64 * 1024

#: The date of the console's kernel time 0 in the names of its recordings (``rosbag record``
#: without ``-O`` writes ``2024-01-01-00-00-05.bag`` five simulated seconds in, where rosbag reads
#: the machine's clock); ``DDES_BAG_DATE`` and ``set_record_date`` override it (docs/bags.md).
CONSOLE_RECORD_DATE = "2024-01-01-00-00-00"

#: Commands of the console itself (the tools come from TOOL_MODULES).
BUILTINS = ("clear", "exit", "help", "quit", "rtf")

#: What ``clear`` writes: ncurses' ``clear`` on an xterm (cursor home, erase the screen and the
#: scrollback); ``clear -x`` leaves the scrollback (:data:`CLEAR_KEEP_SCROLLBACK`).
CLEAR_SCREEN = "\x1b[H\x1b[2J\x1b[3J"
CLEAR_KEEP_SCROLLBACK = "\x1b[H\x1b[2J"

#: Sub-commands offered by tab completion, per tool (only for completion).
_SUBCOMMANDS: dict[str, tuple[str, ...]] = {
    "rostopic": ("bw", "delay", "echo", "find", "hz", "info", "list", "pub", "type"),
    "rosnode": ("cleanup", "info", "kill", "list", "machine", "ping"),
    "rosparam": ("delete", "dump", "get", "list", "load", "set"),
    "rosservice": ("args", "call", "find", "info", "list", "type", "uri"),
    "rosmsg": ("info", "list", "md5", "package", "packages", "show"),
    "rossrv": ("info", "list", "md5", "package", "packages", "show"),
    "rosbag": ("check", "compress", "decompress", "filter", "fix", "info", "play", "record",
               "reindex"),
    "rospack": ("depends", "depends-on", "depends-on1", "depends1", "find", "help", "list",
                "list-names"),
}

_HELP = """ddes console: ROS 1 tools on one simulated world (time stands still while you type).

Commands: {commands}
Console: help [COMMAND], rtf [FACTOR|off], clear, exit (or Ctrl+D)

Commands that run until Ctrl+C in ROS (rosrun talker, roslaunch, rostopic echo)
run in the foreground until they end: interactively paced at the real-time factor
('rtf') until Ctrl+C, in a script up to its time limit (--until).  A count (-n N)
or --duration SECONDS (simulated) bounds them; a trailing & runs them in the
background ('jobs' lists them, 'kill %N' stops one).
'sleep SECONDS' lets the world run; 'time' prints the simulated time.
Type COMMAND -h for a command's options."""


class Console:
    """A console session on one world (the ``roscore``), usable from Python.

    ``ddes.Console`` is this class on a ``ddes.World``; here, without a
    ``world``, it makes a :attr:`world_class` (the graph's World).

    Parameters
    ----------
    world:
        The world to drive (default: a new ``World(seed)``).
    seed:
        Seed of the new world.
    rospack:
        The package path (default: ``DDES_PACKAGE_PATH`` plus bundled packages).
    core:
        Start roscore's ``/rosout`` node and parameters (default True).
    out, err:
        Where output goes between commands (a node logging while you run the
        world yourself); during a command it is captured or streamed.

    The world's ``raise_callback_errors`` is turned off: a failing callback
    is reported after the command (``ERROR: bad callback in node ...``) and
    the node goes on, as in rospy.
    """

    #: The world a console makes when none is given.
    world_class: type[World] = GraphWorld

    def __init__(self, world: World | None = None, *, seed: int = 0,
                 rospack: RosPack | None = None, core: bool = True,
                 out: Callable[[str], None] = print,
                 err: Callable[[str], None] | None = None,
                 rtf: float | None = None, until: float | None = None) -> None:
        from ddes.launch.runtime import LogRouter, start_core
        from ddes.rosbag.recorder import fallback_record_date, set_fallback_record_date
        from ddes.services.loggers import roscpp_logger_services

        self.world = world if world is not None else self.world_class(seed=seed)
        self.world.raise_callback_errors = False
        self.ctx = ToolContext(self.world, rospack, out=out, err=err or out)
        self.rtf = rtf
        self.until = until
        LogRouter(self.world, lambda line: self.ctx.print(line)).install()
        if fallback_record_date(self.world) is None:
            set_fallback_record_date(self.world, CONSOLE_RECORD_DATE)
        roscpp_logger_services(self.world)  # ~get_loggers, ~set_logger_level, as roscpp's
        if core:
            start_core(self.world)
        self._errors_seen = len(self.world.callback_errors)
        #: Ctrl+C was pressed during the last command (interactive only), whether or not it
        #: stopped it: a command that never paced ends as it would have.
        self.ctrl_c_seen = False

    # -- running commands ----------------------------------------------------------------------
    def command(self, line: str, out: Callable[[str], None],
                err: Callable[[str], None]) -> int:
        """Run one command line with its output streamed to ``out``/``err``; returns the exit code."""
        from ddes.console.toolkit import EXIT_INTERRUPTED
        from ddes.rosbag.recorder import flush_recordings

        ctx = self.ctx
        saved = ctx.out, ctx.err
        ctx.out, ctx.err = out, err
        ctx.time_noted = False  # the simulated-time notice prints once per command
        self.ctrl_c_seen = False
        try:
            if len(line) > MAX_LINE:
                ctx.eprint(f"ERROR: {too_long(line)}")
                return 1
            try:
                if ctx.rtf is None:
                    self.world.settle()  # what Python scheduled now (a process, a node) first
                    return self._command(line)
                # Interactive: Ctrl+C sets a flag for the whole command (not a
                # KeyboardInterrupt inside a node's callback, where it could be lost), which
                # the paced run reads; a second Ctrl+C raises KeyboardInterrupt.
                from ddes.kernel.realtime import InterruptFlag

                with InterruptFlag(second_raises=True) as flag:
                    ctx.interrupted = flag
                    try:
                        self.world.settle()
                        code = self._command(line)
                    finally:
                        ctx.interrupted = None
                self.ctrl_c_seen = flag.raised
                if flag.raised and code == EXIT_INTERRUPTED:  # the paced run saw the Ctrl+C
                    ctx.eprint(interrupted_text(line))
                return code
            except KeyboardInterrupt:  # Ctrl+C: the foreground command only
                self.ctrl_c_seen = True
                ctx.eprint(interrupted_text(line))
                return EXIT_INTERRUPTED
        finally:
            try:
                self._report_callback_errors()
                flush_recordings(self.world)
            finally:
                ctx.out, ctx.err = saved

    def close(self, reason: str = "closed") -> list[str]:
        """Close every open recording (index written, ``NAME.bag`` in place); their paths.

        ``ddes console`` calls this when the script or input ends and on SIGINT/SIGTERM.
        """
        from ddes.rosbag.recorder import close_recordings

        closed = close_recordings(self.world, reason)
        return [r.path for r in closed if r.path is not None]

    def _command(self, line: str) -> int:
        ctx = self.ctx
        bare = line.rstrip()
        if bare.endswith("&") and not bare.endswith((" &", "\\&")) and _balanced(bare[:-1]):
            line = bare[:-1] + " &"  # "cmd&" as a shell reads it
        try:
            argv = shlex.split(line, comments=True)
        except ValueError as exc:
            ctx.eprint(f"ERROR: cannot parse the command line: {exc}")
            return 1
        if not argv:
            return 0
        if argv[0] == "help":
            return self._help(argv[1:])
        if argv[0] in ("exit", "quit"):
            return 0
        try:
            if argv[0] == "rtf":
                return self._rtf(argv[1:])
            if argv[0] == "clear":  # a line of its own here; the terminal writes it bare
                ctx.print(clear_sequence(argv[1:]))
                return 0
            return int(find_tool(argv[0])(ctx, argv[1:]))
        except DdesError as exc:
            ctx.eprint(f"ERROR: {_one_line(str(exc))}")
            return 1
        except Exception as exc:  # noqa: BLE001 - a node's own code failed while the world ran
            ctx.eprint(f"ERROR: {type(exc).__name__} raised while the world ran: "
                       f"{_one_line(str(exc))} (at t={ns_to_sec(self.world.now):.9f}s)")
            return 1

    @property
    def rtf(self) -> float | None:
        """Real-time factor of foreground commands (None: unpaced); see the class docstring."""
        return self.ctx.rtf

    @rtf.setter
    def rtf(self, value: float | None) -> None:
        from ddes.kernel.realtime import check_rtf

        self.ctx.rtf = None if value is None else check_rtf(value)

    @property
    def until(self) -> float | None:
        """The session's simulated time limit in seconds (None: none)."""
        return None if self.ctx.until_ns is None else ns_to_sec(self.ctx.until_ns)

    @until.setter
    def until(self, value: float | None) -> None:
        self.ctx.until_ns = None if value is None else duration_to_ns(value, "until")

    def _rtf(self, args: list[str]) -> int:
        """``rtf [FACTOR|off]``: show or set the real-time factor of foreground commands."""
        if len(args) > 1:
            raise ROSConsoleError("rtf takes at most one argument: a factor (1 = real time) "
                                  "or 'off'")
        if args:
            self.rtf = None if args[0] in ("off", "none") else _factor(args[0])
        if self.rtf is None:
            self.ctx.print("real-time factor: off (commands run as fast as possible; one that "
                           "runs until Ctrl+C in ROS needs -n, --duration or &)")
        else:
            self.ctx.print(f"real-time factor: {self.rtf:g} (foreground commands run paced "
                           "until they end or Ctrl+C)")
        return 0

    def _help(self, args: list[str]) -> int:
        if args:
            if args[0] in BUILTINS:
                self.ctx.print(f"{args[0]}: a console command (see 'help')")
                return 0
            return self._command(f"{shlex.quote(args[0])} -h")
        self.ctx.print(_HELP.format(commands=", ".join(self.commands())))
        return 0

    def _report_callback_errors(self) -> None:
        errors = self.world.callback_errors
        for node, callback, exc, _tb in errors[self._errors_seen:]:
            self.ctx.eprint(f"ERROR: bad callback in node {node}: {callback}: "
                            f"{type(exc).__name__}: {_one_line(str(exc))}")
        self._errors_seen = len(errors)

    def execute(self, line: str) -> CommandResult:
        """Run one command; its exit code and captured standard output and error."""
        out: list[str] = []
        err: list[str] = []
        code = self.command(line, out.append, err.append)
        return CommandResult(code, "".join(x + "\n" for x in out),
                             "".join(x + "\n" for x in err))

    def run(self, line: str, check: bool = True) -> str:
        """Run one command and return everything it printed (output and errors, in order).

        With ``check`` (default) a failing command raises
        :class:`~ddes.errors.ROSConsoleError` carrying its output.
        """
        lines: list[str] = []
        code = self.command(line, lines.append, lines.append)
        text = "".join(x + "\n" for x in lines)
        if code != 0 and check:
            raise ROSConsoleError(text.strip() or f"'{line}' exited with {code}")
        return text

    def transcript(self, lines: Iterable[str], *, keep_going: bool = False,
                   prompt: str = "$ ") -> tuple[int, str]:
        """Run script lines; returns ``(exit code, transcript text)`` (see :func:`run_script`)."""
        out: list[str] = []
        code = run_script(self, lines, out.append, keep_going=keep_going, prompt=prompt)
        return code, "".join(x + "\n" for x in out)

    def commands(self) -> list[str]:
        """Every command name: the tools and the console's own."""
        return sorted(set(tool_names()) | set(BUILTINS))

    # -- completion ------------------------------------------------------------------------------
    def complete(self, line: str, text: str) -> list[str]:
        """Completions of ``text``, the word being typed at the end of ``line``."""
        words = shlex.split(line, posix=True) if _balanced(line) else line.split()
        if line.endswith(" ") or not line:
            words.append("")
        index = len(words) - 1
        if index == 0:
            return [c for c in self.commands() if c.startswith(text)]
        return sorted({c for c in self._candidates(words, index) if c.startswith(text)})

    def _candidates(self, words: list[str], index: int) -> list[str]:
        tool = words[0]
        world = self.world
        rospack = self.ctx.rospack
        assert rospack is not None
        topics = sorted(world.master.topics)
        nodes = world.master.node_names()
        services = sorted(world.master.services)
        params = world.master.params.get_param_names()
        if tool in ("rosrun", "roslaunch"):
            args = [w for w in words[1:index] if not w.startswith("-")]
            if not args:
                return rospack.list() + (_paths(words[index]) if tool == "roslaunch" else [])
            if len(args) == 1 and args[0] in rospack:
                folder = rospack.get_path(args[0])
                if tool == "rosrun":
                    from ddes.nodes import load_node_types

                    try:
                        return sorted(load_node_types(folder))
                    except Exception:  # noqa: BLE001 - completion never fails loudly
                        return []
                return sorted(p.name for p in folder.rglob("*.launch"))
            return topics + nodes
        if tool == "kill":
            return [f"%{j.id}" for j in self.ctx.jobs]
        if tool == "roscd" or (tool == "rospack" and index >= 2):
            return rospack.list()
        if index == 1 and tool in _SUBCOMMANDS:
            return list(_SUBCOMMANDS[tool])
        sub = words[1] if len(words) > 1 else ""
        if tool == "rostopic":
            if sub in ("pub",) and index == 3 or sub == "find":
                return list(_types("msg", world))
            return topics
        if tool == "rosnode":
            return nodes
        if tool == "rosparam":
            if sub in ("load", "dump") and index == 2:
                return _paths(words[index])
            return params
        if tool == "rosservice":
            return services
        if tool in ("rosmsg", "rossrv"):
            return list(_types("msg" if tool == "rosmsg" else "srv", world))
        if tool == "rosbag":
            return _paths(words[index]) + topics
        return topics + services + nodes


def _types(kind: str, world: World) -> Iterable[str]:
    try:
        return list(world.messages.iter_types(kind))
    except DdesError:
        return []


def _paths(prefix: str) -> list[str]:
    folder = os.path.dirname(prefix) or "."
    try:
        names = sorted(os.listdir(folder))
    except OSError:
        return []
    base = "" if folder == "." and not prefix.startswith("./") else folder.rstrip("/") + "/"
    return [base + n + ("/" if os.path.isdir(os.path.join(folder, n)) else "") for n in names]


def _factor(text: str) -> float:
    from ddes.kernel.realtime import check_rtf

    try:
        return check_rtf(float(text))
    except (ValueError, DdesError):
        raise ROSConsoleError(f"rtf: invalid real-time factor {text!r}: give a number > 0 "
                              "(1 = real time, 0.5 = half speed) or 'off'") from None


def clear_sequence(args: list[str]) -> str:
    """What ``clear [-x]`` writes (ANSI, as ``clear`` on an xterm); a ROSConsoleError for other
    arguments."""
    if not args:
        return CLEAR_SCREEN
    if args == ["-x"]:
        return CLEAR_KEEP_SCROLLBACK
    raise ROSConsoleError(f"clear: unknown option {args[0]!r} (usage: clear [-x]; -x keeps the "
                          "scrollback)")


def interrupted_text(line: str) -> str:
    """What the console prints when Ctrl+C stopped the foreground command ``line``."""
    return (f"^C: stopped the foreground command '{_shown(line)}' (its nodes were shut down; "
            "background jobs keep running: 'jobs' lists them)")


def too_long(line: str) -> str:
    """The message refusing a command line over :data:`MAX_LINE` characters."""
    return (f"the command line has {len(line)} characters, over the console's limit of "
            f"{MAX_LINE} (MAX_LINE, 64 KiB): split it, or put long data in a file (rosparam "
            "load FILE)")


def _shown(line: str, width: int = 80) -> str:
    """``line`` cut to ``width`` characters for an echo or a message."""
    first = line.split("\n", 1)[0]
    if len(first) <= width and first == line:
        return line
    return f"{first[:width]}... ({len(line)} characters)"


def _balanced(line: str) -> bool:
    try:
        shlex.split(line)
    except ValueError:
        return False
    return True


def _one_line(text: str) -> str:
    return " ".join(part.strip() for part in text.strip().splitlines() if part.strip())


def run_script(console: Console, lines: Iterable[str], write: Callable[[str], None], *,
               keep_going: bool = False, prompt: str = "$ ") -> int:
    """Run script lines on ``console``, writing the transcript with ``write``.

    Blank lines and ``#`` comments are skipped; each command is echoed after
    ``prompt``, then everything it prints (output and errors in order).
    ``exit`` ends the script.  A line with an open quote continues on the
    next lines (echoed after ``> ``), as in a shell, so ``rosservice call
    /add_two_ints "a: 10`` + ``b: 5"`` passes a two-line YAML argument.
    Returns 0, or the exit code of the first failing command (with
    ``keep_going``: 1 if any failed); an unterminated quote at the end of
    the script is an error.
    """
    failed = 0
    pending: list[str] = []
    for raw in lines:
        line = raw.rstrip("\n").rstrip("\r")
        if len(line) > MAX_LINE or sum(map(len, pending)) + len(line) > MAX_LINE:
            write(prompt + _shown(line.strip() or (pending or [""])[0]))
            write(f"ERROR: {too_long(chr(10).join([*pending, line]))}")
            pending = []
            if not keep_going:
                return 1
            failed = 1
            continue
        if pending:  # inside an open quote: the line break belongs to the argument, as in bash
            pending.append(line)
            if not _balanced("\n".join(pending)):
                continue
            stripped = "\n".join(pending)
            pending = []
        else:
            stripped = line.strip()
            if not stripped or stripped.startswith("#"):
                continue
            if not _balanced(stripped) and _open_quote(stripped):
                pending = [stripped]
                continue
        first, *rest = stripped.split("\n")
        write(prompt + first)
        for more in rest:
            write("> " + more)
        if stripped.split()[0] in ("exit", "quit"):
            break
        code = console.command(stripped, write, write)
        if code != 0:
            if not keep_going:
                return code
            failed = 1
    if pending:
        write(prompt + pending[0])
        for more in pending[1:]:
            write("> " + more)
        write("ERROR: cannot parse the command line: No closing quotation at the end of the script")
        return 1
    return failed


def _open_quote(line: str) -> bool:
    """True if ``line`` fails to parse only because a quote is still open."""
    try:
        shlex.split(line)
    except ValueError as exc:
        return "quotation" in str(exc)
    return False


class _Shell(cmd.Cmd):
    """The interactive loop (``cmd.Cmd`` with readline history and completion)."""

    intro = ("ddes console: a simulated roscore. Time stands still while you type; "
             "'help' lists the commands, Ctrl+D exits.")

    def __init__(self, console: Console, history: str | None) -> None:
        super().__init__()
        self.console = console
        self.history = history
        self.last_code = 0
        #: The terminal echoes Ctrl+C as ``^C`` (ECHOCTL): the console's ``^C: stopped ...``
        #: then starts with a carriage return, so the line shows one ``^C``, not two.
        self.echoes_ctl = _echoes_control_characters(sys.stdin)
        self._update_prompt()

    def _update_prompt(self) -> None:
        self.prompt = f"ddes [{ns_to_sec(self.console.world.now):.3f}] $ "

    def preloop(self) -> None:
        try:
            import readline
        except ImportError:  # pragma: no cover - readline is part of CPython on Linux
            return
        readline.set_completer_delims(" \t\n")
        if self.history and os.path.exists(self.history):
            try:
                readline.read_history_file(self.history)
            except OSError:
                pass

    def postloop(self) -> None:
        if not self.history:
            return
        try:
            import readline

            readline.set_history_length(1000)
            readline.write_history_file(self.history)
        except (ImportError, OSError):
            pass

    def emptyline(self) -> bool:
        return False

    def precmd(self, line: str) -> str:
        """An open quote continues on the next line (prompt ``> ``), as in a shell."""
        while len(line) <= MAX_LINE and _open_quote(line):  # a longer line is refused whole
            try:
                more = input("> ") if self.use_rawinput else self.stdin.readline()
            except EOFError:
                break
            if not more:
                break
            line += "\n" + more.rstrip("\n")
        return line

    def do_help(self, arg: str) -> bool:
        """Route ``help`` (and ``?``) to the console's own help."""
        return self.default(f"help {arg}".strip())

    def do_EOF(self, arg: str) -> bool:
        """Ctrl+D ends the session."""
        print()
        return True

    def default(self, line: str) -> bool:  # type: ignore[override]  # True ends cmdloop
        if line.strip() in ("exit", "quit"):
            return True
        words = line.split()
        if words[:1] == ["clear"] and len(line) <= MAX_LINE:
            try:  # as a shell's clear: the screen is erased and the prompt comes back at its top
                sys.stdout.write(clear_sequence(words[1:]))
                self.last_code = 0
            except ROSConsoleError as exc:
                sys.stderr.write(f"ERROR: {exc}\n")
                self.last_code = 1
            sys.stdout.flush()
            return False

        def out(text: str) -> None:
            sys.stdout.write(text + "\n")
            sys.stdout.flush()

        def err(text: str) -> None:
            if self.echoes_ctl and text.startswith("^C: "):
                text = "\r" + text  # over the ^C the terminal echoed, at the line's start
            sys.stderr.write(text + "\n")
            sys.stderr.flush()

        self.last_code = self.console.command(line, out, err)
        if self.console.ctrl_c_seen and self.last_code != 130 and self.echoes_ctl:
            err("")  # a Ctrl+C the command never looked at: the prompt after its ^C, below it
        return False

    def postcmd(self, stop: bool, line: str) -> bool:
        self._update_prompt()
        return stop

    def completenames(self, text: str, *ignored: object) -> list[str]:
        return _spaced(self.console.complete(text, text))

    def completedefault(self, text: str, line: str, begidx: int, endidx: int) -> list[str]:
        return _spaced(self.console.complete(line[:endidx], text))


def _echoes_control_characters(stream: TextIO) -> bool:
    """Whether ``stream`` is a terminal that echoes Ctrl+C as ``^C`` (termios ECHOCTL)."""
    try:
        import termios
    except ImportError:  # pragma: no cover - not POSIX
        return False
    try:
        if not stream.isatty():
            return False
        return bool(termios.tcgetattr(stream.fileno())[3] & termios.ECHOCTL)
    except (termios.error, AttributeError, OSError, ValueError):  # not a terminal after all
        return False


def _spaced(matches: list[str]) -> list[str]:
    """A unique match ends the word (readline here appends nothing itself); folders do not."""
    if len(matches) == 1 and not matches[0].endswith("/"):
        return [matches[0] + " "]
    return matches


def interact(console: Console, history: str | None = None, stdin: TextIO | None = None) -> int:
    """Run the interactive console until ``exit`` or end of input; returns 0."""
    shell = _Shell(console, history)
    if stdin is not None:
        shell.stdin = stdin
        shell.use_rawinput = False
    while True:
        try:
            shell.cmdloop()
            return 0
        except KeyboardInterrupt:
            print("^C")
            shell.intro = ""
