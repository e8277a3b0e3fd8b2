"""``rostopic``: every sub-command's output format, on simulated time, and against real rostopic."""

from __future__ import annotations

import json
from typing import Any

import pytest

from ddes.console.rostopic_live import TopicHz, format_hz, strify_for_echo, value_transform_factory
from ddes.console.shell import Console
from ddes.console.toolkit import node_uri
from ddes.msg import get_message_class, serialize_message

from .rosref import run_with_master


def test_list_sorted(chat: Console) -> None:
    assert chat.run("rostopic list") == "/chatter\n/rosout\n/rosout_agg\n"


def test_list_verbose_layout(chat: Console) -> None:
    assert chat.run("rostopic list -v") == (
        "\n"
        "Published topics:\n"
        " * /rosout_agg [rosgraph_msgs/Log] 1 publisher\n"
        " * /rosout [rosgraph_msgs/Log] 2 publishers\n"
        " * /chatter [std_msgs/String] 1 publisher\n"
        "\n"
        "Subscribed topics:\n"
        " * /rosout [rosgraph_msgs/Log] 1 subscriber\n"
        " * /chatter [std_msgs/String] 1 subscriber\n"
        "\n"
    )


def test_list_filters(chat: Console) -> None:
    assert chat.run("rostopic list -p") == "/chatter\n/rosout\n/rosout_agg\n"
    assert chat.run("rostopic list -s") == "/chatter\n/rosout\n"
    assert chat.run("rostopic list /rosout") == "/rosout\n"
    assert chat.run("rostopic list --host -s") == "Host [localhost]:\n  /chatter\n  /rosout\n"
    assert "you may only specify one of -p, -s" in chat.run("rostopic list -p -s", check=False)


def test_info_layout(chat: Console) -> None:
    assert chat.run("rostopic info /chatter") == (
        "Type: std_msgs/String\n"
        "\n"
        "Publishers: \n"
        f" * /talker_1 ({node_uri('/talker_1')})\n"
        "\n"
        "Subscribers: \n"
        f" * /listener_2 ({node_uri('/listener_2')})\n"
        "\n"
        "\n"
    )
    assert chat.run("rostopic info rosout_agg").splitlines()[4:7] == [
        "", "Subscribers: None", ""]


def test_info_unknown_topic(console: Console) -> None:
    result = console.execute("rostopic info /nope")
    assert (result.code, result.out, result.err) == (1, "", "ERROR: Unknown topic /nope\n")


def test_type_of_topics_and_fields(chat: Console) -> None:
    assert chat.run("rostopic type /chatter") == "std_msgs/String\n"
    assert chat.run("rostopic type /rosout/msg") == "rosgraph_msgs/Log msg string\n"
    assert chat.run("rostopic type /rosout/header/stamp") == \
        "rosgraph_msgs/Log header/stamp time\n"
    result = chat.execute("rostopic type /nope")
    assert (result.code, result.err) == (1, "unknown topic type [/nope]\n")


def test_find(chat: Console) -> None:
    assert chat.run("rostopic find std_msgs/String") == "/chatter\n"
    assert chat.run("rostopic find rosgraph_msgs/Log") == "/rosout_agg\n/rosout\n"
    assert chat.run("rostopic find std_msgs/Int8") == "\n"


def test_echo_count_prints_yaml_and_separator(chat: Console) -> None:
    out = chat.run("rostopic echo -n 3 /chatter")
    assert out == ('data: "hello world 0.1"\n---\n'
                   'data: "hello world 0.2"\n---\n'
                   'data: "hello world 0.3"\n---\n')
    assert chat.world.now == 300_000_000  # it stopped at the third message


def test_echo_field_and_offset(chat: Console) -> None:
    assert chat.run("rostopic echo -n 1 /chatter/data") == '"hello world 0.1"\n---\n'
    out = chat.run("rostopic echo -n 1 /rosout_agg/header/stamp --offset")
    assert out == "\nsecs: 0\nnsecs:         0\n---\n"


def test_echo_nostr_noarr(chat: Console) -> None:
    chat.run("sleep 0.05")
    out = chat.run("rostopic echo -n 1 --nostr --noarr /rosout_agg")
    lines = out.splitlines()
    # the talker's "hello world 0.1" (seq 1 was its latched t=0 line, before this subscriber)
    assert lines[0:6] == ["header: ", "  seq: 2", "  stamp: ", "    secs: 0",
                          "    nsecs: 100000000", '  frame_id: "<string length: 0>"']
    assert lines[6:10] == ["level: 2", 'name: "<string length: 9>"',
                           'msg: "<string length: 15>"', 'file: "<string length: 8>"']
    assert lines[10:] == ['function: "<string length: 6>"', lines[11],
                          'topics: "<array type: string, length: 2>"', "---"]
    assert lines[11].startswith("line: ")


def test_echo_filter_and_width(chat: Console) -> None:
    out = chat.run("rostopic echo -n 1 --filter \"m.data.endswith('0.3')\" /chatter")
    assert out == 'data: "hello world 0.3"\n---\n'
    chat.run("rostopic pub /n std_msgs/Float64 3.25 &")
    assert chat.run("rostopic echo -n 1 -w 6 /n") == "data: 3.2500\n---\n"


def test_echo_needs_a_bound(chat: Console) -> None:
    result = chat.execute("rostopic echo /chatter")
    assert result.code == 1
    assert "runs until Ctrl+C in ROS" in result.err and "--duration" in result.err
    assert result.err.count("\n") == 1
    assert chat.world.nodes.keys() == {"/rosout", "/talker_1", "/listener_2"}


def test_echo_duration_on_a_topic_that_appears(console: Console) -> None:
    result = console.execute("rostopic echo --duration 0.35 /chatter &")
    assert result.err == "WARNING: topic [/chatter] does not appear to be published yet\n"
    console.run("rosrun --quiet rospy_tutorials talker &")
    out = console.run("sleep 0.35")
    assert out.count("---") >= 2 and 'data: "hello world 0.2"' in out


def test_duration_is_seconds_as_the_world_takes_them(chat: Console) -> None:
    """``--duration S`` and ``sleep S`` both go through ddes.time.units (truncated to ns)."""
    from ddes.time.units import to_ns

    start = chat.world.now
    chat.run("rostopic echo --duration 1.2 /chatter")
    assert chat.world.now == start + to_ns(1.2)
    chat.run("sleep 1.2")
    assert chat.world.now == start + 2 * to_ns(1.2)


def test_echo_unknown_topic_is_an_error_without_duration(console: Console) -> None:
    result = console.execute("rostopic echo -n 1 /nope")
    assert result.code == 1
    assert result.err.startswith("ERROR: topic [/nope] does not appear to be published yet")
    result = console.execute("rostopic echo --duration 0.5 /nope")
    assert result.code == 0 and console.world.now == 500_000_000


def test_echo_in_the_background_and_kill(chat: Console) -> None:
    assert chat.run("rostopic echo /chatter &") == "[3] rostopic echo /chatter\n"
    out = chat.run("sleep 0.2")
    assert out == 'data: "hello world 0.1"\n---\ndata: "hello world 0.2"\n---\n'
    assert chat.run("jobs").splitlines()[-1] == \
        "[3]  Running                 rostopic echo /chatter &"
    assert chat.run("kill %3") == "[3]  Terminated              rostopic echo /chatter\n"
    assert chat.run("sleep 0.2") == ""


def test_echo_waits_at_most_the_default_limit(console: Console) -> None:
    console.run("rosrun --quiet rospy_tutorials listener &")
    result = console.execute("rostopic echo -n 1 /chatter")
    assert result.code == 1 and "still waiting for 1 messages after 600" in result.err
    assert console.world.now == 600_000_000_000


def test_hz_reports_once_per_simulated_second(chat: Console) -> None:
    out = chat.run("rostopic hz -n 2 /chatter")
    assert out == ("subscribed to [/chatter]\n"
                   "average rate: 10.000\n"
                   "\tmin: 0.100s max: 0.100s std dev: 0.00000s window: 10\n"
                   "average rate: 10.000\n"
                   "\tmin: 0.100s max: 0.100s std dev: 0.00000s window: 20\n")
    assert chat.world.now == 2_000_000_000


def test_hz_window_and_no_new_messages(chat: Console) -> None:
    out = chat.run("rostopic hz -w 3 --duration 1 /chatter")
    assert out.splitlines()[-1].endswith("window: 3")
    chat.run("rosnode kill /talker_1")
    out = chat.run("rostopic hz --duration 2 /chatter")
    assert out == "subscribed to [/chatter]\nno new messages\nno new messages\n"


def test_hz_several_topics_prints_a_table(chat: Console) -> None:
    chat.run("rostopic pub -r 5 /five std_msgs/Empty &")
    out = chat.run("rostopic hz -n 1 /chatter /five")
    lines = out.splitlines()
    assert lines[:2] == ["subscribed to [/chatter]", "subscribed to [/five]"]
    assert lines[2].split() == ["topic", "rate", "min_delta", "max_delta", "std_dev", "window"]
    assert set(lines[3]) == {"="}
    assert lines[4].split()[:2] == ["/chatter", "10.0"]
    assert lines[5].split()[:2] == ["/five", "5.0"]


def test_topic_hz_statistics() -> None:
    hz = TopicHz(-1)
    assert hz.get_hz() is None
    for t in (1.0, 1.1, 1.3, 1.4):
        hz.callback(t)
    rate, min_d, max_d, std, window = hz.get_hz()  # type: ignore[misc]
    assert window == 4 and round(rate, 6) == round(1 / ((0.1 + 0.2 + 0.1) / 3), 6)
    assert hz.get_hz() is None  # nothing new since the last report
    assert format_hz(None) == "no new messages"
    assert hz.callback(0.0) == "time has reset, resetting counters"


def test_pub_once_latches_for_three_seconds(console: Console) -> None:
    console.run("rostopic echo -n 1 --duration 5 /greet &")
    out = console.run("rostopic pub -1 /greet std_msgs/String 'data: hi'")
    assert out == ("publishing and latching message for 3.0 seconds\n"
                   'data: "hi"\n---\n')
    assert console.world.now == 3_000_000_000
    assert "/greet" not in console.run("rostopic list")


def test_pub_latched_until_killed(console: Console) -> None:
    out = console.run("rostopic pub /flag std_msgs/Bool true &")
    assert out == ("publishing and latching message. Press ctrl-C to terminate\n"
                   "[1] rostopic pub /flag std_msgs/Bool true\n")
    console.run("sleep 10")
    assert console.run("rostopic echo -n 1 /flag") == "data: True\n---\n"
    console.run("kill %1")
    assert console.run("rostopic list") == "/rosout\n/rosout_agg\n"


def test_pub_rate_with_count_and_verbose(console: Console) -> None:
    console.run("rostopic echo /count &")
    out = console.run("rostopic pub -v -r 10 -n 3 /count std_msgs/Int32 7")
    assert out.count("publishing data: 7") == 3
    assert console.world.now == 200_000_000
    assert console.run("sleep 0.1") == ""


def test_pub_substitutes_now(console: Console) -> None:
    console.run("sleep 2.5")
    console.run("rostopic pub /stamp std_msgs/Header '{stamp: now}' &")
    out = console.run("rostopic echo -n 1 /stamp/stamp")
    assert out == "\nsecs: 2\nnsecs: 500000000\n---\n"


@pytest.mark.parametrize("line, text", [
    ("rostopic pub /x std_msgs/Int32", "Please specify message values"),
    ("rostopic pub /x", "topic type must be specified"),
    ("rostopic pub -1 -r 3 /x std_msgs/Int32 1", "You cannot select both -r and -1"),
    ("rostopic pub -r 0 /x std_msgs/Int32 1", "rate must be greater than zero"),
    ("rostopic pub -1 /x std_msgs/NoSuch 1", "invalid message type: std_msgs/NoSuch"),
    ("rostopic pub -1 /x std_msgs/Int32 notanint", "One of the fields has an incorrect type"),
    ("rostopic pub -1 /x std_msgs/Int32 1 2", "Too many arguments"),
    ("rostopic pub /x std_msgs/Int32 1", "runs until Ctrl+C in ROS"),
    ("rostopic pub -n 2 /x std_msgs/Int32 1", "-n COUNT needs -r RATE"),
    ("rostopic delay /rosout", "rostopic delay is not offered by ddes"),
    ("rostopic frob", "unknown command 'rostopic frob'"),
    ("rostopic echo", "topic must be specified"),
    ("rostopic echo -n x /rosout", "COUNT must be an integer"),
    ("rostopic echo --duration soon /rosout", "--duration must be a number"),
    ("rostopic hz", "topic must be specified"),
])
def test_errors_are_one_line(console: Console, line: str, text: str) -> None:
    result = console.execute(line)
    assert result.code != 0
    assert text in result.err
    assert result.err.startswith("ERROR: ") and result.err.count("\n") == 1
    assert console.world.nodes.keys() == {"/rosout"}  # nothing left behind


def test_usage_and_help(console: Console) -> None:
    result = console.execute("rostopic")
    assert result.code == 64 and result.out.startswith("rostopic is a command-line tool")
    assert "\trostopic hz\tdisplay publishing rate of topic    \n" in result.out
    help_text = console.run("rostopic echo -h")
    assert help_text.startswith("Usage: rostopic echo [options] /topic")
    assert "--duration=SECONDS" in help_text


# -- against real rostopic (ROS 1 under the system Python) ------------------------------------

_MESSAGES: list[tuple[str, dict[str, Any]]] = [
    ("std_msgs/String", {"data": "hello world 1.5"}),
    ("geometry_msgs/PoseStamped", {"header": {"seq": 4, "stamp": {"secs": 3, "nsecs": 7},
                                              "frame_id": "map"},
                                   "pose": {"position": {"x": 1.5, "y": -2.0, "z": 0.0},
                                            "orientation": {"w": 1.0}}}),
    ("sensor_msgs/LaserScan", {"angle_min": -1.5, "ranges": [1.0, 2.5, 3.0],
                               "intensities": [], "header": {"frame_id": "laser"}}),
    ("rosgraph_msgs/Log", {"level": 4, "name": "/n", "msg": "two\nlines",
                           "topics": ["/a", "/b"]}),
    ("sensor_msgs/Image", {"height": 1, "width": 2, "encoding": "mono8",
                           "data": [3, 255]}),
]

_ROS_ECHO = r'''
import json, sys, genpy, roslib.message, rostopic
cases = json.loads(sys.stdin.read())
out = []
for type_name, hexdata, nostr, noarr in cases:
    cls = roslib.message.get_message_class(type_name)
    msg = cls().deserialize(bytes.fromhex(hexdata))
    echo = rostopic.CallbackEcho("/t", None)
    out.append(echo.custom_strify_message(
        msg, value_transform=rostopic.create_value_transform(nostr, noarr)))
print(json.dumps(out))
'''


@pytest.mark.ros
def test_echo_text_matches_rostopic(ros_python: Any) -> None:
    from ddes.msg import dict_to_message

    cases = []
    ours = []
    for type_name, data in _MESSAGES:
        msg = dict_to_message(get_message_class(type_name), data)
        for nostr, noarr in ((False, False), (True, False), (False, True), (True, True)):
            cases.append([type_name, serialize_message(msg).hex(), nostr, noarr])
            ours.append(strify_for_echo(msg, None, value_transform_factory(nostr, noarr)))
    theirs = json.loads(ros_python(_ROS_ECHO, stdin=json.dumps(cases)))
    assert ours == theirs


_ROS_INFO = r'''
import rostopic
print(json.dumps({
    "info": rostopic.get_info_text("/chatter"),
    "info_rosout": rostopic.get_info_text("/rosout"),
    "list": capture(rostopic._rostopic_list, None),
    "list_v": capture(rostopic._rostopic_list, None, verbose=True),
    "list_s": capture(rostopic._rostopic_list, None, subscribers_only=True),
    "find": capture(rostopic._rostopic_cmd_find, ["rostopic", "find", "rosgraph_msgs/Log"]),
}))
'''


@pytest.mark.ros
def test_graph_listings_match_rostopic(chat: Console, ros_python: Any) -> None:
    chat.run("sleep 0.5")
    theirs = json.loads(run_with_master(ros_python, chat.world, _ROS_INFO))
    assert chat.run("rostopic info /chatter") == theirs["info"] + "\n"
    assert chat.run("rostopic info /rosout") == theirs["info_rosout"] + "\n"
    assert chat.run("rostopic list") == theirs["list"]
    assert chat.run("rostopic list -v") == theirs["list_v"]
    assert chat.run("rostopic list -s") == theirs["list_s"]
    assert chat.run("rostopic find rosgraph_msgs/Log") == theirs["find"]


_ROS_HZ = r'''
import json, sys, rospy, rostopic
times = json.loads(sys.stdin.read())
hz = rostopic.ROSTopicHz(-1)
lines = []
import io, contextlib
for batch in times:
    for t in batch:
        rostopic.rospy.get_rostime = lambda t=t: rospy.Time.from_sec(t)
        hz.callback_hz(None)
    buf = io.StringIO()
    with contextlib.redirect_stdout(buf):
        hz.print_hz()
    lines.append(buf.getvalue())
print(json.dumps(lines))
'''


@pytest.mark.ros
def test_hz_statistics_match_rostopic(ros_python: Any) -> None:
    import random

    rng = random.Random(5)
    batches = []
    t = 10.0
    for _ in range(4):
        batch = []
        for _ in range(rng.randint(0, 12)):
            t += rng.uniform(0.01, 0.3)
            batch.append(round(t, 9))
        batches.append(batch)
    ours = []
    hz = TopicHz(-1)
    for batch in batches:
        for t in batch:
            hz.callback(t)
        ours.append(format_hz(hz.get_hz()) + "\n")
    assert ours == json.loads(ros_python(_ROS_HZ, stdin=json.dumps(batches)))
