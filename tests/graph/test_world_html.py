"""ddes.World renders as a compact HTML summary in notebooks."""

from __future__ import annotations

import re

import ddes
from ddes.msg import get_message_class, get_service_class

from ..docsnippets import run_snippet

String = get_message_class("std_msgs/String")
AddTwoInts = get_service_class("rospy_tutorials/AddTwoInts")


def cells(html: str) -> dict[str, str]:
    """The name: value rows of the summary table."""
    summary = html.split("</table>", 1)[0]
    return dict(re.findall(r"<th[^>]*>([^<]*)</th><td[^>]*>([^<]*)</td>", summary))


def test_the_summary_names_seed_time_nodes_topics_services_params_trace() -> None:
    world = ddes.World(seed=7)
    talker = world.create_node("talker")
    world.create_node("listener").subscribe("/chatter", String, lambda m: None)
    talker.advertise("/chatter", String, queue_size=1)
    ddes.Service(talker, "/add", AddTwoInts, lambda req: req.a + req.b)
    world.params.set_param("/rate", 10)
    world.params.set_param("/robot/name", "r2")
    world.run(until=1.5)
    html = world._repr_html_()
    row = cells(html)
    assert row["seed"] == "7" and row["time"] == "1.500000000 s"
    assert row["nodes"] == "2: /listener, /talker"
    assert row["parameters"] == str(len(world.params.get_param_names()))
    assert int(row["parameters"]) >= 2
    assert row["services"] == "1" and row["topics"] == str(
        len(world.master.get_topic_types()))
    assert row["trace"] == f"{len(world.trace)} events"
    assert row["digest"] == world.digest()[:16] + "…"
    assert "<caption" in html and ">World<" in html
    topics = html.split(">topics</caption>", 1)[1].split("</table>", 1)[0]
    assert "<code>/chatter</code>" in topics and "<code>std_msgs/String</code>" in topics
    assert "/talker" in topics and "/listener" in topics
    services = html.split(">services</caption>", 1)[1].split("</table>", 1)[0]
    assert "<code>/add</code>" in services and "rospy_tutorials/AddTwoInts" in services


def test_a_world_with_a_filtered_trace_says_it_has_no_digest() -> None:
    world = ddes.World()
    world.trace.set_filter(exclude=["log"])
    world.create_node("n").loginfo("hello")
    world.run(until=0.1)
    assert cells(world._repr_html_())["digest"] == "none: the trace does not hold every event"


def test_an_empty_world() -> None:
    row = cells(ddes.World()._repr_html_())
    assert row["nodes"] == "0" and row["topics"] == "0" and row["time"] == "0.000000000 s"


def test_the_notebook_snippet_of_docs_graph_md_runs() -> None:
    from pathlib import Path

    text = (Path(__file__).resolve().parents[2] / "docs" / "graph.md").read_text(encoding="utf-8")
    section = text[text.index("## In a notebook"):]
    (block,) = re.findall(r"```python\n(.*?)```", section, flags=re.S)
    run_snippet(block, "docs/graph.md", "'In a notebook' block")
