"""Draw the pictures of docs/sim.md ("Pictures"): the pillar run seen from above.

    .venv/bin/python examples/sim_pictures.py [OUT_DIR]     # default docs/images

A P controller steers the simulated SMB to the pillar of ``single_pillar`` (the full example
of docs/sim.md) and publishes a visualization_msgs/Marker on the nearest laser return; after
14 simulated seconds the top view (``top_view.png``), the node/topic graph
(``rqt_graph.png``) and the speeds over time (``rqt_plot.png``) are written.  The same run
draws the same pictures every time.
"""

from __future__ import annotations

import math
import sys
from pathlib import Path

import ddes
from ddes.msg import get_message_class
from ddes.rqt import rqt_graph, rqt_plot
from ddes.sim import Simulator, WorldSpec
from ddes.sim.view import top_view


def pillar_run(until: float = 14.0) -> Simulator:
    world = ddes.World(seed=1)
    sim = Simulator(world, WorldSpec.load("single_pillar"), noise=True)
    Twist = get_message_class("geometry_msgs/Twist")
    Vector3 = get_message_class("geometry_msgs/Vector3")
    Marker = get_message_class("visualization_msgs/Marker")
    node = world.create_node("pillar_controller")
    cmd = ddes.Publisher(node, "/cmd_vel", Twist, queue_size=1)
    marker = ddes.Publisher(node, "/visualization_marker", Marker, queue_size=1)

    def on_scan(scan: object) -> None:
        best, index = math.inf, -1
        for i, r in enumerate(scan.ranges):  # type: ignore[attr-defined]
            if scan.range_min <= r < best:  # type: ignore[attr-defined]
                best, index = r, i
        if index < 0:
            return
        angle = scan.angle_min + index * scan.angle_increment  # type: ignore[attr-defined]
        cmd.publish(Twist(linear=Vector3(x=1.0), angular=Vector3(z=1.0 * angle)))
        m = Marker(type=2, action=0, ns="pillar", id=0)
        m.header.frame_id = "base_laser"
        m.header.stamp = scan.header.stamp  # type: ignore[attr-defined]
        m.pose.position.x, m.pose.position.y = best * math.cos(angle), best * math.sin(angle)
        m.pose.orientation.w = 1.0
        m.scale.x = m.scale.y = m.scale.z = 0.4
        m.color.g, m.color.a = 0.8, 1.0
        marker.publish(m)

    ddes.Subscriber(node, "/scan", get_message_class("sensor_msgs/LaserScan"), on_scan,
                    queue_size=1)
    world.run(until=until)
    return sim


def main(out: Path) -> list[Path]:
    out.mkdir(parents=True, exist_ok=True)
    sim = pillar_run()
    written = []
    for name, fig in (
            ("top_view.png", top_view(sim, markers="/visualization_marker", odometry=True)),
            ("rqt_graph.png", rqt_graph(sim.world, hide_tf=True)),
            ("rqt_plot.png", rqt_plot(sim.world, "/cmd_vel/linear/x", "/cmd_vel/angular/z",
                                      "/odom/twist/twist/linear/x"))):
        path = out / name
        fig.savefig(path, dpi=80, facecolor="white")
        written.append(path)
    return written


if __name__ == "__main__":
    target = Path(sys.argv[1]) if len(sys.argv) > 1 else Path(__file__).resolve().parents[1] / \
        "docs" / "images"
    for p in main(target):
        print(p)
