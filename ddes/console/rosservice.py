"""``rosservice`` (and ``rossrv``) as world-bound tools.

Subcommands, arguments and output follow ros_comm ``tools/rosservice``:

* ``rosservice list [-n] [/namespace]``: sorted names, ``-n`` adds the nodes;
* ``rosservice type|uri|node|info|args /service``; ``find pkg/Type``;
* ``rosservice call [-v] [--wait] /service [args...]``: each argument is
  parsed as YAML; one dict fills fields by name (``"a: 10\\nb: 5"``,
  ``"{a: 10, b: 5}"``), otherwise the values are positional (``10 5``);
  ``now``/``auto`` in a time/Header field take the caller's ROS time
  (genpy ``fill_message_args``).  The response prints as ``str(response)``;
  ``-v`` prints the request and ``---`` first.

Errors print as ROS prints them (``Unknown service [X]``, ``ERROR: Service
[X] is not available.``, ``ERROR: service [X] responded with an error: ...``)
with ROS's exit codes (1, or 2 for ``ERROR:`` and usage errors).

Simulated time: ``call`` runs the world until the response arrives (and
``--wait`` until the service appears), at most :data:`WAIT_LIMIT` simulated
seconds, after which it reports that it is still waiting (ROS would block
until Ctrl+C).  The caller is a temporary anonymous node ``/rosservice_<n>``,
as rosservice's ``init_node('rosservice', anonymous=True)``.

Two ddes conveniences: an argument with a literal ``\\n`` that is not valid
YAML is read with the ``\\n`` as a line break (the lecture slides write
``"a: 10\\nb: 5"`` for what tab completion types as two lines; ROS itself
would reject it); there is no stdin, so a call without arguments to a
service whose request has fields is a usage error, as ROS says on a terminal.
"""

from __future__ import annotations

import optparse
import os
from typing import TYPE_CHECKING, Any, NoReturn

import yaml

from ddes.errors import DdesError, ROSMessageException, ROSSerializationException, ServiceException
from ddes.graph.names import make_global_ns, resolve_name
from ddes.graph.yamlsafe import load_yaml
from ddes.msg.convert import default_keys, fill_message_args
from ddes.time.rostime import Time
from ddes.time.units import duration_to_ns

if TYPE_CHECKING:
    import simpy
    from _typeshed import SupportsWrite

    from ddes.console.tooling import ToolContext
    from ddes.graph.master import ServiceEntry

__all__ = ["TOOLS", "WAIT_LIMIT", "rosservice", "rossrv"]

#: Longest a foreground ``call``/``--wait`` runs the world (simulated seconds).
WAIT_LIMIT = 600.0
_EX_USAGE = getattr(os, "EX_USAGE", 64)

_FULL_USAGE = """Commands:
\trosservice args\tprint service arguments
\trosservice call\tcall the service with the provided args
\trosservice find\tfind services by service type
\trosservice info\tprint information about service
\trosservice list\tlist active services
\trosservice type\tprint service type
\trosservice uri\tprint service ROSRPC uri

Type rosservice <command> -h for more detailed usage, e.g. 'rosservice call -h'
"""


class _Exit(Exception):
    """Stop the tool with an exit code (after printing)."""

    def __init__(self, code: int) -> None:
        super().__init__(code)
        self.code = code


class _ServiceError(DdesError):
    """What rosservice prints as ``ERROR: <text>`` with exit code 2."""


class _Parser(optparse.OptionParser):
    """optparse as rosservice uses it, printing through the tool context."""

    def __init__(self, ctx: ToolContext, usage: str) -> None:
        super().__init__(usage=usage, prog="rosservice")
        self.ctx = ctx

    def error(self, msg: str) -> NoReturn:
        self.ctx.eprint(self.get_usage().rstrip("\n"))
        self.ctx.eprint("")
        self.ctx.eprint(f"rosservice: error: {msg}")
        raise _Exit(2)

    def exit(self, status: int = 0, msg: str | None = None) -> NoReturn:
        if msg:
            self.ctx.eprint(msg.rstrip("\n"))
        raise _Exit(status)

    def print_help(self, file: SupportsWrite[str] | None = None) -> None:
        self.ctx.print(self.format_help().rstrip("\n"))


def _resolve(name: str) -> str:
    """rosgraph ``script_resolve_name('rosservice', name)``."""
    if not name:
        return "/"
    return resolve_name(name, "/rosservice")


def _service_only(ctx: ToolContext, cmd: str, argv: list[str]) -> str:
    parser = _Parser(ctx, f"usage: %prog {cmd} /service")
    _, args = parser.parse_args(argv)
    if not args:
        parser.error("service must be specified")
    if len(args) > 1:
        parser.error("you may only specify one input service")
    return _resolve(args[0])


def _entry(ctx: ToolContext, name: str) -> ServiceEntry | None:
    return ctx.world.master.lookup_service(name)


def _cmd_list(ctx: ToolContext, argv: list[str]) -> int:
    parser = _Parser(ctx, "usage: %prog list [/namespace]")
    parser.add_option("-n", "--nodes", dest="print_nodes", default=False, action="store_true",
                      help="print nodes that provide service(s)")
    options, args = parser.parse_args(argv)
    if len(args) > 1:
        parser.error("you may only specify one input namespace")
    srvs = ctx.world.master.get_system_state()[2]
    if args:
        ns = _resolve(args[0])
        g_ns = make_global_ns(ns)
        srvs = [s for s in srvs if s[0] == ns or s[0].startswith(g_ns)]
    for name, nodes in sorted(srvs, key=lambda s: s[0]):
        ctx.print(name + " " + ",".join(nodes) if options.print_nodes else name)
    return 0


def _cmd_type(ctx: ToolContext, argv: list[str]) -> int:
    name = _service_only(ctx, "type", argv)
    entry = _entry(ctx, name)
    if entry is None:
        ctx.eprint(f"Unknown service [{name}]")
        return 1
    ctx.print(entry.type)
    return 0


def _cmd_uri(ctx: ToolContext, argv: list[str]) -> int:
    name = _service_only(ctx, "uri", argv)
    entry = _entry(ctx, name)
    if entry is None:
        ctx.eprint(f"Unknown service: {name}")
        return 1
    ctx.print(entry.server.uri)
    return 0


def _cmd_node(ctx: ToolContext, argv: list[str]) -> int:
    name = _service_only(ctx, "node", argv)
    entry = _entry(ctx, name)
    if entry is None:
        ctx.eprint(f"Unknown service: {name}")
        return 1
    ctx.print(entry.node.name)
    return 0


def _args_text(entry: ServiceEntry) -> str:
    # genpy.get_printable_message_args on the request *class*: top-level names only
    return " ".join(entry.server.request_class.__slots__)


def _cmd_args(ctx: ToolContext, argv: list[str]) -> int:
    name = _service_only(ctx, "args", argv)
    entry = _entry(ctx, name)
    if entry is None:
        raise _ServiceError(f"Service [{name}] is not available.")
    ctx.print(_args_text(entry))
    return 0


def _cmd_info(ctx: ToolContext, argv: list[str]) -> int:
    parser = _Parser(ctx, "usage: %prog info /service")
    _, args = parser.parse_args(argv)
    if len(args) > 1:
        parser.error("you may only specify one service")
    if not args:
        parser.error("you must specify a service name")
    name = _resolve(args[0])
    entry = _entry(ctx, name)
    if entry is None:
        ctx.eprint("ERROR: unknown service")
        return 1
    ctx.print(f"Node: {entry.node.name}")
    ctx.print(f"URI: {entry.server.uri}")
    ctx.print(f"Type: {entry.type}")
    ctx.print(f"Args: {_args_text(entry)}")
    return 0


def _cmd_find(ctx: ToolContext, argv: list[str]) -> int:
    parser = _Parser(ctx, "usage: %prog find msg-type")
    _, args = parser.parse_args(argv)
    if not args:
        parser.error("please specify a message type")
    if len(args) > 1:
        parser.error("you may only specify one message type")
    srvs = ctx.world.master.get_system_state()[2]
    matches = [name for name, _ in srvs if (e := _entry(ctx, name)) is not None and e.type == args[0]]
    ctx.print("\n".join(matches))
    return 0


def _yaml_arg(arg: str) -> Any:
    if arg == "":
        arg = "''"
    try:
        return load_yaml(arg)  # bounded: no alias bomb, no RecursionError
    except yaml.YAMLError as exc:
        if "\\n" in arg:
            try:
                return load_yaml(arg.replace("\\n", "\n"))
            except yaml.YAMLError:
                pass
        raise _ServiceError(f"Invalid YAML in argument [{arg}]: {exc}") from None


def _argsummary(args: Any) -> str:
    if type(args) in (tuple, list):
        return "\n".join(f" * {a} (type {type(a).__name__})" for a in args)
    return f" * {args} (type {type(args).__name__})"


def _run(ctx: ToolContext, event: simpy.Event, waiting_for: str) -> Any:
    """Step the world until ``event`` is processed, at most :data:`WAIT_LIMIT` seconds.

    Stepping (rather than a deadline event) leaves nothing scheduled behind.
    """
    env = ctx.world.env
    deadline = env.now + duration_to_ns(WAIT_LIMIT)
    if not event.processed:
        event.callbacks.append(_defuse)  # a failure is re-raised below, not by the kernel
        ctx.note_waiting()
    while not event.processed:
        t = env.peek()
        if t == float("inf"):
            raise _ServiceError(f"still waiting for {waiting_for}, and the world has nothing "
                                "left to do (ROS would wait until Ctrl+C)")
        if t > deadline:
            break
        env.step()
    if not event.processed:
        ctx.world.run(until=Time._from_ns(deadline))
        if not event.processed:
            raise _ServiceError(f"still waiting for {waiting_for} after {WAIT_LIMIT:g} simulated "
                                "seconds (ROS would wait until Ctrl+C)")
    if not event.ok:
        raise event.value  # type: ignore[misc]
    return event.value


def _defuse(ev: simpy.Event) -> None:
    ev.defused = True


def _cmd_call(ctx: ToolContext, argv: list[str]) -> int:
    parser = _Parser(ctx, "usage: %prog call /service [args...]")
    parser.add_option("-v", dest="verbose", default=False, action="store_true",
                      help="print verbose output")
    parser.add_option("--wait", dest="wait", default=False, action="store_true",
                      help="wait for service to be advertised")
    options, args = parser.parse_args(argv)
    if not args:
        parser.error("service must be specified")
    world = ctx.world
    name = _resolve(args[0])
    node = world.create_node("rosservice", anonymous=True, disable_rosout=True)
    try:
        if options.wait:
            from ddes.services.waiting import wait_for_service

            _run(ctx, wait_for_service(node, name), f"service [{name}] to be advertised")
        entry = _entry(ctx, name)
        if entry is None:
            raise _ServiceError(f"Service [{name}] is not available.")
        service_class = entry.server.service_class
        service_args = [_yaml_arg(a) for a in args[1:]]
        request = service_class._request_class()
        if not service_args and request.__slots__:
            parser.error("Please specify service arguments")
        try:
            now = node.get_rostime()
            fill_message_args(request, service_args, keys=default_keys(now))
        except ROSMessageException as exc:
            from ddes.msg.convert import get_printable_message_args

            raise _ServiceError(
                f"Incompatible arguments to call service:\n{exc}\nProvided arguments are:\n"
                f"{_argsummary(service_args)}\n\nService arguments are: "
                f"[{get_printable_message_args(request)}]") from None
        from ddes.services.client import ServiceProxy

        proxy = ServiceProxy(node, name, service_class)
        try:
            response = _run(ctx, proxy.call(request), f"the response of [{name}]")
        except ServiceException as exc:
            raise _ServiceError(str(exc)) from None
        except ROSSerializationException as exc:
            from ddes.console.rosmsg import get_srv_text

            raise _ServiceError(
                "Unable to send request. One of the fields has an incorrect type:\n"
                f"  {exc}\n\nsrv file:\n{get_srv_text(ctx.world.messages, service_class._type)}"
            ) from None
        if options.verbose:
            ctx.print(str(request))
            ctx.print("---")
        ctx.print(str(response))
        return 0
    finally:
        node.shutdown("rosservice done")


_COMMANDS = {
    "list": _cmd_list,
    "info": _cmd_info,
    "type": _cmd_type,
    "uri": _cmd_uri,
    "node": _cmd_node,
    "call": _cmd_call,
    "args": _cmd_args,
    "find": _cmd_find,
}


def rosservice(ctx: ToolContext, argv: list[str]) -> int:
    """``rosservice <command> ...`` against ``ctx.world``; returns the exit code."""
    command = _COMMANDS.get(argv[0]) if argv else None
    if command is None:
        ctx.print(_FULL_USAGE.rstrip("\n"))
        return _EX_USAGE
    try:
        return command(ctx, list(argv[1:]))
    except _Exit as stop:
        return stop.code
    except _ServiceError as exc:
        ctx.eprint(f"ERROR: {exc}")
        return 2


def rossrv(ctx: ToolContext, argv: list[str]) -> int:
    """``rossrv show|info|md5|list|package|packages`` on the world's service types (the console's
    ``rosmsg`` twin, :func:`ddes.console.rosmsg.rossrv`)."""
    from ddes.console.rosmsg import rossrv as rossrv_tool

    return rossrv_tool(ctx, argv)


TOOLS = {"rosservice": rosservice, "rossrv": rossrv}
