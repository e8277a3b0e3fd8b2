"""Trace and TraceSelection render as escaped HTML tables in notebooks."""

from __future__ import annotations

import ddes
from ddes.msg import get_message_class

String = get_message_class("std_msgs/String")


def test_a_selection_is_a_table_of_t_kind_source_details(world: ddes.World) -> None:
    node = world.create_node("talker")
    pub = node.advertise("/chatter", String, queue_size=10)
    world.run(until=0.5)
    pub.publish(String(data="hi"))
    sel = world.trace.select(kind="topic.publish", source="/talker")
    html = sel._repr_html_()
    assert html.startswith("<table") and "<th" in html
    assert [h in html for h in ("t [s]", "kind", "source", "details")] == [True] * 4
    (ev,) = [e for e in sel if e.details["topic"] == "/chatter"]
    assert f"{ev.t / 1e9:.9f}" in html and "<code>topic.publish</code>" in html
    assert "<code>/talker</code>" in html and "topic=/chatter" in html
    assert f"{len(sel)} event" in html and "more" not in html


def test_long_selections_stop_after_50_rows(world: ddes.World) -> None:
    for i in range(120):
        world.record("test.mark", "/me", i=i)
    sel = world.trace.select(kind="test.mark")
    html = sel._repr_html_()
    assert html.count("<tr>") == 1 + 50 + 1
    assert "i=49<" in html and "i=50<" not in html
    assert "... 70 more rows" in html
    assert "120 events (test.mark ×120)" in html
    whole = world.trace._repr_html_()
    assert f"trace: {len(world.trace)} events stored" in whole
    assert f"... {len(world.trace) - 50} more rows" in whole


def test_hostile_log_text_is_escaped(world: ddes.World) -> None:
    node = world.create_node("n")
    node.loginfo("<script>alert('pwned')</script> & <b>bold</b>")
    node.set_param("~note", "<img src=x onerror=alert(1)>")
    world.run(until=0.1)
    for html in (world.trace.select()._repr_html_(), world.trace._repr_html_()):
        assert "<script>" not in html and "<b>" not in html and "<img" not in html
        assert "&lt;script&gt;alert(&#x27;pwned&#x27;)&lt;/script&gt; &amp; &lt;b&gt;" in html


def test_counted_only_events_are_mentioned(world: ddes.World) -> None:
    world.trace.enabled = False
    world.record("test.mark", "/me")
    assert "0 events stored, 1 counted only" in world.trace._repr_html_()
