"""Bag renders in notebooks as the tables of ``rosbag info``."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from ddes import Time
from ddes.rosbag import Bag

from .conftest import Int32, String, sample_bag


def cells(html: str) -> dict[str, str]:
    summary = html.split("</table>", 1)[0]
    return dict(re.findall(r"<th[^>]*>([^<]*)</th><td[^>]*>([^<]*)</td>", summary))


def info_rows(text: str) -> dict[str, str]:
    return {k: v.strip() for k, v in re.findall(r"^(\w+):\s+(.*)$", text, re.M)}


@pytest.mark.usefixtures("utc")
def test_the_summary_is_what_rosbag_info_prints(tmp_path: Path) -> None:
    sample_bag().save(tmp_path / "run.bag")
    with Bag(tmp_path / "run.bag") as bag:
        row, info = cells(bag._repr_html_()), info_rows(bag.info())
        assert row["path"] == str(tmp_path / "run.bag")
        for key in ("version", "duration", "start", "end", "size", "messages", "compression"):
            assert row[key] == info[key], key
        assert row["messages"] == "3" and row["start"] == "Jan 01 1970 00:00:00.00 (0.00)"
        html = bag._repr_html_()
    topics = html.split(">topics</caption>", 1)[1]
    assert re.search(r"<code>/chatter</code></td><td[^>]*>2</td><td[^>]*>1.0 Hz</td>"
                     r"<td[^>]*><code>std_msgs/String</code></td><td[^>]*>1</td>", topics)
    assert re.search(r"<code>/n</code></td><td[^>]*>1</td><td[^>]*></td>"
                     r"<td[^>]*><code>std_msgs/Int32</code>", topics)
    types = html.split(">types</caption>", 1)[1].split("</table>", 1)[0]
    assert f"<code>{String._md5sum}</code>" in types and f"<code>{Int32._md5sum}</code>" in types


def test_hostile_topic_names_are_escaped() -> None:
    bag = Bag()
    bag.write("/x<script>alert(1)</script>", String(data="<b>"), Time(1))
    html = bag._repr_html_()
    assert "<script>" not in html and "&lt;script&gt;alert(1)&lt;/script&gt;" in html


def test_empty_in_memory_and_closed_bags() -> None:
    row = cells(Bag()._repr_html_())
    assert row["path"] == "(in memory)" and row["messages"] == "0" and "duration" not in row
    bag = sample_bag()
    bag.close()
    assert bag._repr_html_() == "<p><code>&lt;Bag memory (closed) 2 connections 3 messages&gt;</code></p>"
