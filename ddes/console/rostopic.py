"""``rostopic``: list, info, type, find, echo, hz and pub on the world's topics.

Output follows ros_comm ``tools/rostopic/src/rostopic/__init__.py``:

* ``list`` prints the sorted topic names (``-v``: ``Published topics:`` /
  ``Subscribed topics:`` with ``* /t [type] N publishers``; ``-p``/``-s``
  filter; ``--host`` groups under ``Host [localhost]:``);
* ``info`` prints ``Type: T``, a blank line, ``Publishers: `` with
  `` * /node (uri)`` lines (or ``Publishers: None``), then the subscribers;
* ``type`` prints the type (``T field fieldtype`` for a field path);
* ``echo`` prints each message as genpy's YAML-like text followed by
  ``---`` (``--nostr``/``--noarr`` replace strings/arrays by
  ``<string length: N>``/``<array type: T, length: N>``; ``--offset``,
  ``--filter``, ``-w``, field paths such as ``/odom/pose/pose``);
* ``hz`` prints ``subscribed to [/t]`` and, once per simulated second,
  ``average rate: %.3f`` and ``\\tmin: %.3fs max: %.3fs std dev: %.5fs
  window: N`` (or ``no new messages``);
* ``bw`` prints ``subscribed to [/t]`` and, once per simulated second,
  ``average: 1.23KB/s`` and ``\\tmean: ... min: ... max: ... window: N``
  (:mod:`ddes.console.rostopic_bw`);
* ``pub`` publishes one latched message (``-1``: kept 3 s, then exits) or
  repeats at ``-r HZ``.

Commands that ROS runs until Ctrl+C take ``-n COUNT`` (messages for echo
and ``pub -r``, reports for hz) or ``--duration S`` (simulated seconds), or
run in the background of the world (``&``); see :mod:`ddes.console.toolkit`.
A topic nobody publishes or subscribes is an error for a foreground
``echo``/``hz`` without ``--duration`` (ROS would wait for ever); with one,
the ROS warning prints and the tool waits, as ROS does.  ``delay``,
``echo -b``, ``echo -p`` and ``pub -f`` are not offered.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import TYPE_CHECKING, Any

from ddes.console.toolkit import (
    HelpPrinted,
    ToolParser,
    node_uri,
    script_resolve_name,
)
from ddes.errors import DdesError, ROSConsoleError, ROSTopicException
from ddes.graph.names import make_global_ns

if TYPE_CHECKING:
    from ddes.console.tooling import ToolContext
    from ddes.graph.topics import Publisher, Subscriber
    from ddes.graph.world import World
    from ddes.msg.message import Message

__all__ = ["TOOLS", "MsgEval", "get_info_text", "get_topic_type", "msgevalgen", "rostopic"]

#: Picks a field path (``/pose/position/x``, ``/data[0:2]``) out of a message; None if absent.
MsgEval = Callable[["Message"], object]
#: A topic row: (topic, type, node names).
_TopicRow = tuple[str, str, list[str]]

_EX_USAGE = 64

_USAGE = """rostopic is a command-line tool for printing information about ROS Topics.

Commands:
\trostopic bw\tdisplay bandwidth used by topic
\trostopic delay\tdisplay delay of topic from timestamp in header
\trostopic echo\tprint messages to screen
\trostopic find\tfind topics by type
\trostopic hz\tdisplay publishing rate of topic{HZ_PAD}
\trostopic info\tprint information about active topic
\trostopic list\tlist active topics
\trostopic pub\tpublish data to topic
\trostopic type\tprint topic or field type

Type rostopic <command> -h for more detailed usage, e.g. 'rostopic echo -h'
""".replace("{HZ_PAD}", "    ")  # rostopic's usage text has trailing spaces on that line


# -- the graph, as the master describes it ----------------------------------------------------
def _topic_types(world: World) -> list[tuple[str, str]]:
    return world.master.get_topic_types()


def _topic_class(world: World, topic: str, type_name: str) -> type[Message]:
    """The message class of ``topic``: the one its publishers/subscribers use, else the registry's.

    Only generated message classes count: not ``AnyMsg``, nor the raw-bytes classes of
    ``rosbag play``, which carry the type's name but cannot show fields.
    """
    from ddes.msg import get_message_class
    from ddes.msg.message import Message

    entry = world.master.topics.get(topic)
    if entry is not None:
        ends: list[Publisher | Subscriber] = [*entry.publishers, *entry.subscribers]
        for end in ends:
            cls = end.data_class
            if isinstance(cls, type) and issubclass(cls, Message) and end.type == type_name:
                return cls
    try:
        return get_message_class(type_name)
    except DdesError:
        raise ROSTopicException(
            f"Cannot load message class for [{type_name}]. Are your messages built?") from None


def _field_class(type_name: str) -> type[Message]:
    from ddes.msg import get_message_class

    return get_message_class(type_name.split("[", 1)[0])


def _nested_attribute(msg: Message, attrs: str) -> object:
    value: object = msg
    for attr in attrs.split("/"):
        value = getattr(value, attr)
    return value


def get_topic_type(world: World, topic: str) -> tuple[str | None, str | None, MsgEval | None]:
    """``(type, real topic, field evaluator)`` of ``topic`` (a topic or a field path).

    An exact topic match wins; otherwise the longest topic that is a prefix
    of ``topic`` and whose type has the field (rostopic's ``_get_topic_type``).
    """
    types = _topic_types(world)
    matches = [(t, ty) for t, ty in types if t == topic]
    if not matches:
        matches = sorted(((t, ty) for t, ty in types if topic.startswith(t + "/")), reverse=True)
        while matches:
            t, ty = matches[0]
            try:
                cls = _topic_class(world, t, ty)
            except DdesError:
                break
            attrs = topic[len(t) + 1:].rstrip("/").split("[")[0]
            if not attrs:
                break
            try:
                _nested_attribute(cls(), attrs)
            except AttributeError:
                matches.pop(0)
                continue
            matches = [(t, ty)]
            break
    if not matches:
        return None, None, None
    t, ty = matches[0]
    if ty == "*":
        return None, None, None
    return ty, t, msgevalgen(topic[len(t):])


def _slice(text: str) -> int | slice:
    if text == "":
        raise ROSConsoleError("empty array index")
    parts = text.split(":")
    if len(parts) > 3:
        raise ROSConsoleError("too many slice arguments")
    try:
        if len(parts) == 1:
            return int(parts[0])
        return slice(*[int(p) if p != "" else None for p in parts])
    except ValueError:
        raise ROSConsoleError(f"non-integer array index or slice '{text}'") from None


def msgevalgen(pattern: str) -> MsgEval | None:
    """A function picking the field path ``pattern`` (``/pose/position/x``, ``/data[0:2]``) out of a message."""
    evals: list[tuple[str, int | slice | None]] = []
    for f in (f for f in pattern.split("/") if f):
        if "[" in f:
            name, rest = f.split("[", 1)
            if not rest.endswith("]"):
                raise ROSConsoleError(f"missing closing ']' in slice spec '{f}'")
            evals.append((name, _slice(rest[:-1])))
        else:
            evals.append((f, None))
    if not evals:
        return None

    def msgeval(msg: Any, steps: list[tuple[str, int | slice | None]]) -> Any:
        for i, (name, index) in enumerate(steps):
            try:
                msg = getattr(msg, name)
            except AttributeError:
                return None
            if index is not None:
                try:
                    msg = msg[index]
                except IndexError:
                    return None
                if isinstance(msg, list):
                    return [msgeval(m, steps[i + 1:]) for m in msg]
        return msg

    return lambda msg: msgeval(msg, evals)


# -- list / info / type / find -------------------------------------------------------------------
def _topic_list(world: World) -> tuple[list[_TopicRow], list[_TopicRow]]:
    types = dict(_topic_types(world))
    pubs, subs, _ = world.master.get_system_state()
    return ([(t, types.get(t, "unknown type"), nodes) for t, nodes in pubs],
            [(t, types.get(t, "unknown type"), nodes) for t, nodes in subs])


def _sub_list(ctx: ToolContext, pubs: list[_TopicRow], subs: list[_TopicRow],
              publishers_only: bool, subscribers_only: bool, verbose: bool, indent: str = "") -> None:
    if verbose:
        if not subscribers_only:
            ctx.print(f"\n{indent}Published topics:")
            for t, ty, nodes in pubs:
                if len(nodes) > 1:
                    ctx.print(f"{indent} * {t} [{ty}] {len(nodes)} publishers")
                else:
                    ctx.print(f"{indent} * {t} [{ty}] 1 publisher")
        if not publishers_only:
            ctx.print(indent)
            ctx.print(f"{indent}Subscribed topics:")
            for t, ty, nodes in subs:
                if len(nodes) > 1:
                    ctx.print(f"{indent} * {t} [{ty}] {len(nodes)} subscribers")
                else:
                    ctx.print(f"{indent} * {t} [{ty}] 1 subscriber")
        ctx.print("")
        return
    if publishers_only:
        topics = [t for t, _, _ in pubs]
    elif subscribers_only:
        topics = [t for t, _, _ in subs]
    else:
        topics = list({t for t, _, _ in pubs} | {t for t, _, _ in subs})
    ctx.print("\n".join(f"{indent}{t}" for t in sorted(topics)))


def _list(ctx: ToolContext, argv: list[str]) -> int:
    parser = ToolParser(ctx, "usage: %prog list [/namespace]", "rostopic")
    parser.add_option("-b", "--bag", dest="bag", default=None, metavar="BAGFILE",
                      help="list topics in .bag file")
    parser.add_option("-v", "--verbose", dest="verbose", default=False, action="store_true",
                      help="list full details about each topic")
    parser.add_option("-p", dest="publishers", default=False, action="store_true",
                      help="list only publishers")
    parser.add_option("-s", dest="subscribers", default=False, action="store_true",
                      help="list only subscribers")
    parser.add_option("--host", dest="hostname", default=False, action="store_true",
                      help="group by host name")
    options, args = parser.parse_args(argv)
    topic = None
    if len(args) == 1:
        topic = script_resolve_name("rostopic", args[0])
    elif len(args) > 1:
        parser.error("you may only specify one input topic")
    if options.bag:
        raise ROSConsoleError("rostopic list -b is not offered by ddes; use 'rosbag info BAG'")
    if options.subscribers and options.publishers:
        parser.error("you may only specify one of -p, -s")
    pubs, subs = _topic_list(ctx.world)
    if topic:
        ns = make_global_ns(topic)
        pubs = [x for x in pubs if x[0] == topic or x[0].startswith(ns)]
        subs = [x for x in subs if x[0] == topic or x[0].startswith(ns)]
    if options.hostname:
        if (pubs and not options.subscribers) or (subs and not options.publishers):
            ctx.print("Host [localhost]:")
            _sub_list(ctx, pubs, subs, options.publishers, options.subscribers,
                      options.verbose, indent="  ")
        return 0
    _sub_list(ctx, pubs, subs, options.publishers, options.subscribers, options.verbose)
    return 0


def get_info_text(world: World, topic: str) -> str:
    """The text ``rostopic info`` prints (before print's newline)."""
    pubs, subs = _topic_list(world)
    pubs = [x for x in pubs if x[0] == topic]
    subs = [x for x in subs if x[0] == topic]
    if not pubs and not subs:
        raise ROSTopicException(f"Unknown topic {topic}")
    types = dict(_topic_types(world))
    buff = f"Type: {types.get(topic, 'unknown type')}\n\n"
    if pubs:
        buff += "Publishers: \n"
        buff += "".join(f" * {n} ({node_uri(n)})\n" for _, _, nodes in pubs for n in nodes)
    else:
        buff += "Publishers: None\n"
    buff += "\n"
    if subs:
        buff += "Subscribers: \n"
        buff += "".join(f" * {n} ({node_uri(n)})\n" for _, _, nodes in subs for n in nodes)
    else:
        buff += "Subscribers: None\n"
    return buff + "\n"


def _info(ctx: ToolContext, argv: list[str]) -> int:
    parser = ToolParser(ctx, "usage: %prog info /topic", "rostopic")
    _options, args = parser.parse_args(argv)
    if not args:
        parser.error("you must specify a topic name")
    if len(args) > 1:
        parser.error("you may only specify one topic name")
    ctx.print(get_info_text(ctx.world, script_resolve_name("rostopic", args[0])))
    return 0


def _type(ctx: ToolContext, argv: list[str]) -> int:
    parser = ToolParser(ctx, "usage: %prog type topic_or_field", "rostopic type")
    _options, args = parser.parse_args(argv)
    if len(args) != 1:
        parser.error("the following arguments are required: topic_or_field" if not args
                     else f"unrecognized arguments: {' '.join(args[1:])}")
    topic = script_resolve_name("rostopic", args[0])
    type_name, real, _ = get_topic_type(ctx.world, topic)
    if type_name is None or real is None:
        ctx.eprint(f"unknown topic type [{topic}]")
        return 1
    if topic == real:
        ctx.print(type_name)
        return 0
    field = topic[len(real) + 1:]
    field_type = type_name
    for current in field.split("/"):
        try:
            cls = _field_class(field_type)
            field_type = cls._slot_types[cls.__slots__.index(current)]
        except (DdesError, ValueError):
            ctx.eprint(f"unknown topic type [{topic}]")
            return 1
    ctx.print(f"{type_name} {field} {field_type}")
    return 0


def _find(ctx: ToolContext, argv: list[str]) -> int:
    parser = ToolParser(ctx, "usage: %prog find msg-type", "rostopic")
    _options, args = parser.parse_args(argv)
    if not args:
        parser.error("please specify a message type")
    if len(args) > 1:
        parser.error("you may only specify one message type")
    ctx.print("\n".join(t for t, ty in _topic_types(ctx.world) if ty == args[0]))
    return 0


def _unsupported(name: str) -> Callable[[ToolContext, list[str]], int]:
    def tool(ctx: ToolContext, argv: list[str]) -> int:
        raise ROSConsoleError(f"rostopic {name} is not offered by ddes; see 'rostopic' for the "
                              "commands it has")

    return tool


def _live(name: str) -> Callable[[ToolContext, list[str]], int]:
    def tool(ctx: ToolContext, argv: list[str]) -> int:
        from ddes.console import rostopic_live

        fn: Callable[[ToolContext, list[str]], int] = getattr(rostopic_live, name)
        return fn(ctx, argv)

    return tool


def _bw(ctx: ToolContext, argv: list[str]) -> int:
    from ddes.console.rostopic_bw import bw

    return bw(ctx, argv)


_COMMANDS: dict[str, Callable[[ToolContext, list[str]], int]] = {
    "echo": _live("echo"), "find": _find, "hz": _live("hz"), "info": _info, "list": _list,
    "pub": _live("pub"),
    "type": _type, "bw": _bw, "delay": _unsupported("delay"),
}


def rostopic(ctx: ToolContext, argv: list[str]) -> int:
    """The ``rostopic`` tool (see the module docstring)."""
    if not argv or argv[0] in ("-h", "--help"):
        ctx.print(_USAGE)
        return 0 if argv else _EX_USAGE
    if argv[0] not in _COMMANDS:
        raise ROSConsoleError(f"unknown command 'rostopic {argv[0]}'; rostopic commands: "
                              + ", ".join(sorted(_COMMANDS)))
    try:
        return _COMMANDS[argv[0]](ctx, argv[1:])
    except HelpPrinted:
        return 0


TOOLS = {"rostopic": rostopic}
