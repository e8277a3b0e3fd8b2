"""The ``rostopic`` sub-commands that let time pass: ``echo``, ``hz`` and ``pub``.

See :mod:`ddes.console.rostopic` for the formats; this module holds their
machinery: rostopic's ``--nostr``/``--noarr`` value transform,
``ROSTopicHz`` statistics, and the publishing loops.  Each runs as a
:class:`~ddes.console.toolkit.Task` owning an anonymous ``/rostopic_N`` node
(as rostopic's ``init_node('rostopic', anonymous=True)``).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import TYPE_CHECKING, Any

import yaml

from ddes import expr as safe_expr
from ddes._floats import left_sum
from ddes.console.rostopic import MsgEval, _field_class, _topic_class, get_topic_type
from ddes.console.toolkit import (
    Task,
    ToolParser,
    add_run_options,
    command_label,
    open_ended,
    parse_count,
    parse_duration,
    run_task,
    script_resolve_name,
    take_background,
)
from ddes.errors import (
    DdesError,
    ResourceLimitError,
    ROSConsoleError,
    ROSTopicException,
    UnsafeExpressionError,
)
from ddes.graph.yamlsafe import load_yaml
from ddes.time.rostime import Duration, Time
from ddes.time.units import duration_to_ns

if TYPE_CHECKING:
    import simpy
    from simpy.events import ProcessGenerator

    from ddes.console.tooling import ToolContext
    from ddes.graph.world import World
    from ddes.msg.anymsg import AnyMsg
    from ddes.msg.message import Message

__all__ = ["TopicHz", "ValueTransform", "echo", "end_of_instant", "format_hz",
           "format_hz_table", "hz", "pub", "strify_for_echo", "value_transform_factory"]

_ONCE_DELAY = 3.0

#: rostopic's value transform: ``(message or field value, field type or None) -> shown value``.
ValueTransform = Callable[[object, "str | None"], object]
#: A ``--filter`` expression: is the message shown/counted?
MsgFilter = Callable[["Message | AnyMsg"], bool]
#: Called once the topic's type is known: ``start(type, real topic, field evaluator)``.
_Start = Callable[[str, str, "MsgEval | None"], None]


# -- echo --------------------------------------------------------------------------------------------
def value_transform_factory(nostr: bool, noarr: bool) -> ValueTransform:
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

    def transform(val: object, type_information: str | None = None) -> object:
        if not isinstance(val, Message):
            if type_information is None:
                return val
            return field_value(val, type_information)
        names = list(val.__slots__)
        types = list(val._slot_types)
        values: list[object] = []
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
        shown: type[Message] = type("TransformedMessage", (Message,),
                          {"__slots__": tuple(names), "_slot_types": types, "_type": val._type})
        out = object.__new__(shown)
        for name, v in zip(names, values):
            setattr(out, name, v)
        return out

    return transform


def strify_for_echo(val: Any, type_information: str | None = None,
                    transform: ValueTransform | None = None,
                    time_offset: Time | None = None, fixed_numeric_width: int | None = None) -> str:
    """The text ``rostopic echo`` prints for one message or field value (without ``---``)."""
    from ddes.msg import strify_message

    if type_information and type_information.startswith("uint8["):
        val = list(val) if isinstance(val, (bytes, bytearray)) else [ord(x) for x in val]
    if transform is not None:
        val = transform(val, type_information)
    return strify_message(val, time_offset=time_offset,
                          fixed_numeric_width=fixed_numeric_width)


def _field_type_information(cls: type[Message], topic: str, real: str) -> str | None:
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


class UnsafeFilterExpression(ROSConsoleError, UnsafeExpressionError):
    """A ``--filter`` expression outside ddes's safe subset (both error kinds at once)."""


class CostlyFilterExpression(ROSConsoleError, ResourceLimitError):
    """A ``--filter`` expression that would cost more than ddes allows."""


def _filter_error(exc: DdesError, message: str) -> ROSConsoleError:
    if isinstance(exc, UnsafeExpressionError):
        return UnsafeFilterExpression(message)
    if isinstance(exc, ResourceLimitError):
        return CostlyFilterExpression(message)
    return ROSConsoleError(message)


_TIME_METHODS = frozenset({"to_sec", "to_nsec", "is_zero"})


def _filter_fn(expr: str | None, topic: str) -> MsgFilter | None:
    """``--filter EXPR``: ``m`` (the message) and ``topic`` in ddes's safe subset (no eval).

    rostopic ``eval``s the text with its module's globals; ddes parses it once
    with :mod:`ddes.expr`, so a typo or a refused construct fails before any
    message arrives, and a failure on a message is a ``ROSConsoleError``.
    """
    if not expr:
        return None
    try:
        parsed = safe_expr.parse(expr, methods={Time: _TIME_METHODS, Duration: _TIME_METHODS})
    except DdesError as exc:
        raise _filter_error(exc, f"invalid --filter expression {expr!r}: {exc}") from None

    def fn(m: Message | AnyMsg) -> bool:
        try:
            return bool(parsed.evaluate({"m": m, "topic": topic, "math": math}))
        except DdesError as exc:
            raise _filter_error(exc, f"--filter expression {expr!r} failed on a message of "
                                     f"{topic}: {exc}") from None

    return fn


def _wait_for_type(ctx: ToolContext, task: Task, topic: str,
                   start: _Start) -> None:
    """Call ``start(type, real, eval)`` once ``topic`` is known, polling every 0.1 s as rostopic."""
    world = ctx.world
    type_name, real, msg_eval = get_topic_type(world, topic)
    if type_name is not None and real is not None:
        start(type_name, real, msg_eval)
        return
    ctx.eprint(f"WARNING: topic [{topic}] does not appear to be published yet")

    def poll() -> ProcessGenerator:
        while not task.done:
            yield world.timeout(0.1)
            t, r, e = get_topic_type(world, topic)
            if t is not None and r is not None and not task.done:
                start(t, r, e)
                return

    world.env.process(poll())


def _require_bound(tool: str, background: bool, duration: float | None, has_end: bool) -> None:
    if not (background or duration is not None or has_end):
        raise ROSConsoleError(
            f"'{tool}' runs until Ctrl+C in ROS and would never end here: give a count (-n), "
            "--duration SECONDS (simulated), end the line with & to keep it running in the "
            "background, or give the script a time limit (ddes console --until SECONDS)")


def _check_known(world: World, topic: str, background: bool, duration: float | None) -> None:
    if get_topic_type(world, topic)[0] is None and not background and duration is None:
        raise ROSTopicException(
            f"topic [{topic}] does not appear to be published yet; give --duration SECONDS "
            "to wait for it (see 'rostopic list')")


def echo(ctx: ToolContext, argv: list[str]) -> int:
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
    _require_bound("rostopic echo", background or open_ended(ctx), duration, count is not None)
    world = ctx.world
    _check_known(world, topic, background or open_ended(ctx), duration)
    filter_fn = _filter_fn(options.filter_expr, topic)
    transform = value_transform_factory(options.nostr, options.noarr)
    task = Task(world, command_label("rostopic", ["echo", *argv]))
    node = task.own(world.create_node("rostopic", anonymous=True))
    if topic.endswith("/") and len(topic) > 1:
        topic = topic[:-1]
    received = [0]

    def start(type_name: str, real: str, msg_eval: MsgEval | None) -> None:
        cls = _topic_class(world, real, type_name)
        type_information = _field_type_information(cls, topic, real)

        def callback(data: Message) -> None:
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
        mean = left_sum(self.times) / n
        rate = 1.0 / mean if mean > 0.0 else 0
        std_dev = math.sqrt(left_sum((x - mean) ** 2 for x in self.times) / n)
        self.last_printed_tn = self.msg_tn
        return rate, min(self.times), max(self.times), std_dev, n + 1


def format_hz(stats: tuple[float, float, float, float, int] | None) -> str:
    """The two lines ``rostopic hz`` prints for one report (or ``no new messages``)."""
    if stats is None:
        return "no new messages"
    rate, min_d, max_d, std, window = stats
    return (f"average rate: {rate:.3f}\n\tmin: {min_d:.3f}s max: {max_d:.3f}s "
            f"std dev: {std:.5f}s window: {window}")


def format_hz_table(rows: list[tuple[str, tuple[float, float, float, float, int] | None]]) -> str:
    """rostopic's report for several topics (``print_hz``): its table, or ``no new messages``.

    Topics without new messages are left out.  rostopic appends each topic's window twice, so
    from the second row on the window column shows an earlier topic's window; kept, as printed.
    """
    header = ["topic", "rate", "min_delta", "max_delta", "std_dev", "window"]
    cols: dict[str, list[str]] = {h: [] for h in header}
    for topic, hz in rows:
        if hz is None:
            continue
        rate, min_d, max_d, std, win = hz
        cols["window"].append(str(win))
        cols["topic"].append(topic)
        cols["rate"].append(f"{rate:.4}")
        cols["min_delta"].append(f"{min_d:.4}")
        cols["max_delta"].append(f"{max_d:.4}")
        cols["std_dev"].append(f"{std:.4}")
        cols["window"].append(str(win))
    return _ascii_table(header, cols) if cols["topic"] else "no new messages"


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


class _EndOfInstant:
    """One event per instant that fires once the other events due then have run."""

    #: At most this many rounds of zero-time waiting (a zero-time livelock elsewhere is caught
    #: by the world's instant budget; this only keeps the wait itself finite).
    MAX_ROUNDS = 10_000

    def __init__(self, world: World) -> None:
        self.world = world
        self.at = -1
        self.event: simpy.Event | None = None

    def wait(self) -> simpy.Event:
        env = self.world.env
        if self.event is None or self.at != env.now or self.event.triggered:
            self.at, self.event = env.now, env.event()
            env.process(self._drive(self.event))
        return self.event

    def _drive(self, done: simpy.Event) -> ProcessGenerator:
        env = self.world.env
        for _ in range(self.MAX_ROUNDS):
            if env.peek() != env.now:
                break
            yield env.timeout(0)  # queued behind everything already due now
        done.succeed()


def end_of_instant(world: World) -> simpy.Event:
    """An event that fires when the events due at the current instant have run (shared by every
    ``rostopic hz`` of the world, so two never wait for each other)."""
    return world.extension("rostopic.hz.end_of_instant", _EndOfInstant).wait()


def hz(ctx: ToolContext, argv: list[str]) -> int:
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
    _require_bound("rostopic hz", background or open_ended(ctx), duration, reports is not None)
    world = ctx.world
    topics = [script_resolve_name("rostopic", t) for t in args]
    for topic in topics:
        _check_known(world, topic, background or open_ended(ctx), duration)
    task = Task(world, command_label("rostopic", ["hz", *argv]))
    node = task.own(world.create_node("rostopic", anonymous=True))
    stats = {t: TopicHz(window) for t in topics}

    def now_sec() -> float:
        # rostopic: rospy.get_rostime().to_sec(), secs + nsecs / 1e9 (not ns / 1e9: the last bit
        # shows in the table's std_dev)
        return (Time._from_ns(world.now) if options.use_wtime else node.get_rostime()).to_sec()

    for topic in topics:
        filter_fn = _filter_fn(options.filter_expr, topic)

        def start(type_name: str, real: str, _eval: MsgEval | None, topic: str = topic,
                  filter_fn: MsgFilter | None = filter_fn) -> None:
            from ddes.graph.topics import AnyMsg

            cls = _topic_class(world, real, type_name) if filter_fn is not None else AnyMsg
            rt = stats[topic]

            def callback(m: Message | AnyMsg) -> None:
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

    def reporter() -> ProcessGenerator:
        while not task.done:
            yield world.timeout(1)
            # rostopic's 1 s sleep begins after its subscribe call returns: a message arriving
            # in the instant the second ends is in the report (a 10 Hz topic shows window: 10)
            yield end_of_instant(world)
            if task.done:
                return
            if len(topics) == 1:
                ctx.print(format_hz(stats[topics[0]].get_hz()))
            else:
                ctx.print(format_hz_table([(t, stats[t].get_hz()) for t in topics]))
            done[0] += 1
            if reports is not None and done[0] >= reports:
                task.finish(0)

    world.env.process(reporter())
    if duration is None:
        return run_task(ctx, task, background=background, duration=None,
                        waiting_for=None if reports is None else f"{reports} reports")

    def finisher(duration_ns: int) -> ProcessGenerator:
        # --duration S ends once instant S has run, like `sleep S`: a report due at S is printed
        # and counts the messages arriving then
        yield world.env.timeout(duration_ns)
        yield end_of_instant(world)
        yield end_of_instant(world)  # after the reporter, woken by the same end of instant
        task.finish(0)

    world.env.process(finisher(duration_to_ns(duration, "--duration")))
    # the task ends itself at S; run_task's own limit (just after) never comes first
    return run_task(ctx, task, background=background, duration=duration + 0.001,
                    waiting_for=f"--duration {duration:g}")


# -- pub ---------------------------------------------------------------------------------------------
def pub(ctx: ToolContext, argv: list[str]) -> int:
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
            pub_args.append(load_yaml(arg))  # bounded: no alias bomb, no RecursionError
        except yaml.YAMLError as exc:
            parser.error(f"Argument error: {exc}")
    count = parse_count(options.count)
    duration = parse_duration(options.duration)
    if count is not None and rate is None:
        parser.error("-n COUNT needs -r RATE (without a rate one latched message is published)")
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
    _require_bound("rostopic pub", background or open_ended(ctx), duration, options.once or count is not None)
    topic = script_resolve_name("rostopic", topic_name)
    latch = rate is None or options.latch
    task = Task(world, command_label("rostopic", ["pub", *argv]))
    node = task.own(world.create_node("rostopic", anonymous=True, disable_rosout=True,
                                      use_sim_time=world.use_sim_time and options.use_rostime))

    def fill() -> Message:
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

    def publish(m: Message) -> None:
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
            ev = world.timeout(_ONCE_DELAY)
            ev.callbacks.append(lambda _ev: task.finish(0))
        return run_task(ctx, task, background=background, duration=duration,
                        waiting_for="3 seconds" if options.once else None)
    hz = rate
    sent = [0]

    def loop() -> ProcessGenerator:
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


