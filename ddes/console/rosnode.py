"""``rosnode``: list, info, kill and ping the nodes of the world.

Output follows ros_comm ``tools/rosnode/src/rosnode/__init__.py``
character for character: ``rosnode list`` prints the sorted names,
``-u`` their URIs and ``-a`` both (``uri \\tname``); ``rosnode info`` prints
the 80-dash rule, ``Node [/n]``, ``Publications:``/``Subscriptions:``/
``Services:`` (``None`` when empty) and the node's connections;
``rosnode kill`` prints ``killing /n`` then ``killed``; ``rosnode ping``
prints ``rosnode: node is [/n]``, ``pinging /n with a timeout of 3.0s`` and
one ``xmlrpc reply from URI\\ttime=...ms`` per simulated second.

ddes specifics: URIs and pids are synthetic (:func:`ddes.launch.runtime.node_uri`);
a ping takes ``world.connect_delay`` of simulated time (the XML-RPC round
trip) and, since ROS pings until Ctrl+C, needs ``-c COUNT`` or
``--duration S`` (or ``&``).  An unknown node prints rosnode's text
(``cannot contact [/n]: unknown node`` after the empty ``info`` block,
``cannot ping [/n]: unknown node``, ``ERROR: Unknown node(s):`` and a
`` * /n`` line each) with exit code 1 (rosnode exits 0 after the first
two) so scripts stop there.  rospy's connection details (``outbound (PORT
- IP:PORT) [FD]``) are not shown: there are no sockets.
``rosnode machine`` lists ``localhost``; ``rosnode cleanup`` has nothing
to purge (every registration belongs to a live node).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from ddes.console.toolkit import (
    HelpPrinted,
    Task,
    ToolParser,
    add_run_options,
    command_label,
    node_pid,
    node_uri,
    parse_duration,
    run_task,
    script_resolve_name,
    take_background,
)
from ddes.errors import ROSConsoleError
from ddes.graph.names import make_global_ns
from ddes.time.rostime import Duration
from ddes.time.units import ns_to_sec, to_ns

if TYPE_CHECKING:
    from simpy.events import ProcessGenerator

    from ddes.console.tooling import ToolContext
    from ddes.graph.world import World

__all__ = ["TOOLS", "get_node_info_description", "get_node_names", "rosnode"]

_EX_USAGE = 64

_USAGE = """rosnode is a command-line tool for printing information about ROS Nodes.

Commands:
\trosnode ping\ttest connectivity to node
\trosnode list\tlist active nodes
\trosnode info\tprint information about node
\trosnode machine\tlist nodes running on a particular machine or list machines
\trosnode kill\tkill a running node
\trosnode cleanup\tpurge registration information of unreachable nodes

Type rosnode <command> -h for more detailed usage, e.g. 'rosnode ping -h'
"""


def get_node_names(world: World, namespace: str | None = None) -> list[str]:
    """Names of the live nodes (under ``namespace``), sorted as ``rosnode list`` prints them."""
    names = world.master.node_names()
    if namespace:
        g_ns = make_global_ns(namespace)
        names = [n for n in names if n.startswith(g_ns) or n == namespace]
    return sorted(names)


def _topic_type(world: World, topic: str) -> str:
    entry = world.master.topics.get(topic)
    return entry.type if entry is not None and entry.publishers else "unknown type"


def get_node_info_description(world: World, node_name: str) -> str:
    """The first part of ``rosnode info``: publications, subscriptions, services."""
    pubs_state, subs_state, srvs_state = world.master.get_system_state()
    pubs = sorted(t for t, nodes in pubs_state if node_name in nodes)
    subs = sorted(t for t, nodes in subs_state if node_name in nodes)
    srvs = sorted(s for s, nodes in srvs_state if node_name in nodes)
    buff = f"Node [{node_name}]"
    if pubs:
        buff += "\nPublications: \n"
        buff += "\n".join(f" * {t} [{_topic_type(world, t)}]" for t in pubs) + "\n"
    else:
        buff += "\nPublications: None\n"
    if subs:
        buff += "\nSubscriptions: \n"
        buff += "\n".join(f" * {t} [{_topic_type(world, t)}]" for t in subs) + "\n"
    else:
        buff += "\nSubscriptions: None\n"
    if srvs:
        buff += "\nServices: \n"
        buff += "\n".join(f" * {s}" for s in srvs) + "\n"
    else:
        buff += "\nServices: None\n"
    return buff


def get_node_connection_info_description(world: World, node_name: str) -> str:
    """The second part of ``rosnode info``: pid and the node's live connections."""
    node = world.master.lookup_node(node_name)
    buff = f"Pid: {node_pid(node_name)}\n"
    if node is None:
        return buff
    lines: list[str] = []
    for pub in node._published:
        for conn in pub.connections:
            lines += [f" * topic: {pub.resolved_name}", f"    * to: {conn.sub.node.name}",
                      "    * direction: outbound", "    * transport: TCPROS"]
    for sub in node._subscribed:
        for conn in sub.connections:
            lines += [f" * topic: {sub.resolved_name}", f"    * to: {conn.pub.node.name}",
                      "    * direction: inbound", "    * transport: TCPROS"]
    if lines:
        buff += "Connections:\n" + "".join(line + "\n" for line in lines)
    return buff


def _list(ctx: ToolContext, argv: list[str]) -> int:
    parser = ToolParser(ctx, "usage: %prog list", "rosnode")
    parser.add_option("-u", dest="list_uri", default=False, action="store_true",
                      help="list XML-RPC URIs")
    parser.add_option("-a", "--all", dest="list_all", default=False, action="store_true",
                      help="list all information")
    options, args = parser.parse_args(argv)
    namespace = None
    if len(args) > 1:
        parser.error("invalid args: you may only specify one namespace")
    elif len(args) == 1:
        namespace = script_resolve_name("rostopic", args[0])
    nodes = get_node_names(ctx.world, namespace)
    if options.list_all:
        ctx.print("\n".join(f"{node_uri(n)} \t{n}" for n in nodes))
    elif options.list_uri:
        ctx.print("\n".join(node_uri(n) for n in nodes))
    else:
        ctx.print("\n".join(nodes))
    return 0


def _info(ctx: ToolContext, argv: list[str]) -> int:
    parser = ToolParser(ctx, "usage: %prog info [options] node1 [node2...]", "rosnode")
    parser.add_option("-q", "--quiet", dest="quiet", default=False, action="store_true",
                      help="Prints only basic information such as pubs/subs and does not "
                           "contact nodes for more information")
    options, args = parser.parse_args(argv)
    if not args:
        parser.error("You must specify at least one node name")
    world = ctx.world
    code = 0
    for arg in args:
        name = script_resolve_name("rosnode", arg)
        ctx.print("-" * 80)
        ctx.print(get_node_info_description(world, name))
        if world.master.lookup_node(name) is None:
            ctx.eprint(f"cannot contact [{name}]: unknown node")
            code = 1  # rosnode goes on to the next node and exits 0; ddes stops a script
            continue
        if not options.quiet:
            ctx.print(f"\ncontacting node {node_uri(name)} ...")
            ctx.print(get_node_connection_info_description(world, name))
    return code


def _kill(ctx: ToolContext, argv: list[str]) -> int:
    parser = ToolParser(ctx, "usage: %prog kill [node]...", "rosnode")
    parser.add_option("-a", "--all", dest="kill_all", default=False, action="store_true",
                      help="kill all nodes")
    options, args = parser.parse_args(argv)
    world = ctx.world
    if options.kill_all:
        if args:
            parser.error("invalid arguments with kill all (-a) option")
        names = get_node_names(world)
    elif not args:
        parser.error("give the node(s) to kill, or -a for all: ddes has no interactive "
                     "selection prompt (see 'rosnode list')")
    else:
        names = [script_resolve_name("rosnode", n) for n in args]
        known = get_node_names(world)
        unknown = [n for n in names if n not in known]
        if unknown:
            ctx.eprint("ERROR: Unknown node(s):\n" + "\n".join(f" * {n}" for n in unknown))
            return 1
    if len(names) > 1:
        ctx.print("killing:\n" + "\n".join(f" * {n}" for n in names))
    elif names:
        ctx.print(f"killing {names[0]}")
    for n in names:
        node = world.master.lookup_node(n)
        if node is not None:
            node.shutdown("user request")
    ctx.print("killed")
    return 0


def _ping(ctx: ToolContext, argv: list[str]) -> int:
    argv, background = take_background(argv)
    parser = ToolParser(ctx, "usage: %prog ping [options] <node>", "rosnode")
    parser.add_option("--all", "-a", dest="ping_all", default=False, action="store_true",
                      help="ping all nodes")
    parser.add_option("-c", dest="ping_count", default=None, metavar="COUNT", type="int",
                      help="number of pings to send. Not available with --all")
    add_run_options(parser)
    options, args = parser.parse_args(argv)
    world = ctx.world
    if options.ping_all:
        if args:
            parser.error(f"Invalid arguments '{' '.join(args)}' used with --all")
        elif options.ping_count:
            parser.error("-c may not be used with --all")
        nodes = get_node_names(world)
        ctx.print("Will ping the following nodes: \n" + "".join(f" * {n}\n" for n in nodes))
        for n in nodes:
            ctx.print(f"pinging {n} with a timeout of 3.0s")
            ctx.print(f"xmlrpc reply from {node_uri(n)}\ttime={_rtt_ms(world):f}ms")
            world.run_for(Duration.from_nsec(world.connect_delay_ns))
        return 0
    if not args:
        parser.error("Please enter a node to ping. Available nodes are:\n"
                     + "\n".join(get_node_names(world)))
    if len(args) > 1:
        parser.error("you may only specify one input node")
    name = script_resolve_name("rosnode", args[0])
    ctx.print(f"rosnode: node is [{name}]")
    if world.master.lookup_node(name) is None:
        ctx.eprint(f"cannot ping [{name}]: unknown node")
        return 1  # rosnode exits 0 here; ddes stops a script
    count = options.ping_count
    if count is not None and count <= 0:
        count = None
    duration = parse_duration(options.duration)
    task = Task(world, command_label("rosnode", ["ping", *argv]))
    ctx.print(f"pinging {name} with a timeout of 3.0s")
    results: list[float] = []

    def pinger() -> ProcessGenerator:
        while not task.done:
            if world.master.lookup_node(name) is None:
                ctx.eprint(f"cannot ping [{name}]: unknown node")
                task.code = 1
                task.finish(1)
                return
            rtt = _rtt_ms(world)
            yield world.timeout_ns(world.connect_delay_ns)
            results.append(rtt)
            ctx.print(f"xmlrpc reply from {node_uri(name)}\ttime={rtt:f}ms")
            if count is not None and len(results) >= count:
                average()
                task.finish(0)
                return
            yield world.timeout_ns(to_ns(1) - world.connect_delay_ns)

    def average() -> None:
        if len(results) > 1:
            ctx.print(f"ping average: {sum(results) / len(results):f}ms")

    world.env.process(pinger())
    task.on_stop(average)
    return run_task(ctx, task, background=background, duration=duration,
                    waiting_for=None if count is None else f"{count} pings")


def _rtt_ms(world: World) -> float:
    return ns_to_sec(world.connect_delay_ns) * 1000.0  # milliseconds


def _machine(ctx: ToolContext, argv: list[str]) -> int:
    parser = ToolParser(ctx, "usage: %prog machine [machine-name]", "rosnode")
    _options, args = parser.parse_args(argv)
    if len(args) > 1:
        parser.error("please enter only one machine name")
    if not args:
        ctx.print("localhost")
    elif args[0] == "localhost":
        ctx.print("\n".join(get_node_names(ctx.world)))
    else:
        ctx.print("")
    return 0


def _cleanup(ctx: ToolContext, argv: list[str]) -> int:
    parser = ToolParser(ctx, "usage: %prog cleanup", "rosnode")
    parser.parse_args(argv)
    return 0


_COMMANDS = {"list": _list, "info": _info, "kill": _kill, "ping": _ping,
             "machine": _machine, "cleanup": _cleanup}


def rosnode(ctx: ToolContext, argv: list[str]) -> int:
    """The ``rosnode`` tool (see the module docstring)."""
    if not argv or argv[0] in ("-h", "--help"):
        ctx.print(_USAGE)
        return 0 if argv else _EX_USAGE
    if argv[0] not in _COMMANDS:
        raise ROSConsoleError(
            f"unknown command 'rosnode {argv[0]}'; rosnode commands: {', '.join(_COMMANDS)}")
    try:
        return _COMMANDS[argv[0]](ctx, argv[1:])
    except HelpPrinted:
        return 0


TOOLS = {"rosnode": rosnode}
