"""``rosbag``: record, play, info, check, filter, compress, decompress, reindex.

Two ways in, one implementation:

* as a world-bound tool (``rosbag ...`` in the console, or
  ``run_command(world, "rosbag info x.bag")``): every subcommand.
  ``record`` and ``play`` follow the console's rule for commands ROS runs
  until Ctrl+C: in the foreground they run the world until they end by
  themselves (``record --duration``/``--limit``; ``play`` at the end of the
  bag); with a trailing ``&`` they keep running in the background (``jobs``
  lists them, ``kill %N`` stops them; a stopped recording is written).
  ``record`` without ``--duration``/``--limit``, and ``play --loop``,
  ``--keep-alive``, ``--pause`` or ``--wait-for-subscribers``, need the ``&``;
* as a one-shot command on files (``ddes rosbag info|check|filter|compress|
  decompress|reindex FILE...``), which needs no world.

A recording writes ``NAME.bag.active`` as it goes (chunks of ``--chunksize``
KB, and whatever is pending after every console command); the console closes
every open recording when a script ends, on Ctrl+D, SIGINT and SIGTERM.  The
``.active`` file a killed process (SIGKILL) leaves is recovered with
``rosbag reindex NAME.bag.active``; ``rosbag check`` says whether a bag is
readable, indexed and needs no migration.

``record`` and ``play`` print what the C++ programs behind rosbag_main.py
print (``[ INFO] [t]: Subscribing to /chatter``, ``Opening x.bag``, ``Hit
space to toggle paused, or 's' to step.``; play's status line once per pass,
see docs/bags.md); their options are :mod:`ddes.rosbag.options`, shared with
the ``rosbag/record`` and ``rosbag/play`` node types.  File names are
relative to the console's directory (``ctx.resolve_path``, set by ``roscd``).
A default recording name takes its date from ``DDES_BAG_DATE`` when the world
has none (:func:`ddes.rosbag.recorder.default_record_date`).

Options, messages and exit codes follow ``rosbag_main.py``.  Deviations:
no progress meter (it reads the wall clock); ``compress``, ``decompress``
and ``reindex`` exit 1 when a file failed (rosbag prints the error and
exits 0); options ddes does not model (``--split``, ``--size``,
``--max-splits``, ``--repeat-latched``, ``--pause-topics``,
``--rate-control-topic``) are refused with an error instead of ignored.
"""

from __future__ import annotations

import argparse
import os
import sys
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, NoReturn

from ddes.errors import (
    DdesError,
    DdesKeyError,
    ROSBagException,
    ROSBagUnindexedException,
    ROSConsoleError,
)

if TYPE_CHECKING:
    import simpy
    from _typeshed import SupportsWrite

    from ddes.console.tooling import ToolContext
    from ddes.console.toolkit import Task

__all__ = ["TOOLS", "register", "rosbag_main", "run"]

_COMMANDS = {
    "check": "Determine whether a bag is playable in the current system, or if it can be "
             "migrated.",
    "compress": "Compress one or more bag files.",
    "decompress": "Decompress one or more bag files.",
    "filter": "Filter the contents of the bag.",
    "info": "Summarize the contents of one or more bag files.",
    "play": "Play back the contents of one or more bag files in a time-synchronized fashion.",
    "record": "Record a bag file with the contents of specified topics.",
    "reindex": "Reindexes one or more bag files.",
}


@dataclass
class _IO:
    out: Callable[[str], None]
    err: Callable[[str], None]
    ctx: ToolContext | None


class _Exit(Exception):
    def __init__(self, code: int) -> None:
        super().__init__(code)
        self.code = code


class _Parser(argparse.ArgumentParser):
    """argparse that writes through the tool's sinks and never calls sys.exit."""

    def __init__(self, io: _IO, *, prog: str, usage: str, description: str) -> None:
        super().__init__(prog=prog, usage=usage, description=description)
        self._io = io

    def error(self, message: str) -> NoReturn:
        self._io.err(self.format_usage().rstrip())
        self._io.err(f"{self.prog}: error: {message}")
        raise _Exit(2)

    def exit(self, status: int = 0, message: str | None = None) -> NoReturn:
        if message:
            self._io.err(message.rstrip())
        raise _Exit(status)

    def print_help(self, file: SupportsWrite[str] | None = None) -> None:
        self._io.out(self.format_help().rstrip())


def _parser(io: _IO, cmd: str, usage: str) -> _Parser:
    return _Parser(io, prog=f"rosbag {cmd}", usage=usage, description=_COMMANDS[cmd])


def _resolve(io: _IO, path: str) -> str:
    """``path`` as the tool opens it: relative to the console's directory (``roscd``)."""
    return io.ctx.resolve_path(path) if io.ctx is not None else path


def _reason(exc: BaseException, path: str) -> str:
    text = str(exc)
    return text[len(path) + 2:] if text.startswith(path + ": ") else text


# -- info -------------------------------------------------------------------------------------

def _info(io: _IO, argv: list[str]) -> int:
    from ddes.rosbag import Bag

    p = _parser(io, "info", "rosbag info [options] BAGFILE1 [BAGFILE2 BAGFILE3 ...]")
    p.add_argument("bags", nargs="*")
    p.add_argument("-y", "--yaml", action="store_true", help="print information in YAML format")
    p.add_argument("-k", "--key", help="print information on the given key")
    p.add_argument("--freq", action="store_true", help="display topic message frequency statistics")
    a = p.parse_args(argv)
    if not a.bags:
        p.error("You must specify at least 1 bag file.")
    if a.key and not a.yaml:
        p.error("You can only specify key when printing in YAML format.")
    for i, path in enumerate(a.bags):
        try:
            bag = Bag(_resolve(io, path), "r", skip_index=not a.freq, filename=path)
            if a.yaml:
                try:
                    io.out(bag.yaml_info(a.key, freq=a.freq))
                except DdesKeyError as exc:
                    io.err(str(exc))
            else:
                io.out(bag.info(freq=a.freq))
            bag.close()
        except ROSBagUnindexedException:
            io.err(f"ERROR bag unindexed: {path}.  Run rosbag reindex.")
            return 1
        except ROSBagException as exc:
            io.err(f"ERROR reading {path}: {_reason(exc, path)}")
            return 1
        if i < len(a.bags) - 1:
            io.out("---")
    return 0


# -- check ------------------------------------------------------------------------------------

def _check(io: _IO, argv: list[str]) -> int:
    from ddes.rosbag.repair import check_bag

    p = _parser(io, "check", "rosbag check BAG [-g RULEFILE] [EXTRARULES1 EXTRARULES2 ...]")
    p.add_argument("bags", nargs="*")
    p.add_argument("-g", "--genrules", dest="rulefile", help="(not modelled by ddes)")
    p.add_argument("-a", "--append", action="store_true", help="(not modelled by ddes)")
    p.add_argument("-n", "--noplugins", action="store_true", help="(no effect in ddes)")
    a = p.parse_args(argv)
    if not a.bags:
        p.error("You must specify a bag file to check.")
    if a.append and a.rulefile is None:
        p.error("Cannot specify -a without also specifying -g.")
    if a.rulefile is not None:
        return _refuse(io, ["--genrules (migration rules)"])
    path = a.bags[0]
    try:
        result = check_bag(_resolve(io, path), io.ctx.world.messages if io.ctx is not None else None)
    except ROSBagUnindexedException:
        io.err(f"ERROR bag unindexed: {path}.  Run rosbag reindex.")
        return 1
    except ROSBagException as exc:
        io.err(f"ERROR reading {path}: {_reason(exc, _resolve(io, path))}")
        return 1
    for line in result.lines():
        io.out(line)
    return 1 if result.migrations else 0


# -- filter -----------------------------------------------------------------------------------

def _filter(io: _IO, argv: list[str]) -> int:
    from ddes.rosbag import Bag
    from ddes.rosbag.ops import compile_expression, filter_bag

    p = _parser(io, "filter", "rosbag filter [options] INBAG OUTBAG EXPRESSION")
    p.epilog = ("EXPRESSION can be any Python-legal expression. The following variables are "
                "available: topic (name of topic), m (message), t (time of message: t.secs, "
                "t.nsecs)")
    p.add_argument("args", nargs="*")
    p.add_argument("-p", "--print", dest="verbose_pattern", metavar="PRINT-EXPRESSION",
                   help="Python expression to print for verbose debugging")
    a = p.parse_args(argv)
    if len(a.args) == 0:
        p.error("You must specify an in bag, an out bag, and an expression.")
    if len(a.args) == 1:
        p.error("You must specify an out bag and an expression.")
    if len(a.args) == 2:
        p.error("You must specify an expression.")
    if len(a.args) > 3:
        p.error("Too many arguments.")
    inbag, outbag, expr = a.args
    in_path, out_path = _resolve(io, inbag), _resolve(io, outbag)
    if not os.path.isfile(in_path):
        io.err(f"Cannot locate input bag file [{inbag}]")
        return 2
    if os.path.realpath(in_path) == os.path.realpath(out_path):
        io.err(f"Cannot use same file as input and output [{inbag}]")
        return 3
    try:
        compile_expression(expr)
        if a.verbose_pattern:
            compile_expression(a.verbose_pattern, "print expression")
        source = Bag(in_path, filename=inbag)
    except ROSBagUnindexedException:
        io.err(f"ERROR bag unindexed: {inbag}.  Run rosbag reindex.")
        return 1
    except ROSBagException as exc:
        io.err(f"ERROR: {exc}")
        return 1
    result = Bag(None, "w")
    try:
        filter_bag(source, result, expr, print_expr=a.verbose_pattern, out=io.out)
        result.save(out_path)
    except DdesError as exc:
        io.err(f"ERROR: {exc}")
        return 1
    return 0


# -- compress / decompress / reindex ------------------------------------------------------------

def _bag_op(io: _IO, cmd: str, argv: list[str]) -> int:
    from ddes.rosbag.ops import change_compression, reindex_file

    p = _parser(io, cmd, f"rosbag {cmd} [options] BAGFILE1 [BAGFILE2 ...]")
    p.add_argument("bags", nargs="*")
    p.add_argument("--output-dir", metavar="DIR", help="write to directory DIR")
    p.add_argument("-f", "--force", action="store_true",
                   help="force overwriting of backup file if it exists")
    p.add_argument("-q", "--quiet", action="store_true", help="suppress noncritical messages")
    if cmd == "compress":
        p.add_argument("-j", "--bz2", dest="compression", action="store_const", const="bz2",
                       default="bz2", help="use BZ2 compression")
        p.add_argument("--lz4", dest="compression", action="store_const", const="lz4",
                       help="use lz4 compression")
    a = p.parse_args(argv)
    if not a.bags:
        p.error("You must specify at least one bag file.")
    failed = False
    output_dir = None if a.output_dir is None else _resolve(io, a.output_dir)
    for path in a.bags:
        where = _resolve(io, path)
        try:
            if cmd == "reindex":
                skipped = reindex_file(where, output_dir=output_dir, force=a.force)
            else:
                kind = a.compression if cmd == "compress" else "none"
                skipped = change_compression(where, kind, output_dir=output_dir, force=a.force)
        except ROSBagUnindexedException:
            io.err(f"ERROR bag unindexed: {path}.  Run rosbag reindex.")
            failed = True
            continue
        except ROSBagException as exc:
            io.err(f"ERROR reading {path}: {_reason(exc, where)}")
            failed = True
            continue
        if skipped is not None and not a.quiet:
            io.err(skipped)
    return 1 if failed else 0


# -- record / play (need a world) -----------------------------------------------------------------

def _need_world(io: _IO, cmd: str) -> ToolContext | None:
    if io.ctx is None:
        io.err(f"ERROR: rosbag {cmd} needs a running world: use it in the ddes console, or "
               f"ddes.console.tooling.run_command(world, 'rosbag {cmd} ...')")
    return io.ctx


def _refuse(io: _IO, what: list[str]) -> int:
    io.err(f"ERROR: ddes does not model {', '.join(what)} (see docs/bags.md)")
    return 1


def _record(io: _IO, argv: list[str]) -> int:
    from ddes.console.toolkit import run_task, take_background
    from ddes.rosbag import Recorder
    from ddes.rosbag.options import BagOptionsError, add_record_arguments, record_options
    from ddes.rosbag.recorder import default_record_date

    argv, background = take_background(argv)
    p = _parser(io, "record", "rosbag record TOPIC1 [TOPIC2 TOPIC3 ...]")
    add_record_arguments(p)
    try:
        opts = record_options(p.parse_args(argv))
    except BagOptionsError as exc:
        p.error(str(exc))
    if opts.unsupported:
        return _refuse(io, opts.unsupported)
    ctx = _need_world(io, "record")
    if ctx is None:
        return 1
    ends = opts.ends_by_itself
    if ends is None and not background and not _open_ended(ctx):
        raise ROSConsoleError(
            "'rosbag record' runs until Ctrl+C in ROS; in ddes give --duration or --limit, or "
            "end the line with & to keep it recording in the background ('kill %N' stops it)")
    if opts.node:
        io.out(f"Recording from: {opts.node}")
    if not opts.topics and opts.limit > 0:
        io.err("Specifying a count is not valid with automatic topic subscription.")
        return 1
    try:
        # DDES_BAG_DATE stands in for the machine's clock, which rosbag reads for default names.
        rec = Recorder(ctx.world, opts.topics, cwd=ctx.cwd,
                       date=default_record_date(ctx.world, os.environ), **opts.recorder_kwargs())
    except ROSBagException as exc:
        io.err(f"ERROR: {exc}")
        return 1
    except DdesError as exc:
        io.err(f"ERROR: Error reading options: {exc}")
        return 1
    task = _task(ctx, "record", argv, rec.done, rec.stop, io)
    return run_task(ctx, task, background=background, duration=None, waiting_for=ends)


def _open_ended(ctx: ToolContext) -> bool:
    """A foreground command that runs until Ctrl+C can run here: interactively, or in a script
    with a time limit (``ddes console --until``)."""
    return getattr(ctx, "rtf", None) is not None or getattr(ctx, "until_ns", None) is not None


def _task(ctx: ToolContext, cmd: str, argv: list[str], done: simpy.Event,
          stop: Callable[[], None], io: _IO) -> Task:
    """A console Task following a recorder or player: stopping it stops them."""
    from ddes.console.toolkit import Task, command_label

    task = Task(ctx.world, command_label("rosbag", [cmd, *argv]))
    task.on_stop(stop)

    def ended(ev: simpy.Event) -> None:
        if not ev.ok:
            ev.defused = True
            io.err(f"ERROR: {ev.value}")
        task.finish(0 if ev.ok else 1)

    done.callbacks.append(ended)
    return task


def _play(io: _IO, argv: list[str]) -> int:
    from ddes.console.toolkit import run_task, take_background
    from ddes.rosbag import Player
    from ddes.rosbag.options import add_play_arguments, play_options
    from ddes.rosbag.player import NO_MESSAGES

    argv, background = take_background(argv)
    p = _parser(io, "play", "rosbag play BAGFILE1 [BAGFILE2 BAGFILE3 ...]")
    add_play_arguments(p)
    opts = play_options(p.parse_args(argv))
    if not opts.bags:
        p.error("You must specify at least 1 bag file to play back.")
    if opts.unsupported:
        return _refuse(io, opts.unsupported)
    ctx = _need_world(io, "play")
    if ctx is None:
        return 1
    endless = opts.endless
    if endless and not background and not _open_ended(ctx):
        raise ROSConsoleError(
            f"'rosbag play {endless[0]}' may run until Ctrl+C; in ddes end the line with & to "
            "keep it playing in the background ('kill %N' stops it)")
    try:
        player = Player(ctx.world, opts.bags, cwd=ctx.cwd, out=io.out, **opts.player_kwargs())
    except ROSBagUnindexedException as exc:
        io.err(str(exc))
        return 1
    except ROSBagException as exc:
        text = str(exc)
        if text == NO_MESSAGES:
            io.err(text)
        elif any(text.startswith(f"{path}: ") for path in opts.bags):
            io.err(f"ERROR reading {text}")
        else:
            io.err(f"ERROR: {text}")
        return 1
    except DdesError as exc:
        io.err(f"ERROR: {exc}")
        return 1
    task = _task(ctx, "play", argv, player.done, player.stop, io)
    return run_task(ctx, task, background=background, duration=None,
                    waiting_for="the end of the bag")


# -- dispatch ---------------------------------------------------------------------------------------

def _usage() -> str:
    lines = ["Usage: rosbag <subcommand> [options] [args]", "",
             "A bag is a file format in ROS for storing ROS message data. The rosbag command can "
             "record, replay and manipulate bags.", "", "Available subcommands:"]
    lines += [f"   {name}  \t{text}" for name, text in sorted({**_COMMANDS, "help": ""}.items())]
    lines += ["", "For additional information, see http://wiki.ros.org/rosbag", ""]
    return "\n".join(lines)


def run(argv: Sequence[str], out: Callable[[str], None], err: Callable[[str], None],
        ctx: ToolContext | None = None) -> int:
    """Run ``rosbag ARGV``; ``ctx`` (a ToolContext) enables ``record`` and ``play``."""
    argv = list(argv)
    io = _IO(out, err, ctx)
    if not argv or argv[0] in ("help", "-h", "--help"):
        rest = [x for x in argv[1:] if x not in ("-h", "--help")]
        if rest and rest[0] in _COMMANDS:
            return run([rest[0], "-h"], out, err, ctx)
        if rest:
            err(f"Unknown command: '{rest[0]}'")
            return 1
        out(_usage())
        return 0
    cmd, args = argv[0], argv[1:]
    try:
        if cmd == "info":
            return _info(io, args)
        if cmd == "check":
            return _check(io, args)
        if cmd == "filter":
            return _filter(io, args)
        if cmd in ("compress", "decompress", "reindex"):
            return _bag_op(io, cmd, args)
        if cmd == "record":
            return _record(io, args)
        if cmd == "play":
            return _play(io, args)
    except _Exit as exc:
        return exc.code
    err(f"Unknown command: '{cmd}'")
    err(_usage())
    return 1


def _tool(ctx: ToolContext, argv: list[str]) -> int:
    return run(argv, ctx.print, ctx.eprint, ctx)


#: World-bound tools of this module.
TOOLS = {"rosbag": _tool}


def rosbag_main(args: argparse.Namespace) -> int:
    """``ddes rosbag ...``: the file subcommands, printing to stdout/stderr."""
    return run(args.argv, print, lambda line: print(line, file=sys.stderr))


def register(subparsers: argparse._SubParsersAction[argparse.ArgumentParser]) -> None:
    """Add ``ddes rosbag`` (info, filter, compress, decompress, reindex on files)."""
    tool = subparsers.add_parser(
        "rosbag", add_help=False, prefix_chars="+",
        help="bag files: info, check, filter, compress, decompress, reindex (record/play in a "
             "world)")
    tool.add_argument("argv", nargs=argparse.REMAINDER)
    tool.set_defaults(func=rosbag_main)
