"""The simulator's speed: the pillar scenario against a raw SimPy loop of the same work.

The pillar scenario (exercise 3's shape): ``ddes.sim.Simulator`` in ``single_pillar`` with noise
(100 Hz physics and IMU, 50 Hz odometry and TF, 10 Hz scan, 100 Hz /clock), a P-controller node
steering to the nearest laser return at 10 Hz, and a tf2_ros TransformListener filling a Buffer
from /tf and /tf_static; 60 simulated seconds.  ``value`` is the real-time factor (simulated
seconds per CPU second, ``time.process_time``).

The baseline is a raw SimPy loop with the same rates doing the same computation without ROS: the
same unicycle step, the same exact ray casting (``ddes.sim.geometry``), the same noise code
(``ddes.sim.noise``: the scan's per-beam noise and REP 117 limits, the Irwin-Hall Gaussians of
odometry and IMU) and trig (``ddes.sim._trig.sincos``), and a P controller called directly with
the ranges.  Whatever makes that shared work faster speeds both up, so the ratio measures what
the ROS side (messages, graph, trace, TF listener) adds.  ``ratio`` is ddes's real-time factor over
the raw loop's, measured in back-to-back pairs in this run (median pair).
"""

from __future__ import annotations

import math
import random
import time
from typing import Any

import simpy
from common import row

import ddes
from ddes.msg import get_message_class
from ddes.sim import ANGLE_INCREMENT, ANGLE_MIN, N_BEAMS, RANGE_MAX, RANGE_MIN, Simulator, WorldSpec
from ddes.sim._trig import sincos
from ddes.sim.geometry import LaserGeometry, prepare
from ddes.sim.noise import gauss as _gauss
from ddes.sim.noise import scan_ranges

SIM_SECONDS = 60.0
REPEAT = 5
DT_NS = 10_000_000


def ddes_pillar() -> float:
    """Simulated seconds per CPU second of the ddes scenario."""
    world = ddes.World(seed=1)
    world.log_output = False
    Simulator(world, WorldSpec.load("single_pillar"), noise=True)
    ctl = world.create_node("pillar_controller")
    twist = get_message_class("geometry_msgs/Twist")
    vec = get_message_class("geometry_msgs/Vector3")
    pub = ctl.advertise("/cmd_vel", twist, queue_size=1)

    def on_scan(scan: Any) -> None:
        best, index = math.inf, -1
        for i, r in enumerate(scan.ranges):
            if scan.range_min <= r < best:
                best, index = r, i
        if index >= 0:
            angle = scan.angle_min + index * scan.angle_increment
            pub.publish(twist(linear=vec(x=0.5), angular=vec(z=0.5 * angle)))

    ctl.subscribe("/scan", get_message_class("sensor_msgs/LaserScan"), on_scan, queue_size=1)
    try:
        from ddes.tf2_ros import Buffer, TransformListener
    except ImportError:  # pragma: no cover - TF not there yet
        pass
    else:
        TransformListener(ctl, Buffer(node=ctl))
    t0 = time.process_time()
    world.run(until=SIM_SECONDS)
    return SIM_SECONDS / (time.process_time() - t0)


def raw_pillar() -> float:
    """The same rates and computation on bare SimPy: no messages, no graph, no trace."""
    env = simpy.Environment()
    obstacles = [prepare(ob) for ob in WorldSpec.load("single_pillar").obstacles]
    laser = LaserGeometry(ANGLE_MIN, ANGLE_INCREMENT, N_BEAMS, RANGE_MAX)
    rng_odom, rng_imu, rng_scan = (random.Random(k) for k in (1, 2, 3))
    state = {"x": 0.0, "y": 0.0, "yaw": 0.0, "v": 0.0, "w": 0.0, "cv": 0.0, "cw": 0.0,
             "ox": 0.0, "oy": 0.0, "oyaw": 0.0}

    def controller(ranges: list[float]) -> None:
        best, index = math.inf, -1
        for i, r in enumerate(ranges):
            if RANGE_MIN <= r < best:
                best, index = r, i
        if index >= 0:
            state["cv"], state["cw"] = 0.5, 0.5 * (ANGLE_MIN + index * ANGLE_INCREMENT)

    def loop() -> Any:
        step = 0
        while True:
            yield env.timeout(DT_NS)
            step += 1
            s = state
            v = s["v"] + max(-0.02, min(0.02, s["cv"] - s["v"]))
            w = s["w"] + max(-0.03, min(0.03, s["cw"] - s["w"]))
            sn, cs = sincos(s["yaw"] + w * 0.005)
            s["x"] += v * cs * 0.01
            s["y"] += v * sn * 0.01
            s["yaw"] += w * 0.01
            s["v"], s["w"] = v, w
            vm = v + _gauss(rng_odom, 0.01 * abs(v))
            wm = w + _gauss(rng_odom, 0.02 * abs(w) + 0.002)
            sn, cs = sincos(s["oyaw"] + wm * 0.005)
            s["ox"] += vm * cs * 0.01
            s["oy"] += vm * sn * 0.01
            s["oyaw"] += wm * 0.01
            if step % 2 == 0:
                sincos(0.5 * s["oyaw"])  # odometry and TF orientation
            for _ in range(5):  # IMU: yaw, gyro, three accelerations
                _gauss(rng_imu, 0.05)
            sincos(0.5 * s["yaw"])
            if step % 10 == 0:
                sn, cs = sincos(s["yaw"])
                raw = laser.cast(obstacles, s["x"] + 0.2 * cs, s["y"] + 0.2 * sn, s["yaw"])
                controller(scan_ranges(raw, rng_scan))  # the simulator's noise and limits

    env.process(loop())
    t0 = time.process_time()
    env.run(until=int(SIM_SECONDS * 1e9))
    return SIM_SECONDS / (time.process_time() - t0)


def benchmarks() -> list[dict[str, Any]]:
    pairs = []
    for _ in range(REPEAT):
        b = raw_pillar()
        d = ddes_pillar()
        pairs.append((d / b, d, b))
    pairs.sort()
    _, d, b = pairs[len(pairs) // 2]
    return [row("sim_pillar_rtf", d, "x real time (CPU)", b, "raw SimPy loop, same rates and "
                "ray casting", sim_seconds=SIM_SECONDS)]


if __name__ == "__main__":
    import json

    for r in benchmarks():
        print(json.dumps(r))
