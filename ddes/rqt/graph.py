"""``rqt_graph``: the nodes and topics of a running world, as rqt_graph's "Nodes/Topics (all)".

Nodes are ellipses, topics boxes, arrows run publisher -> topic -> subscriber, left to right.
The layout is a layered one of its own (no graphviz): cycles broken by a depth-first search
in name order, each vertex one layer right of its furthest predecessor, then a few
barycentre sweeps ordering each layer, ties broken by name.  The same graph gives the same
picture on every run.

As rqt_graph does by default, the debug topics and node (``/rosout``, ``/rosout_agg``)
are hidden (``hide_debug=False`` shows them).  Unlike rqt_graph's default, topics with
publishers but no subscriber (leaf topics) are shown (``hide_leaf_topics=True`` hides them).
"""

from __future__ import annotations

from typing import Any, NamedTuple

__all__ = ["DEBUG_NAMES", "GraphData", "graph_data", "layered_layout", "rqt_graph"]

#: What rqt_graph's "Hide: Debug" leaves out.
DEBUG_NAMES = ("/rosout", "/rosout_agg")
#: What "Hide: tf" leaves out.
TF_NAMES = ("/tf", "/tf_static")


class GraphData(NamedTuple):
    """Node names, topic names and edges ``(from, to)``; each end is ``("node", name)`` or
    ``("topic", name)``."""

    nodes: list[str]
    topics: list[str]
    edges: list[tuple[tuple[str, str], tuple[str, str]]]


def graph_data(world: Any, *, hide_debug: bool = True, hide_tf: bool = False,
               hide_leaf_topics: bool = False) -> GraphData:
    """The world's graph now: publisher -> topic and topic -> subscriber edges."""
    pubs, subs, _ = world.master.get_system_state()
    hidden_topics = set(DEBUG_NAMES if hide_debug else ()) | set(TF_NAMES if hide_tf else ())
    hidden_nodes = {"/rosout"} if hide_debug else set()
    subscribed = {t for t, nodes in subs if nodes}
    edges: list[tuple[tuple[str, str], tuple[str, str]]] = []
    topics: list[str] = []
    for topic, nodes in sorted(pubs):
        if topic in hidden_topics or (hide_leaf_topics and topic not in subscribed):
            continue
        for n in sorted(nodes):
            if n not in hidden_nodes:
                edges.append((("node", n), ("topic", topic)))
        topics.append(topic)
    for topic, nodes in sorted(subs):
        if topic in hidden_topics:
            continue
        for n in sorted(nodes):
            if n not in hidden_nodes:
                edges.append((("topic", topic), ("node", n)))
        if topic not in topics:
            topics.append(topic)
    names = sorted(set(world.nodes) - hidden_nodes)
    return GraphData(names, sorted(topics), edges)


Vertex = tuple[str, str]


def layered_layout(vertices: list[Vertex], edges: list[tuple[Vertex, Vertex]],
                   sweeps: int = 4) -> dict[Vertex, tuple[int, int]]:
    """``vertex -> (layer, position)``: a deterministic layered (Sugiyama-style) layout."""
    order = sorted(vertices, key=lambda v: (v[1], v[0]))
    out: dict[Vertex, list[Vertex]] = {v: [] for v in order}
    for a, b in edges:
        if b not in out[a]:
            out[a].append(b)
    for v in order:
        out[v].sort(key=lambda w: (w[1], w[0]))
    # break cycles: keep only edges of the DFS forest and cross/forward edges
    state: dict[Vertex, int] = {}
    dag: dict[Vertex, list[Vertex]] = {v: [] for v in order}
    has_in = {b for a, b in edges}
    # sources first, then nodes before topics, each by name: a cycle is entered at a node
    roots = sorted(order, key=lambda v: (v in has_in, v[0] != "node", v[1]))
    for root in roots:
        if root in state:
            continue
        stack: list[tuple[Vertex, int]] = [(root, 0)]
        state[root] = 1
        while stack:
            v, i = stack[-1]
            if i < len(out[v]):
                stack[-1] = (v, i + 1)
                w = out[v][i]
                if state.get(w) == 1:
                    continue  # a back edge: drawn, but not used for layering
                dag[v].append(w)
                if w not in state:
                    state[w] = 1
                    stack.append((w, 0))
            else:
                state[v] = 2
                stack.pop()
    preds: dict[Vertex, list[Vertex]] = {v: [] for v in order}
    for v in order:
        for w in dag[v]:
            preds[w].append(v)
    layer: dict[Vertex, int] = {}

    def depth(v: Vertex) -> int:
        if v not in layer:
            todo = [v]
            while todo:
                u = todo[-1]
                missing = [p for p in preds[u] if p not in layer]
                if missing:
                    todo.extend(missing)
                    continue
                todo.pop()
                layer[u] = max((layer[p] + 1 for p in preds[u]), default=0)
        return layer[v]

    for v in order:
        depth(v)
    n_layers = max(layer.values(), default=-1) + 1
    rows: list[list[Vertex]] = [[v for v in order if layer[v] == k] for k in range(n_layers)]
    neighbours: dict[Vertex, list[Vertex]] = {v: [] for v in order}
    for v in order:
        for w in dag[v]:
            neighbours[v].append(w)
            neighbours[w].append(v)
    for sweep in range(sweeps):
        forward = sweep % 2 == 0
        ks = range(1, n_layers) if forward else range(n_layers - 2, -1, -1)
        for k in ks:
            ref = rows[k - 1] if forward else rows[k + 1]
            pos = {v: i for i, v in enumerate(ref)}
            current = {v: i for i, v in enumerate(rows[k])}

            def key(v: Vertex, pos: dict[Vertex, int] = pos,
                    current: dict[Vertex, int] = current) -> tuple[float, int]:
                near = [pos[w] for w in neighbours[v] if w in pos]
                return (sum(near) / len(near) if near else float(current[v]), current[v])

            rows[k] = sorted(rows[k], key=key)
    return {v: (k, i) for k, row in enumerate(rows) for i, v in enumerate(row)}


def rqt_graph(world: Any, *, hide_debug: bool = True, hide_tf: bool = False,
              hide_leaf_topics: bool = False, ax: Any = None, title: str | None = None) -> Any:
    """Draw the world's node/topic graph; returns the figure (a new DisplayFigure unless
    ``ax`` is given).  Artists carry gids: ``node:/talker``, ``topic:/chatter``,
    ``edge:/talker->/chatter``."""
    from ddes.display.figure import new_figure

    data = graph_data(world, hide_debug=hide_debug, hide_tf=hide_tf,
                      hide_leaf_topics=hide_leaf_topics)
    vertices = [("node", n) for n in data.nodes] + [("topic", t) for t in data.topics]
    place = layered_layout(vertices, data.edges)
    n_layers = max((k for k, _ in place.values()), default=0) + 1
    height = max((sum(1 for k2, _ in place.values() if k2 == k) for k in range(n_layers)),
                 default=1)
    if ax is None:
        fig = new_figure(figsize=(min(3.0 + 2.6 * n_layers, 24.0), min(1.5 + 0.75 * height, 18.0)))
        ax = fig.add_subplot(1, 1, 1)
    else:
        fig = ax.figure
    ax.set_axis_off()
    ax.set_title(title if title is not None else "rqt_graph", fontsize=11)
    xy: dict[Vertex, tuple[float, float]] = {}
    for v, (k, i) in place.items():
        size = sum(1 for k2, _ in place.values() if k2 == k)
        xy[v] = (3.0 * k, (size - 1) / 2.0 - i)
    texts = {}
    for v in vertices:
        x, y = xy[v]
        kind, name = v
        style = ({"boxstyle": "ellipse,pad=0.35", "fc": "#f4f4f4", "ec": "#1f3b73", "lw": 1.2}
                 if kind == "node" else
                 {"boxstyle": "square,pad=0.35", "fc": "#ffffff", "ec": "#5a7a2a", "lw": 1.2})
        texts[v] = ax.text(x, y, name, ha="center", va="center", fontsize=9, bbox=style,
                           zorder=3, gid=f"{kind}:{name}")
    for a, b in data.edges:
        # drawn after the labels (zorder 4 > 3), so the label boxes are placed when the
        # arrow is clipped to them (patchA/patchB)
        back = xy[b][0] <= xy[a][0]
        ax.annotate("", xy=xy[b], xytext=xy[a],
                    arrowprops={"arrowstyle": "-|>", "color": "#444444", "lw": 1.0,
                                "patchA": texts[a].get_bbox_patch(),
                                "patchB": texts[b].get_bbox_patch(), "shrinkA": 1, "shrinkB": 1,
                                "connectionstyle": "arc3,rad=0.35" if back else "arc3,rad=0.0"},
                    zorder=4, gid=f"edge:{a[1]}->{b[1]}")
    if not vertices:
        ax.text(0.5, 0.5, "no nodes", ha="center", va="center", transform=ax.transAxes)
        return fig
    xs = [p[0] for p in xy.values()]
    ys = [p[1] for p in xy.values()]
    ax.set_xlim(min(xs) - 1.6, max(xs) + 1.6)
    ax.set_ylim(min(ys) - 0.8, max(ys) + 0.8)
    return fig
