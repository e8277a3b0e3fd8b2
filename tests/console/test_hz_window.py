"""``rostopic hz``'s windows as rostopic counts them (issue 14, item 4).

rostopic subscribes, prints ``subscribed to [/chatter]``, then sleeps one second and reports,
again and again.  The first message after the subscription starts the clock (it is not an
interval), each later one adds an interval, and the window is intervals + 1.  A 10 Hz talker
gives ``window: 10``, ``20``, ``30`` (recorded from Noetic: ``rostopic hz /chatter`` against
``rospy_tutorials``' talker).  In ddes the talker publishes exactly one second after the
subscription; that message is in the report, as in ROS where the sleep starts after the
subscribe call returns.
"""

from __future__ import annotations

import json
from collections.abc import Callable
from typing import Any

import pytest

from ddes.console.rostopic_live import TopicHz, format_hz, format_hz_table
from ddes.console.shell import Console
from ddes.time.rostime import Time

TEN_HZ = ("average rate: 10.000\n"
          "\tmin: 0.100s max: 0.100s std dev: 0.00000s window: {}\n")


@pytest.mark.parametrize("wait", ["0", "0.3", "0.35", "1"])
def test_a_10hz_topic_reports_windows_10_20_30(wait: str) -> None:
    console = Console(seed=0, out=lambda _line: None)
    console.run("rosrun --quiet rospy_tutorials talker &")
    console.run(f"sleep {wait}")
    out = console.run("rostopic hz -n 3 /chatter")
    assert out == "subscribed to [/chatter]\n" + "".join(TEN_HZ.format(w) for w in (10, 20, 30))
    assert console.world.now == round((float(wait) + 3) * 1e9)  # the run ends with the report


def test_duration_includes_its_last_instant() -> None:
    console = Console(seed=0, out=lambda _line: None)
    console.run("rosrun --quiet roscpp_tutorials talker &")
    out = console.run("rostopic hz --duration 2 /chatter")
    assert out == "subscribed to [/chatter]\n" + TEN_HZ.format(10) + TEN_HZ.format(20)
    assert console.world.now == 2_000_000_000
    assert console.run("rostopic hz --duration 0.5 /chatter") == "subscribed to [/chatter]\n"
    assert console.world.now == 2_500_000_000


def test_two_background_hz_report_in_the_same_instant() -> None:
    console = Console(seed=0, out=lambda _line: None)
    console.run("rosrun --quiet rospy_tutorials talker &")
    console.run("rostopic hz /chatter &")
    console.run("rostopic hz /chatter &")
    out = console.run("sleep 1")
    assert out == 2 * TEN_HZ.format(10)


def test_several_topics_print_rostopics_table() -> None:
    console = Console(seed=0, out=lambda _line: None)
    console.run("rosrun --quiet rospy_tutorials talker &")
    console.run("rostopic pub -r 5 /five std_msgs/Empty &")
    out = console.run("rostopic hz -n 1 /chatter /five")
    # rostopic appends each window twice: the /five row shows /chatter's window, as it prints
    # (the float noise of the std dev is rostopic's too: see the test against real rostopic)
    assert out == ("subscribed to [/chatter]\nsubscribed to [/five]\n"
                   " topic     rate   min_delta   max_delta    std_dev    window\n"
                   "============================================================\n"
                   "/chatter   10.0   0.1         0.1         3.701e-17   10    \n"
                   "/five      5.0    0.2         0.2         4.807e-17   10    \n\n")


def test_topic_hz_counts_the_first_message_as_the_start() -> None:
    hz = TopicHz(-1)
    assert hz.get_hz() is None
    hz.callback(0.4)
    assert hz.get_hz() is None  # one message: no interval yet
    for k in range(5, 14):
        hz.callback(k / 10)
    stats = hz.get_hz()
    assert stats is not None and stats[4] == 10
    assert hz.get_hz() is None  # nothing new since
    assert format_hz(None) == "no new messages"


ROSTOPIC_HZ = r'''
import contextlib, io, json, sys
import rospy
import rostopic
calls = json.loads(sys.stdin.read())
out = []
for topics, arrivals in calls:
    now = [0.0]
    rospy.get_rostime = lambda: rospy.Time.from_sec(now[0])
    rt = rostopic.ROSTopicHz(-1)
    for t, topic in arrivals:
        now[0] = t
        rt.callback_hz(None, topic)
    buf = io.StringIO()
    with contextlib.redirect_stdout(buf):
        rt.print_hz(topics)
        rt.print_hz(topics)
    out.append(buf.getvalue())
print(json.dumps(out))
'''


@pytest.mark.ros
def test_reports_match_rostopics_print_hz(ros_python: Callable[..., Any]) -> None:
    """Real rostopic's ROSTopicHz fed the arrivals ddes sees prints what ddes prints."""
    ten = [(0.4 + k / 10, "/chatter") for k in range(10)]
    five = [(0.5 + k / 5, "/five") for k in range(5)]
    calls = [[["/chatter"], ten], [["/chatter", "/five"], sorted(ten + five)],
             [["/chatter", "/five"], ten[:1] + five], [["/chatter"], ten[:1]]]
    real = ros_python(ROSTOPIC_HZ, stdin=json.dumps(calls), as_json=True)
    ours = []
    for topics, arrivals in calls:
        stats = {t: TopicHz(-1) for t in topics}
        for t, topic in arrivals:
            stats[topic].callback(Time.from_sec(t).to_sec())  # what get_rostime().to_sec() gives
        lines = []
        for _ in range(2):
            if len(topics) == 1:
                lines.append(format_hz(stats[topics[0]].get_hz()) + "\n")
            else:
                lines.append(format_hz_table([(t, stats[t].get_hz()) for t in topics]) + "\n")
        ours.append("".join(lines))
    assert ours == real
