"""The one callback runner: every callback kind follows the node's spinner policy."""

from __future__ import annotations

from collections.abc import Generator
from typing import Any

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import ddes
from ddes.errors import DdesValueError
from ddes.graph.callbacks import CallbackQueue, parse_policy
from ddes.msg import get_message_class, get_service_class

String = get_message_class("std_msgs/String")
Empty = get_service_class("std_srvs/Empty")
MS = 1_000_000


def _probe(oneshot: bool, generator_sub: bool) -> list[str]:
    """A 1 Hz timer whose callback takes 0.5 s; a message arrives at 1.2 s."""
    world = ddes.World()
    node = world.create_node("probe")
    other = world.create_node("other")
    pub = ddes.Publisher(other, "t", String, queue_size=10)
    log: list[str] = []

    def timer_cb(_ev: Any) -> Generator[Any, Any, None]:
        log.append(f"timer start {world.now / 1e9:.1f}")
        yield node.sleep(0.5)
        log.append(f"timer end {world.now / 1e9:.1f}")

    def sub_cb(_msg: Any) -> Any:
        log.append(f"sub cb {world.now / 1e9:.1f}")
        if generator_sub:
            return iter(())
        return None

    ddes.Subscriber(node, "t", String, sub_cb, queue_size=10)
    ddes.Timer(node, 1.0, timer_cb, oneshot=oneshot)
    world.call_at(1_200 * MS, lambda: pub.publish(String(data="x")))
    world.run(until=1.9)
    return log


@pytest.mark.parametrize("oneshot", [False, True])
@pytest.mark.parametrize("generator_sub", [False, True])
def test_a_generator_timer_callback_holds_the_single_spinner(oneshot: bool,
                                                              generator_sub: bool) -> None:
    # The regression of issue 12: the periodic timer's fast path let the
    # subscriber run in the middle of the timer callback.
    assert _probe(oneshot, generator_sub) == ["timer start 1.0", "timer end 1.5", "sub cb 1.5"]


def test_policies_parse_and_bad_ones_name_the_fix() -> None:
    assert parse_policy("single") == (1, False)
    assert parse_policy("manual") == (1, True)
    assert parse_policy(3) == (3, False)
    assert parse_policy("rospy")[0] > 1_000_000
    for bad in (0, -1, True, "multi", 2.0, None):
        with pytest.raises(DdesValueError, match="'single', 'manual', 'rospy'"):
            parse_policy(bad)  # type: ignore[arg-type]


def test_every_node_has_one_queue() -> None:
    world = ddes.World()
    node = world.create_node("n", spinner=2)
    assert isinstance(node.callbacks, CallbackQueue)
    assert node.callbacks.policy == 2 and node.callbacks.threads == 2
    node.shutdown()
    assert node.callbacks.closed and not node.callbacks.free


# -- a property over mixed callback kinds -----------------------------------------------------
KINDS = ("sub", "timer", "oneshot", "service")

job = st.tuples(
    st.sampled_from(KINDS),
    st.integers(min_value=1, max_value=40),      # start, ms
    st.sampled_from([0, 0, 5, 20, 70]),          # simulated ms the callback takes (0: plain)
)


def _run(policy: Any, jobs: list[tuple[str, int, int]]) -> tuple[list[tuple[str, int, int]], Any]:
    """Run jobs on one node; returns (owner, start, end) intervals of every callback."""
    world = ddes.World(seed=1)
    node = world.create_node("n", spinner=policy)
    driver = world.create_node("driver")
    spans: list[tuple[str, int, int]] = []

    def make_cb(owner: str, dur: int, value: Any = None) -> Any:
        def cb(*_args: Any) -> Any:
            start = world.now
            if dur == 0:
                spans.append((owner, start, start))
                return value

            def body() -> Generator[Any, Any, Any]:
                yield node.sleep(dur / 1000)
                spans.append((owner, start, world.now))
                return value

            return body()
        return cb

    for k, (kind, at, dur) in enumerate(jobs):
        owner = f"{kind}{k}"
        if kind == "sub":
            topic = f"t{k}"
            pub = ddes.Publisher(driver, topic, String, queue_size=100)
            ddes.Subscriber(node, topic, String, make_cb(owner, dur), queue_size=100)
            for j in range(3):  # three messages each: the same owner is called again
                world.call_at(at * MS + j * MS, lambda p=pub: p.publish(String(data="m")))
        elif kind in ("timer", "oneshot"):
            ddes.Timer(node, at / 1000, make_cb(owner, dur), oneshot=kind == "oneshot")
        else:
            name = f"s{k}"
            ddes.Service(node, name, Empty, make_cb(owner, dur, Empty._response_class()))
            proxy = ddes.ServiceProxy(driver, name, Empty)

            def call(p: Any = proxy) -> Generator[Any, Any, None]:
                yield p.call(Empty._request_class())

            world.call_at(at * MS + 2 * MS, lambda c=call: driver.process(c()) and None)
    windows: list[tuple[int, int]] = []
    if policy == "manual":
        def loop() -> Generator[Any, Any, None]:
            while True:
                yield node.sleep(0.010)
                windows.append((world.now, 10**18))  # open until this spin ends
                yield node.spin_once()
                windows[-1] = (windows[-1][0], world.now)
        node.process(loop())
    world.run(until=0.4)
    return spans, windows


def _max_overlap(spans: list[tuple[str, int, int]]) -> int:
    """Most callbacks running at one instant (intervals are half-open [start, end))."""
    points = sorted([(s, 1) for _, s, e in spans if e > s] + [(e, -1) for _, s, e in spans if e > s],
                    key=lambda p: (p[0], p[1]))
    best = cur = 0
    for _, d in points:
        cur += d
        best = max(best, cur)
    return best


@settings(max_examples=40)
@given(st.lists(job, min_size=1, max_size=6),
       st.sampled_from(["single", 2, "rospy", "manual"]))
def test_each_policy_over_mixed_callback_kinds(jobs: list[tuple[str, int, int]],
                                               policy: Any) -> None:
    spans, windows = _run(policy, jobs)
    assert spans, "some callback must have run"
    # One owner's callbacks never overlap, in every policy.
    by_owner: dict[str, list[tuple[int, int]]] = {}
    for owner, s, e in spans:
        by_owner.setdefault(owner, []).append((s, e))
    for owner, ivs in by_owner.items():
        ivs.sort()
        for (_s1, e1), (s2, _e2) in zip(ivs, ivs[1:]):
            assert s2 >= e1, f"{owner} overlaps itself under {policy!r}: {ivs}"
    limit = {"single": 1, 2: 2, "manual": 1}.get(policy)
    if limit is not None:
        assert _max_overlap(spans) <= limit, (policy, spans)
    if policy == "manual":
        # Nothing runs except inside the node's own spin_once calls.
        for _, s, _e in spans:
            assert any(ws <= s <= we for ws, we in windows), (s, windows)


def test_rospy_policy_runs_different_owners_concurrently() -> None:
    jobs = [("sub", 5, 70), ("timer", 5, 70)]
    spans, _ = _run("rospy", jobs)
    assert _max_overlap(spans) == 2
    spans, _ = _run("single", jobs)
    assert _max_overlap(spans) == 1
