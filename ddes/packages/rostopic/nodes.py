"""Node type of ``rostopic``: the ``rostopic`` program as launch files and ``rosrun`` start it.

``<node pkg="rostopic" type="rostopic" name="pub" args="pub /chatter
std_msgs/String 'data: hi' -r 2"/>`` runs ros_comm's
``tools/rostopic/src/rostopic/__init__.py`` (``rostopicmain``) as a process of
the launch; so does this, as a node of the world:

* ``rostopic pub`` calls ``init_node('rostopic', anonymous=True,
  disable_rosout=True, disable_rostime=not --use-rostime)``: the launch's
  ``name=`` (roslaunch passes ``__name:=pub``) turns ``anonymous`` off, so the
  node is ``/pub`` (``/g/pub`` in ``<group ns="g">``) and its messages carry
  that caller id; it logs nothing on ``/rosout``, and it runs on the kernel
  clock (the wall clock of ROS) unless ``--use-rostime``;
* the options are rostopic's: ``-r HZ`` publishes at a rate, ``-1``/``--once``
  publishes one latched message and exits after 3 seconds, without either the
  message is latched and the node stays until it is killed, ``-l``/``--latch``
  latches with ``-r``, ``-s`` substitutes ``now``/``auto`` in every message,
  ``-v`` prints what it publishes, ``-f FILE`` publishes the YAML documents of
  a file (10 Hz unless ``-r``, ``-l`` or ``-1``), ``--`` ends the options (``-- -5``);
  the values are YAML, one argument per field or one dictionary (``'data:
  hi'``, ``'{x: 1, y: 2}'``, ``1 2 3``);
* relative topics resolve in the node's namespace, ``~t`` under
  ``<ns>/rostopic/t`` (rosgraph's ``script_resolve_name``); the launch's
  ``<remap>``s apply to the resolved name, as rospy applies them;
* ``rostopic echo`` (``init_node('rostopic', anonymous=True)``) waits for the
  topic (``WARNING: topic [/t] does not appear to be published yet``), prints
  every message (or field: ``/odom/pose/pose``) with ``---``, ``-n COUNT``
  ends it (the node exits at its next 0.1 s poll), ``--nostr``,
  ``--noarr``, ``--offset``, ``-w``, ``-c`` and ``--filter EXPR`` (in ddes's safe
  expression subset, :mod:`ddes.expr`, not ``eval``) work as in rostopic;
* what rostopic prints goes to the node's standard output (shown with
  ``output="screen"``) and its errors to standard error (``ERROR: ...``, exit
  code 1; a usage error prints the usage and exits 2, as optparse does).

``list``, ``type`` and ``find`` print what rostopic prints and exit.  Not
offered as a node (the console's ``rostopic`` has them): ``info``, ``hz``,
``bw``, ``delay``, ``echo -b``, ``echo -p`` and ``list -b``; they print
``ERROR: ...`` and exit 1.  Nor is reading ``pub`` values from standard input:
a launch node has no terminal, so ``pub`` without values is rostopic's usage
error ``Please specify message values`` (exit 2), as at a terminal.
"""

from __future__ import annotations

import argparse
import math
import optparse
import os
import sys
from collections.abc import Callable, Generator, Mapping
from typing import TYPE_CHECKING, Any, NoReturn

import yaml

from ddes import expr as safe_expr
from ddes.errors import DdesError
from ddes.graph.names import make_caller_id, ns_join
from ddes.graph.yamlsafe import load_yaml, load_yaml_all, read_bounded
from ddes.msg import (
    Message,
    default_keys,
    fill_message_args,
    get_printable_message_args,
    strify_message,
)
from ddes.nodes import NodeType, node_cwd, print_line
from ddes.time.rostime import Duration, Time

if TYPE_CHECKING:
    import simpy

    from ddes.graph.node import Node
    from ddes.graph.topics import Publisher, Subscriber

#: rostopic's ``NAME``: its optparse ``prog`` and the base name of its nodes.
NAME = "rostopic"
#: How long ``pub -1`` stays after publishing (rostopic's ``_ONCE_DELAY``), seconds.
ONCE_DELAY = 3.0
#: How long ``pub -f`` waits for a subscriber (rostopic's ``SUBSCRIBER_TIMEOUT``), seconds.
SUBSCRIBER_TIMEOUT = 5.0
#: os.EX_USAGE: rostopic's exit code after printing its full usage.
EX_USAGE = 64

_FULL_USAGE = """rostopic is a command-line tool for printing information about ROS Topics.

Commands:
\trostopic bw\tdisplay bandwidth used by topic
\trostopic delay\tdisplay delay of topic from timestamp in header
\trostopic echo\tprint messages to screen
\trostopic find\tfind topics by type
\trostopic hz\tdisplay publishing rate of topic    
\trostopic info\tprint information about active topic
\trostopic list\tlist active topics
\trostopic pub\tpublish data to topic
\trostopic type\tprint topic or field type

Type rostopic <command> -h for more detailed usage, e.g. 'rostopic echo -h'
"""  # noqa: W291 - rostopic's usage has trailing spaces on the hz line

_CONSOLE_ONLY = ("bw", "delay", "hz", "info")

Steps = Generator["simpy.Event", Any, int]


class _Exit(Exception):
    """The program ends with ``code`` (optparse's exit, rostopic's sys.exit)."""

    def __init__(self, code: int) -> None:
        super().__init__(code)
        self.code = code


class _Failure(Exception):
    """rostopic's ``ROSTopicException``: ``ERROR: <text>`` on standard error, exit code 1."""


def _out(node: Node, text: str, *, stderr: bool = False) -> None:
    for line in text.split("\n"):
        print_line(node, line, stderr=stderr)


class _Parser(optparse.OptionParser):
    """rostopic's ``OptionParser``, printing through the node and ending with :class:`_Exit`."""

    def __init__(self, node: Node, usage: str) -> None:
        super().__init__(usage=usage, prog=NAME)
        self.node = node

    def print_help(self, file: Any = None) -> None:
        _out(self.node, self.format_help().rstrip("\n"))

    def exit(self, status: int = 0, msg: str | None = None) -> NoReturn:
        if msg:
            _out(self.node, msg.rstrip("\n"), stderr=True)
        raise _Exit(status)

    def error(self, msg: str) -> NoReturn:
        _out(self.node, self.get_usage(), stderr=True)  # "Usage: ...\n" and print's newline
        self.exit(2, f"{self.get_prog_name()}: error: {msg}\n")


def _resolve(node: Node, name: str) -> str:
    """rosgraph's ``script_resolve_name('rostopic', name)`` in the node's namespace."""
    ns = node.namespace
    if not name:
        return ns
    if name.startswith("/"):
        return name
    if name.startswith("~"):
        return ns_join(make_caller_id(NAME, ns), name[1:])
    return ns_join(ns, name)


def _message_class(node: Node, type_name: str) -> type[Message]:
    return node.world.messages.get_message_class(type_name)


# -- pub -----------------------------------------------------------------------------------------
def _pub_parser(node: Node) -> _Parser:
    parser = _Parser(node, "usage: %prog pub /topic type [args...]")
    parser.add_option("-v", dest="verbose", default=False, action="store_true",
                      help="print verbose output")
    parser.add_option("-r", "--rate", dest="rate", default=None,
                      help="publishing rate (hz).  For -f and stdin input, this defaults to 10."
                           "  Otherwise it is not set.")
    parser.add_option("-1", "--once", action="store_true", dest="once", default=False,
                      help="publish one message and exit")
    parser.add_option("-f", "--file", dest="file", metavar="FILE", default=None,
                      help="read args from YAML file (Bagy)")
    parser.add_option("-l", "--latch", dest="latch", default=False, action="store_true",
                      help="enable latching for -f, -r and piped input.  This latches the "
                           "first message.")
    parser.add_option("-s", "--substitute-keywords", dest="substitute_keywords", default=False,
                      action="store_true",
                      help="When publishing with a rate, performs keyword ('now' or 'auto') "
                           "substitution for each message")
    parser.add_option("--use-rostime", dest="use_rostime", default=False, action="store_true",
                      help="use rostime for time stamps, else walltime is used")
    return parser


def _quiet_parse(argv: list[str]) -> optparse.Values | None:
    """The ``pub`` options of ``argv`` without printing anything (None if they do not parse)."""

    class Quiet(optparse.OptionParser):
        def error(self, msg: str) -> NoReturn:
            raise _Exit(2)

        def exit(self, status: int = 0, msg: str | None = None) -> NoReturn:
            raise _Exit(status)

    parser = Quiet(add_help_option=False)
    parser.add_option("-v", action="store_true")
    parser.add_option("-r", "--rate")
    parser.add_option("-1", "--once", action="store_true")
    parser.add_option("-f", "--file")
    parser.add_option("-l", "--latch", action="store_true")
    parser.add_option("-s", "--substitute-keywords", action="store_true")
    parser.add_option("--use-rostime", dest="use_rostime", default=False, action="store_true")
    try:
        return parser.parse_args(argv)[0]
    except _Exit:
        return None


def node_options(argv: list[str]) -> Mapping[str, Any]:
    """What rostopic passes to ``init_node``: ``pub`` has no ``/rosout`` and, without
    ``--use-rostime``, no ROS time (rospy's ``disable_rostime``: the wall clock)."""
    if not argv or argv[0] != "pub":
        return {}
    options = _quiet_parse(argv[1:])
    use_rostime = bool(options is not None and options.use_rostime)
    return {"disable_rosout": True, **({} if use_rostime else {"use_sim_time": False})}


def _fill(node: Node, msg_class: type[Message], pub_args: list[Any]) -> Message:
    """rostopic's ``_fillMessageArgs`` on a new message (``now`` and ``auto`` substituted)."""
    msg = msg_class()
    header = _message_class(node, "std_msgs/Header")
    try:
        fill_message_args(msg, pub_args, default_keys(node.get_rostime(), header))
    except DdesError as exc:
        raise _Failure(f"{exc}\n\nArgs are: [{get_printable_message_args(msg)}]") from None
    return msg


def _publish(pub: Publisher[Any], msg: Message) -> None:
    try:
        pub.publish(msg)
    except DdesError as exc:
        definition = type(msg)._full_text.split("\n" + "=" * 80, 1)[0]
        raise _Failure("Unable to publish message. One of the fields has an incorrect type:\n"
                       f"  {exc}\n\nmsg file:\n{definition}") from None


def _publish_message(node: Node, pub: Publisher[Any], msg_class: type[Message],
                     pub_args: list[Any], rate: float | None, once: bool, verbose: bool,
                     substitute_keywords: bool = False) -> Steps:
    """rostopic's ``publish_message``: latched (and spinning unless ``once``) or at ``rate``."""
    msg = _fill(node, msg_class, pub_args)
    if rate is None:
        text = f"publishing and latching [{msg}]" if verbose else "publishing and latching message"
        text += f" for {ONCE_DELAY} seconds" if once else ". Press ctrl-C to terminate"
        _out(node, text)
        _publish(pub, msg)
        if not once:
            yield node.spin()  # rospy.spin()
        return 0
    r = node.create_rate(rate)
    while not node.is_shutdown():
        if substitute_keywords:
            msg = _fill(node, msg_class, pub_args)
        if verbose:
            _out(node, f"publishing {msg}")
        _publish(pub, msg)
        yield r.sleep()
    return 0


def _argv_publish(node: Node, pub: Publisher[Any], msg_class: type[Message],
                  pub_args: list[Any], rate: float | None, once: bool, verbose: bool,
                  substitute_keywords: bool) -> Steps:
    yield from _publish_message(node, pub, msg_class, pub_args, rate, once, verbose,
                                substitute_keywords)
    if once:
        # "stick around long enough for others to grab": 0.2 s sleeps until 3 s of wall time
        until = node.world.now + round(ONCE_DELAY * 1e9)
        while not node.is_shutdown() and node.world.now < until:
            yield node.world.timeout(0.2)
    return 0


def _file_publish(node: Node, pub: Publisher[Any], msg_class: type[Message], rate: float | None,
                  once: bool, filename: str, verbose: bool) -> Steps:
    """rostopic's ``stdin_publish`` with a file: one message per YAML document."""
    path = os.path.join(node_cwd(node) or os.getcwd(), filename)
    if not os.path.isfile(path):
        raise _Failure(f"file does not exist: {filename}")
    try:
        text = read_bounded(path, what="rostopic pub -f file", error=DdesError)
        docs = load_yaml_all(text.decode("utf-8", errors="replace"))
    except (yaml.YAMLError, DdesError) as exc:
        raise _Failure(f"invalid YAML in file: {exc}") from None
    exactly_one_message = len(docs) == 1
    r = node.create_rate(rate) if rate is not None else None
    wait_until = node.world.now + round(SUBSCRIBER_TIMEOUT * 1e9)
    while pub.get_num_connections() == 0 and node.world.now < wait_until:
        yield node.world.timeout(0.01)
    for doc in docs:
        if node.is_shutdown():
            break
        if doc:
            pub_args = doc if isinstance(doc, list) else [doc]
            if exactly_one_message and rate is not None:
                _out(node, "Got one message and a rate, publishing repeatedly")
                yield from _publish_message(node, pub, msg_class, pub_args, rate, once, verbose)
            else:
                yield from _publish_message(node, pub, msg_class, pub_args, None,
                                            r is not None or once, verbose)
        if r is not None:
            yield r.sleep()
        if node.is_shutdown() or once:
            break
    return 0


def _pub(node: Node, argv: list[str]) -> Steps:
    """``rostopic pub`` (rostopic's ``_rostopic_cmd_pub``)."""
    parser = _pub_parser(node)
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
    if len(args) > 2 and options.file:
        parser.error("args conflict with -f setting")
    topic_name, topic_type = args[0], args[1]
    pub_args: list[Any] = []
    for arg in args[2:]:
        try:
            pub_args.append(load_yaml(arg))  # bounded: no alias bomb, no RecursionError
        except (yaml.YAMLError, DdesError) as exc:
            parser.error(f"Argument error: {exc}")
    latch = rate is None or options.latch
    topic = _resolve(node, topic_name)
    try:
        msg_class = _message_class(node, topic_type)
    except DdesError:
        package = topic_type.split("/", 1)[0] if "/" in topic_type else None
        raise _Failure(f"invalid message type: {topic_type}.\nIf this is a valid message type, "
                       f"perhaps you need to type 'rosmake {package}'") from None
    pub = node.advertise(topic, msg_class, latch=latch, queue_size=100)
    if not pub_args and len(msg_class.__slots__):
        if not options.file:
            parser.error("Please specify message values")  # ddes: a launch node has no stdin
        if rate is None and not options.latch and not options.once:
            rate = 10.0
        return (yield from _file_publish(node, pub, msg_class, rate, options.once,
                                         options.file, options.verbose))
    return (yield from _argv_publish(node, pub, msg_class, pub_args, rate, options.once,
                                     options.verbose, options.substitute_keywords))


# -- echo ----------------------------------------------------------------------------------------
#: rostopic's msg_eval: picks a field path out of a message (None: absent).
MsgEval = Callable[[Any], Any]


def _index(text: str) -> int | slice:
    """rostopic's ``_get_array_index_or_slice_object``."""
    if text == "":
        raise ValueError("empty array index")
    parts = text.split(":")
    if len(parts) == 1:
        try:
            return int(parts[0])
        except ValueError:
            raise ValueError(f"non-integer array index step '{parts[0]}'") from None
    if len(parts) > 3:
        raise ValueError("too many slice arguments")
    bounds: list[int | None] = []
    for label, part in zip(("start", "stop", "step"), parts):
        try:
            bounds.append(int(part) if part != "" else None)
        except ValueError:
            raise ValueError(f"non-integer slice {label} '{part}'") from None
    return slice(*bounds)


def msgevalgen(node: Node, pattern: str) -> MsgEval | None:
    """rostopic's ``msgevalgen``: a function returning the field(s) ``pattern`` names."""
    evals: list[tuple[str, int | slice | None]] = []
    for f in (f for f in pattern.split("/") if f):
        if "[" in f:
            field_name, rest = f.split("[", 1)
            if not rest.endswith("]"):
                _out(node, f"missing closing ']' in slice spec '{f}'", stderr=True)
                return None
            try:
                evals.append((field_name, _index(rest[:-1])))
            except ValueError as exc:
                _out(node, f"field '{field_name}' has invalid slice argument '{rest[:-1]}': "
                     f"{exc}", stderr=True)
                return None
        else:
            evals.append((f, None))

    def msgeval(msg: Any, steps: list[tuple[str, int | slice | None]]) -> Any:
        for i, (field_name, index) in enumerate(steps):
            try:
                msg = getattr(msg, field_name)
            except AttributeError:
                _out(node, f"no field named {field_name} in {pattern}", stderr=True)
                return None
            if index is not None:
                try:
                    msg = msg[index]
                except IndexError as exc:
                    _out(node, f"{exc}: {pattern}", stderr=True)
                    return None
                if isinstance(msg, list):
                    return [msgeval(m, steps[i + 1:]) for m in msg]
        return msg

    return (lambda msg: msgeval(msg, evals)) if evals else None


def _nested_attribute(msg: Any, attrs: str) -> Any:
    value = msg
    for attr in attrs.split("/"):
        value = getattr(value, attr)
    return value


def _topic_type(node: Node, topic: str) -> tuple[str | None, str | None, MsgEval | None]:
    """rostopic's ``_get_topic_type``: exact topic first, then the longest topic holding the
    field path ``topic`` names."""
    types = node.world.master.get_topic_types()
    matches = [(t, ty) for t, ty in types if t == topic]
    if not matches:
        matches = sorted(((t, ty) for t, ty in types if topic.startswith(t + "/")),
                         key=lambda m: m[0], reverse=True)
        while matches:
            t, ty = matches[0]
            try:
                msg = _message_class(node, ty)()
            except DdesError:
                break
            attrs = topic[len(t) + 1:].rstrip("/").split("[")[0]
            if attrs == "":
                break
            try:
                _nested_attribute(msg, attrs)
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
    return ty, t, msgevalgen(node, topic[len(t):])


def _topic_class(node: Node, topic: str, type_name: str) -> type[Message]:
    """The class of ``topic``'s messages: its publishers' or subscribers' (not AnyMsg), else the
    world's registry's."""
    entry = node.world.master.topics.get(topic)
    if entry is not None:
        ends: list[Publisher[Any] | Subscriber[Any]] = [*entry.publishers, *entry.subscribers]
        for end in ends:
            cls = end.data_class
            if isinstance(cls, type) and issubclass(cls, Message) and end.type == type_name:
                return cls
    try:
        return _message_class(node, type_name)
    except DdesError:
        raise _Failure(f"Cannot load message class for [{type_name}]. Are your messages "
                       "built?") from None


def _value_transform(nostr: bool, noarr: bool) -> Callable[[Any, str | None], Any]:
    """rostopic's ``create_value_transform`` (``--nostr``, ``--noarr``)."""

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
            return val if type_information is None else field_value(val, type_information)
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
        shown: type[Message] = type("TransformedMessage", (Message,),
                                    {"__slots__": tuple(names), "_slot_types": types,
                                     "_type": val._type})
        out = object.__new__(shown)
        for name, v in zip(names, values):
            setattr(out, name, v)
        return out

    return transform


_TIME_METHODS = frozenset({"to_sec", "to_nsec", "is_zero"})


def _filter(node: Node, text: str, topic: str) -> Callable[[Any], bool]:
    """``--filter EXPR`` with ``m`` and ``topic``: ddes's safe subset (rostopic ``eval``s it)."""
    try:
        parsed = safe_expr.parse(text, methods={Time: _TIME_METHODS, Duration: _TIME_METHODS})
    except DdesError as exc:
        raise _Failure(f"invalid --filter expression {text!r}: {exc}") from None

    def fn(m: Any) -> bool:
        return bool(parsed.evaluate({"m": m, "topic": topic, "math": math}))

    return fn


def _echo_parser(node: Node) -> _Parser:
    parser = _Parser(node, "usage: %prog echo [options] /topic")
    parser.add_option("-b", "--bag", dest="bag", default=None, metavar="BAGFILE",
                      help="echo messages from .bag file")
    parser.add_option("-p", dest="plot", default=False, action="store_true",
                      help="echo in a plotting friendly format")
    parser.add_option("-w", dest="fixed_numeric_width", default=None, metavar="NUM_WIDTH",
                      help="fixed width for numeric values")
    parser.add_option("--filter", dest="filter_expr", default=None, metavar="FILTER-EXPRESSION",
                      help="Python expression to filter messages that are printed. Expression "
                           "can use Python builtins as well as m (the message) and topic (the "
                           "topic name).")
    parser.add_option("--nostr", dest="nostr", default=False, action="store_true",
                      help="exclude string fields")
    parser.add_option("--noarr", dest="noarr", default=False, action="store_true",
                      help="exclude arrays")
    parser.add_option("-c", "--clear", dest="clear", default=False, action="store_true",
                      help="clear screen before printing next message")
    parser.add_option("-a", "--all", dest="all_topics", default=False, action="store_true",
                      help="display all message in bag, only valid with -b option")
    parser.add_option("-n", dest="msg_count", default=None, metavar="COUNT",
                      help="number of messages to echo")
    parser.add_option("--offset", dest="offset_time", default=False, action="store_true",
                      help="display time as offsets from current time (in seconds)")
    return parser


def _field_type_information(node: Node, cls: type[Message], topic: str, real: str) -> str | None:
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
                current = _message_class(node, info.split("[", 1)[0])
            except DdesError:
                raise _Failure(f"Cannot load message class for [{info}]. Are your messages "
                               "built?") from None
    return info


def _echo(node: Node, argv: list[str]) -> Steps:
    """``rostopic echo`` (rostopic's ``_rostopic_cmd_echo`` and ``_rostopic_echo``)."""
    parser = _echo_parser(node)
    options, args = parser.parse_args(argv)
    if len(args) > 1:
        parser.error("you may only specify one input topic")
    if options.all_topics and not options.bag:
        parser.error("Display all option is only valid when echoing from bag files")
    if options.offset_time and options.bag:
        parser.error("offset time option is not valid with bag files")
    if not args:
        parser.error("topic must be specified")
    topic = _resolve(node, args[0])
    try:
        count = int(options.msg_count) if options.msg_count else None
    except ValueError:
        parser.error("COUNT must be an integer")
    width = None
    if options.fixed_numeric_width:
        try:
            width = int(options.fixed_numeric_width)
        except ValueError:
            parser.error("NUM_WIDTH must be an integer")
        if width < 2:
            parser.error("Fixed width for numeric values must be at least 2")
    if options.bag or options.plot:
        raise _Failure(f"rostopic echo {'-b' if options.bag else '-p'} is not offered by ddes's "
                       "rostopic node; run it in the ddes console (docs/console.md)")
    filter_fn = _filter(node, options.filter_expr, topic) if options.filter_expr else None
    transform = _value_transform(options.nostr, options.noarr)
    if topic.endswith("/") and len(topic) > 1:
        topic = topic[:-1]
    world = node.world
    # get_topic_class(topic, blocking=True): poll the master every 0.1 s (wall time)
    type_name, real, msg_eval = _topic_type(node, topic)
    if type_name is None:
        _out(node, f"WARNING: topic [{topic}] does not appear to be published yet", stderr=True)
        while type_name is None and not node.is_shutdown():
            yield world.timeout(0.1)
            type_name, real, msg_eval = _topic_type(node, topic)
    if type_name is None or real is None or node.is_shutdown():
        return 0
    cls = _topic_class(node, real, type_name)
    type_information = _field_type_information(node, cls, topic, real)
    state = {"count": 0, "done": False}
    prefix = "\033[2J\033[;H" if options.clear else ""

    def callback(data: Any) -> None:
        if state["done"] or (filter_fn is not None and not filter_fn(data)):
            return
        if count is not None and state["count"] >= count:
            state["done"] = True
            return
        value = msg_eval(data) if msg_eval is not None else data
        if value is not None:
            state["count"] += 1
            if type_information and type_information.startswith("uint8["):
                value = list(value) if isinstance(value, (bytes, bytearray)) else [
                    ord(x) for x in value]
            value = transform(value, type_information)
            offset = node.get_rostime() if options.offset_time else None
            _out(node, prefix + strify_message(value, time_offset=offset,
                                               fixed_numeric_width=width) + "\n---")
        if count is not None and state["count"] >= count:
            state["done"] = True

    def guarded(data: Any) -> None:
        try:
            callback(data)
        except Exception as exc:  # noqa: BLE001 - rostopic prints the traceback and stops
            _out(node, f"{type(exc).__name__}: {exc}", stderr=True)
            state["done"] = True

    node.subscribe(real, cls, guarded)
    if node.get_param("/use_sim_time", False):
        # "#2950: print warning if nothing received for two seconds" (wall time)
        until = world.now + 2_000_000_000
        while world.now < until and state["count"] == 0 and not node.is_shutdown() \
                and not state["done"]:
            yield world.timeout(0.1)
        if state["count"] == 0 and not node.is_shutdown() and not state["done"]:
            _out(node, "WARNING: no messages received and simulated time is active.\n"
                       "Is /clock being published?", stderr=True)
    while not node.is_shutdown() and not state["done"]:
        yield world.timeout(0.1)
    return 0


# -- list / type / find --------------------------------------------------------------------------
def _list(node: Node, argv: list[str]) -> int:
    """``rostopic list [-v] [-p|-s] [--host] [/namespace]`` (rostopic's ``_rostopic_list``)."""
    parser = _Parser(node, "usage: %prog list [/namespace]")
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
        topic = _resolve(node, args[0])
    elif len(args) > 1:
        parser.error("you may only specify one input topic")
    if options.bag:
        raise _Failure("rostopic list -b is not offered by ddes's rostopic node; run 'rosbag "
                       "info BAG' in the ddes console")
    if options.subscribers and options.publishers:
        parser.error("you may only specify one of -p, -s")
    master = node.world.master
    types = dict(master.get_topic_types())
    pubs_state, subs_state, _ = master.get_system_state()
    pubs = [(t, types.get(t, "unknown type"), n) for t, n in pubs_state]
    subs = [(t, types.get(t, "unknown type"), n) for t, n in subs_state]
    if topic:
        ns = topic if topic.endswith("/") else topic + "/"
        pubs = [x for x in pubs if x[0] == topic or x[0].startswith(ns)]
        subs = [x for x in subs if x[0] == topic or x[0].startswith(ns)]
    indent = ""
    if options.hostname:
        if not ((pubs and not options.subscribers) or (subs and not options.publishers)):
            return 0
        _out(node, "Host [localhost]:")
        indent = "  "
    if options.verbose:
        if not options.subscribers:
            _out(node, f"\n{indent}Published topics:")
            for t, ty, nodes in pubs:
                many = f"{len(nodes)} publishers" if len(nodes) > 1 else "1 publisher"
                _out(node, f"{indent} * {t} [{ty}] {many}")
        if not options.publishers:
            _out(node, indent)
            _out(node, f"{indent}Subscribed topics:")
            for t, ty, nodes in subs:
                many = f"{len(nodes)} subscribers" if len(nodes) > 1 else "1 subscriber"
                _out(node, f"{indent} * {t} [{ty}] {many}")
        _out(node, "")
        return 0
    if options.publishers:
        names = {t for t, _, _ in pubs}
    elif options.subscribers:
        names = {t for t, _, _ in subs}
    else:
        names = {t for t, _, _ in pubs} | {t for t, _, _ in subs}
    _out(node, "\n".join(f"{indent}{t}" for t in sorted(names)))
    return 0


class _ArgParser(argparse.ArgumentParser):
    """rostopic type's ``argparse`` parser, printing through the node."""

    def __init__(self, node: Node, prog: str) -> None:
        super().__init__(prog=prog)
        self.node = node

    def _print_message(self, message: str, file: Any = None) -> None:
        if message:
            _out(self.node, message.rstrip("\n"), stderr=file is sys.stderr)

    def exit(self, status: int = 0, message: str | None = None) -> NoReturn:
        if message:
            _out(self.node, message.rstrip("\n"), stderr=True)
        raise _Exit(status)


def _type(node: Node, argv: list[str]) -> int:
    """``rostopic type /topic_or_field`` (rostopic's ``_rostopic_cmd_type``)."""
    parser = _ArgParser(node, f"{NAME} type")
    parser.add_argument("topic_or_field", help="Topic or field name")
    args = [parser.parse_args(argv).topic_or_field]
    topic = _resolve(node, args[0])
    type_name, real, _ = _topic_type(node, topic)
    if type_name is None or real is None:
        _out(node, f"unknown topic type [{topic}]", stderr=True)
        return 1
    if topic == real:
        _out(node, type_name)
        return 0
    field = topic[len(real) + 1:]
    field_type = type_name
    for current in field.split("/"):
        try:
            cls = _message_class(node, field_type)
            field_type = cls._slot_types[cls.__slots__.index(current)]
        except (DdesError, ValueError) as exc:
            _out(node, f"{type(exc).__name__}: {exc}", stderr=True)  # rostopic's traceback
            return 1
    _out(node, f"{type_name} {field} {field_type}")
    return 0


def _find(node: Node, argv: list[str]) -> int:
    """``rostopic find msg-type`` (rostopic's ``_rostopic_cmd_find``)."""
    parser = _Parser(node, "usage: %prog find msg-type")
    _options, args = parser.parse_args(argv)
    if not args:
        parser.error("please specify a message type")
    if len(args) > 1:
        parser.error("you may only specify one message type")
    found = [t for t, ty in node.world.master.get_topic_types() if ty == args[0]]
    _out(node, "\n".join(found))
    return 0


# -- the program -----------------------------------------------------------------------------------
def rostopic(node: Node) -> Steps:
    """``rostopic pub|echo ...``: rostopic's ``rostopicmain`` on this node (its exit code)."""
    argv = node.argv
    if not argv or argv[0] not in ("pub", "echo", "list", "type", "find", *_CONSOLE_ONLY):
        _out(node, _FULL_USAGE)
        return EX_USAGE
    command, rest = argv[0], argv[1:]
    try:
        if command == "pub":
            return (yield from _pub(node, rest))
        if command == "echo":
            return (yield from _echo(node, rest))
        if command in _ONE_SHOT:
            return _ONE_SHOT[command](node, rest)
        raise _Failure(f"rostopic {command} is not offered by ddes's rostopic node (pub, echo, "
                       "list, type and find are); run it in the ddes console (docs/console.md)")
    except _Exit as done:
        return done.code
    except _Failure as exc:
        _out(node, f"ERROR: {exc}", stderr=True)
        return 1


_ONE_SHOT: dict[str, Callable[[Node, list[str]], int]] = {"list": _list, "type": _type,
                                                         "find": _find}

NODES: dict[str, NodeType] = {
    "rostopic": NodeType(rostopic, name=NAME, anonymous=True, doc=rostopic.__doc__ or "",
                         node_options=node_options),
}
