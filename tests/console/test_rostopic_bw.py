"""``rostopic bw``: serialized bytes per second over a window, as rostopic prints them."""

from __future__ import annotations

import json
from typing import Any

import pytest
from hypothesis import given
from hypothesis import strategies as st

from ddes.console.rostopic_bw import DEFAULT_WINDOW, TopicBandwidth, format_bw
from ddes.console.shell import Console
from ddes.msg import get_message_class, serialize_message

SESSION = """\
rostopic pub -r 10 /chatter std_msgs/String "data: hello" &
rostopic bw -n 2 /chatter
rostopic bw -w 5 --duration 1 /chatter
rostopic bw /chatter &
sleep 2
kill %2
rostopic bw --duration 0.5 /nope
time
"""

TRANSCRIPT = """\
$ rostopic pub -r 10 /chatter std_msgs/String "data: hello" &
[1] rostopic pub -r 10 /chatter std_msgs/String 'data: hello'
$ rostopic bw -n 2 /chatter
subscribed to [/chatter]
average: 100.00B/s
\tmean: 9.00B min: 9.00B max: 9.00B window: 10
average: 94.74B/s
\tmean: 9.00B min: 9.00B max: 9.00B window: 20
$ rostopic bw -w 5 --duration 1 /chatter
subscribed to [/chatter]
average: 112.50B/s
\tmean: 9.00B min: 9.00B max: 9.00B window: 5
$ rostopic bw /chatter &
subscribed to [/chatter]
[2] rostopic bw /chatter
$ sleep 2
average: 100.00B/s
\tmean: 9.00B min: 9.00B max: 9.00B window: 10
average: 94.74B/s
\tmean: 9.00B min: 9.00B max: 9.00B window: 20
$ kill %2
[2]  Terminated              rostopic bw /chatter
$ rostopic bw --duration 0.5 /nope
WARNING: topic [/nope] does not appear to be published yet
$ time
simulated time: 5.500000000 s
"""


def test_transcript() -> None:
    # a 9-byte message (4-byte length + "hello") at 10 Hz: the first report has 10 messages
    # over the 0.9 s since the first one, 90 / 0.9 = 100 B/s
    code, text = Console(seed=0).transcript(SESSION.splitlines())
    assert (code, text) == (0, TRANSCRIPT)


def test_counts_serialized_bytes(console: Console) -> None:
    console.run("rostopic pub -r 5 /p geometry_msgs/Point '{x: 1, y: 2, z: 3}' &")
    out = console.run("rostopic bw -n 1 /p")
    assert out.splitlines()[2] == "\tmean: 24.00B min: 24.00B max: 24.00B window: 5"


def test_rosout_in_kilobytes(console: Console) -> None:
    console.run("rosrun --quiet rospy_tutorials talker &")
    lines = console.run("rostopic bw -n 1 /rosout").splitlines()
    assert lines[1].startswith("average: ") and lines[1].endswith("KB/s")
    assert lines[2].startswith("\tmean: 0.") and "KB min: 0." in lines[2]


@pytest.mark.parametrize("line, text", [
    ("rostopic bw", "topic must be specified (usage: rostopic bw /topic)"),
    ("rostopic bw /a /b", "you may only specify one input topic"),
    ("rostopic bw -w x /rosout", "window size must be an integer"),
    ("rostopic bw /rosout", "'rostopic bw' runs until Ctrl+C in ROS"),
    ("rostopic bw -n 0 /rosout", "COUNT must be at least 1"),
])
def test_errors_are_one_line(console: Console, line: str, text: str) -> None:
    result = console.execute(line)
    assert result.code == 1
    assert result.err.startswith("ERROR: ") and text in result.err
    assert result.err.count("\n") == 1


def test_window_and_units() -> None:
    bw = TopicBandwidth(None)
    assert bw.window_size == DEFAULT_WINDOW == TopicBandwidth(0).window_size
    assert bw.get_bw(1.0) is None
    bw.callback(1.0, 10)
    assert bw.get_bw(2.0) is None  # fewer than two messages: rostopic prints nothing
    bw.callback(1.5, 30)
    assert bw.get_bw(1.0) is None  # no time spanned: nothing (rostopic would divide by zero)
    assert bw.get_bw(3.0) == (20.0, 20.0, 10, 30, 2)
    assert format_bw((20.0, 20.0, 10, 30, 2)) == \
        "average: 20.00B/s\n\tmean: 20.00B min: 10.00B max: 30.00B window: 2"
    assert format_bw((1000.0, 512.5, 100, 1000, 3)) == \
        "average: 1.00KB/s\n\tmean: 0.51KB min: 0.10KB max: 1.00KB window: 3"
    assert format_bw((2.5e6, 1e6, 999, 2e6, 4)) == \
        "average: 2.50MB/s\n\tmean: 1.00MB min: 0.00MB max: 2.00MB window: 4"
    never = TopicBandwidth(-3)  # a negative window keeps nothing, as in rostopic
    never.callback(1.0, 5)
    never.callback(2.0, 5)
    assert never.get_bw(3.0) is None


@given(st.integers(1, 6), st.lists(st.integers(0, 3000), min_size=1, max_size=30))
def test_window_keeps_the_last_messages(window: int, sizes: list[int]) -> None:
    bw = TopicBandwidth(window)
    for i, size in enumerate(sizes):
        bw.callback(float(i), size)
    assert bw.sizes == sizes[-window:]
    assert bw.times == [float(i) for i in range(len(sizes))][-window:]


# -- real rostopic -----------------------------------------------------------------------------------

_ROS_BW = r'''
import contextlib, io, json, sys
import rostopic
cases = json.loads(sys.stdin.read())
out = []
for window, batches in cases:
    bw = rostopic.ROSTopicBandwidth(window)
    texts = []
    for arrivals, report_at in batches:
        for t, hexdata in arrivals:
            rostopic.time.time = lambda t=t: t
            msg = type("AnyMsg", (), {})()
            msg._buff = bytes.fromhex(hexdata)
            bw.callback(msg)
        rostopic.time.time = lambda t=report_at: t
        buf = io.StringIO()
        with contextlib.redirect_stdout(buf):
            bw.print_bw()
        texts.append(buf.getvalue())
    out.append(texts)
print(json.dumps(out))
'''


@pytest.mark.ros
def test_reports_match_rostopic(ros_python: Any) -> None:
    import random

    String = get_message_class("std_msgs/String")
    rng = random.Random(14)
    cases = []
    ours = []
    for window in (None, 0, 3, 100, -2):
        batches = []
        texts = []
        bw = TopicBandwidth(window)
        t = 1700000000.0
        for _ in range(5):
            arrivals = []
            for _ in range(rng.randint(0, 40)):
                t += rng.uniform(0.0001, 0.2)
                data = serialize_message(String(data="x" * rng.choice([0, 5, 700, 90000])))
                arrivals.append([t, data.hex()])
                bw.callback(t, len(data))
            t += rng.uniform(0.0, 0.3)
            batches.append([arrivals, t])
            report = bw.get_bw(t)
            texts.append("" if report is None else format_bw(report) + "\n")
        cases.append([window, batches])
        ours.append(texts)
    assert ours == json.loads(ros_python(_ROS_BW, stdin=json.dumps(cases)))


@pytest.mark.ros
def test_a_console_run_reads_as_rostopic(console: Console, ros_python: Any) -> None:
    """The bytes and times a console run counts, fed to rostopic's own class, print the same."""
    from ddes.msg.anymsg import AnyMsg

    console.run("rostopic pub -r 7 /c std_msgs/String 'data: some text' &")
    seen: list[list[Any]] = []
    world = console.world
    node = world.create_node("probe")
    node.subscribe("/c", AnyMsg, lambda m: seen.append([world.now / 1e9, m._buff.hex()]))
    out = console.run("rostopic bw -n 3 /c")
    reports = out.splitlines()[1:]
    assert len(reports) == 6
    # the reports fall on whole seconds after the command; the probe saw what bw saw
    starts = [world.now / 1e9 - 3 + k for k in (1, 2, 3)]
    batches = [[[a for a in seen if (starts[k - 1] if k else 0) < a[0] <= starts[k]], starts[k]]
               for k in range(3)]
    theirs = json.loads(ros_python(_ROS_BW, stdin=json.dumps([[None, batches]])))[0]
    assert "".join(theirs) == out.split("\n", 1)[1]
