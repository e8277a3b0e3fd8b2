"""``ddes rosmsg`` and ``ddes rossrv``: the ROS 1 tools for message and service types.

Subcommands and output follow ``rosmsg``/``rossrv`` (ros_comm
``tools/rosmsg``): ``show`` (alias ``info``; ``-r/--raw`` for the file text),
``md5``, ``list``, ``package`` (``-s`` one line), ``packages`` (``-s``).
``show`` prints constants as ``type NAME=value`` and fields as ``type name``,
nested types expanded below their field and indented two spaces per
level; ``rossrv show`` prints the request, ``---``, then the response.  A bare
``Type`` (no package) prints a ``[pkg/Type]:`` header per matching package.

Types are looked up on the package path (bundled packages plus
``DDES_PACKAGE_PATH``), read afresh on each command.  ``rosmsg show -b BAG``
is not offered.
"""

from __future__ import annotations

import argparse
import os
import sys

from ddes.errors import InvalidMsgSpec, MsgNotFound
from ddes.msg.registry import MessageRegistry
from ddes.msg.spec import MsgSpec, bare_msg_type, is_builtin

__all__ = ["get_msg_text", "get_srv_text", "main", "register", "spec_to_str"]

_EX_USAGE = getattr(os, "EX_USAGE", 64)


class _ToolError(Exception):
    """A failure the tool reports on stderr with exit code 1."""


def spec_to_str(registry: MessageRegistry, spec: MsgSpec, indent: str = "") -> str:
    """The text ``rosmsg show`` prints for ``spec`` (nested types expanded)."""
    lines: list[str] = []
    for c in spec.constants:
        lines.append(f"{indent}{c.type} {c.name}={c.val_text}\n")
    for f in spec.fields:
        lines.append(f"{indent}{f.type} {f.name}\n")
        base = bare_msg_type(f.type)
        if not is_builtin(base):
            lines.append(spec_to_str(registry, registry.get_msg_spec(base), indent + "  "))
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


def _clean_type(arg: str, mode: str, parser: argparse.ArgumentParser) -> str:
    ext = "." + mode
    if arg.endswith(ext):
        arg = arg[: -len(ext)]
    if "::" in arg:
        parser.error(f"ros{mode} does not understand C++-style namespaces (i.e. '::').\n"
                     "Please refer to msg/srv types as 'package_name/Type'.")
    if "." in arg:
        parser.error(f"invalid message type '{arg}'.\n"
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


def _cmd_show(args: argparse.Namespace, registry: MessageRegistry) -> int:
    mode = args.mode
    arg = _clean_type(args.type, mode, args.parser)
    if "/" in arg:
        print(_text(registry, mode, arg, args.raw))
        return 0
    found = registry.find(arg, mode)
    if not found:
        print(f"Could not find msg '{arg}'", file=sys.stderr)
        return 1
    for name in found:
        print(f"[{name}]:")
        print(_text(registry, mode, name, args.raw))
    return 0


def _md5(registry: MessageRegistry, mode: str, type_name: str) -> str:
    if mode == "msg":
        return registry.get_message_class(type_name)._md5sum
    return registry.get_service_class(type_name)._md5sum


def _cmd_md5(args: argparse.Namespace, registry: MessageRegistry) -> int:
    mode, arg = args.mode, args.type
    if "/" in arg:
        try:
            print(_md5(registry, mode, arg))
        except (MsgNotFound, InvalidMsgSpec):
            print(f"Cannot locate [{arg}]", file=sys.stderr)
        return 0
    matches = registry.find(arg, mode)
    for name in matches:
        try:
            print(f"[{name}]: {_md5(registry, mode, name)}")
        except (MsgNotFound, InvalidMsgSpec):
            print(f"Cannot locate [{name}]", file=sys.stderr)
    if not matches:
        print(f"No messages matching the name [{arg}]", file=sys.stderr)
    return 0


def _cmd_list(args: argparse.Namespace, registry: MessageRegistry) -> int:
    for name in registry.iter_types(args.mode):
        print(name)
    return 0


def _cmd_package(args: argparse.Namespace, registry: MessageRegistry) -> int:
    try:
        names = registry.list_types(args.package, args.mode)
    except MsgNotFound as exc:
        print(f"Invalid package: {exc}", file=sys.stderr)
        return _EX_USAGE
    print((" " if args.single_line else "\n").join(names))
    return 0


def _cmd_packages(args: argparse.Namespace, registry: MessageRegistry) -> int:
    print((" " if args.single_line else "\n").join(registry.list_packages(args.mode)))
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


def main(args: argparse.Namespace) -> int:
    """Run a parsed ``rosmsg``/``rossrv`` command; returns the exit code."""
    handler = getattr(args, "handler", None)
    if handler is None:
        print(_usage(args.mode))
        return 0
    registry = MessageRegistry.from_environment()  # the ddes command starts here
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
            show = verbs.add_parser(verb, help=f"show {kind} description")
            show.add_argument("type", help=f"{kind} type, pkg/Type or a bare Type")
            show.add_argument("-r", "--raw", action="store_true",
                              help=f"show raw {kind} text, including comments")
            show.set_defaults(handler=_cmd_show, parser=show)
        md5 = verbs.add_parser("md5", help=f"display {kind} md5sum")
        md5.add_argument("type", help=f"{kind} type, pkg/Type or a bare Type")
        md5.set_defaults(handler=_cmd_md5)
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
