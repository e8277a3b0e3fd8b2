"""``rosparam``: get, set, list, load, dump and delete parameters of the world.

Output follows ros_comm ``tools/rosparam/src/rosparam/__init__.py``:
``get`` prints ``yaml.dump`` of the value without the ``...`` document end
(``-p`` pretty-prints dicts, sorted); ``dump`` writes ``yaml.dump`` of the
tree to a file or, without one, to the screen; ``list`` prints the sorted
names under a namespace; ``set`` parses its value as YAML (a dict is
merged key by key, the empty string stays a string); ``load`` reads every
YAML document of a file into a namespace (``_ns`` keys honoured,
``!degrees``/``!radians`` converted).  Errors use rosparam's wording:
``Parameter [/x] is not set``, ``parameter [/x] is not set`` (delete).
Relative file names (``load``, ``dump``, ``set -t/-b``) start at the
console's working directory (``roscd``, ``cd``), ``ctx.resolve_path``.
"""

from __future__ import annotations

import optparse
import sys
from pathlib import Path
from typing import TYPE_CHECKING

import yaml

from ddes.console.toolkit import HelpPrinted, ToolParser, script_resolve_name
from ddes.errors import DdesError, ROSConsoleError, ROSParamException
from ddes.graph.names import GLOBALNS, make_global_ns, ns_join
from ddes.graph.yamlsafe import load_yaml, read_bounded
from ddes.launch.values import ParamValue

if TYPE_CHECKING:
    from ddes.console.tooling import ToolContext
    from ddes.graph.params import ParamServer

__all__ = ["TOOLS", "dump_text", "get_text", "pretty_text", "rosparam"]

_USAGE = """rosparam is a command-line tool for getting, setting, and deleting parameters from the ROS Parameter Server.

Commands:
\trosparam set\tset parameter
\trosparam get\tget parameter
\trosparam load\tload parameters from file
\trosparam dump\tdump parameters to file
\trosparam delete\tdelete parameter
\trosparam list\tlist parameter names
"""


def get_text(value: ParamValue) -> str:
    """What ``rosparam get`` writes for ``value`` (``yaml.dump`` minus ``...``, plus a newline)."""
    dump = yaml.dump(value)
    if dump.endswith("\n...\n"):
        dump = dump[:-5]
    return dump + "\n"


def pretty_text(value: dict[str, ParamValue], indent: str = "") -> str:
    """What ``rosparam get -p`` writes for a dict (rosparam's ``_pretty_print``)."""
    out: list[str] = []
    for k in sorted(value):
        v = value[k]
        if type(v) is dict:
            out.append(f"{indent}{k}:\n")
            out.append(pretty_text(v, indent + "  "))
        elif type(v) is str:
            if "\n" in v:
                out.append(f"{indent}{k}: |\n")
                out.extend(f"{indent}  {line}\n" for line in v.split("\n"))
            else:
                out.append(f"{indent}{k}: {v}\n")
        else:
            dump = yaml.dump(v)
            if dump.endswith("\n...\n"):
                dump = dump[:-4]
            out.append(f"{indent}{k}: {dump}")
    return "".join(out)


def dump_text(value: ParamValue) -> str:
    """What ``rosparam dump`` writes (``yaml.dump`` of the tree)."""
    return yaml.dump(value)


def _write(ctx: ToolContext, text: str) -> None:
    """``sys.stdout.write(text)`` through the context's line-based output."""
    if not text:
        return
    if text.endswith("\n"):
        text = text[:-1]
    ctx.print(text)


def _get(params: ParamServer, key: str) -> ParamValue:
    if not params.has_param(key):
        raise ROSParamException(f"Parameter [{key}] is not set")
    return params.get_param(key)


def _set_raw(params: ParamServer, key: str, value: ParamValue, verbose: bool,
             ctx: ToolContext) -> None:
    """rosparam's ``set_param_raw``: dicts are merged key by key."""
    if type(value) is dict:
        for k, v in value.items():
            if not isinstance(k, str):
                raise ROSParamException(
                    f"YAML dictionaries must have string keys. Invalid dictionary is:\n{value}")
            _set_raw(params, ns_join(key, k), v, verbose, ctx)
        return
    if type(value) is int and value > sys.maxsize:
        raise ROSParamException(
            "Overflow: Parameter Server integers must be 32-bit signed integers:\n"
            f"\t-{2**31 - 1} <= value <= {2**31 - 1}")
    try:
        params.set_param(key, value)
    except DdesError as exc:
        raise ROSParamException(str(exc)) from None
    if verbose:
        ctx.print(f"set parameter [{key}] to [{value!s}]")  # bytes print as b'...'


def _print_params(ctx: ToolContext, params: ParamValue, ns: str) -> None:
    if type(params) is dict:
        for k, v in params.items():
            if type(v) is dict:
                _print_params(ctx, v, ns_join(ns, k))
            else:
                ctx.print(f"{ns_join(ns, k)}={v!s}")
    else:
        ctx.print(str(params))


def _get_dump(ctx: ToolContext, cmd: str, argv: list[str]) -> int:
    if cmd == "dump":
        parser = ToolParser(ctx, "usage: %prog dump [options] file [namespace]", "rosparam")
    else:
        parser = ToolParser(ctx, "usage: %prog get [options] parameter", "rosparam")
        parser.add_option("-p", dest="pretty", default=False, action="store_true",
                          help="pretty print. WARNING: not YAML-safe")
    parser.add_option("-v", dest="verbose", default=False, action="store_true",
                      help="turn on verbose output")
    options, args = parser.parse_args(argv)
    arg: str | None = None
    ns = ""
    if not args:
        if cmd == "get":
            parser.error("invalid arguments. Please specify a parameter name")
    elif len(args) == 1:
        arg = args[0]
    elif len(args) == 2 and cmd == "dump":
        arg, ns = args
    else:
        parser.error("too many arguments")
    params = ctx.world.master.params
    if cmd == "get":
        assert arg is not None
        key = script_resolve_name("rosparam", arg)
        if options.verbose:
            ctx.print(f"getting parameter [{key}]")
        val = _get(params, key)
        if options.pretty and type(val) is dict:
            _write(ctx, pretty_text(val))
        elif options.pretty and type(val) is str:
            ctx.print(val)
        else:
            _write(ctx, get_text(val))
        return 0
    key = script_resolve_name("rosparam", ns)
    if options.verbose:
        ctx.print(f"dumping namespace [{ns}] to file [{arg}]")
    tree = _get(params, key)
    if options.verbose:
        _print_params(ctx, tree, key)
    if not arg:
        _write(ctx, dump_text(tree))
    else:
        Path(ctx.resolve_path(arg)).write_text(dump_text(tree), encoding="utf-8")
    return 0


def _set_load(ctx: ToolContext, cmd: str, argv: list[str]) -> int:
    if cmd == "load":
        parser = ToolParser(ctx, "usage: %prog load [options] file [namespace]", "rosparam")
    else:
        parser = ToolParser(ctx, "usage: %prog set [options] parameter value", "rosparam")
        parser.add_option("-t", "--textfile", dest="text_file", default=None,
                          metavar="TEXT_FILE", help="set parameters to contents of text file")
        parser.add_option("-b", "--binfile", dest="bin_file", default=None,
                          metavar="BINARY_FILE", help="set parameters to contents of binary file")
    parser.add_option("-v", dest="verbose", default=False, action="store_true",
                      help="turn on verbose output")
    if cmd == "set":
        options, args = _neg_args(parser, argv)
        if options.text_file and options.bin_file:
            parser.error("you may only specify one of --textfile or --binfile")
    else:
        options, args = parser.parse_args(argv)
    arg2: str | None = None
    if not args:
        if cmd == "load":
            parser.error("invalid arguments. Please specify a file name or - for stdin")
        parser.error("invalid arguments. Please specify a parameter name")
    elif len(args) == 1:
        arg = args[0]
        if cmd == "set" and not (options.text_file or options.bin_file):
            parser.error("invalid arguments. Please specify a parameter value")
    elif len(args) == 2:
        arg, arg2 = args
    else:
        parser.error("too many arguments")
    params = ctx.world.master.params
    if cmd == "set":
        name = script_resolve_name("rosparam", arg)
        if options.text_file:
            path = Path(ctx.resolve_path(options.text_file))
            if not path.exists():
                parser.error(f"file '{options.text_file}' does not exist")
            data = read_bounded(path, what="text file", error=ROSParamException)
            try:
                text_value = data.decode("utf-8")
            except UnicodeDecodeError as exc:
                raise ROSParamException(
                    f"text file '{options.text_file}' is not UTF-8 ({exc.reason} at byte "
                    f"{exc.start}); use --binfile for binary data") from None
            _set_raw(params, name, text_value, options.verbose, ctx)
        elif options.bin_file:
            bin_path = ctx.resolve_path(options.bin_file)
            if not Path(bin_path).exists():
                parser.error(f"file '{options.bin_file}' does not exist")
            _set_raw(params, name, read_bounded(bin_path, what="binary file",
                                                error=ROSParamException),
                     options.verbose, ctx)
        else:
            assert arg2 is not None
            text = "!!str" if arg2 == "" else arg2
            try:
                value = load_yaml(text)
            except yaml.YAMLError as exc:
                raise ROSParamException(f"invalid YAML value {arg2!r}: {exc}") from None
            _set_raw(params, name, value, options.verbose, ctx)
        return 0
    if arg == "-":
        raise ROSParamException("ddes reads no parameters from stdin; give a YAML file")
    path = Path(ctx.resolve_path(arg))
    if not path.exists():
        raise ROSParamException(f"file [{arg}] does not exist")
    if options.verbose:
        ctx.print(f"reading parameters from [{arg}]")
    ns = script_resolve_name("rosparam", arg2 or "")
    try:
        loaded = params.load(path, ns)
    except DdesError as exc:
        raise ROSParamException(str(exc)) from None
    if options.verbose:
        for target, doc in loaded:
            _print_params(ctx, doc, target)
    return 0


def _neg_args(parser: ToolParser, argv: list[str]) -> tuple[optparse.Values, list[str]]:
    """rosparam's option split that lets ``rosparam set x -1`` take -1 as a value."""
    args: list[str] = []
    opt_args: list[str] = []
    skip = False
    for s in argv:
        if s.startswith("-"):
            if s in ("-t", "--textfile", "-b", "--binfile"):
                skip = True
                opt_args.append(s)
            elif skip:
                parser.error("-t and --textfile options require an argument")
            elif len(s) > 1 and s[1].isdigit():
                args.append(s)
            else:
                opt_args.append(s)
        elif skip:
            skip = False
            opt_args.append(s)
        else:
            args.append(s)
    options, _ = parser.parse_args(opt_args)
    return options, args


def _list(ctx: ToolContext, argv: list[str]) -> int:
    parser = ToolParser(ctx, "usage: %prog list [namespace]", "rosparam")
    _options, args = parser.parse_args(argv)
    ns = GLOBALNS
    if len(args) == 1:
        ns = script_resolve_name("rosparam", args[0])
    elif len(args) >= 2:
        parser.error("too many arguments")
    prefix = make_global_ns(ns)
    names = [n for n in ctx.world.master.params.get_param_names() if n.startswith(prefix)]
    ctx.print("\n".join(sorted(names)))
    return 0


def _delete(ctx: ToolContext, argv: list[str]) -> int:
    parser = ToolParser(ctx, "usage: %prog delete [options] parameter", "rosparam")
    parser.add_option("-v", dest="verbose", default=False, action="store_true",
                      help="turn on verbose output")
    options, args = parser.parse_args(argv)
    if not args:
        parser.error("invalid arguments. Please specify a parameter name")
    if len(args) > 1:
        parser.error("too many arguments")
    key = script_resolve_name("rosparam", args[0])
    params = ctx.world.master.params
    if key == GLOBALNS:
        params.set_param(GLOBALNS, {})
        if options.verbose:
            ctx.print("deleted ENTIRE parameter server")
        return 0
    if not params.has_param(key):
        raise ROSParamException(f"parameter [{key}] is not set")
    params.delete_param(key)
    if options.verbose:
        ctx.print(f"deleted parameter [{key}]")
    return 0


def rosparam(ctx: ToolContext, argv: list[str]) -> int:
    """The ``rosparam`` tool (see the module docstring)."""
    commands = ("set", "get", "load", "dump", "delete", "list")
    if not argv or argv[0] in ("-h", "--help"):
        ctx.print(_USAGE)
        return 0
    if argv[0] not in commands:
        raise ROSConsoleError(
            f"unknown command 'rosparam {argv[0]}'; rosparam commands: {', '.join(commands)}")
    cmd, rest = argv[0], argv[1:]
    try:
        if cmd in ("get", "dump"):
            return _get_dump(ctx, cmd, rest)
        if cmd in ("set", "load"):
            return _set_load(ctx, cmd, rest)
        if cmd == "delete":
            return _delete(ctx, rest)
        return _list(ctx, rest)
    except HelpPrinted:
        return 0


TOOLS = {"rosparam": rosparam}
