"""rqt_graph: the edges are the world's publishers and subscribers; the layout is layered and
the same every time."""

from __future__ import annotations

from pathlib import Path

import ddes
from ddes.msg import get_message_class
from ddes.rqt.graph import graph_data, layered_layout, rqt_graph

String = get_message_class("std_msgs/String")


def chain(cycle: bool = False) -> ddes.World:
    world = ddes.World(seed=0)
    a, b, c = (world.create_node(n) for n in ("talker", "relay", "listener"))
    a.advertise("/chatter", String, queue_size=1)
    b.subscribe("/chatter", String)
    b.advertise("/relayed", String, queue_size=1)
    c.subscribe("/relayed", String)
    c.advertise("/feedback", String, queue_size=1)
    if cycle:
        a.subscribe("/feedback", String)
    world.run(until=0.1)
    return world


def test_edges_match_the_master() -> None:
    world = chain()
    data = graph_data(world)
    pubs, subs, _ = world.master.get_system_state()
    expected = {(("node", n), ("topic", t)) for t, ns in pubs for n in ns if t != "/rosout"}
    expected |= {(("topic", t), ("node", n)) for t, ns in subs for n in ns
                 if t not in ("/rosout", "/rosout_agg") and n != "/rosout"}
    assert set(data.edges) == expected and len(data.edges) == len(expected)
    assert data.topics == ["/chatter", "/feedback", "/relayed"]
    assert "/rosout" not in data.nodes and "/rosout" in graph_data(world, hide_debug=False).topics


def test_figure_artists_and_layout(tmp_path: Path) -> None:
    world = chain()
    fig = rqt_graph(world)
    ax = fig.axes[0]
    gids = {a.get_gid() for a in ax.get_children() if a.get_gid()}
    for name in ("node:/talker", "node:/relay", "node:/listener", "topic:/chatter"):
        assert name in gids
    edges = {g for g in gids if g.startswith("edge:")}
    assert edges == {f"edge:{a[1]}->{b[1]}" for a, b in graph_data(world).edges}
    texts = {t.get_gid(): t.get_position() for t in ax.texts if t.get_gid()}
    # left to right along the chain: talker, /chatter, relay, /relayed, listener
    xs = [texts[g][0] for g in ("node:/talker", "topic:/chatter", "node:/relay",
                                 "topic:/relayed", "node:/listener")]
    assert xs == sorted(xs) and len(set(xs)) == 5
    assert texts["node:/listener"][0] < texts["topic:/feedback"][0]
    looped = {t.get_gid(): t.get_position() for t in rqt_graph(chain(cycle=True)).axes[0].texts
              if t.get_gid()}
    assert len({p[0] for p in looped.values()}) == 6        # the cycle broken: six layers
    out = tmp_path / "graph.png"
    fig.savefig(out)
    assert out.read_bytes()[:4] == b"\x89PNG"
    again = rqt_graph(chain()).axes[0]
    assert {t.get_gid(): t.get_position() for t in again.texts if t.get_gid()} == texts


def test_layered_layout_orders_by_name_and_breaks_cycles() -> None:
    a, b, t = ("node", "a"), ("node", "b"), ("topic", "t")
    place = layered_layout([b, a, t], [(a, t), (b, t)])
    assert place == {a: (0, 0), b: (0, 1), t: (1, 0)}
    # a -> t -> a is a cycle; b is the only source, so the search starts there
    place = layered_layout([b, a, t], [(a, t), (b, t), (t, a)])
    assert place[b] == (0, 0) and place[t][0] == 1 and place[a][0] == 2
