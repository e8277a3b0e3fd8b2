"""``rosmsg`` and ``rossrv``: the ROS 1 tools for message and service types.

Subcommands and output follow ``rosmsg``/``rossrv`` (ros_comm
``tools/rosmsg``): ``show`` (alias ``info``; ``-r/--raw`` for the file text),
``md5``, ``list``, ``package`` (``-s`` one line), ``packages`` (``-s``).
``show`` prints constants as ``type NAME=value`` and fields as ``type name``,
nested types expanded below their field and indented two spaces per
level; ``rossrv show`` prints the request, ``---``, then the response.  A bare
``Type`` (no package) prints a ``[pkg/Type]:`` header per matching package.

Two front ends share the commands below:

* ``ddes rosmsg`` / ``ddes rossrv`` (:func:`register`, :func:`main`): types
  on the package path of the environment (bundled packages plus
  ``DDES_PACKAGE_PATH``), read afresh on each command;
* the console tool ``rosmsg`` (:data:`TOOLS`; :func:`rossrv` is the same
  for services): the types of the console's world, ``ctx.world.messages``,
  with the console's one-line usage errors.

``rosmsg show -b BAG`` is not offered, and the type is never read from
standard input (rosmsg reads it there when it is missing).

``show`` prints every nested type in full, as rosmsg does, so types that hold
the next type twice ("diamonds": A has two B, B two C, ...) expand
exponentially.  The size of the text is computed first, memoised per type,
and a type that would print more than :data:`MAX_SHOW_CHARS` characters is
refused (exit code 1, the sizes and ``show -r`` named) before any text is
built; rosmsg prints for hours.
"""

from __future__ import annotations

import argparse
import os
import sys
from collections.abc import Callable
from typing import TYPE_CHECKING

from ddes.errors import InvalidMsgSpec, MsgNotFound, ResourceLimitError, ROSConsoleError
from ddes.msg.registry import MessageRegistry
from ddes.msg.spec import MsgSpec, bare_msg_type, is_builtin
from ddes.rospack import command_package_path

if TYPE_CHECKING:
    from ddes.console.tooling import ToolContext
    from ddes.console.toolkit import ToolParser

__all__ = ["MAX_SHOW_CHARS", "TOOLS", "get_msg_text", "get_srv_text", "main", "register",
           "rosmsg", "rossrv", "show_size", "spec_to_str"]

#: The most text ``rosmsg show`` prints for one type (16 MiB), nested types expanded.
MAX_SHOW_CHARS = 16 << 20

_EX_USAGE = getattr(os, "EX_USAGE", 64)

#: Where a command writes a line (``print``, ``ctx.print``).
Write = Callable[[str], None]


class _ToolError(Exception):
    """A failure the tool reports on stderr with exit code 1."""


def show_size(registry: MessageRegistry, spec: MsgSpec,
              memo: dict[str, tuple[int, int]] | None = None) -> tuple[int, int]:
    """``(lines, characters)`` of ``spec_to_str(registry, spec)``, without building it.

    Memoised per type, so a diamond of 40 types costs 40 steps; a line nested
    ``k`` levels deep carries ``2 * k`` characters of indent.
    """
    memo = {} if memo is None else memo
    got = memo.get(spec.full_name)
    if got is not None:
        return got
    lines = chars = 0
    for c in spec.constants:
        lines += 1
        chars += len(f"{c.type} {c.name}={c.val_text}\n")
    for f in spec.fields:
        lines += 1
        chars += len(f"{f.type} {f.name}\n")
        base = bare_msg_type(f.type)
        if not is_builtin(base):
            n, k = show_size(registry, registry.get_msg_spec(base), memo)
            lines += n
            chars += k + 2 * n
    memo[spec.full_name] = (lines, chars)
    return lines, chars


def spec_to_str(registry: MessageRegistry, spec: MsgSpec, indent: str = "") -> str:
    """The text ``rosmsg show`` prints for ``spec`` (nested types expanded).

    Raises :class:`~ddes.errors.ResourceLimitError` before building a text
    longer than :data:`MAX_SHOW_CHARS`.
    """
    n, chars = show_size(registry, spec)
    chars += len(indent) * n
    if chars > MAX_SHOW_CHARS:
        raise ResourceLimitError(
            f"rosmsg show {spec.full_name} would print {n} lines ({chars} characters) once its "
            f"nested types are expanded, more than ddes.console.rosmsg.MAX_SHOW_CHARS "
            f"({MAX_SHOW_CHARS}): its types nest each other many times (a type holding the "
            "next one twice doubles the text at every level); 'show -r' prints the definition "
            "as written")
    return _spec_text(registry, spec, indent)


def _spec_text(registry: MessageRegistry, spec: MsgSpec, indent: str) -> str:
    lines: list[str] = []
    for c in spec.constants:
        lines.append(f"{indent}{c.type} {c.name}={c.val_text}\n")
    for f in spec.fields:
        lines.append(f"{indent}{f.type} {f.name}\n")
        base = bare_msg_type(f.type)
        if not is_builtin(base):
            lines.append(_spec_text(registry, registry.get_msg_spec(base), indent + "  "))
    return "".join(lines)


def get_msg_text(registry: MessageRegistry, type_name: str, raw: bool = False) -> str:
    """What ``rosmsg show [-r] pkg/Type`` prints (before print's newline)."""
    spec = registry.get_msg_spec(type_name)
    if raw:
        return spec.text
    registry.md5sum(type_name)  # loads and checks every nested type
    return spec_to_str(registry, spec)


def get_srv_text(registry: MessageRegistry, type_name: str, raw: bool = False) -> str:
    """What ``rossrv show [-r] pkg/Type`` prints (before print's newline)."""
    spec = registry.get_srv_spec(type_name)
    if raw:
        return spec.text
    registry.srv_md5sum(type_name)
    return spec_to_str(registry, spec.request) + "---\n" + spec_to_str(registry, spec.response)


def _clean_type(arg: str, mode: str, error: Callable[[str], object]) -> str:
    """rosmsg's checks of a type argument (``.msg`` suffix dropped); ``error`` reports misuse."""
    ext = "." + mode
    if arg.endswith(ext):
        arg = arg[: -len(ext)]
    if "::" in arg:
        error(f"ros{mode} does not understand C++-style namespaces (i.e. '::').\n"
              "Please refer to msg/srv types as 'package_name/Type'.")
    elif "." in arg:
        error(f"invalid message type '{arg}'.\n"
              "Please refer to msg/srv types as 'package_name/Type'.")
    return arg


def _text(registry: MessageRegistry, mode: str, type_name: str, raw: bool) -> str:
    try:
        if mode == "msg":
            return get_msg_text(registry, type_name, raw)
        return get_srv_text(registry, type_name, raw)
    except (MsgNotFound, InvalidMsgSpec) as exc:
        what = "Unable to load msg" if mode == "msg" else "Unknown srv type"
        raise _ToolError(f"{what} [{type_name}]: {exc}") from None
    except ResourceLimitError as exc:
        raise _ToolError(f"ERROR: {exc}") from None


# -- the commands, writing through out/err -------------------------------------------------------
def show(registry: MessageRegistry, mode: str, arg: str, raw: bool, out: Write,
         err: Write) -> int:
    """``rosmsg show [-r] TYPE`` on a checked type argument; raises _ToolError on a bad type."""
    if "/" in arg:
        out(_text(registry, mode, arg, raw))
        return 0
    found = registry.find(arg, mode)
    if not found:
        err(f"Could not find msg '{arg}'")
        return 1
    for name in found:
        out(f"[{name}]:")
        out(_text(registry, mode, name, raw))
    return 0


def _md5(registry: MessageRegistry, mode: str, type_name: str) -> str:
    if mode == "msg":
        return registry.get_message_class(type_name)._md5sum
    return registry.get_service_class(type_name)._md5sum


def md5(registry: MessageRegistry, mode: str, arg: str, out: Write, err: Write) -> int:
    """``rosmsg md5 TYPE`` (rosmsg exits 0 even when the type is unknown)."""
    if "/" in arg:
        try:
            out(_md5(registry, mode, arg))
        except (MsgNotFound, InvalidMsgSpec):
            err(f"Cannot locate [{arg}]")
        return 0
    matches = registry.find(arg, mode)
    for name in matches:
        try:
            out(f"[{name}]: {_md5(registry, mode, name)}")
        except (MsgNotFound, InvalidMsgSpec):
            err(f"Cannot locate [{name}]")
    if not matches:
        err(f"No messages matching the name [{arg}]")
    return 0


def list_all(registry: MessageRegistry, mode: str, out: Write) -> int:
    """``rosmsg list``: every type, by package then name."""
    for name in registry.iter_types(mode):
        out(name)
    return 0


def package(registry: MessageRegistry, mode: str, name: str, single_line: bool, out: Write,
            err: Write) -> int:
    """``rosmsg package [-s] PKG`` (exit code 64, EX_USAGE, for an unknown package)."""
    try:
        names = registry.list_types(name, mode)
    except MsgNotFound as exc:
        err(f"Invalid package: {exc}")
        return _EX_USAGE
    out((" " if single_line else "\n").join(names))
    return 0


def packages(registry: MessageRegistry, mode: str, single_line: bool, out: Write) -> int:
    """``rosmsg packages [-s]``: the packages defining types of this kind."""
    out((" " if single_line else "\n").join(registry.list_packages(mode)))
    return 0


def _usage(mode: str) -> str:
    cmd, kind = f"ros{mode}", "message" if mode == "msg" else "service"
    return (
        f"{cmd} is a command-line tool for displaying information about ROS "
        f"{kind.capitalize()} types.\n\nCommands:\n"
        f"\t{cmd} show\tShow {kind} description\n"
        f"\t{cmd} info\tAlias for {cmd} show\n"
        f"\t{cmd} list\tList all {kind}s\n"
        f"\t{cmd} md5\tDisplay {kind} md5sum\n"
        f"\t{cmd} package\tList {kind}s in a package\n"
        f"\t{cmd} packages\tList packages that contain {kind}s\n\n"
        f"Type {cmd} <command> -h for more detailed usage\n"
    )


# -- ddes rosmsg / ddes rossrv (argparse) ----------------------------------------------------------
def _stdout(text: str) -> None:
    print(text)


def _stderr(text: str) -> None:
    print(text, file=sys.stderr)


def _cmd_show(args: argparse.Namespace, registry: MessageRegistry) -> int:
    arg = _clean_type(args.type, args.mode, args.parser.error)
    return show(registry, args.mode, arg, args.raw, _stdout, _stderr)


def _cmd_md5(args: argparse.Namespace, registry: MessageRegistry) -> int:
    return md5(registry, args.mode, args.type, _stdout, _stderr)


def _cmd_list(args: argparse.Namespace, registry: MessageRegistry) -> int:
    return list_all(registry, args.mode, _stdout)


def _cmd_package(args: argparse.Namespace, registry: MessageRegistry) -> int:
    return package(registry, args.mode, args.package, args.single_line, _stdout, _stderr)


def _cmd_packages(args: argparse.Namespace, registry: MessageRegistry) -> int:
    return packages(registry, args.mode, args.single_line, _stdout)


def main(args: argparse.Namespace) -> int:
    """Run a parsed ``rosmsg``/``rossrv`` command; returns the exit code."""
    handler = getattr(args, "handler", None)
    if handler is None:
        print(_usage(args.mode))
        return 0
    # the ddes command starts here: the package path of DDES_PACKAGE_PATH and the working folder
    registry = MessageRegistry(command_package_path(os.environ, os.getcwd()))
    try:
        return int(handler(args, registry))
    except _ToolError as exc:
        print(str(exc), file=sys.stderr)
        return 1


def register(subparsers: argparse._SubParsersAction[argparse.ArgumentParser]) -> None:
    """Add the ``rosmsg`` and ``rossrv`` subcommands to the ``ddes`` parser."""
    for mode in ("msg", "srv"):
        kind = "message" if mode == "msg" else "service"
        tool = subparsers.add_parser(f"ros{mode}", help=f"show information about ROS {kind} types",
                                     description=_usage(mode),
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
        tool.set_defaults(func=main, mode=mode)
        verbs = tool.add_subparsers(metavar="COMMAND")
        for verb in ("show", "info"):
            show_p = verbs.add_parser(verb, help=f"show {kind} description")
            show_p.add_argument("type", help=f"{kind} type, pkg/Type or a bare Type")
            show_p.add_argument("-r", "--raw", action="store_true",
                                help=f"show raw {kind} text, including comments")
            show_p.set_defaults(handler=_cmd_show, parser=show_p)
        md5_p = verbs.add_parser("md5", help=f"display {kind} md5sum")
        md5_p.add_argument("type", help=f"{kind} type, pkg/Type or a bare Type")
        md5_p.set_defaults(handler=_cmd_md5)
        lst = verbs.add_parser("list", help=f"list all {kind}s")
        lst.set_defaults(handler=_cmd_list)
        pkg = verbs.add_parser("package", help=f"list {kind}s in a package")
        pkg.add_argument("package")
        pkg.add_argument("-s", dest="single_line", action="store_true",
                         help=f"list all {kind}s on a single line")
        pkg.set_defaults(handler=_cmd_package)
        pkgs = verbs.add_parser("packages", help=f"list packages that contain {kind}s")
        pkgs.add_argument("-s", dest="single_line", action="store_true",
                          help="list all packages on a single line")
        pkgs.set_defaults(handler=_cmd_packages)


# -- the console tools (optparse, as rosmsg itself) ---------------------------------------------------
def _one_arg(parser: ToolParser, args: list[str], full: str) -> str:
    """The single type/package argument (rosmsg reads a missing one from stdin; ddes asks)."""
    if not args:
        parser.error(f"give the {full}: the console reads no {full} from standard input")
    if len(args) > 1:
        parser.error(f"you may only specify one {full}")
    return args[0]


def _console(ctx: ToolContext, argv: list[str], mode: str) -> int:
    from ddes.console.toolkit import HelpPrinted, ToolParser

    cmd = f"ros{mode}"
    full = "message type" if mode == "msg" else "service type"
    if not argv or argv[0] in ("-h", "--help"):
        ctx.print(_usage(mode))
        return 0
    verb, rest = argv[0], argv[1:]
    registry = ctx.world.messages
    try:
        if verb in ("show", "info"):
            parser = ToolParser(ctx, f"usage: {cmd} {verb} [options] <{full}>", cmd)
            parser.add_option("-r", "--raw", dest="raw", default=False, action="store_true",
                              help="show raw message text, including comments")
            parser.add_option("-b", "--bag", dest="bag", default=None, metavar="BAGFILE",
                              help="show message from .bag file (not offered by ddes)")
            options, args = parser.parse_args(rest)
            arg = _clean_type(_one_arg(parser, args, full), mode, parser.error)
            if options.bag:
                raise ROSConsoleError(f"{cmd} show -b is not offered by ddes; 'rosbag info "
                                      f"{options.bag}' lists the bag's types")
            return show(registry, mode, arg, options.raw, ctx.print, ctx.eprint)
        if verb == "md5":
            parser = ToolParser(ctx, f"usage: {cmd} md5 <{full}>", cmd)
            _options, args = parser.parse_args(rest)
            return md5(registry, mode, _one_arg(parser, args, full), ctx.print, ctx.eprint)
        if verb in ("package", "packages"):
            usage = f"usage: {cmd} package <package>" if verb == "package" else \
                f"usage: {cmd} packages"
            parser = ToolParser(ctx, usage, cmd)
            parser.add_option("-s", dest="single_line", default=False, action="store_true",
                              help=f"list all {'msgs' if verb == 'package' else 'packages'} on "
                                   "a single line")
            options, args = parser.parse_args(rest)
            if verb == "packages":
                return packages(registry, mode, options.single_line, ctx.print)
            return package(registry, mode, _one_arg(parser, args, "package"),
                           options.single_line, ctx.print, ctx.eprint)
        if verb == "list":
            parser = ToolParser(ctx, f"usage: {cmd} list", cmd)
            parser.parse_args(rest)
            return list_all(registry, mode, ctx.print)
    except HelpPrinted:
        return 0
    except _ToolError as exc:
        ctx.eprint(str(exc))
        return 1
    raise ROSConsoleError(f"unknown command '{cmd} {verb}'; {cmd} commands: info, list, md5, "
                          "package, packages, show")


def rosmsg(ctx: ToolContext, argv: list[str]) -> int:
    """The console's ``rosmsg``: ``show|info [-r]``, ``md5``, ``list``, ``package [-s]``,
    ``packages [-s]`` on the world's message types."""
    return _console(ctx, argv, "msg")


def rossrv(ctx: ToolContext, argv: list[str]) -> int:
    """``rossrv`` on the world's service types (what :func:`rosmsg` is for messages)."""
    return _console(ctx, argv, "srv")


TOOLS = {"rosmsg": rosmsg}
