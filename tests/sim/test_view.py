"""The top view and its animation: the artists lie where the geometry says, the laser's points
on the obstacles' surfaces, the files are written, and the same run draws the same data."""

from __future__ import annotations

import math
from pathlib import Path

import pytest
from IPython.core.formatters import DisplayFormatter

import ddes
from ddes.display.figure import DisplayFigure
from ddes.errors import DdesValueError
from ddes.msg import get_message_class
from ddes.sim import Box, Circle, Segment, Simulator, WorldSpec
from ddes.sim.view import animate, footprint_corners, scan_points, top_view

Twist = get_message_class("geometry_msgs/Twist")
Vector3 = get_message_class("geometry_msgs/Vector3")
Marker = get_message_class("visualization_msgs/Marker")


def run(until: float = 3.0, noise: bool = False) -> Simulator:
    """Drive towards a pillar and a box, turning, while a marker sits on the pillar."""
    world = ddes.World(seed=4)
    spec = WorldSpec((Circle(4.0, 1.0, 0.5, "pillar"), Segment(-1.0, 3.0, 6.0, 3.0, "wall"),
                      Box(5.0, -1.5, 0.3, 1.0, 0.6, "crate")), "mixed")
    sim = Simulator(world, spec, noise=noise)
    node = world.create_node("driver")
    cmd = ddes.Publisher(node, "/cmd_vel", Twist, queue_size=1)
    marks = ddes.Publisher(node, "/visualization_marker", Marker, queue_size=1)

    def tick(_event: object) -> None:
        cmd.publish(Twist(linear=Vector3(x=0.6), angular=Vector3(z=0.15)))
        m = Marker(type=2, action=0, ns="pillar", id=1)
        m.header.frame_id = "odom"
        m.pose.position.x, m.pose.position.y = 4.0, 1.0
        m.pose.orientation.w = 1.0
        m.scale.x = m.scale.y = m.scale.z = 0.4
        m.color.g, m.color.a = 1.0, 1.0
        marks.publish(m)

    node.create_timer(0.1, tick)
    world.run(until=until)
    return sim


def artist(ax, gid: str):  # type: ignore[no-untyped-def]
    found = [a for a in ax.get_children() if a.get_gid() == gid]
    assert found, gid
    return found[0]


def test_the_footprint_is_the_pose_geometry() -> None:
    sim = run()
    fig = top_view(sim)
    assert isinstance(fig, DisplayFigure)
    robot = artist(fig.axes[0], "robot")
    x, y, yaw = sim.pose
    c, s = math.cos(yaw), math.sin(yaw)
    expected = [(x + c * dx - s * dy, y + s * dx + c * dy)
                for dx, dy in ((0.3025, 0.205), (-0.3025, 0.205), (-0.3025, -0.205), (0.3025, -0.205))]
    flat = [v for p in expected for v in p]
    assert [float(v) for p in robot.get_xy()[:4] for v in p] == pytest.approx(flat, abs=1e-12)
    assert [v for p in footprint_corners(sim.pose) for v in p] == pytest.approx(flat, abs=1e-12)


def test_laser_points_lie_on_the_obstacles() -> None:
    sim = run()
    pts = scan_points(sim)                     # the latest /scan, from the trace
    assert len(pts) > 20

    def gap(px: float, py: float) -> float:
        d_pillar = abs(math.hypot(px - 4.0, py - 1.0) - 0.5)
        d_wall = abs(py - 3.0) if -1.0 <= px <= 6.0 else math.inf
        crate = [e for e in sim.spec.obstacle("crate").edges()]
        d_crate = min(_seg_dist(px, py, e.x1, e.y1, e.x2, e.y2) for e in crate)
        return min(d_pillar, d_wall, d_crate)

    assert max(gap(px, py) for px, py in pts) < 1e-5   # float32 ranges
    line = artist(top_view(sim).axes[0], "scan")
    assert list(zip(line.get_xdata(), line.get_ydata())) == pts


def _seg_dist(px: float, py: float, x1: float, y1: float, x2: float, y2: float) -> float:
    dx, dy = x2 - x1, y2 - y1
    t = max(0.0, min(1.0, ((px - x1) * dx + (py - y1) * dy) / (dx * dx + dy * dy)))
    return math.hypot(px - (x1 + t * dx), py - (y1 + t * dy))


def test_a_scan_message_is_drawn_from_the_pose_at_its_stamp() -> None:
    sim = run(until=2.0)
    world = sim.world
    cls = get_message_class("sensor_msgs/LaserScan")
    first = world.trace.select(kind="topic.publish", topic="/scan")[5]
    scan = cls().deserialize(first.details["data"])
    pts = scan_points(sim, scan)
    assert max(abs(math.hypot(x - 4.0, y - 1.0) - 0.5) for x, y in pts
               if math.hypot(x - 4.0, y - 1.0) < 1.0) < 1e-5
    now = scan_points(sim, sim.ranges())        # ranges cast now: from the pose now, as doubles
    near = [(x, y) for x, y in now if math.hypot(x - 4.0, y - 1.0) < 1.0]
    assert near and max(abs(math.hypot(x - 4.0, y - 1.0) - 0.5) for x, y in near) < 1e-9


def test_frames_markers_trajectory_and_world() -> None:
    sim = run()
    ax = top_view(sim, markers="/visualization_marker", odometry=True).axes[0]
    for ob in ("pillar", "wall", "crate"):
        artist(ax, f"obstacle:{ob}")
    assert artist(ax, "obstacle:pillar").get_radius() == 0.5
    h = sim.history()
    traj = artist(ax, "trajectory")
    assert list(traj.get_xdata())[:-1] == h.x and list(traj.get_ydata())[:-1] == h.y
    bx = artist(ax, "frame:base_link:x").get_xydata()
    assert tuple(bx[0]) == (sim.pose.x, sim.pose.y)
    odom = artist(ax, "frame:odom:x").get_xydata()
    assert tuple(odom[0]) == (0.0, 0.0)          # the odom frame starts at the start pose
    marker = artist(ax, "marker:pillar/1")       # frame odom = world here (start at origin)
    assert marker.center == (4.0, 1.0) and marker.get_radius() == 0.2
    artist(ax, "odometry")
    labels = [t.get_text() for t in ax.get_legend().get_texts()]
    assert labels == ["trajectory (truth)", "/scan"]


def test_png_jupyter_and_determinism(tmp_path: Path) -> None:
    figs = [top_view(run(noise=True), markers=[(4.0, 1.0)]) for _ in range(2)]

    def data(fig: DisplayFigure) -> list[object]:
        ax = fig.axes[0]
        out: list[object] = [ax.get_xlim(), ax.get_ylim(), ax.get_title()]
        for a in ax.get_children():
            if hasattr(a, "get_xydata"):
                out.append((a.get_gid(), a.get_xydata().tolist()))
            elif hasattr(a, "get_xy") and a.get_gid():
                out.append((a.get_gid(), [list(map(float, p)) for p in a.get_xy()]))
        return out

    assert data(figs[0]) == data(figs[1])
    path = tmp_path / "top_view.png"
    figs[0].savefig(path)
    assert path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and path.stat().st_size > 5000
    formats, _ = DisplayFormatter().format(figs[1])
    assert "image/png" in formats


def test_drawing_changes_nothing() -> None:
    digests = []
    for draw in (False, True):
        sim = run(until=1.0, noise=True)
        if draw:
            top_view(sim, markers="/visualization_marker")
        sim.world.run(until=2.0)
        digests.append(sim.world.digest())
    assert digests[0] == digests[1]


def test_animation_gif_and_html(tmp_path: Path) -> None:
    sim = run(until=2.0)
    anim = animate(sim, every=4)
    assert anim.frames == 5                      # samples 0, 4, 8, 12, 16 of 20
    gif = anim.save(tmp_path / "run.gif")
    data = Path(gif).read_bytes()
    assert data[:6] == b"GIF89a" and len(data) > 1000
    html = anim.save(tmp_path / "run.html")
    assert "<script" in Path(html).read_text()
    with pytest.raises(DdesValueError, match=r"\.gif or \.html"):
        anim.save(tmp_path / "run.mp4")
    fresh = Simulator(ddes.World(seed=1), WorldSpec.load("empty"))
    with pytest.raises(DdesValueError, match="no history yet"):
        animate(fresh)


def test_the_docs_pictures_and_their_script(tmp_path: Path) -> None:
    import runpy

    repo = Path(__file__).resolve().parents[2]
    assert "images/top_view.png" in (repo / "docs" / "sim.md").read_text()
    for name in ("top_view.png", "rqt_graph.png", "rqt_plot.png"):
        assert (repo / "docs" / "images" / name).read_bytes()[:4] == b"\x89PNG"
    script = runpy.run_path(str(repo / "examples" / "sim_pictures.py"))
    written = script["main"](tmp_path)
    assert [p.name for p in written] == ["top_view.png", "rqt_graph.png", "rqt_plot.png"]
    assert all(p.stat().st_size > 5000 for p in written)
