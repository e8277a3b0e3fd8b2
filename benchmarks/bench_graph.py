"""Topic delivery throughput (1→1 and 1→4) against raw SimPy callback delivery.

The baseline is what a hand-written SimPy model does: per message and
subscriber, one event scheduled with one callback appended to it.
ddes does per message: build + serialize the message, trace the publish,
schedule one arrival per connection, deserialize per subscriber, queue
through the node's spinner, trace the delivery, call the callback.
"""

from __future__ import annotations

import sys
from pathlib import Path
from typing import Any

import simpy

sys.path.insert(0, str(Path(__file__).resolve().parent))

from common import compare, row  # noqa: E402

import ddes  # noqa: E402
from ddes.msg import get_message_class  # noqa: E402

N = 20_000
String = get_message_class("std_msgs/String")


def raw(n_subs: int) -> Any:
    def run() -> int:
        env = simpy.Environment()
        got = [0]

        def cb(ev: Any) -> None:
            got[0] += 1

        def pub() -> Any:
            for _i in range(N):
                for _ in range(n_subs):
                    env.timeout(0, "hello").callbacks.append(cb)
                yield env.timeout(1000)

        env.process(pub())
        env.run()
        return got[0]

    return run


def ddes_delivery(n_subs: int) -> Any:
    def run() -> int:
        world = ddes.World()
        talker = world.create_node("talker", disable_rosout=True)
        pub = talker.advertise("chatter", String, queue_size=10)
        got = [0]

        def cb(msg: Any) -> None:
            got[0] += 1

        for i in range(n_subs):
            world.create_node(f"listener{i}", disable_rosout=True).subscribe("chatter", String, cb,
                                                                              queue_size=10)
        world.run(until=0.01)  # let connections form
        msg = String(data="hello")

        def loop() -> Any:
            for _ in range(N):
                pub.publish(msg)
                yield world.env.timeout(1000)

        talker.process(loop())
        world.run()
        return got[0]

    return run


def benchmarks() -> list[dict[str, Any]]:
    out = []
    for n in (1, 4):
        value, base = compare(ddes_delivery(n), raw(n), repeat=5)
        out.append(row(f"topic_delivery_1to{n}", value, "deliveries/s", base,
                       "simpy event + callback per message", n=N, subscribers=n))
    return out
