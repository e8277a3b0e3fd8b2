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
* ``pub`` publishes one latched message (``-1``: kept 3 s, then exits) or
  repeats at ``-r HZ``.

Commands that ROS runs until Ctrl+C take ``-n COUNT`` (messages for echo
and ``pub -r``, reports for hz) or ``--duration S`` (simulated seconds), or
run in the background of the world (``&``); see :mod:`ddes.cli.toolkit`.
A topic nobody publishes or subscribes is an error for a foreground
``echo``/``hz`` without ``--duration`` (ROS would wait for ever); with one,
the ROS warning prints and the tool waits, as ROS does.  ``bw``, ``delay``,
``echo -b``, ``echo -p`` and ``pub -f`` are not offered.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Generator
from typing import TYPE_CHECKING, Any

import yaml

from ddes.cli.toolkit import (
    HelpPrinted,
    Task,
    ToolParser,
    add_run_options,
    command_label,
    node_uri,
    parse_count,
    parse_duration,
    run_task,
    script_resolve_name,
    take_background,
)
from ddes.errors import DdesError, ROSConsoleError, ROSTopicException
from ddes.graph.names import make_global_ns

if TYPE_CHECKING:
    from ddes.cli.tooling import ToolContext
    from ddes.kernel.world import World

__all__ = ["TOOLS", "TopicHz", "get_info_text", "get_topic_type", "msgevalgen", "rostopic",
           "strify_for_echo", "value_transform_factory"]

_EX_USAGE = 64
_ONCE_DELAY = 3.0

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


def _topic_class(world: World, topic: str, type_name: str) -> Any:
    """The message class of ``topic``: the one its publishers/subscribers use, else the registry's."""
    from ddes.graph.topics import AnyMsg
    from ddes.msg import get_message_class

    entry = world.master.topics.get(topic)
    if entry is not None:
        for end in [*entry.publishers, *entry.subscribers]:
            if end.data_class is not AnyMsg and end.type == type_name:
                return end.data_class
    try:
        return get_message_class(type_name)
    except DdesError:
        raise ROSTopicException(
            f"Cannot load message class for [{type_name}]. Are your messages built?") from None


def _field_class(type_name: str) -> Any:
    from ddes.msg import get_message_class

    return get_message_class(type_name.split("[", 1)[0])


def _nested_attribute(msg: Any, attrs: str) -> Any:
    value = msg
    for attr in attrs.split("/"):
        value = getattr(value, attr)
    return value


def get_topic_type(world: World, topic: str) -> tuple[str | None, str | None,
                                                       Callable[[Any], Any] | None]:
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


def msgevalgen(pattern: str) -> Callable[[Any], Any] | None:
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
def _topic_list(world: World) -> tuple[list[tuple[str, str, list[str]]],
                                        list[tuple[str, str, list[str]]]]:
    types = dict(_topic_types(world))
    pubs, subs, _ = world.master.get_system_state()
    return ([(t, types.get(t, "unknown type"), nodes) for t, nodes in pubs],
            [(t, types.get(t, "unknown type"), nodes) for t, nodes in subs])


def _sub_list(ctx: ToolContext, pubs: list[Any], subs: list[Any], publishers_only: bool,
              subscribers_only: bool, verbose: bool, indent: str = "") -> None:
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


# -- echo --------------------------------------------------------------------------------------------
def value_transform_factory(nostr: bool, noarr: bool) -> Callable[[Any, str | None], Any]:
    """rostopic's ``create_value_transform``: hide strings and/or arrays of a message."""
    from ddes.msg import Message

    def field_value(value: Any, value_type: str) -> Any:
        if noarr and "[" in value_type:
            return f"<array type: {value_type.rstrip('[]')}, length: {len(value)}>"
        if nostr and value_type == "string":
            return f"<string length: {len(value)}>"
        if nostr and value_type == "string[]":
            return f"<array type: string, length: {len(value)}>"
        return value

    def transform(val: Any, type_information: str | None = None) -> Any:
        if not isinstance(val, Message):
            if type_information is None:
                return val
            return field_value(val, type_information)
        names = list(val.__slots__)
        types = list(val._slot_types)
        values: list[Any] = []
        for index, (name, ty) in enumerate(zip(names, types)):
            f_val = getattr(val, name)
            new = field_value(f_val, ty)
            if new != f_val:
                types[index] = "string"
                values.append(new)
            elif isinstance(f_val, Message):
                values.append(transform(f_val))
            else:
                values.append(f_val)
        shown = type("TransformedMessage", (Message,),
                     {"__slots__": tuple(names), "_slot_types": types, "_type": val._type})
        out = shown.__new__(shown)
        for name, v in zip(names, values):
            setattr(out, name, v)
        return out

    return transform


def strify_for_echo(val: Any, type_information: str | None = None,
                    transform: Callable[[Any, str | None], Any] | None = None,
                    time_offset: Any = None, fixed_numeric_width: int | None = None) -> str:
    """The text ``rostopic echo`` prints for one message or field value (without ``---``)."""
    from ddes.msg import strify_message

    if type_information and type_information.startswith("uint8["):
        val = list(val) if isinstance(val, (bytes, bytearray)) else [ord(x) for x in val]
    if transform is not None:
        val = transform(val, type_information)
    return strify_message(val, time_offset=time_offset,
                          fixed_numeric_width=fixed_numeric_width)


def _field_type_information(cls: Any, topic: str, real: str) -> str | None:
    sub = topic[len(real):].strip("/")
    if not sub:
        return None
    info = None
    fields = sub.split("/")
    current = cls
    while fields:
        name = fields.pop(0).split("[")[0]
        try:
            info = current._slot_types[current.__slots__.index(name)]
        except ValueError:
            return None
        if fields:
            try:
                current = _field_class(info)
            except DdesError:
                raise ROSTopicException(
                    f"Cannot load message class for [{info}]. Are your messages built?") from None
    return info


def _filter_fn(expr: str | None, topic: str) -> Callable[[Any], bool] | None:
    if not expr:
        return None
    try:
        code = compile(expr, "<filter>", "eval")
    except SyntaxError as exc:
        raise ROSConsoleError(f"invalid --filter expression {expr!r}: {exc.msg}") from None

    def fn(m: Any) -> bool:
        return bool(eval(code, {"__builtins__": __builtins__}, {"m": m, "topic": topic}))

    return fn


def _wait_for_type(ctx: ToolContext, task: Task, topic: str,
                   start: Callable[[str, str, Callable[[Any], Any] | None], None]) -> None:
    """Call ``start(type, real, eval)`` once ``topic`` is known, polling every 0.1 s as rostopic."""
    world = ctx.world
    type_name, real, msg_eval = get_topic_type(world, topic)
    if type_name is not None and real is not None:
        start(type_name, real, msg_eval)
        return
    ctx.eprint(f"WARNING: topic [{topic}] does not appear to be published yet")

    def poll() -> Generator[Any, Any, None]:
        while not task.done:
            yield world.env.timeout(100_000_000)
            t, r, e = get_topic_type(world, topic)
            if t is not None and r is not None and not task.done:
                start(t, r, e)
                return

    world.env.process(poll())


def _require_bound(tool: str, background: bool, duration: float | None, has_end: bool) -> None:
    if not (background or duration is not None or has_end):
        raise ROSConsoleError(
            f"'{tool}' runs until Ctrl+C in ROS; in ddes give a count (-n), --duration SECONDS "
            f"(simulated), or end the line with & to keep it running in the background")


def _check_known(world: World, topic: str, background: bool, duration: float | None) -> None:
    if get_topic_type(world, topic)[0] is None and not background and duration is None:
        raise ROSTopicException(
            f"topic [{topic}] does not appear to be published yet; give --duration SECONDS "
            "to wait for it (see 'rostopic list')")


def _echo(ctx: ToolContext, argv: list[str]) -> int:
    argv, background = take_background(argv)
    parser = ToolParser(ctx, "usage: %prog echo [options] /topic", "rostopic")
    parser.add_option("-b", "--bag", dest="bag", default=None, metavar="BAGFILE",
                      help="echo messages from .bag file")
    parser.add_option("-p", dest="plot", default=False, action="store_true",
                      help="echo in a plotting friendly format")
    parser.add_option("-w", dest="fixed_numeric_width", default=None, metavar="NUM_WIDTH",
                      help="fixed width for numeric values")
    parser.add_option("--filter", dest="filter_expr", default=None, metavar="FILTER-EXPRESSION",
                      help="Python expression to filter messages that are printed")
    parser.add_option("--nostr", dest="nostr", default=False, action="store_true",
                      help="exclude string fields")
    parser.add_option("--noarr", dest="noarr", default=False, action="store_true",
                      help="exclude arrays")
    parser.add_option("-c", "--clear", dest="clear", default=False, action="store_true",
                      help="clear screen before printing next message")
    parser.add_option("--offset", dest="offset_time", default=False, action="store_true",
                      help="display time as offsets from current time (in seconds)")
    add_run_options(parser, count="number of messages to echo")
    options, args = parser.parse_args(argv)
    if len(args) > 1:
        parser.error("you may only specify one input topic")
    if not args:
        parser.error("topic must be specified")
    if options.bag:
        raise ROSConsoleError("rostopic echo -b is not offered by ddes; read the bag with "
                              "ddes.rosbag or 'rosbag play' it")
    if options.plot:
        raise ROSConsoleError("rostopic echo -p (plot format) is not offered by ddes")
    topic = script_resolve_name("rostopic", args[0])
    count = parse_count(options.count)
    width = None
    if options.fixed_numeric_width:
        try:
            width = int(options.fixed_numeric_width)
        except ValueError:
            parser.error("NUM_WIDTH must be an integer")
        if width < 2:
            parser.error("Fixed width for numeric values must be at least 2")
    duration = parse_duration(options.duration)
    _require_bound("rostopic echo", background, duration, count is not None)
    world = ctx.world
    _check_known(world, topic, background, duration)
    filter_fn = _filter_fn(options.filter_expr, topic)
    transform = value_transform_factory(options.nostr, options.noarr)
    task = Task(world, command_label("rostopic", ["echo", *argv]))
    node = task.own(world.create_node("rostopic", anonymous=True))
    if topic.endswith("/") and len(topic) > 1:
        topic = topic[:-1]
    received = [0]

    def start(type_name: str, real: str, msg_eval: Callable[[Any], Any] | None) -> None:
        cls = _topic_class(world, real, type_name)
        type_information = _field_type_information(cls, topic, real)

        def callback(data: Any) -> None:
            if task.done or (filter_fn is not None and not filter_fn(data)):
                return
            value = msg_eval(data) if msg_eval is not None else data
            if value is None:
                return
            received[0] += 1
            offset = node.get_rostime() if options.offset_time else None
            prefix = "\033[2J\033[;H" if options.clear else ""
            ctx.print(prefix + strify_for_echo(value, type_information, transform, offset, width)
                      + "\n---")
            if count is not None and received[0] >= count:
                task.finish(0)

        if not node.is_shutdown():
            node.subscribe(real, cls, callback)

    _wait_for_type(ctx, task, topic, start)
    return run_task(ctx, task, background=background, duration=duration,
                    waiting_for=None if count is None else f"{count} messages")


# -- hz ----------------------------------------------------------------------------------------------
class TopicHz:
    """rostopic's ``ROSTopicHz`` for one topic: inter-arrival statistics over a window."""

    def __init__(self, window_size: int) -> None:
        self.window_size = 50000 if window_size < 0 else window_size
        self.msg_t0 = -1.0
        self.msg_tn = 0.0
        self.last_printed_tn = 0.0
        self.times: list[float] = []

    def callback(self, now_sec: float) -> str | None:
        """Record a message received at ``now_sec``; returns a line to print (time reset) or None."""
        if now_sec == 0:
            if self.times:
                self.times = []
                return "time has reset, resetting counters"
            return None
        if self.msg_t0 < 0 or self.msg_t0 > now_sec:
            self.msg_t0 = now_sec
            self.msg_tn = now_sec
            self.times = []
        else:
            self.times.append(now_sec - self.msg_tn)
            self.msg_tn = now_sec
        if len(self.times) > self.window_size - 1:
            self.times.pop(0)
        return None

    def get_hz(self) -> tuple[float, float, float, float, int] | None:
        """(rate, min delta, max delta, std dev, window) or None if nothing new."""
        if not self.times or self.msg_tn == self.last_printed_tn:
            return None
        n = len(self.times)
        mean = sum(self.times) / n
        rate = 1.0 / mean if mean > 0.0 else 0
        std_dev = math.sqrt(sum((x - mean) ** 2 for x in self.times) / n)
        self.last_printed_tn = self.msg_tn
        return rate, min(self.times), max(self.times), std_dev, n + 1


def format_hz(stats: tuple[float, float, float, float, int] | None) -> str:
    """The two lines ``rostopic hz`` prints for one report (or ``no new messages``)."""
    if stats is None:
        return "no new messages"
    rate, min_d, max_d, std, window = stats
    return (f"average rate: {rate:.3f}\n\tmin: {min_d:.3f}s max: {max_d:.3f}s "
            f"std dev: {std:.5f}s window: {window}")


def _ascii_table(header: list[str], cols: dict[str, list[str]]) -> str:
    aligned: list[str] = []
    widths: list[int] = []
    for h in header:
        width = max(len(h), max(len(el) for el in cols[h]))
        widths.append(width)
        aligned.append(h.center(width))
        cols[h] = [str(el).ljust(width) for el in cols[h]]
    table_width = sum(widths) + 3 * (len(header) - 1)
    rows = len(cols[header[0]])
    body = "\n".join("   ".join(cols[h][i] for h in header) for i in range(rows))
    return "{}\n{}\n{}\n".format("   ".join(aligned), "=" * table_width, body)


def _hz(ctx: ToolContext, argv: list[str]) -> int:
    argv, background = take_background(argv)
    parser = ToolParser(ctx, "usage: %prog hz [options] /topic_0 [/topic_1 [topic_2 [..]]]",
                        "rostopic")
    parser.add_option("-w", "--window", dest="window_size", default=-1, metavar="WINDOW",
                      help="window size, in # of messages, for calculating rate")
    parser.add_option("--filter", dest="filter_expr", default=None, metavar="EXPR",
                      help="only measure messages matching the specified Python expression")
    parser.add_option("--wall-time", dest="use_wtime", default=False, action="store_true",
                      help="calculates rate using wall time (the kernel clock in ddes)")
    parser.add_option("--tcpnodelay", dest="tcp_nodelay", action="store_true",
                      help="use the TCP_NODELAY transport hint when subscribing to topics")
    add_run_options(parser, count="ddes: number of reports (one per simulated second)")
    options, args = parser.parse_args(argv)
    if not args:
        parser.error("topic must be specified")
    try:
        window = int(options.window_size)
    except ValueError:
        parser.error("window size must be an integer")
    reports = parse_count(options.count)
    duration = parse_duration(options.duration)
    _require_bound("rostopic hz", background, duration, reports is not None)
    world = ctx.world
    topics = [script_resolve_name("rostopic", t) for t in args]
    for topic in topics:
        _check_known(world, topic, background, duration)
    task = Task(world, command_label("rostopic", ["hz", *argv]))
    node = task.own(world.create_node("rostopic", anonymous=True))
    stats = {t: TopicHz(window) for t in topics}

    def now_sec() -> float:
        return world.now / 1e9 if options.use_wtime else node.get_time()

    for topic in topics:
        filter_fn = _filter_fn(options.filter_expr, topic)

        def start(type_name: str, real: str, _eval: Any, topic: str = topic,
                  filter_fn: Callable[[Any], bool] | None = filter_fn) -> None:
            from ddes.graph.topics import AnyMsg

            cls = _topic_class(world, real, type_name) if filter_fn is not None else AnyMsg
            rt = stats[topic]

            def callback(m: Any) -> None:
                if filter_fn is not None and not filter_fn(m):
                    return
                line = rt.callback(now_sec())
                if line:
                    ctx.print(line)

            if not node.is_shutdown():
                node.subscribe(real, cls, callback)
                ctx.print(f"subscribed to [{real}]")

        _wait_for_type(ctx, task, topic, start)
    if world.master.params.get_param("/use_sim_time", False):
        ctx.eprint("WARNING: may be using simulated time")
    done = [0]

    def reporter() -> Generator[Any, Any, None]:
        while not task.done:
            yield world.env.timeout(1_000_000_000)
            if task.done:
                return
            if len(topics) == 1:
                ctx.print(format_hz(stats[topics[0]].get_hz()))
            else:
                header = ["topic", "rate", "min_delta", "max_delta", "std_dev", "window"]
                cols: dict[str, list[str]] = {h: [] for h in header}
                for topic in topics:
                    hz = stats[topic].get_hz()
                    if hz is None:
                        continue
                    rate, min_d, max_d, std, win = hz
                    cols["topic"].append(topic)
                    cols["rate"].append(f"{rate:.4}")
                    cols["min_delta"].append(f"{min_d:.4}")
                    cols["max_delta"].append(f"{max_d:.4}")
                    cols["std_dev"].append(f"{std:.4}")
                    cols["window"].append(str(win))
                ctx.print(_ascii_table(header, cols) if cols["topic"] else "no new messages")
            done[0] += 1
            if reports is not None and done[0] >= reports:
                task.finish(0)

    world.env.process(reporter())
    return run_task(ctx, task, background=background, duration=duration,
                    waiting_for=None if reports is None else f"{reports} reports")


# -- pub ---------------------------------------------------------------------------------------------
def _pub(ctx: ToolContext, argv: list[str]) -> int:
    argv, background = take_background(argv)
    parser = ToolParser(ctx, "usage: %prog pub /topic type [args...]", "rostopic")
    parser.add_option("-v", dest="verbose", default=False, action="store_true",
                      help="print verbose output")
    parser.add_option("-r", "--rate", dest="rate", default=None,
                      help="publishing rate (hz).  For -f and stdin input, this defaults to 10.  "
                           "Otherwise it is not set.")
    parser.add_option("-1", "--once", action="store_true", dest="once", default=False,
                      help="publish one message and exit")
    parser.add_option("-f", "--file", dest="file", metavar="FILE", default=None,
                      help="read args from YAML file (Bagy)")
    parser.add_option("-l", "--latch", dest="latch", default=False, action="store_true",
                      help="enable latching for -f, -r and piped input.  This latches the first "
                           "message.")
    parser.add_option("-s", "--substitute-keywords", dest="substitute_keywords", default=False,
                      action="store_true",
                      help="When publishing with a rate, performs keyword ('now' or 'auto') "
                           "substitution for each message")
    parser.add_option("--use-rostime", dest="use_rostime", default=False, action="store_true",
                      help="use rostime for time stamps, else walltime is used")
    add_run_options(parser, count="ddes: with -r, stop after COUNT messages")
    options, args = parser.parse_args(argv)
    rate: float | None = None
    if options.rate is not None:
        if options.once:
            parser.error("You cannot select both -r and -1 (--once)")
        try:
            rate = float(options.rate)
        except ValueError:
            parser.error("rate must be a number")
        if rate <= 0:
            parser.error("rate must be greater than zero")
    if not args:
        parser.error("/topic must be specified")
    if len(args) == 1:
        parser.error("topic type must be specified")
    if options.file:
        raise ROSConsoleError("rostopic pub -f is not offered by ddes; give the values as "
                              "arguments")
    topic_name, topic_type = args[0], args[1]
    pub_args: list[Any] = []
    for arg in args[2:]:
        try:
            pub_args.append(yaml.safe_load(arg))
        except yaml.YAMLError as exc:
            parser.error(f"Argument error: {exc}")
    count = parse_count(options.count)
    duration = parse_duration(options.duration)
    if count is not None and rate is None:
        parser.error("-n COUNT needs -r RATE (without a rate one latched message is published)")
    _require_bound("rostopic pub", background, duration, options.once or count is not None)
    world = ctx.world
    from ddes.msg import (
        default_keys,
        fill_message_args,
        get_message_class,
        get_printable_message_args,
    )

    try:
        msg_class = get_message_class(topic_type)
    except DdesError as exc:
        raise ROSTopicException(f"invalid message type: {topic_type}: {exc}") from None
    if not pub_args and len(msg_class.__slots__):
        parser.error("Please specify message values")
    topic = script_resolve_name("rostopic", topic_name)
    latch = rate is None or options.latch
    task = Task(world, command_label("rostopic", ["pub", *argv]))
    node = task.own(world.create_node("rostopic", anonymous=True, disable_rosout=True,
                                      use_sim_time=world.use_sim_time and options.use_rostime))

    def fill() -> Any:
        msg = msg_class()
        try:
            fill_message_args(msg, pub_args, default_keys(node.get_rostime()))
        except DdesError as exc:
            raise ROSTopicException(
                f"{exc}; args are: [{get_printable_message_args(msg)}]") from None
        return msg

    try:
        msg = fill()
        pub = node.advertise(topic, msg_class, latch=latch, queue_size=100)
    except BaseException:
        task.finish(1)
        raise

    def publish(m: Any) -> None:
        try:
            pub.publish(m)
        except DdesError as exc:
            raise ROSTopicException("Unable to publish message. One of the fields has an "
                                    f"incorrect type: {exc}") from None

    if rate is None:
        text = f"publishing and latching [{msg}]" if options.verbose else \
            "publishing and latching message"
        text += f" for {_ONCE_DELAY} seconds" if options.once else ". Press ctrl-C to terminate"
        ctx.print(text)
        try:
            publish(msg)
        except BaseException:
            task.finish(1)
            raise
        if options.once:
            ev = world.env.timeout(int(_ONCE_DELAY * 1e9))
            ev.callbacks.append(lambda _ev: task.finish(0))
        return run_task(ctx, task, background=background, duration=duration,
                        waiting_for="3 seconds" if options.once else None)
    hz = rate
    sent = [0]

    def loop() -> Generator[Any, Any, None]:
        r = node.create_rate(hz)
        current = msg
        while not task.done:
            if options.substitute_keywords:
                current = fill()
            if options.verbose:
                ctx.print(f"publishing {current}")
            publish(current)
            sent[0] += 1
            if count is not None and sent[0] >= count:
                task.finish(0)
                return
            yield r.sleep()

    node.process(loop())
    return run_task(ctx, task, background=background, duration=duration,
                    waiting_for=None if count is None else f"{count} messages")


def _unsupported(name: str) -> Callable[[ToolContext, list[str]], int]:
    def tool(ctx: ToolContext, argv: list[str]) -> int:
        raise ROSConsoleError(f"rostopic {name} is not offered by ddes; see 'rostopic' for the "
                              "commands it has")

    return tool


_COMMANDS: dict[str, Callable[[ToolContext, list[str]], int]] = {
    "echo": _echo, "find": _find, "hz": _hz, "info": _info, "list": _list, "pub": _pub,
    "type": _type, "bw": _unsupported("bw"), "delay": _unsupported("delay"),
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
