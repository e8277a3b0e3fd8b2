"""Topic delivery throughput (1→1 and 1→4) against raw SimPy callback delivery.

The raw baseline is what a hand-written SimPy model does: per message and
subscriber, one event scheduled with one callback appended to it.  The fair
baseline adds exactly the work ROS semantics require: serialize the message
once, one ``topic.publish`` trace row, and per subscriber deserialize it and
one ``topic.deliver`` trace row (through the same fast paths ddes uses:
``msg._serialize_to_bytes()``, ``cls.__new__(cls)._deserialize_from(data)``
and ``Trace.append_row``).
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

from common import compare, repeats, result, size  # noqa: E402

import ddes  # noqa: E402
from ddes.kernel.trace import Trace  # noqa: E402
from ddes.msg import get_message_class  # noqa: E402

N = size(20_000)
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


def fair(n_subs: int) -> Any:
    def run() -> int:
        env = simpy.Environment()
        trace = Trace()
        append = trace.append_row
        got = [0]
        pub_keys, deliver_keys = ("topic", "seq", "connections", "data"), ("topic", "publisher", "seq")

        def cb(ev: Any) -> None:
            data, seq = ev.value
            String.__new__(String)._deserialize_from(data)
            append((env.now, "topic.deliver", "/listener", deliver_keys, "/chatter", "/talker", seq))
            got[0] += 1

        def pub() -> Any:
            msg = String(data="hello")
            for i in range(N):
                data = msg._serialize_to_bytes()
                append((env.now, "topic.publish", "/talker", pub_keys, "/chatter", i, n_subs, data))
                for _ in range(n_subs):
                    env.timeout(0, (data, i)).callbacks.append(cb)
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
        c = compare(ddes_delivery(n), raw(n), repeat=repeats(7), fair_fn=fair(n))
        out.append(result(f"topic_delivery_1to{n}", c, "deliveries/s",
                          "simpy event + callback per message",
                          "+ serialize, deserialize per subscriber, publish and deliver trace rows",
                          n=N, subscribers=n))
    return out
