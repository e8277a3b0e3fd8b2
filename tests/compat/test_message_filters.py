"""ddes.compat.message_filters: rospy's message_filters in scripts, and against Noetic's."""

from __future__ import annotations

import json
import textwrap
from pathlib import Path
from typing import Any

import pytest
from hypothesis import given
from hypothesis import strategies as st

import ddes
from ddes.compat import message_filters as mf
from ddes.compat import rospy
from ddes.compat.scripts import run_script
from ddes.graph.blocking import spawn

PointStamped = ddes.msg.get_message_class("geometry_msgs/PointStamped")


def _run(tmp_path: Path, body: str, until: float = 2.0,
         world: ddes.World | None = None) -> list[str]:
    path = tmp_path / "node.py"
    path.write_text(textwrap.dedent(body))
    out: list[str] = []
    world = world or ddes.World(seed=11)
    done, _ = run_script(world, path, print_line=lambda text, _err: out.append(text))
    world.run(until=until)
    assert done.triggered and done.ok and done.value == 0
    return out


def _in_node(fn: Any) -> Any:
    """``fn()`` run inside a rospy node of a fresh world (rospy.Time.now() needs one)."""
    world = ddes.World(seed=2)

    def main() -> Any:
        rospy.init_node("filters")
        return fn()

    done = spawn(world, main)
    world.run(until=0.1)
    assert done.ok
    return done.value


def _msg(secs: int, nsecs: int, tag: float) -> Any:
    m = PointStamped()
    m.header.stamp = ddes.Time(secs, nsecs)
    m.point.x = tag
    return m


def test_a_script_synchronises_two_topics_exactly(tmp_path: Path) -> None:
    out = _run(tmp_path, """
        import rospy
        import message_filters
        from geometry_msgs.msg import PointStamped

        rospy.init_node("sync")
        left = message_filters.Subscriber("left", PointStamped)
        right = message_filters.Subscriber("right", PointStamped, queue_size=5)
        cache = message_filters.Cache(left, 3)
        ts = message_filters.TimeSynchronizer([left, right], 10)

        def both(a, b, tag):
            print("pair %s %.0f %.0f %s" % (a.header.stamp, a.point.x, b.point.x, tag))

        print(ts.registerCallback(both, "x"), left.getTopic(), right.sub.resolved_name,
              left.resolved_name)
        pl = rospy.Publisher("left", PointStamped, queue_size=10)
        pr = rospy.Publisher("right", PointStamped, queue_size=10)
        rospy.sleep(0.1)
        for i in range(5):
            m = PointStamped()
            m.header.stamp = rospy.Time(1, i * 10)
            m.point.x = i
            pl.publish(m)
            if i % 2 == 0:
                m2 = PointStamped()
                m2.header.stamp = m.header.stamp
                m2.point.x = 100 + i
                pr.publish(m2)
            rospy.sleep(0.1)
        print("cache", [m.point.x for m in cache.cache_msgs], cache.getLastestTime(),
              cache.getOldestTime(), cache.getLast().point.x)
        left.unregister()
        pl.publish(PointStamped())
        rospy.sleep(0.1)
        print("after", len(cache.cache_msgs), cache.getLast().point.x)
    """)
    assert out == [
        "0 left /right /left",
        "pair 1000000000 0 100 x",
        "pair 1000000020 2 102 x",
        "pair 1000000040 4 104 x",
        "cache [2.0, 3.0, 4.0] 1000000040 1000000020 4.0",
        "after 3 4.0",
    ]


def test_a_script_synchronises_approximately_and_warns_about_headerless(tmp_path: Path) -> None:
    lines: list[str] = []
    world = ddes.World(seed=11)
    world.log_output = lambda line, _level: lines.append(line)
    out = _run(tmp_path, """
        import rospy
        import message_filters
        from geometry_msgs.msg import PointStamped
        from std_msgs.msg import String

        rospy.init_node("approx")
        a = message_filters.SimpleFilter()
        b = message_filters.SimpleFilter()
        ats = message_filters.ApproximateTimeSynchronizer([a, b], 5, 0.05)
        ats.registerCallback(lambda x, y: print("pair", x.point.x, y.point.x))

        def stamped(t, tag):
            m = PointStamped()
            m.header.stamp = rospy.Time.from_sec(t)
            m.point.x = tag
            return m

        a.signalMessage(stamped(1.00, 1))
        b.signalMessage(stamped(1.03, 2))
        b.signalMessage(stamped(1.20, 3))
        a.signalMessage(stamped(1.26, 4))
        a.signalMessage(stamped(1.19, 5))
        a.signalMessage(String("no header"))
        cache = message_filters.Cache(message_filters.SimpleFilter(), 2, allow_headerless=True)
        rospy.sleep(0.25)
        cache.add(String("late"))
        print("cache", cache.getLatestTime(), cache.getLast().data)
    """, world=world)
    assert out == ["pair 1 2", "pair 5 3", "cache 250000000 late"]
    assert lines == ["[WARN] [0.000000]: Cannot use message filters with non-stamped messages. "
                     "Use the 'allow_headerless' constructor option to auto-assign ROS time to "
                     "headerless messages."]


def test_signal_message_calls_callbacks_in_registration_order_with_their_args() -> None:
    f = mf.SimpleFilter()
    calls: list[tuple[Any, ...]] = []
    assert f.registerCallback(lambda *a: calls.append(("first", *a)), 1) == 0
    assert f.registerCallback(lambda *a: calls.append(("second", *a))) == 1
    f.signalMessage("m", "n")
    assert calls == [("first", "m", "n", 1), ("second", "m", "n")]


def test_cache_queries() -> None:
    def body() -> list[Any]:
        source = mf.SimpleFilter()
        cache = mf.Cache(source, cache_size=3)
        seen: list[float] = []
        cache.registerCallback(lambda m: seen.append(m.point.x))
        for secs, tag in [(5, 1.0), (3, 2.0), (7, 3.0), (9, 4.0)]:
            source.signalMessage(_msg(secs, 0, tag))
        t = ddes.Time
        return [seen, [m.point.x for m in cache.getInterval(t(3), t(7))],
                cache.getElemAfterTime(t(4)).point.x, cache.getElemBeforeTime(t(8)).point.x,
                cache.getElemAfterTime(t(10)), cache.getElemBeforeTime(t(2)),
                cache.getOldestTime(), cache.getLatestTime(), cache.getLast().point.x]

    assert _in_node(body) == [[1.0, 2.0, 3.0, 4.0], [2.0, 3.0], 3.0, 3.0, None, None,
                              ddes.Time(3), ddes.Time(9), 4.0]
    empty = mf.Cache(mf.SimpleFilter())
    assert (empty.getLast(), empty.getLastestTime(), empty.getOldestTime()) == (None, None, None)


@given(st.lists(st.tuples(st.integers(0, 2), st.integers(0, 8)), max_size=40),
       st.sampled_from([1, 2, 4, 40]))
def test_time_synchronizer_never_pairs_different_stamps(feed: list[tuple[int, int]],
                                                        queue_size: int) -> None:
    def body() -> list[tuple[Any, ...]]:
        inputs = [mf.SimpleFilter() for _ in range(3)]
        ts = mf.TimeSynchronizer(inputs, queue_size)
        sets: list[tuple[Any, ...]] = []
        ts.registerCallback(lambda *msgs: sets.append(msgs))
        for n, (which, stamp) in enumerate(feed):
            inputs[which].signalMessage(_msg(stamp, 0, float(n)))
            assert all(len(q) <= queue_size for q in ts.queues)
        return sets

    sets = _in_node(body)
    for msgs in sets:
        assert len(msgs) == 3
        assert len({m.header.stamp for m in msgs}) == 1
    # each message is used at most once, in the place of the input it came in on
    tags = [int(m.point.x) for msgs in sets for m in msgs]
    assert len(tags) == len(set(tags))
    for msgs in sets:
        assert [feed[int(m.point.x)][0] for m in msgs] == [0, 1, 2]
    if queue_size >= len(feed):  # nothing dropped: every stamp all three inputs got is a set
        everywhere = set.intersection(*[{t for w, t in feed if w == i} for i in range(3)])
        assert {msgs[0].header.stamp.secs for msgs in sets} == everywhere


@given(st.lists(st.tuples(st.integers(0, 1), st.integers(0, 40)), max_size=30),
       st.sampled_from([0.05, 0.1, 0.3]))
def test_approximate_sets_span_less_than_the_slop(feed: list[tuple[int, int]],
                                                  slop: float) -> None:
    def body() -> list[tuple[Any, ...]]:
        inputs = [mf.SimpleFilter(), mf.SimpleFilter()]
        ats = mf.ApproximateTimeSynchronizer(inputs, 4, slop)
        sets: list[tuple[Any, ...]] = []
        ats.registerCallback(lambda *msgs: sets.append(msgs))
        for n, (which, tenths) in enumerate(feed):
            inputs[which].signalMessage(_msg(tenths // 10, (tenths % 10) * 10**8, float(n)))
        return sets

    for a, b in _in_node(body):
        assert abs(a.header.stamp - b.header.stamp) < ddes.Duration.from_sec(slop)


# One fixed sequence fed to this module (in a script) and to Noetic's (with rospy's time
# initialised, no master): which sets each filter signals, in order.
_REFERENCE = r"""
import json
import message_filters as mf
import rospy
from geometry_msgs.msg import PointStamped

def msg(secs, nsecs, tag):
    m = PointStamped()
    m.header.stamp = rospy.Time(secs, nsecs)
    m.point.x = tag
    return m

FEED = [(0, 1, 0), (1, 1, 0), (2, 1, 5), (0, 2, 0), (1, 2, 1), (0, 3, 0), (2, 3, 0),
        (1, 3, 0), (2, 2, 0), (0, 4, 0), (0, 5, 0), (0, 6, 0), (0, 7, 0), (1, 5, 0),
        (2, 5, 0), (1, 9, 0), (2, 9, 0), (0, 9, 0), (1, 1, 0), (2, 1, 0), (0, 1, 0),
        (0, 10, 0), (0, 10, 3), (1, 10, 500000000), (2, 10, 8), (1, 11, 0), (0, 11, 40000000),
        (2, 11, 20000000), (2, 11, 30000000), (1, 12, 0), (1, 12, 900000000), (0, 12, 950000000),
        (2, 13, 0), (0, 13, 10000000), (1, 12, 990000000), (0, 14, 0), (2, 14, 0), (1, 14, 0)]
out = {}
for name, make, n in [("exact2", lambda fs: mf.TimeSynchronizer(fs, 3), 2),
                      ("exact3", lambda fs: mf.TimeSynchronizer(fs, 2), 3),
                      ("approx2", lambda fs: mf.ApproximateTimeSynchronizer(fs, 3, 0.1), 2),
                      ("approx3", lambda fs: mf.ApproximateTimeSynchronizer(fs, 4, 0.05), 3),
                      ("approx3_wide", lambda fs: mf.ApproximateTimeSynchronizer(fs, 10, 1.5), 3)]:
    inputs = [mf.SimpleFilter() for _ in range(n)]
    sync = make(inputs)
    sets = []
    sync.registerCallback(lambda *ms: sets.append([[m.header.stamp.secs, m.header.stamp.nsecs,
                                                    m.point.x] for m in ms]))
    for tag, (which, secs, nsecs) in enumerate(FEED):
        if which < n:
            inputs[which].signalMessage(msg(secs, nsecs, tag))
    out[name] = sets
    out[name + "_left"] = [sorted([t.secs, t.nsecs] for t in q) for q in sync.queues]
src = mf.SimpleFilter()
cache = mf.Cache(src, 4)
for tag, (which, secs, nsecs) in enumerate(FEED[:12]):
    src.signalMessage(msg(secs, nsecs, tag))
T = rospy.Time
out["cache"] = [[m.point.x for m in cache.cache_msgs],
                [m.point.x for m in cache.getInterval(T(2), T(6))],
                cache.getElemAfterTime(T(3)).point.x, cache.getElemBeforeTime(T(5)).point.x,
                cache.getElemAfterTime(T(100)), cache.getElemBeforeTime(T(1)),
                str(cache.getOldestTime()), str(cache.getLastestTime()), cache.getLast().point.x]
print(json.dumps(out))
"""


@pytest.mark.ros
def test_pairing_matches_noetic(ros_python, tmp_path: Path) -> None:
    expected = ros_python("import rospy.rostime\nrospy.rostime.set_rostime_initialized(True)\n"
                          + _REFERENCE, as_json=True)
    out = _run(tmp_path, "import rospy\nrospy.init_node('mf')\n" + _REFERENCE)
    got = json.loads(out[0])
    assert all(expected[k] for k in ("exact2", "exact3", "approx2", "approx3", "approx3_wide"))
    assert got.keys() == expected.keys()
    for key in expected:
        assert got[key] == expected[key], key
