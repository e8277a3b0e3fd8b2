"""The pillar scenario (exercise 3's shape): the simulator with noise, a P controller that steers
toward the nearest laser return, 20 simulated seconds, until it hits the pillar.

Run as a script it prints the world's digest and whether numpy was imported (the determinism
test runs it under several PYTHONHASHSEED values).
"""

from __future__ import annotations

import math
import sys

import ddes
from ddes.msg import get_message_class
from ddes.sim import Simulator, WorldSpec


def build(seed: int = 11, until: float = 20.0) -> tuple[ddes.World, Simulator]:
    world = ddes.World(seed=seed)
    sim = Simulator(world, WorldSpec.load("single_pillar"), x=0.0, y=0.0, yaw=0.0, noise=True)
    ctl = world.create_node("pillar_controller")
    twist = get_message_class("geometry_msgs/Twist")
    vec = get_message_class("geometry_msgs/Vector3")
    pub = ctl.advertise("/cmd_vel", twist, queue_size=1)
    gain = 1.0

    def on_scan(scan: object) -> None:
        best, index = math.inf, -1
        for i, r in enumerate(scan.ranges):  # type: ignore[attr-defined]
            if scan.range_min <= r < best:  # type: ignore[attr-defined]
                best, index = r, i
        if index < 0:
            return
        angle = scan.angle_min + index * scan.angle_increment  # type: ignore[attr-defined]
        pub.publish(twist(linear=vec(x=1.0), angular=vec(z=gain * angle)))

    ctl.subscribe("/scan", get_message_class("sensor_msgs/LaserScan"), on_scan, queue_size=1)
    world.run(until=until)
    return world, sim


if __name__ == "__main__":
    world, sim = build()
    print(world.digest(), len(sim.collisions), "numpy" in sys.modules)
