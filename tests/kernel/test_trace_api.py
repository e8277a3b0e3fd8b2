"""The public API of the trace: append/append_row, filters, select, and an unchanged digest."""

from __future__ import annotations

import re
from collections import Counter
from pathlib import Path
from typing import Any

import pytest
from hypothesis import given
from hypothesis import strategies as st

import ddes
from ddes.errors import DdesTypeError, DdesValueError, DigestError
from ddes.kernel.kinds import TRACE_KINDS
from ddes.kernel.trace import Trace, TraceEvent, TraceSelection

from ..docsnippets import run_snippet

_FIRE = ("expected", "real")
_PUB = ("topic", "seq", "connections")

#: The digest of :func:`fill_fixed`, computed once with the trace as it was before
#: append/append_row/filters/select existed.  It must never change: it pins the
#: canonical form that every recorded run's digest is made of.
# The canonical form of issue 13: bytes as "sha256:<hex>" (was a list of ints before).
FIXED_DIGEST = "9009300a16aee201cb8b23312ba9aa3980e3a4865e09184180eeb4cf85c631de"


def fill_fixed(trace: Any, fast: str, slow: str) -> None:
    """Append a fixed mix of events through the dict form and the row form."""
    rec = getattr(trace, slow)
    row = getattr(trace, fast)
    rec(0, "node.start", "/talker", {"use_sim_time": False})
    rec(0, "topic.advertise", "/talker", {"topic": "/chatter", "type": "std_msgs/String", "latch": True})
    row((1_000_000, "timer.fire", "/ticker", _FIRE, ddes.Time(0, 1_000_000), ddes.Time(0, 1_000_000)))
    row((2_500_000, "topic.publish", "/talker", _PUB, "/chatter", 1, 2))
    rec(3_000_000, "log", "/listener", {"level": "INFO", "msg": "héllo ✓", "file": "x.py", "line": 7})
    rec(4_000_000, "action.server.cancel", "/fib",
        {"ns": "/fib", "id": "", "stamp": ddes.Duration(1, 5), "matched": ["a", "b"],
         "requested": ("a",), "placeholder": False})
    rec(5_000_000, "reconfigure.update", "/dyn",
        {"ns": "/dyn", "config": {"b": 1.5, "a": None, "c": b"\x00\x01"}})
    rec(6_000_000, "rosbag.record", "/rec", {"path": "x.bag", "topics": {"/b", "/a"}})
    rec(7_000_000, "node.exit", "/talker", None)
    row((8_000_000, "service.call", "/client", ("service", "call"), "/add", 3))


# -- the digest ------------------------------------------------------------------------


@pytest.mark.parametrize(("fast", "slow"), [("append_row", "append"), ("record_fast", "record")])
def test_digest_of_a_fixed_run_is_unchanged(fast: str, slow: str) -> None:
    trace = Trace()
    fill_fixed(trace, fast, slow)
    assert trace.digest() == FIXED_DIGEST
    assert trace.complete


def test_digest_is_the_same_through_the_slow_paths() -> None:
    """Listeners, an all-including filter, or a re-enabled trace store the very same rows."""
    seen: list[TraceEvent] = []
    listened = Trace()
    listened.subscribe(seen.append)
    fill_fixed(listened, "append_row", "append")
    assert listened.digest() == FIXED_DIGEST and len(seen) == 10
    assert seen == listened.events

    filtered = Trace()
    filtered.set_filter(include=sorted({k.split(".")[0] + "." if "." in k else k for k in TRACE_KINDS}))
    fill_fixed(filtered, "append_row", "append")
    assert filtered.complete
    with pytest.raises(DigestError, match="a recording filter is set"):
        filtered.digest()  # nothing was filtered out, but the filter could have
    filtered.set_filter()
    assert filtered.digest() == FIXED_DIGEST

    toggled = Trace()
    toggled.enabled = False
    toggled.enabled = True
    fill_fixed(toggled, "append_row", "append")
    assert toggled.digest() == FIXED_DIGEST


def test_lines_are_the_canonical_form() -> None:
    trace = Trace()
    fill_fixed(trace, "append_row", "append")
    lines = list(trace.lines())
    assert lines[2] == '[1000000,"timer.fire","/ticker",{"expected":1000000,"real":1000000}]'
    assert lines[6] == '[5000000,"reconfigure.update","/dyn",{"config":{"a":null,"b":1.5,"c":"sha256:b413f47d13ee2fe6c845b2ee141af81de858df4ec549a58b7970bb96645bc8d2"},"ns":"/dyn"}]'
    assert lines[8] == '[7000000,"node.exit","/talker",{}]'


# -- append / append_row ----------------------------------------------------------------


def test_append_and_record_are_one_method() -> None:
    assert Trace.record is Trace.append
    trace = Trace()
    trace.append(5, "log", "/n", {"level": "INFO", "msg": "hi", "file": "f.py", "line": 1})
    trace.record(6, "node.shutdown", "/n", {"reason": "done"})
    trace.append(7, "node.exit", "/n")
    assert [(e.t, e.kind, e.source) for e in trace] == [
        (5, "log", "/n"), (6, "node.shutdown", "/n"), (7, "node.exit", "/n")]
    assert trace[2].details == {}
    assert trace[0] == TraceEvent(5, "log", "/n", {"level": "INFO", "msg": "hi", "file": "f.py", "line": 1})


def test_append_row_builds_details_when_read() -> None:
    trace = Trace()
    trace.append_row((1, "topic.publish", "/a", _PUB, "/t", 3, 0))
    trace.append_row((2, "service.call", "/a", ()))  # no details at all
    assert trace[0].details == {"topic": "/t", "seq": 3, "connections": 0}
    assert trace[1].details == {}
    assert trace[1].to_json() == '[2,"service.call","/a",{}]'


def _is_list_append(trace: Trace) -> bool:
    fn = trace.append_row
    return getattr(fn, "__self__", None) is trace._raw and getattr(fn, "__name__", "") == "append"


def test_append_row_is_list_append_only_when_nothing_is_active() -> None:
    trace = Trace()
    assert _is_list_append(trace) and trace.record_fast is trace.append_row

    def listener(ev: TraceEvent) -> None:
        pass

    trace.subscribe(listener)
    assert not _is_list_append(trace) and trace.record_fast is trace.append_row
    trace.unsubscribe(listener)
    assert _is_list_append(trace)

    trace.enabled = False
    assert not _is_list_append(trace) and trace.enabled is False
    trace.enabled = True
    assert _is_list_append(trace) and trace.enabled is True

    trace.set_filter(exclude=["log"])
    assert not _is_list_append(trace) and trace.filtered
    trace.set_filter()
    assert _is_list_append(trace) and not trace.filtered

    trace.subscribe(listener)
    trace.set_filter(include=["topic."])
    trace.unsubscribe(listener)
    assert not _is_list_append(trace)  # the filter still needs the checking path
    trace.set_filter()
    assert _is_list_append(trace)


def test_a_captured_append_row_follows_the_binding_it_was_read_with() -> None:
    """Hot-path callers read ``trace.append_row`` per event; the attribute is always right."""
    trace = Trace()
    got: list[str] = []
    trace.subscribe(lambda ev: got.append(ev.kind))
    trace.append_row((1, "topic.publish", "/a", _PUB, "/t", 1, 0))
    trace.append(2, "node.shutdown", "/a", {"reason": "x"})
    assert got == ["topic.publish", "node.shutdown"]


def test_copies_and_pickles_get_their_own_append_row() -> None:
    import copy
    import pickle

    trace = Trace()
    trace.append(1, "log", "/a", {"msg": "x"})
    trace.set_filter(exclude=["node.exit"])
    trace.set_filter()
    for twin in (copy.deepcopy(trace), pickle.loads(pickle.dumps(trace))):
        assert _is_list_append(twin)
        twin.append_row((2, "topic.publish", "/a", _PUB, "/t", 1, 0))
        twin.append(3, "log", "/a", {})
        assert len(twin) == 3 and len(trace) == 1
    filtered = Trace()
    filtered.set_filter(include=["log"])
    twin = copy.deepcopy(filtered)
    twin.append(1, "node.exit", "/a", {"code": 0})
    assert len(twin) == 0 and twin.counts["node.exit"] == 1 and filtered.complete


def test_disabled_counts_without_storing() -> None:
    trace = Trace()
    trace.enabled = False
    trace.append_row((1, "topic.publish", "/a", _PUB, "/t", 1, 0))
    trace.append_row((1, "service.call", "/a", ("service", "call", "persistent", "request")))
    trace.append(2, "log", "/a", {})
    assert len(trace) == 0 and not trace.complete
    assert trace.counts == Counter({"topic.publish": 1, "service.call": 1, "log": 1})
    assert trace.counted_only == trace.counts
    trace.enabled = True
    trace.append(3, "log", "/a", {})
    assert len(trace) == 1 and trace.counts["log"] == 2 and not trace.complete


def test_listeners_see_stored_events_only_and_may_unsubscribe_themselves() -> None:
    trace = Trace()
    a: list[str] = []
    b: list[str] = []

    def once(ev: TraceEvent) -> None:
        a.append(ev.kind)
        trace.unsubscribe(once)

    trace.subscribe(once)
    trace.subscribe(lambda ev: b.append(ev.kind))
    trace.set_filter(exclude=["log"])
    trace.append(1, "log", "/a", {})
    trace.append(2, "node.start", "/a", {"use_sim_time": False})
    trace.append(3, "node.start", "/b", {"use_sim_time": False})
    assert a == ["node.start"] and b == ["node.start", "node.start"]


def test_old_hot_path_callers_route_through_the_checks_while_a_filter_is_set() -> None:
    """Code still written ``if trace.enabled and not trace._listeners: trace._raw.append(row)``."""
    trace = Trace()
    assert not trace._listeners
    trace.set_filter(exclude=["timer.fire"])
    assert trace._listeners  # so such code calls record_fast, which applies the filter
    trace.set_filter()
    assert not trace._listeners


# -- filters ---------------------------------------------------------------------------


def _fill_kinds(trace: Trace, kinds: list[str]) -> None:
    for i, kind in enumerate(kinds):
        if i % 2:
            trace.append_row((i, kind, "/s", ("i",), i))
        else:
            trace.append(i, kind, "/s", {"i": i})


def test_include_exclude_and_prefixes() -> None:
    kinds = ["topic.publish", "timer.fire", "log", "topic.deliver", "action.server.goal",
             "action.client.send", "topic.drop"]
    trace = Trace()
    trace.set_filter(include=["topic.", "log"], exclude=["topic.drop"])
    _fill_kinds(trace, kinds)
    assert [e.kind for e in trace] == ["topic.publish", "log", "topic.deliver"]
    assert trace.counts == Counter(kinds)
    assert trace.counted_only == Counter(["timer.fire", "action.server.goal", "action.client.send",
                                          "topic.drop"])
    assert not trace.complete

    only = Trace()
    only.set_filter(include="action.server.")  # one name, not an iterable of letters
    _fill_kinds(only, kinds)
    assert [e.kind for e in only] == ["action.server.goal"]

    nothing = Trace()
    nothing.set_filter(include=[])
    _fill_kinds(nothing, kinds)
    assert len(nothing) == 0 and sum(nothing.counts.values()) == len(kinds)


def test_set_filter_applies_from_now_on_and_clears() -> None:
    trace = Trace()
    trace.append(0, "log", "/s", {})
    trace.set_filter(exclude=["log"])
    trace.append(1, "log", "/s", {})
    trace.set_filter()
    trace.append(2, "log", "/s", {})
    assert trace.select(kind="log").times() == [0, 2]
    assert trace.counts["log"] == 3 and not trace.complete


def test_a_filter_changes_the_digest() -> None:
    full, part = Trace(), Trace()
    part.set_filter(exclude=["timer.fire"])
    fill_fixed(full, "append_row", "append")
    fill_fixed(part, "append_row", "append")
    assert full.digest() == FIXED_DIGEST
    with pytest.raises(DigestError, match="counted but not stored: timer.fire"):
        part.digest()
    assert full.complete and not part.complete
    assert part.counts == full.counts


def test_filter_names_are_checked() -> None:
    trace = Trace()
    with pytest.raises(DdesValueError, match="timer.fire"):
        trace.set_filter(include=["timer.fier"])
    with pytest.raises(DdesValueError, match=r"'topic\.'"):
        trace.set_filter(exclude=["topic"])
    with pytest.raises(DdesTypeError):
        trace.set_filter(include=[3])  # type: ignore[list-item]
    assert not trace.filtered  # a refused filter changes nothing
    trace.set_filter(include=["my.custom", "mine."], strict=False)
    trace.append(1, "my.custom", "/s", {})
    trace.append(2, "mine.too", "/s", {})
    trace.append(3, "log", "/s", {})
    assert [e.kind for e in trace] == ["my.custom", "mine.too"]


_SOME_KINDS = sorted(TRACE_KINDS)[:12] + ["my.own.kind"]
_NAMES = st.sampled_from(sorted({*TRACE_KINDS, "topic.", "action.", "action.server.", "service.",
                                 "my.", "my.own.kind"}))


@given(
    kinds=st.lists(st.sampled_from(_SOME_KINDS + sorted(TRACE_KINDS)[-12:]), max_size=40),
    include=st.none() | st.lists(_NAMES, max_size=4),
    exclude=st.none() | st.lists(_NAMES, max_size=4),
)
def test_filtering_splits_every_event_into_stored_or_counted(
    kinds: list[str], include: list[str] | None, exclude: list[str] | None
) -> None:
    trace = Trace()
    trace.set_filter(include=include, exclude=exclude, strict=False)
    _fill_kinds(trace, kinds)

    def matches(kind: str, names: list[str]) -> bool:
        return any(kind == n or (n.endswith(".") and kind.startswith(n)) for n in names)

    kept = [k for k in kinds if (include is None or matches(k, include))
            and not (exclude is not None and matches(k, exclude))]
    assert [e.kind for e in trace] == kept
    assert [e.t for e in trace] == [i for i, k in enumerate(kinds) if k in kept and
                                    (include is None or matches(k, include))
                                    and not (exclude is not None and matches(k, exclude))]
    assert trace.counts == Counter(kinds)
    assert Counter(e.kind for e in trace) + trace.counted_only == Counter(kinds)
    assert trace.complete == (len(kept) == len(kinds))


# -- select ----------------------------------------------------------------------------


def _sample() -> Trace:
    trace = Trace()
    trace.append(0, "node.start", "/talker", {"use_sim_time": False})
    trace.append_row((100, "topic.publish", "/talker", _PUB, "/chatter", 1, 1))
    trace.append_row((150, "topic.deliver", "/listener", ("topic", "publisher", "seq"),
                      "/chatter", "/talker", 1))
    trace.append_row((200, "topic.publish", "/talker", _PUB, "/chatter", 2, 1))
    trace.append_row((250, "topic.drop", "/listener", ("topic", "publisher", "seq", "reason"),
                      "/chatter", "/talker", 2, "loss"))
    trace.append_row((300, "timer.fire", "/ticker", _FIRE, 300, 300))
    trace.append(400, "action.client.send", "/client",
                 {"ns": "/fib", "id": "g1", "stamp": ddes.Time(0, 400)})
    return trace


def test_select_by_kind_source_and_prefix() -> None:
    trace = _sample()
    sel = trace.select(kind="topic.publish")
    assert isinstance(sel, TraceSelection) and isinstance(sel, list)
    assert sel.times() == [100, 200]
    assert trace.select(kind="topic.").kinds() == Counter(
        {"topic.publish": 2, "topic.deliver": 1, "topic.drop": 1})
    assert trace.select(kind=("timer.fire", "topic.drop")).times() == [250, 300]
    assert trace.select(kind=("timer.fire", "action.")).times() == [300, 400]
    assert trace.select(source="/listener").kinds() == Counter({"topic.deliver": 1, "topic.drop": 1})
    assert trace.select(source=("/ticker", "/client")).times() == [300, 400]
    assert trace.select(prefix="topic.d").times() == [150, 250]
    assert trace.select(kind="topic.", source="/talker").times() == [100, 200]
    assert trace.select().times() == [e.t for e in trace]
    assert trace.select(kind="service.call") == []


def test_select_by_time_in_nanoseconds_or_time() -> None:
    trace = _sample()
    assert trace.select(since_ns=150, until_ns=250).times() == [150, 200, 250]
    assert trace.select(since_ns=ddes.Time(0, 201)).times() == [250, 300, 400]
    assert trace.select(until_ns=ddes.Duration(0, 100)).times() == [0, 100]
    with pytest.raises(DdesTypeError, match="nanoseconds"):
        trace.select(since_ns=0.5)
    with pytest.raises(DdesTypeError):
        trace.select(until_ns="1s")
    with pytest.raises(DdesTypeError, match="since_ns"):
        trace.select(since=1)  # a detail key would match nothing: refused instead
    with pytest.raises(TypeError, match="until_ns"):
        trace.select(until=ddes.Time(1))


def test_select_by_details() -> None:
    trace = _sample()
    assert trace.select(kind="topic.publish", seq=2).times() == [200]
    assert trace.select(topic="/chatter", reason="loss").kinds() == Counter({"topic.drop": 1})
    assert trace.select(seq=1).times() == [100, 150]
    assert trace.select(nonexistent=None) == []  # a missing key never matches
    assert trace.select(kind="action.client.send", stamp=400).times() == [400]  # Time == its ns
    assert trace.select(stamp=ddes.Time(0, 400)).times() == [400]


def test_select_refuses_an_unknown_kind_with_close_matches() -> None:
    trace = _sample()
    with pytest.raises(DdesValueError, match="topic.publish"):
        trace.select(kind="topic.publsh")
    with pytest.raises(DdesValueError, match=r"'topic\.'"):
        trace.select(kind="topic")
    with pytest.raises(ValueError):  # DdesValueError is a ValueError too
        trace.select(kind="nothing.like.it")
    # Tuples are not checked; a kind this trace recorded is known.
    assert trace.select(kind=("nothing.like.it",)) == []
    trace.append(500, "my.event", "/me", {"x": 1})
    assert trace.select(kind="my.event").times() == [500]
    assert trace.select(kind="my.").times() == [500]


def test_selection_helpers() -> None:
    trace = _sample()
    sel = trace.select(kind="topic.")
    assert sel.first() == trace[1] and sel.last() == trace[4]
    empty = trace.select(kind="service.")
    assert empty.first() is None and empty.last() is None and empty.kinds() == Counter()
    assert empty.times() == [] and empty.to_rows() == []
    assert sel.where(seq=2).times() == [200, 250]
    assert sel.where(seq=2, reason="loss").kinds() == Counter({"topic.drop": 1})
    assert isinstance(sel.where(), TraceSelection) and sel.where() == sel
    assert sel.sources() == Counter({"/talker": 2, "/listener": 2})
    assert sel.to_rows()[0] == {"t": 100, "kind": "topic.publish", "source": "/talker",
                                "topic": "/chatter", "seq": 1, "connections": 1}
    odd = Trace()
    odd.append(1, "mine", "/s", {"source": "x", "t": 2, "v": 3})
    assert odd.select().to_rows() == [{"t": 1, "kind": "mine", "source": "/s",
                                       "details.source": "x", "details.t": 2, "v": 3}]


def test_filter_keeps_its_old_lenient_behaviour() -> None:
    trace = _sample()
    assert [e.t for e in trace.filter(kind="topic.publish")] == [100, 200]
    assert trace.filter(kind="topic.") == []  # kind is exact in filter()
    assert trace.filter(kind="no.such.kind") == []  # and unknown kinds are fine
    assert [e.t for e in trace.filter(prefix="topic.", source="/listener")] == [150, 250]
    assert trace.filter() == trace.events


def test_catalogue_is_reachable_from_the_trace() -> None:
    assert Trace.kinds_catalogue() is TRACE_KINDS
    assert "timer.fire" in Trace().describe("timer.fire")


# -- a world -------------------------------------------------------------------------


def _chatter_world(seed: int, setup: Any = None) -> ddes.World:
    string = ddes.get_message_class("std_msgs/String")
    world = ddes.World(seed=seed)
    if setup is not None:
        setup(world.trace)
    talker = world.create_node("talker")
    pub = talker.advertise("chatter", string, queue_size=10)
    listener = world.create_node("listener")
    heard: list[str] = []
    listener.subscribe("chatter", string, lambda m: heard.append(m.data))
    talker.create_timer(0.1, lambda ev: pub.publish(f"hi {talker.get_time():.1f}"))
    world.set_link("/chatter", latency=0.01, loss=0.2)
    world.run(until=2)
    assert heard
    return world


def test_select_on_a_world() -> None:
    world = _chatter_world(1)
    trace = world.trace
    assert trace.complete
    pubs = trace.select(kind="topic.publish", source="/talker")
    fires = trace.select(kind="timer.fire", source="/talker")
    assert len(pubs) == len(fires) > 0
    assert pubs.times() == fires.times()
    delivered = trace.select(kind="topic.deliver", topic="/chatter")
    dropped = trace.select(kind="topic.drop", reason="loss")
    assert len(delivered) + len(dropped) <= len(pubs)
    assert all(b - a == 10_000_000 for a, b in zip(
        [e.t for e in pubs if e.details["seq"] in {d.details["seq"] for d in delivered}],
        delivered.times()))
    window = trace.select(since_ns=ddes.Time(1), until_ns=int(1.5e9))
    assert window and all(1_000_000_000 <= t <= 1_500_000_000 for t in window.times())


@pytest.mark.parametrize("spec", [{"include": ["topic."]}, {"exclude": ["topic.", "log"]},
                                  {"include": ["timer.fire", "topic.drop"]}])
def test_a_filtered_run_stores_the_matching_part_of_the_same_run(spec: dict[str, Any]) -> None:
    full = _chatter_world(7)
    part = _chatter_world(7, lambda trace: trace.set_filter(**spec))
    names = list(spec.get("include") or spec["exclude"])
    include = "include" in spec
    wanted = [e for e in full.trace
              if any(e.kind == n or (n.endswith(".") and e.kind.startswith(n)) for n in names) == include]
    assert part.trace.events == wanted
    assert part.trace.counts == full.trace.counts
    assert not part.trace.complete
    with pytest.raises(DigestError):
        part.digest()


def test_the_snippets_of_docs_trace_md_run() -> None:
    text = (Path(__file__).resolve().parents[2] / "docs" / "trace.md").read_text(encoding="utf-8")
    blocks = re.findall(r"```python\n(.*?)```", text, flags=re.S)
    assert len(blocks) >= 3
    namespace: dict[str, Any] = {}
    for i, block in enumerate(blocks):
        run_snippet(block, "docs/trace.md", i, namespace)


# -- issue 13: a digest that means what it says ----------------------------------------------


def _talk(data: str, seed: int = 0) -> str:
    world = ddes.World(seed=seed)
    node = world.create_node("talker")
    pub = ddes.Publisher(node, "chatter", ddes.get_message_class("std_msgs/String"),
                         queue_size=1)
    world.call_at(1000, lambda: pub.publish(data=data))
    world.run(until=1)
    return world.digest()


def test_the_digest_covers_message_payloads() -> None:
    assert _talk("hello") == _talk("hello")
    assert _talk("hello") != _talk("hellp")


def test_the_digest_holds_no_memory_addresses() -> None:
    class Thing:
        pass

    digests = set()
    for _ in range(3):
        world = ddes.World()
        world.record("user.note", "/me", thing=Thing(), text=repr(Thing()))
        digests.add(world.digest())
        assert " at 0x…>" in next(world.trace.lines())
    assert len(digests) == 1


def test_a_world_without_recording_is_not_digested() -> None:
    world = ddes.World()
    world.trace.enabled = False
    with pytest.raises(DigestError, match="switched off"):
        world.digest()
    world.create_node("n")
    with pytest.raises(DigestError, match="counted but not stored: node.start"):
        world.digest()
