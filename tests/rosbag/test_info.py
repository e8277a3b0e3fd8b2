"""``rosbag info`` text, YAML and keys: rows, widths and number formats of rosbag's bag.py."""

from __future__ import annotations

import datetime

import pytest

from ddes import Time
from ddes.errors import DdesKeyError
from ddes.rosbag import Bag
from ddes.rosbag.info import (
    human_readable_frequency,
    human_readable_size,
    median,
    time_to_str,
)

from .conftest import Int32, String, sample_bag


@pytest.mark.parametrize("size,text", [(0, "0.0 KB"), (500, "0.5 KB"), (5228, "5.1 KB"),
                                       (1024 * 1024 * 1.5, "1.5 MB"), (1023 * 1024, "1023.0 KB"),
                                       (1024**9, "-")])
def test_sizes(size: float, text: str) -> None:
    assert human_readable_size(size) == text


@pytest.mark.parametrize("freq,text", [(10.0, "10.0 Hz"), (999.94, "999.9 Hz"),
                                       (1500.0, "1.5 kHz"), (2e6, "2.0 MHz")])
def test_frequencies(freq: float, text: str) -> None:
    assert human_readable_frequency(freq) == text


def test_median_and_times() -> None:
    assert median([3.0, 1.0, 2.0]) == 2.0
    assert median([4.0, 1.0, 2.0, 3.0]) == 2.5
    assert median([]) != median([])  # nan
    utc = datetime.timezone.utc
    assert time_to_str(1486033546.09, utc) == "Feb 02 2017 11:05:46.09"
    assert time_to_str(0.999, utc) == "Jan 01 1970 00:00:00.00"  # rosbag's %.2f quirk
    plus2 = datetime.timezone(datetime.timedelta(hours=2))
    assert time_to_str(0.5, plus2) == "Jan 01 1970 02:00:00.50"


def test_sample_bag_text(utc: None) -> None:
    assert sample_bag().info(freq=True) == "\n".join([
        "version:     2.0",
        "duration:    1.0s",
        "start:       Jan 01 1970 00:00:00.00 (0.00)",
        "end:         Jan 01 1970 00:00:01.00 (1.00)",
        "size:        5.1 KB",
        "messages:    3",
        "compression: none [1/1 chunks]",
        "types:       std_msgs/Int32  [da5909fbe378aeaf85e547e830cc1bb7]",
        "             std_msgs/String [992ce8a1687cec8c8bd883ec73ca41d1]",
        "topics:      /chatter   2 msgs @ 1.0 Hz : std_msgs/String",
        "             /n         1 msg           : std_msgs/Int32",
    ])
    without = sample_bag().info(freq=False).splitlines()
    assert without[-2:] == ["topics:      /chatter   2 msgs    : std_msgs/String",
                            "             /n         1 msg     : std_msgs/Int32"]
    assert str(sample_bag()) == sample_bag().info(freq=True)
    assert str(Bag.from_bytes(sample_bag().to_bytes(), skip_index=True)) == \
        sample_bag().info(freq=False)


@pytest.mark.parametrize("seconds,text", [(59.94, "59.9s"), (61.5, "1:01s (61s)"),
                                          (3599.0, "59:59s (3599s)"),
                                          (3600 * 2 + 65.0, "2hr 1:05s (7265s)")])
def test_duration_formats(utc: None, seconds: float, text: str) -> None:
    bag = Bag()
    bag.write("/a", Int32(data=0), Time(1000))
    bag.write("/a", Int32(data=1), Time.from_sec(1000 + seconds))
    assert bag.info().splitlines()[1] == f"duration:    {text}"


def test_compression_rows_connections_and_widths(utc: None) -> None:
    bag = Bag(compression="bz2", chunk_threshold=100)
    header = {"type": String._type, "md5sum": String._md5sum,
              "message_definition": String._full_text}
    bag.write("/t", Int32(data=1), Time(100))
    for i in range(30):
        bag._write_raw("/long/topic/name", {**header, "callerid": f"/n{i % 2}"},
                       String(data="x" * 50)._serialize_to_bytes(), 10**9 * (100 + i))
    lines = bag.info(freq=True).splitlines()
    width = len("uncompressed: ")
    rows = {line[:width].strip().rstrip(":"): line[width:] for line in lines
            if not line.startswith(" ")}
    info = bag.get_compression_info()
    n = len(list(bag.reindex()))
    assert n > 3
    ratio = 100.0 * info.compressed / info.uncompressed
    assert rows["compression"] == f"bz2 [{n}/{n} chunks; {ratio:.2f}%]"
    assert rows["uncompressed"].endswith("/s") and " @ " in rows["uncompressed"]
    assert rows["compressed"].endswith("%)")
    assert info.compression == "bz2"
    # rosbag's quirk, kept: the span is first chunk's start to *last* chunk's end
    late = Bag(chunk_threshold=0)
    late.write("/a", Int32(data=0), Time(5))
    late.write("/a", Int32(data=0), Time(1))
    assert late.info().splitlines()[1] == "duration:    -4.0s"
    assert Bag.from_bytes(late.to_bytes()).get_start_time() == 5.0
    assert lines[-2] == ("topics:       /long/topic/name   30 msgs @ 1.0 Hz : std_msgs/String "
                         "(2 connections)")
    assert lines[-1] == "              " + "/t".ljust(16) + "    1 msg " + " " * 9 + " : std_msgs/Int32"


def test_empty_bag_has_only_version_and_size() -> None:
    assert Bag().info() == "version: 2.0\nsize:    4.0 KB"
    assert Bag().yaml_info() == "version: 2.0\nsize: 4117\nindexed: False\n"


def test_yaml_and_keys(utc: None) -> None:
    bag = sample_bag()
    assert bag.yaml_info(freq=True).splitlines()[-7:] == [
        "    - topic: /chatter",
        "      type: std_msgs/String",
        "      messages: 2",
        "      frequency: 1.0000",
        "    - topic: /n",
        "      type: std_msgs/Int32",
        "      messages: 1",
    ]
    text = bag.yaml_info(freq=True)
    assert "      frequency: 1.0000\n" in text and text.startswith("version: 2.0\nduration: ")
    assert bag.yaml_info("duration") == "1.0"
    assert bag.yaml_info("messages") == "3"
    assert bag.yaml_info("compression") == "none"
    assert bag.yaml_info("topics[1].type") == "std_msgs/Int32"
    assert bag.yaml_info("types") == ("- type: std_msgs/Int32\n  md5: da5909fbe378aeaf85e547e830cc1bb7\n"
                                      "- type: std_msgs/String\n  md5: 992ce8a1687cec8c8bd883ec73ca41d1\n")
    for bad in ("nope", "topics[9]", "__class__", "topics.x", "duration()"):
        with pytest.raises(DdesKeyError, match='Error getting key'):
            bag.yaml_info(bad)
