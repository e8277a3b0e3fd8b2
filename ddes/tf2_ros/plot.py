"""A drawing of the TF tree: ``plot_frames(buffer)``, view_frames' picture with matplotlib.

Frames are boxes, each parent above its children (roots at the top, children in the order tf2
lists them), every edge labelled as view_frames labels it, shortened: the broadcaster
(authority) and the average rate (``static`` for a static transform, which tf2 reports as rate
10000 at time 0).  The figure is a :class:`ddes.display.figure.DisplayFigure` (no pyplot, shown by a
notebook as it is); ``fig.savefig("frames.pdf")`` writes the file view_frames would.
"""

from __future__ import annotations

from typing import Any

from ddes.tf2_ros.tools import frames_data

__all__ = ["plot_frames", "tree_layout"]

#: tf2's rate for a frame whose cache is static (``allFramesAsYAML``'s 10000).
_STATIC_RATE = 10000.0


def tree_layout(data: dict[str, dict[str, Any]]) -> dict[str, tuple[float, int]]:
    """``frame -> (x, depth)``: roots at depth 0, leaves spread one unit apart, parents centred."""
    children: dict[str, list[str]] = {}
    frames: list[str] = []
    for child, info in data.items():
        parent = str(info["parent"])
        children.setdefault(parent, []).append(str(child))
        for f in (parent, str(child)):
            if f not in frames:
                frames.append(f)
    roots = [f for f in frames if f not in data or str(data[f]["parent"]) not in frames]
    pos: dict[str, tuple[float, int]] = {}
    next_x = [0.0]

    def place(frame: str, depth: int, seen: tuple[str, ...]) -> float:
        kids = [k for k in children.get(frame, []) if k not in seen and k not in pos]
        if not kids:
            x = next_x[0]
            next_x[0] += 1.0
        else:
            xs = [place(k, depth + 1, seen + (frame,)) for k in kids]
            x = (xs[0] + xs[-1]) / 2.0
        pos[frame] = (x, depth)
        return x

    for r in roots:
        place(r, 0, ())
    for f in frames:  # a loop has no root: start it anywhere
        if f not in pos:
            place(f, 0, ())
    return pos


def _is_static(info: dict[str, Any]) -> bool:
    """tf2 reports a static frame as rate 10000 with both stamps 0."""
    return bool(info.get("rate") == _STATIC_RATE and not info.get("most_recent_transform")
                and not info.get("oldest_transform"))


def _label(info: dict[str, Any]) -> str:
    rate = info.get("rate")
    rate_text = "static" if _is_static(info) else f"{float(rate or 0):.1f} Hz"
    return f"{info.get('broadcaster', '')}\n{rate_text}"


def plot_frames(buffer: Any, *, title: str | None = None, ax: Any = None) -> Any:
    """Draw ``buffer``'s frames as a tree; returns the figure (a new one unless ``ax`` is given).

    ``buffer`` is a Buffer/BufferCore, or the mapping of ``yaml.safe_load(all_frames_as_yaml())``.
    """
    from ddes.display.figure import new_figure

    data = buffer if isinstance(buffer, dict) else frames_data(buffer)
    pos = tree_layout(data)
    width = max(4.0, 1.8 * (max((x for x, _ in pos.values()), default=0.0) + 1))
    depth = max((d for _, d in pos.values()), default=0)
    if ax is None:
        fig = new_figure(figsize=(min(width, 16.0), 1.6 + 1.3 * depth))
        ax = fig.add_subplot(1, 1, 1)
    else:
        fig = ax.figure
    ax.set_axis_off()
    ax.set_title(title if title is not None else "TF tree", fontsize=11)
    if not pos:
        ax.text(0.5, 0.5, "No tf data received", ha="center", va="center", fontsize=11,
                transform=ax.transAxes)
        return fig
    for child, info in data.items():
        parent = str(info["parent"])
        (x0, d0), (x1, d1) = pos[parent], pos[str(child)]
        ax.annotate("", xy=(x1, -d1 + 0.18), xytext=(x0, -d0 - 0.18),
                    arrowprops={"arrowstyle": "->", "color": "0.35", "lw": 1.2})
        ax.text((x0 + x1) / 2.0, -(d0 + d1) / 2.0, _label(info), ha="center", va="center",
                fontsize=9, color="0.2",
                bbox={"boxstyle": "round,pad=0.2", "fc": "white", "ec": "none", "alpha": 0.85})
    for frame, (x, d) in pos.items():
        static = frame in data and _is_static(data[frame])
        ax.text(x, -d, frame, ha="center", va="center", fontsize=10,
                bbox={"boxstyle": "round,pad=0.35", "fc": "#e8eef7" if not static else "#eef7e8",
                      "ec": "#3b5b92" if not static else "#3b8a3b"})
    xs = [x for x, _ in pos.values()]
    ax.set_xlim(min(xs) - 0.7, max(xs) + 0.7)
    ax.set_ylim(-depth - 0.5, 0.5)
    return fig
