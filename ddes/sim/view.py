"""An RViz-like top view of the simulator: ``top_view(sim)`` and ``animate(sim)``.

Drawn in the world frame (the simulator's ground truth) with matplotlib's object API (no
pyplot): the obstacles (circles, segments, boxes), the robot's footprint at its true pose, the
points of a laser scan, the TF frames as small axes (x red, y green), optional
visualization_msgs/Marker, and the trajectory from ``sim.history()``.  ``top_view`` returns a
:class:`ddes.display.figure.DisplayFigure` (a notebook shows it; ``fig.savefig("top.png")``);
``animate`` returns a :class:`TopViewAnimation` (``save("run.gif")`` with Pillow, which
matplotlib depends on; ``save("run.html")`` or, in a notebook, the animation itself as
JavaScript HTML).

Where things come from:

* the scan: ``scan="latest"`` (default) is the last ``/scan`` message in the world's trace
  (every publish holds its bytes), drawn from the laser's true pose at the scan's stamp; a
  LaserScan message is drawn the same way; ``None``/``False`` draws none.  With no scan in the
  trace it casts one noiseless scan now (``sim.ranges()``);
* frames: ``odom`` at the start pose (the odometry frame starts at the robot), ``base_link``,
  ``base_laser`` and ``imu_link`` at the true pose; ``odometry=True`` adds a dashed footprint
  where the wheel odometry believes the robot is;
* markers: ``markers="/visualization_marker"`` draws the last marker of each (ns, id) on that
  topic (ADD/DELETE/DELETEALL; a visualization_msgs/MarkerArray topic too), in frames
  ``world``/``map``/``odom``/``base_link``/``base_laser``/``imu_link``; colours with their
  alpha, as RViz shows them.  ``markers=[(x, y), ...]`` draws plain points in the world;
* collisions: ``sim.collisions`` as red crosses at the robot's pose of each contact.

Drawing records nothing and draws from no random stream: looking never changes a run.

The trig is :mod:`ddes.transformations`' (the same bits on every machine), so the same run
draws the same figure data.
"""

from __future__ import annotations

import math
import os
from collections.abc import Sequence
from typing import Any

from ddes.errors import DdesValueError
from ddes.sim._trig import atan2, sincos
from ddes.sim.simulator import IMU_OFFSET, LASER_OFFSET, Pose2D, Simulator
from ddes.sim.worlds import Box, Circle, Segment

__all__ = ["TopViewAnimation", "animate", "footprint_corners", "scan_points", "top_view"]

_ROBOT_FC = "#4a78c2"
_OBSTACLE_FC = "#9a9a9a"


def _compose(a: Pose2D, bx: float, by: float, byaw: float = 0.0) -> Pose2D:
    s, c = sincos(a.yaw)
    return Pose2D(a.x + c * bx - s * by, a.y + s * bx + c * by, a.yaw + byaw)


def footprint_corners(pose: Pose2D | Sequence[float], length: float = 0.605,
                      width: float = 0.410) -> list[tuple[float, float]]:
    """The footprint's corners in the world: front-left, rear-left, rear-right, front-right."""
    p = Pose2D(float(pose[0]), float(pose[1]), float(pose[2]))
    hx, hy = length / 2.0, width / 2.0
    return [(q.x, q.y) for q in (_compose(p, sx, sy) for sx, sy in
                                 ((hx, hy), (-hx, hy), (-hx, -hy), (hx, -hy)))]


def _pose_at(sim: Simulator, stamp_ns: int | None) -> Pose2D:
    """The true pose at a simulated stamp (the 10 Hz history sample at or before it)."""
    if stamp_ns is None:
        return sim.pose
    h = sim.history()
    best = None
    for i, t in enumerate(h.t_ns):
        if t <= stamp_ns:
            best = i
        else:
            break
    if best is None:
        return sim.pose
    return Pose2D(h.x[best], h.y[best], h.yaw[best])


def _scan_topic(sim: Simulator) -> str:
    return str(sim.node.resolve_name("scan"))


def _latest(world: Any, topic: str, until_ns: int | None = None) -> tuple[int, Any] | None:
    """The last message published on ``topic`` (at or before kernel time ``until_ns``)."""
    first = world.trace.select(kind="topic.advertise", topic=topic).first()
    entry = world.master.topics.get(topic)
    type_name = first.details["type"] if first is not None else entry.type if entry else None
    if type_name is None:
        return None
    events = world.trace.select(kind="topic.publish", topic=topic, until_ns=until_ns)
    if not events:
        return None
    ev = events[-1]
    return ev.t, world.messages.get_message_class(type_name)().deserialize(ev.details["data"])


def scan_points(sim: Simulator, scan: Any = "latest") -> list[tuple[float, float]]:
    """The finite returns of a scan as world points, from the laser's true pose at its stamp.

    ``scan``: ``"latest"`` (the last ``/scan`` in the trace, else one noiseless scan now),
    a sensor_msgs/LaserScan, or a list of ranges taken now (``sim.ranges()``).
    """
    if isinstance(scan, str):
        if scan != "latest":
            raise DdesValueError(f"scan must be 'latest', a LaserScan or a list of ranges, got "
                                 f"{scan!r}")
        found = _latest(sim.world, _scan_topic(sim))
        scan = found[1] if found is not None else sim.ranges()
    if isinstance(scan, (list, tuple)):
        from ddes.sim.simulator import ANGLE_INCREMENT, ANGLE_MIN

        ranges, a0, inc, pose = list(scan), ANGLE_MIN, ANGLE_INCREMENT, sim.pose
    else:
        ranges, a0, inc = list(scan.ranges), float(scan.angle_min), float(scan.angle_increment)
        pose = _pose_at(sim, scan.header.stamp.to_nsec())
    laser = _compose(pose, LASER_OFFSET[0], LASER_OFFSET[1])
    out = []
    for i, r in enumerate(ranges):
        if math.isfinite(r):
            s, c = sincos(laser.yaw + (a0 + i * inc))
            out.append((laser.x + r * c, laser.y + r * s))
    return out


def _yaw_of(q: Any) -> float:
    return atan2(2.0 * (q.w * q.z + q.x * q.y), 1.0 - 2.0 * (q.y * q.y + q.z * q.z))


def _frame_pose(sim: Simulator, frame: str, stamp_ns: int | None) -> Pose2D | None:
    frame = frame.lstrip("/")
    if frame in ("", "world", "map"):
        return Pose2D(0.0, 0.0, 0.0)
    if frame == "odom":
        return _start(sim)
    base = _pose_at(sim, stamp_ns)
    if frame == "base_link":
        return base
    if frame == "base_laser":
        return _compose(base, LASER_OFFSET[0], LASER_OFFSET[1])
    if frame == "imu_link":
        return _compose(base, IMU_OFFSET[0], IMU_OFFSET[1])
    return None


def _start(sim: Simulator) -> Pose2D:
    """Where the odom frame lies in the world: the start pose (the odometry starts there)."""
    return sim._start  # noqa: SLF001 - same package


def _markers(sim: Simulator, topic: str) -> list[tuple[Pose2D, Any]]:
    """The markers RViz would show now: the last ADD of each (ns, id), minus deletions."""
    world = sim.world
    first = world.trace.select(kind="topic.advertise", topic=topic).first()
    if first is None:
        return []
    cls = world.messages.get_message_class(first.details["type"])
    shown: dict[tuple[str, int], Any] = {}
    for ev in world.trace.select(kind="topic.publish", topic=topic):
        msg = cls().deserialize(ev.details["data"])
        for m in getattr(msg, "markers", None) or [msg]:  # a MarkerArray or a Marker
            if m.action == 3:
                shown.clear()
            elif m.action == 2:
                shown.pop((m.ns, m.id), None)
            else:
                shown[(m.ns, m.id)] = m
    out = []
    for m in shown.values():
        stamp = m.header.stamp.to_nsec() or None
        frame = _frame_pose(sim, m.header.frame_id, stamp)
        if frame is not None:
            out.append((frame, m))
    return out


def _draw_marker(ax: Any, frame: Pose2D, m: Any) -> None:
    from matplotlib.patches import Circle as CirclePatch
    from matplotlib.patches import FancyArrow, Polygon

    color = (m.color.r, m.color.g, m.color.b, m.color.a)
    gid = f"marker:{m.ns}/{m.id}"
    p = _compose(frame, m.pose.position.x, m.pose.position.y, _yaw_of(m.pose.orientation))
    if m.type in (2, 3):  # SPHERE, CYLINDER
        ax.add_patch(CirclePatch((p.x, p.y), m.scale.x / 2.0, color=color, zorder=5, gid=gid))
    elif m.type == 1:  # CUBE
        ax.add_patch(Polygon(footprint_corners(p, m.scale.x, m.scale.y), closed=True,
                             color=color, zorder=5, gid=gid))
    elif m.type == 0:  # ARROW (pose form)
        s, c = sincos(p.yaw)
        ax.add_patch(FancyArrow(p.x, p.y, c * m.scale.x, s * m.scale.x, width=m.scale.y or 0.05,
                                length_includes_head=True, color=color, zorder=5, gid=gid))
    elif m.type in (4, 5, 6, 7, 8):  # LINE_STRIP, LINE_LIST, CUBE_LIST, SPHERE_LIST, POINTS
        pts = [_compose(p, q.x, q.y) for q in m.points]
        xs, ys = [q.x for q in pts], [q.y for q in pts]
        if m.type == 4:
            ax.plot(xs, ys, color=color, zorder=5, gid=gid)
        elif m.type == 5:
            for i in range(0, len(pts) - 1, 2):
                ax.plot(xs[i:i + 2], ys[i:i + 2], color=color, zorder=5, gid=gid)
        else:
            ax.plot(xs, ys, "o", color=color, markersize=4, zorder=5, gid=gid)
    elif m.type == 9:  # TEXT_VIEW_FACING
        ax.text(p.x, p.y, m.text, color=color, ha="center", va="center", zorder=5, gid=gid)


def _draw_frame(ax: Any, pose: Pose2D, name: str, size: float, label: bool = True) -> None:
    s, c = sincos(pose.yaw)
    ax.plot([pose.x, pose.x + c * size], [pose.y, pose.y + s * size], color="#d62728", lw=1.5,
            zorder=6, gid=f"frame:{name}:x")
    ax.plot([pose.x, pose.x - s * size], [pose.y, pose.y + c * size], color="#2ca02c", lw=1.5,
            zorder=6, gid=f"frame:{name}:y")
    if label:
        ax.text(pose.x - 0.05 * size, pose.y - 0.05 * size, name, fontsize=7, color="0.25",
                ha="right", va="top", zorder=6)


def _draw_world(ax: Any, sim: Simulator) -> None:
    from matplotlib.patches import Circle as CirclePatch
    from matplotlib.patches import Polygon

    for ob in sim.obstacles:
        gid = f"obstacle:{ob.name}"
        if isinstance(ob, Circle):
            ax.add_patch(CirclePatch((ob.x, ob.y), ob.radius, fc=_OBSTACLE_FC, ec="0.3", zorder=2,
                                     gid=gid))
        elif isinstance(ob, Box):
            ax.add_patch(Polygon(list(ob.corners()), closed=True, fc=_OBSTACLE_FC, ec="0.3",
                                 zorder=2, gid=gid))
        elif isinstance(ob, Segment):
            ax.plot([ob.x1, ob.x2], [ob.y1, ob.y2], color="0.3", lw=2.5, zorder=2, gid=gid)


def _extent(sim: Simulator, extra: list[tuple[float, float]]) -> tuple[float, float, float, float]:
    xs, ys = [p[0] for p in extra], [p[1] for p in extra]
    for ob in sim.obstacles:
        cx, cy, r = ob.bounds()
        xs += [cx - r, cx + r]
        ys += [cy - r, cy + r]
    return min(xs), max(xs), min(ys), max(ys)


def _fit(fig: Any, dx: float, dy: float) -> None:
    """Size a new figure to the view's aspect (7 in wide, 3 to 9 in high)."""
    if dx > 0.0:
        fig.set_size_inches(7.0, min(9.0, max(3.0, 7.0 * dy / dx + 0.8)))


def top_view(sim: Simulator, *, scan: Any = "latest", frames: bool = True,
             trajectory: bool = True, markers: Any = None, odometry: bool = False,
             extent: tuple[float, float, float, float] | None = None, margin: float = 1.0,
             ax: Any = None, title: str | None = None) -> Any:
    """Draw the simulator's world now, from above; returns the figure (see the module text).

    ``extent`` is ``(xmin, xmax, ymin, ymax)`` in metres (default: the obstacles, the
    trajectory and the scan points, plus ``margin``).  Artists carry gids:
    ``obstacle:NAME``, ``robot``, ``odometry``, ``scan``, ``trajectory``, ``frame:NAME:x``,
    ``marker:NS/ID``, ``markers``, ``collisions``.  The legend names the trajectory, the
    scan topic and the collisions.
    """
    from matplotlib.patches import Polygon

    from ddes.display.figure import new_figure

    if ax is None:
        fig = new_figure(figsize=(7.0, 6.0))
        ax = fig.add_subplot(1, 1, 1)
        fit = True
    else:
        fig, fit = ax.figure, False
    ax.set_aspect("equal")
    ax.grid(True, color="0.92", zorder=0)
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    _draw_world(ax, sim)
    pose = sim.pose
    corners = footprint_corners(pose, sim.footprint.length, sim.footprint.width)
    seen = list(corners)
    if trajectory:
        h = sim.history()
        ax.plot(h.x + [pose.x], h.y + [pose.y], color=_ROBOT_FC, lw=1.2, alpha=0.7, zorder=3,
                gid="trajectory", label="trajectory (truth)")
        seen += list(zip(h.x, h.y))
    if scan is not None and scan is not False:
        pts = scan_points(sim, scan)
        ax.plot([p[0] for p in pts], [p[1] for p in pts], ".", color="#e0301e", markersize=2.5,
                zorder=4, gid="scan", label=_scan_topic(sim))
        seen += pts
    if sim.collisions:
        ax.plot([c.pose.x for c in sim.collisions], [c.pose.y for c in sim.collisions], "x",
                color="#d00000", markersize=9, mew=2.0, zorder=7, gid="collisions",
                label="collisions")
    if odometry:
        est = _compose(_start(sim), *sim.odometry)
        ax.add_patch(Polygon(footprint_corners(est, sim.footprint.length, sim.footprint.width),
                             closed=True, fill=False, ec=_ROBOT_FC, ls="--", zorder=4,
                             gid="odometry"))
    ax.add_patch(Polygon(corners, closed=True, fc=_ROBOT_FC, ec="#1f3b73", alpha=0.85, zorder=5,
                         gid="robot"))
    if isinstance(markers, str):
        for frame, m in _markers(sim, str(sim.node.resolve_name(markers))):
            _draw_marker(ax, frame, m)
    elif markers:
        xy = [(float(p[0]), float(p[1])) for p in markers]
        ax.plot([p[0] for p in xy], [p[1] for p in xy], "o", color="#9b30d0", markersize=6,
                zorder=6, gid="markers")
    if frames:
        size = 0.35
        _draw_frame(ax, _start(sim), "odom", size)
        _draw_frame(ax, pose, "base_link", size)
        _draw_frame(ax, _compose(pose, LASER_OFFSET[0], LASER_OFFSET[1]), "base_laser", size * 0.6,
                    label=False)
    x0, x1, y0, y1 = extent if extent is not None else _extent(sim, seen)
    if extent is None:
        x0, x1, y0, y1 = x0 - margin, x1 + margin, y0 - margin, y1 + margin
    ax.set_xlim(x0, x1)
    ax.set_ylim(y0, y1)
    if fit:
        _fit(fig, x1 - x0, y1 - y0)
    if ax.get_legend_handles_labels()[0]:
        ax.legend(loc="best", fontsize=8)
    t = sim.sim_time.to_sec()
    ax.set_title(title if title is not None else
                 f"{sim.spec.name or 'world'} at t = {t:.2f} s", fontsize=11)
    return fig


class TopViewAnimation:
    """A top-view animation: ``save(path)`` (``.gif`` with Pillow, ``.html`` as JavaScript
    HTML), ``to_jshtml()``; a notebook shows it as its JavaScript player."""

    def __init__(self, figure: Any, animation: Any, frames: int) -> None:
        self.figure = figure
        self.animation = animation
        self.frames = frames

    def save(self, path: str | os.PathLike[str], fps: float | None = None) -> str:
        """Write the animation; returns the path.  ``.gif``: PillowWriter; ``.html``: jshtml."""
        from matplotlib.animation import PillowWriter

        path = os.fspath(path)
        fps = fps if fps is not None else self._fps
        if path.endswith(".gif"):
            self.animation.save(path, writer=PillowWriter(fps=round(fps)), dpi=self.figure.dpi)
        elif path.endswith((".html", ".htm")):
            with open(path, "w", encoding="utf-8") as f:
                f.write(self.to_jshtml())
        else:
            raise DdesValueError(f"save: {path!r} must end in .gif or .html (writers that need "
                                 "no external program)")
        return path

    _fps: float = 10.0

    def to_jshtml(self) -> str:
        """The animation as a self-contained HTML/JavaScript player."""
        return str(self.animation.to_jshtml(fps=self._fps))

    def _repr_html_(self) -> str:
        return self.to_jshtml()


def animate(sim: Simulator, *, every: int = 1, fps: float = 10.0, scans: bool = True,
            trajectory: bool = True, extent: tuple[float, float, float, float] | None = None,
            margin: float = 1.0, title: str | None = None) -> TopViewAnimation:
    """Replay the run's history (10 Hz samples, each ``every``-th) as an animation.

    Each frame shows the robot's footprint at that sample, the trajectory up to it and,
    with ``scans``, the ``/scan`` published at that stamp (from the trace).
    """
    from matplotlib.animation import FuncAnimation
    from matplotlib.patches import Polygon

    from ddes.display.figure import new_figure

    if every < 1:
        raise DdesValueError(f"every must be >= 1, got {every!r}")
    h = sim.history()
    if not h.t_ns:
        raise DdesValueError("animate: the simulator has no history yet; run the world first")
    idx = list(range(0, len(h.t_ns), every))
    by_stamp: dict[int, list[tuple[float, float]]] = {}
    if scans:
        found = _latest(sim.world, _scan_topic(sim))
        if found is not None:
            cls = type(found[1])
            for ev in sim.world.trace.select(kind="topic.publish", topic=_scan_topic(sim)):
                msg = cls().deserialize(ev.details["data"])
                by_stamp[msg.header.stamp.to_nsec()] = scan_points(sim, msg)
    fig = new_figure(figsize=(7.0, 6.0))
    ax = fig.add_subplot(1, 1, 1)
    ax.set_aspect("equal")
    ax.grid(True, color="0.92", zorder=0)
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    _draw_world(ax, sim)
    fp = sim.footprint
    seen = list(zip(h.x, h.y))
    x0, x1, y0, y1 = extent if extent is not None else _extent(sim, seen)
    if extent is None:
        x0, x1, y0, y1 = x0 - margin, x1 + margin, y0 - margin, y1 + margin
    ax.set_xlim(x0, x1)
    ax.set_ylim(y0, y1)
    _fit(fig, x1 - x0, y1 - y0)
    (path,) = ax.plot([], [], color=_ROBOT_FC, lw=1.2, alpha=0.7, zorder=3, gid="trajectory")
    (points,) = ax.plot([], [], ".", color="#e0301e", markersize=2.5, zorder=4, gid="scan")
    robot = Polygon(footprint_corners((h.x[0], h.y[0], h.yaw[0]), fp.length, fp.width),
                    closed=True, fc=_ROBOT_FC, ec="#1f3b73", alpha=0.85, zorder=5, gid="robot")
    ax.add_patch(robot)
    label = title if title is not None else (sim.spec.name or "world")
    head = ax.set_title(label, fontsize=11)

    def draw(k: int) -> tuple[Any, ...]:
        i = idx[k]
        robot.set_xy(footprint_corners((h.x[i], h.y[i], h.yaw[i]), fp.length, fp.width))
        if trajectory:
            path.set_data(h.x[:i + 1], h.y[:i + 1])
        pts = by_stamp.get(h.t_ns[i], [])
        points.set_data([p[0] for p in pts], [p[1] for p in pts])
        head.set_text(f"{label} at t = {h.t_ns[i] / 1e9:.2f} s")
        return robot, path, points, head

    anim = FuncAnimation(fig, draw, frames=len(idx), interval=1000.0 / fps, blit=False)
    out = TopViewAnimation(fig, anim, len(idx))
    out._fps = fps
    return out
