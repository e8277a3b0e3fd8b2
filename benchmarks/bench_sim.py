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
the ROS side (messages, graph, trace, TF listener) adds.  ``ratio`` is the median of the rounds'
ratios of ddes's real-time factor to the raw loop's, the two run one after the other in rotating
order (``ratio_min``/``ratio_max`` beside it); ``value`` and ``baseline`` are the median factors,
``value_min``/``value_max`` the spread of ddes's.
"""

from __future__ import annotations

import math
import random
import time
from typing import Any

import simpy
from common import TINY, compare_values, repeats, result

import ddes
from ddes.msg import get_message_class
from ddes.sim import (
    ANGLE_INCREMENT,
    ANGLE_MIN,
    N_BEAMS,
    RANGE_MAX,
    RANGE_MIN,
    Footprint,
    RobotLimits,
    Simulator,
    WorldSpec,
)
from ddes.sim._trig import sincos
from ddes.sim.geometry import LaserGeometry, collides, prepare, wrap_angle
from ddes.sim.noise import gauss as _gauss
from ddes.sim.noise import scan_ranges

SIM_SECONDS = 0.5 if TINY else 60.0
REPEAT = repeats(5)
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
        lo = scan.range_min
        for i, r in enumerate(scan.ranges):
            if lo <= r < best:
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
    """The same rates and computation on bare SimPy: no messages, no graph, no trace, no TF.

    Per 10 ms step, as the simulator: the command (zero after 0.25 s), clamped and slewed within
    the limits, midpoint integration, yaw wrapped, the footprint tested against the obstacles near
    it (a contact stops the robot against the obstacle, by the same bisection); wheel odometry with
    its slip and noise; the IMU's values and noise and its orientation's sincos; at 50 Hz the
    odometry orientation's sincos; at 10 Hz the laser's pose, the ray casting, the noise and REP
    117 limits, the P controller on the ranges and the 10 Hz history.
    """
    env = simpy.Environment()
    obstacles = [prepare(ob) for ob in WorldSpec.load("single_pillar").obstacles]
    laser = LaserGeometry(ANGLE_MIN, ANGLE_INCREMENT, N_BEAMS, RANGE_MAX)
    rng_odom, rng_imu, rng_scan = (random.Random(k) for k in (1, 2, 3))
    fp = Footprint().parts()
    lim = RobotLimits()
    timeout_ns = round(lim.cmd_vel_timeout * 1e9)
    slip_v, slip_w, gyro_bias = _gauss(rng_odom, 0.01), _gauss(rng_odom, 0.05), \
        _gauss(rng_imu, 0.002)
    s: dict[str, Any] = {"x": 0.0, "y": 0.0, "yaw": 0.0, "v": 0.0, "w": 0.0, "cv": 0.0,
                         "cw": 0.0, "cmd_ns": -(1 << 62), "ox": 0.0, "oy": 0.0, "oyaw": 0.0,
                         "pressing": False, "imu": None}
    history: list[tuple[float, ...]] = []

    def hit(x: float, y: float, yaw: float) -> bool:
        heading = None
        for p in obstacles:
            fx, fy = p.bx - x, p.by - y
            reach = fp[2] + p.br
            if fx * fx + fy * fy > reach * reach * 1.0001 + 1e-12:
                continue
            if heading is None:
                heading = sincos(yaw)
            if collides(fp, x, y, heading[0], heading[1], p):
                return True
        return False

    def controller(ranges: list[float], now_ns: int) -> None:
        best, index = math.inf, -1
        lo = RANGE_MIN
        for i, r in enumerate(ranges):
            if lo <= r < best:
                best, index = r, i
        if index >= 0:
            s["cv"], s["cw"] = 0.5, 0.5 * (ANGLE_MIN + index * ANGLE_INCREMENT)
            s["cmd_ns"] = now_ns

    def loop() -> Any:
        step = 0
        while True:
            yield env.timeout(DT_NS)
            step += 1
            now_ns = step * DT_NS
            if now_ns - s["cmd_ns"] <= timeout_ns:
                cv, cw = s["cv"], s["cw"]
            else:
                cv = cw = 0.0
            cv = min(max(cv, -lim.v_max), lim.v_max)
            cw = min(max(cw, -lim.w_max), lim.w_max)
            dv, dw = lim.a_max * 0.01, lim.alpha_max * 0.01
            v_prev = s["v"]
            v = v_prev + min(max(cv - v_prev, -dv), dv)
            w = s["w"] + min(max(cw - s["w"], -dw), dw)
            x, y, yaw = s["x"], s["y"], s["yaw"]
            sn, cs = sincos(yaw + w * 0.005)
            nx, ny, nyaw = x + v * cs * 0.01, y + v * sn * 0.01, wrap_angle(yaw + w * 0.01)
            if not hit(nx, ny, nyaw):
                s["x"], s["y"], s["yaw"], s["v"], s["w"] = nx, ny, nyaw, v, w
                s["pressing"] = False
            else:
                if not hit(x, y, nyaw):
                    s["yaw"], s["w"] = nyaw, w
                else:
                    s["w"] = 0.0
                lo, hi = 0.0, 1.0
                for _ in range(0 if s["pressing"] else 20):
                    mid = 0.5 * (lo + hi)
                    if hit(x + mid * (nx - x), y + mid * (ny - y), s["yaw"]):
                        hi = mid
                    else:
                        lo = mid
                s["x"], s["y"], s["v"], s["pressing"] = x + lo * (nx - x), y + lo * (ny - y), \
                    0.0, True
            v, w = s["v"], s["w"]
            if v != 0.0 or w != 0.0:
                vm = v * (1.0 + slip_v) + _gauss(rng_odom, 0.01 * abs(v))
                wm = w * (1.0 + slip_w) + _gauss(rng_odom, 0.02 * abs(w) + 0.002)
            else:
                vm, wm = v, w
            sn, cs = sincos(s["oyaw"] + wm * 0.005)
            s["ox"] += vm * cs * 0.01
            s["oy"] += vm * sn * 0.01
            s["oyaw"] = wrap_angle(s["oyaw"] + wm * 0.01)
            if step % 2 == 0:
                sincos(0.5 * s["oyaw"])  # odometry and TF orientation
            # the IMU: yaw, gyro and accelerations with their noise (inline, as the simulator)
            r = rng_imu.random
            iyaw = s["yaw"] + 0.002 * ((r() + r() + r() + r() + r() + r() + r() + r() + r() + r()
                                        + r() + r()) - 6.0)
            gz = w + gyro_bias + 0.005 * ((r() + r() + r() + r() + r() + r() + r() + r() + r()
                                           + r() + r() + r()) - 6.0)
            ax = (v - v_prev) / 0.01 + 0.05 * ((r() + r() + r() + r() + r() + r() + r() + r()
                                                 + r() + r() + r() + r()) - 6.0)
            ay = v * w + 0.05 * ((r() + r() + r() + r() + r() + r() + r() + r() + r() + r() + r()
                                  + r()) - 6.0)
            az = 9.80665 + 0.05 * ((r() + r() + r() + r() + r() + r() + r() + r() + r() + r()
                                    + r() + r()) - 6.0)
            s["imu"] = (sincos(0.5 * iyaw), gz, ax, ay, az)
            if step % 10 == 0:
                sn, cs = sincos(s["yaw"])
                raw = laser.cast(obstacles, s["x"] + 0.2 * cs, s["y"] + 0.2 * sn, s["yaw"])
                controller(scan_ranges(raw, rng_scan), now_ns)  # the simulator's noise, limits
                history.append((now_ns, s["x"], s["y"], s["yaw"], s["v"], s["w"]))

    env.process(loop())
    t0 = time.process_time()
    env.run(until=int(SIM_SECONDS * 1e9))
    return SIM_SECONDS / (time.process_time() - t0)


def benchmarks() -> list[dict[str, Any]]:
    c = compare_values({"base": raw_pillar, "ddes": ddes_pillar}, REPEAT)
    d = c.rounds["ddes"]
    # the real-time factor's own spread too: issue 18's target is on it, not only on the ratio
    return [result("sim_pillar_rtf", c, "x real time (CPU)", "raw SimPy loop, same rates and "
                   "ray casting", sim_seconds=SIM_SECONDS, value_min=round(min(d), 1),
                   value_max=round(max(d), 1))]


if __name__ == "__main__":
    import json

    for r in benchmarks():
        print(json.dumps(r))
