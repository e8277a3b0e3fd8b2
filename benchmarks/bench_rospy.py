"""Plain rospy code on greenlets (ddes.compat.rospy) against the same work in the yield style.

Each row's ``value`` is the blocking (greenlet) style's rate, its ``baseline`` the yield style's,
so ``ratio`` is the blocking style's share of the yield style's speed (issue 16: ≈ 0.5 expected for
a bare Rate loop, a greenlet switch pair per tick; ≥ 0.7 the goal for talker/listener and
add_two_ints).  Rates are CPU time (``time.process_time``), not wall time: the machine is shared,
and another process's burst then slows neither side.  The two styles run interleaved ``REPEAT`` times
(``common.compare``); the row gives the medians and the ratio's spread.
"""

from __future__ import annotations

import sys
from pathlib import Path
from typing import Any

sys.path.insert(0, str(Path(__file__).resolve().parent))

from common import compare, result, size  # noqa: E402

import ddes  # noqa: E402
from ddes.compat import rospy  # noqa: E402
from ddes.graph.blocking import spawn  # noqa: E402

N = size(20_000)
HZ = 1000
REPEAT = 9
String = ddes.get_message_class("std_msgs/String")
AddTwoInts = ddes.get_service_class("rospy_tutorials/AddTwoInts")


def _world() -> ddes.World:
    world = ddes.World()
    world.log_output = False
    return world


# -- a bare Rate loop -------------------------------------------------------------------------
def yield_rate() -> int:
    world = _world()
    node = world.create_node("bench")
    rate = ddes.Rate(node, HZ)

    def loop() -> Any:
        for _ in range(N):
            yield rate.sleep()

    node.process(loop())
    world.run()
    return N


def green_rate() -> int:
    world = _world()

    def main() -> None:
        rospy.init_node("bench")
        rate = rospy.Rate(HZ)
        for _ in range(N):
            rate.sleep()

    spawn(world, main)
    world.run()
    return N


# -- talker / listener --------------------------------------------------------------------------
def yield_chatter() -> int:
    world = _world()
    talker = world.create_node("talker")
    listener = world.create_node("listener")
    heard = [0]
    pub = ddes.Publisher(talker, "chatter", String, queue_size=10)
    ddes.Subscriber(listener, "chatter", String, lambda m: heard.__setitem__(0, heard[0] + 1))

    def talk() -> Any:
        rate = ddes.Rate(talker, HZ)
        for i in range(N):
            pub.publish(String(data=f"hello {i}"))
            yield rate.sleep()

    talker.process(talk())
    world.run()
    return heard[0]


def green_chatter() -> int:
    world = _world()
    heard = [0]

    def talker() -> None:
        pub = rospy.Publisher("chatter", String, queue_size=10)
        rospy.init_node("talker")
        rate = rospy.Rate(HZ)
        for i in range(N):
            pub.publish(String(data=f"hello {i}"))
            rate.sleep()

    def listener() -> None:
        rospy.init_node("listener")
        rospy.Subscriber("chatter", String, lambda m: heard.__setitem__(0, heard[0] + 1))
        rospy.spin()

    spawn(world, listener)
    spawn(world, talker)
    world.run(until=(N + 10) / HZ)
    return heard[0]


# -- add_two_ints --------------------------------------------------------------------------------
def yield_add() -> int:
    world = _world()
    ddes.Service(world.create_node("server"), "add_two_ints", AddTwoInts,
                 lambda req: req.a + req.b)
    client = world.create_node("client")
    done = [0]

    def main() -> Any:
        yield ddes.wait_for_service(client, "add_two_ints")
        add = ddes.ServiceProxy(client, "add_two_ints", AddTwoInts)
        for i in range(N):
            resp = yield add(i, 1)
            done[0] += resp.sum == i + 1

    client.process(main())
    world.run()
    return done[0]


def green_add() -> int:
    world = _world()
    done = [0]

    def server() -> None:
        rospy.init_node("server")
        rospy.Service("add_two_ints", AddTwoInts, lambda req: req.a + req.b)
        rospy.spin()

    def client() -> None:
        rospy.init_node("client")
        rospy.wait_for_service("add_two_ints")
        add = rospy.ServiceProxy("add_two_ints", AddTwoInts)
        for i in range(N):
            done[0] += add(i, 1).sum == i + 1
        rospy.signal_shutdown("done")

    spawn(world, server)
    spawn(world, client)
    world.run(until=100.0)
    return done[0]


def benchmarks() -> list[dict[str, Any]]:
    out = []
    for name, unit, green, plain in (
            ("rospy_rate_loop", "ticks/s", green_rate, yield_rate),
            ("rospy_talker_listener", "messages/s", green_chatter, yield_chatter),
            ("rospy_add_two_ints", "calls/s", green_add, yield_add)):
        c = compare(green, plain, repeat=REPEAT)
        out.append(result(name, c, unit, "the same work in the yield style", n=N,
                          clock="process_time"))
    return out


if __name__ == "__main__":
    import json

    for r in benchmarks():
        print(json.dumps(r))
