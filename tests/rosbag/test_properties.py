"""Round trips: memory → .bag → memory and memory → .mcap → memory keep every message,
time, type, md5sum, definition, connection header and latching flag (hypothesis, over many
bundled message types)."""

from __future__ import annotations

from typing import Any

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from ddes import Time
from ddes.msg import default_registry, get_message_class
from ddes.rosbag import Bag
from ddes.testing import messages
from ddes.testing.strategies import times

from .conftest import contents

_REG = default_registry()
TYPES = sorted(_REG.iter_types("msg"))
_SETTINGS = settings(max_examples=40, deadline=None,
                     suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])

_writes = st.lists(
    st.tuples(st.sampled_from(TYPES), st.sampled_from(["/a", "/b/c", "/d"]), times(),
              st.sampled_from([None, "0", "1"]), st.sampled_from(["", "/talker", "/other"])),
    min_size=0, max_size=12)


def _build(data: st.DataObject, writes: list[tuple[str, str, Time, Any, str]],
           chunk_threshold: int) -> Bag:
    bag = Bag(chunk_threshold=chunk_threshold)
    for type_name, topic, t, latching, callerid in writes:
        cls = get_message_class(type_name)
        msg = data.draw(messages(cls, max_size=2))
        topic = f"{topic}/{type_name.replace('/', '_')}"  # one type per topic
        header = {"topic": topic, "type": cls._type, "md5sum": cls._md5sum,
                  "message_definition": cls._full_text}
        if callerid:
            header["callerid"] = callerid
        if latching is not None:
            header["latching"] = latching
        if callerid == "/other":  # the recorder's path: one connection per distinct header
            bag._write_raw(topic, header, msg._serialize_to_bytes(), t.to_nsec())
        else:
            bag.write(topic, msg, t, connection_header=header)
    return bag


def _deep(bag: Bag) -> list[Any]:
    """Contents plus the decoded messages and their classes' identities."""
    out = []
    for m in bag.read_messages(return_connection_header=True):
        cls = type(m.message)
        out.append((m.topic, m.timestamp, m.message, cls._type, cls._md5sum, cls._full_text,
                    m.connection_header))
    return out


@_SETTINGS
@given(data=st.data(), writes=_writes,
       compression=st.sampled_from(["none", "bz2", "lz4"]),
       chunk_threshold=st.sampled_from([0, 300, 768 * 1024]))
def test_bag_file_round_trip(data: st.DataObject, writes: list[Any], compression: str,
                             chunk_threshold: int) -> None:
    bag = _build(data, writes, chunk_threshold)
    back = Bag.from_bytes(bag.to_bytes(compression=compression))
    assert contents(back) == contents(bag)
    assert _deep(back) == _deep(bag)
    assert [c.latching for c in back.get_connections()] == \
        [c.latching for c in bag.get_connections()]
    assert back.get_type_and_topic_info() == bag.get_type_and_topic_info()
    again = Bag.from_bytes(back.to_bytes(compression=compression))
    assert again.to_bytes(compression=compression) == back.to_bytes(compression=compression)


@_SETTINGS
@given(data=st.data(), writes=_writes, compression=st.sampled_from(["none", "lz4"]))
def test_mcap_round_trip(data: st.DataObject, writes: list[Any], compression: str) -> None:
    bag = _build(data, writes, 768 * 1024)
    back = Bag.from_bytes(bag.to_bytes("mcap", compression=compression))
    assert contents(back) == contents(bag)
    assert _deep(back) == _deep(bag)
    assert [c.header for c in back.get_connections()] == \
        [c.header for c in bag.get_connections()]
    if writes:
        assert back.get_start_time() == bag.get_start_time()
        assert back.get_end_time() == bag.get_end_time()
