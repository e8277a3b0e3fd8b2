"""``read_messages`` looks each connection's class up once and reads one unbounded connection
straight from its index: ``raw=True`` yields exactly what ``return_connection_header=True``
yields, and both what the writes say (topics, bounds, time order), for any topics, bounds and
chunking, from a file and in memory."""

from __future__ import annotations

from pathlib import Path
from typing import Any

from hypothesis import given
from hypothesis import strategies as st

from ddes import Time
from ddes.msg import get_message_class
from ddes.rosbag import Bag

String = get_message_class("std_msgs/String")
Int32 = get_message_class("std_msgs/Int32")
TOPICS = ["/a", "/b", "/c"]


def expected(writes: list[tuple[str, int, int]], topics: Any, start: Time | None,
             end: Time | None) -> list[tuple[str, bytes, int]]:
    """(topic, bytes, ns) of what a read should give, from the writes alone: the wanted topics
    (None or [] all of them), inclusive bounds (a zero Time is none), in time order, ties by
    connection (first write of a topic) and then by write."""
    wanted = set(TOPICS if not topics else [topics] if isinstance(topics, str) else topics)
    lo = start.to_nsec() if start else None
    hi = end.to_nsec() if end else None
    first = {topic: i for i, (topic, _, _) in reversed(list(enumerate(writes)))}
    rows = [(t_ns, first[topic], i, topic, k) for i, (topic, t_ns, k) in enumerate(writes)
            if topic in wanted and (lo is None or t_ns >= lo) and (hi is None or t_ns <= hi)]
    return [(topic, (Int32(data=k) if topic == "/c" else String(data=f"m{k}"))
             ._serialize_to_bytes(), t_ns) for t_ns, _, _, topic, k in sorted(rows)]


def general(bag: Bag, **kw: Any) -> list[tuple[Any, ...]]:
    return [(m.topic, m.message, m.timestamp)
            for m in bag.read_messages(raw=True, return_connection_header=True, **kw)]


writes = st.lists(st.tuples(st.sampled_from(TOPICS), st.integers(0, 3_000_000_000),
                            st.integers(0, 9)), max_size=25)
bounds = st.one_of(st.none(), st.integers(0, 3_000_000_000).map(Time._from_ns))


@given(writes=writes, topics=st.one_of(st.none(), st.sampled_from(TOPICS),
                                       st.lists(st.sampled_from(TOPICS), max_size=3)),
       start=bounds, end=bounds, chunk=st.sampled_from([0, 64, 768 * 1024]))
def test_raw_reads_as_the_general_path(tmp_path_factory: Any, writes: list[tuple[str, int, int]],
                                       topics: Any, start: Time | None, end: Time | None,
                                       chunk: int) -> None:
    path = Path(tmp_path_factory.mktemp("bags")) / "x.bag"
    bag = Bag(str(path), "w", chunk_threshold=chunk)
    memory = Bag(chunk_threshold=chunk)
    for topic, t_ns, k in writes:
        msg = Int32(data=k) if topic == "/c" else String(data=f"m{k}")
        bag.write(topic, msg, Time._from_ns(t_ns))
        memory.write(topic, msg, Time._from_ns(t_ns))
    bag.close()
    for b in (Bag(str(path)), memory):  # a file read back, a bag in memory
        kw = {"topics": topics, "start_time": start, "end_time": end}
        fast = [(m.topic, m.message, m.timestamp) for m in b.read_messages(raw=True, **kw)]
        assert fast == general(b, **kw)
        assert [(m[0], m[1][1], m[2].to_nsec()) for m in fast] == expected(writes, topics, start,
                                                                           end)
        assert all(type(m).__name__ == "BagMessage" for m in b.read_messages(raw=True, **kw))
        for m in b.read_messages(raw=True, **kw):
            datatype, data, md5sum, _, pytype = m.message
            assert pytype is not None and pytype._type == datatype and pytype._md5sum == md5sum
            assert type(m.timestamp) is Time and m.timestamp.nsecs < 1_000_000_000


def test_a_type_with_no_class_reads_raw_with_pytype_none(tmp_path: Path) -> None:
    path = tmp_path / "x.bag"
    bag = Bag(str(path), "w")
    header = {"topic": "/x", "type": "nowhere/Nothing", "md5sum": "0" * 32,
              "message_definition": ""}
    bag.write("/x", ("nowhere/Nothing", b"\x01\x02", "0" * 32, None), Time(1), raw=True,
              connection_header=header)
    bag.write("/x", ("nowhere/Nothing", b"\x03", "0" * 32, None), Time(2), raw=True,
              connection_header=header)
    bag.close()
    read = Bag(str(path))
    got = [(m.topic, m.message, m.timestamp) for m in read.read_messages(raw=True)]
    assert got == general(read)
    assert [m[1] for m in got] == [("nowhere/Nothing", b"\x01\x02", "0" * 32, None, None),
                                   ("nowhere/Nothing", b"\x03", "0" * 32, None, None)]
