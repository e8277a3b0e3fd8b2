"""robot_localization's ekf_localization_node (ddes.sim.ekf + the bundled package): a straight
drive and a turn against the simulator's truth, determinism, the rule for measurements stamped
in the future of ROS time, and the parameter errors."""

from __future__ import annotations

import math
from typing import Any

import pytest
from hypothesis import given
from hypothesis import strategies as st

import ddes
from ddes.errors import DdesValueError
from ddes.msg import get_message_class
from ddes.nodes import start_node
from ddes.sim import Simulator
from ddes.sim.ekf import PlanarEkf, wrap

ODOM0 = [False] * 6 + [True, True, False, False, False, True] + [False] * 3
IMU0 = [False] * 5 + [True] + [False] * 5 + [True] + [True, True, False]


def _world(seed: int, *, noise: bool = True, **overrides: Any) -> tuple[ddes.World, Simulator]:
    world = ddes.World(seed=seed)
    world.use_sim_time = True
    cfg: dict[str, Any] = {"frequency": 50.0, "two_d_mode": True, "publish_tf": True,
                           "odom0": "odom", "odom0_config": ODOM0,
                           "imu0": "imu/data", "imu0_config": IMU0}
    cfg.update(overrides)
    for k, v in cfg.items():
        world.params.set_param("/ekf/" + k, v)
    sim = Simulator(world, noise=noise, publish_odom_tf=False)
    start_node(world, "robot_localization", "ekf_localization_node", name="ekf")
    return world, sim


def _drive(world: ddes.World, turn_after: float) -> list[Any]:
    probe = world.create_node("probe")
    twist = get_message_class("geometry_msgs/Twist")
    vec = get_message_class("geometry_msgs/Vector3")
    pub = probe.advertise("/cmd_vel", twist, queue_size=1)
    out: list[Any] = []
    probe.subscribe("/odometry/filtered", get_message_class("nav_msgs/Odometry"), out.append)

    def cmd(_e: object) -> None:
        w = 0.5 if probe.get_time() >= turn_after else 0.0
        pub.publish(twist(linear=vec(x=0.5), angular=vec(z=w)))

    probe.create_timer(0.1, cmd)
    return out


def _yaw(m: Any) -> float:
    o = m.pose.pose.orientation
    return math.atan2(2.0 * o.w * o.z, 1.0 - 2.0 * o.z * o.z)


def test_straight_drive_without_noise_follows_the_truth() -> None:
    world, sim = _world(0, noise=False)
    out = _drive(world, turn_after=1e9)
    world.run(until=8.0)
    m = out[-1]
    assert m.header.frame_id == "odom" and m.child_frame_id == "base_link"
    assert abs(m.pose.pose.position.x - sim.truth.x) < 0.05
    assert abs(m.pose.pose.position.y) < 1e-6 and abs(_yaw(m)) < 1e-6
    assert abs(m.twist.twist.linear.x - 0.5) < 0.01
    # published at ~frequency (50 Hz) once the first measurement arrived
    assert 390 <= len(out) <= 400


def test_turn_with_noise_beats_the_wheel_odometry() -> None:
    world, sim = _world(2021)
    out = _drive(world, turn_after=4.0)
    world.run(until=14.0)
    m, t, od = out[-1], sim.truth, sim.odometry
    ekf_err = math.hypot(m.pose.pose.position.x - t.x, m.pose.pose.position.y - t.y)
    odom_err = math.hypot(od.x - t.x, od.y - t.y)
    assert ekf_err < 0.15
    assert ekf_err < odom_err  # the IMU's yaw corrects the skid-slip of the odometry
    assert abs(wrap(_yaw(m) - t.yaw)) < 0.02


def test_tf_odom_to_base_link_is_the_filter_pose() -> None:
    world, _sim = _world(3)
    out = _drive(world, turn_after=2.0)
    tfs: list[Any] = []
    world.create_node("tfprobe").subscribe("/tf", get_message_class("tf2_msgs/TFMessage"),
                                           tfs.append)
    world.run(until=5.0)
    last = tfs[-1].transforms[0]
    assert (last.header.frame_id, last.child_frame_id) == ("odom", "base_link")
    match = [m for m in out if m.header.stamp == last.header.stamp]
    assert match and match[-1].pose.pose.position.x == last.transform.translation.x
    stamps = [t.transforms[0].header.stamp for t in tfs]
    assert stamps == sorted(set(stamps))  # never the same stamp twice (no TF_REPEATED_DATA)


def test_same_seed_same_estimate() -> None:
    runs = []
    for _ in range(2):
        world, _sim = _world(7)
        out = _drive(world, turn_after=2.0)
        world.run(until=6.0)
        runs.append([(m.header.stamp.to_nsec(), m.pose.pose.position.x.hex(),
                      m.pose.pose.position.y.hex(), m.pose.covariance[0].hex()) for m in out])
    assert runs[0] == runs[1]


def test_measurements_in_the_future_of_ros_time_wait() -> None:
    """Upstream's integrateMeasurements stops at the first queued measurement later than now."""
    world = ddes.World(seed=0)  # no use_sim_time: ROS time is kernel time, near 0
    for k, v in {"two_d_mode": True, "odom0": "odom", "odom0_config": ODOM0}.items():
        world.params.set_param("/ekf/" + k, v)
    start_node(world, "robot_localization", "ekf_localization_node", name="ekf")
    src = world.create_node("src")
    odom = get_message_class("nav_msgs/Odometry")
    pub = src.advertise("odom", odom, queue_size=10)
    out: list[Any] = []
    src.subscribe("/odometry/filtered", odom, out.append)

    def send(_e: object) -> None:
        m = odom()
        m.header.stamp = ddes.Time(1612345678) + ddes.Duration(src.get_time())
        m.child_frame_id = "base_link"
        m.twist.twist.linear.x = 1.0
        pub.publish(m)

    src.create_timer(0.1, send)
    world.run(until=3.0)
    assert out == []


def test_parameter_errors_name_the_fix() -> None:
    with pytest.raises(DdesValueError, match="two_d_mode"):
        _world(0, two_d_mode=False)
    with pytest.raises(DdesValueError, match="should have 15 entries"):
        _world(0, odom0_config=[True, False])
    with pytest.raises(DdesValueError, match="world_frame"):
        _world(0, world_frame="map")


def test_first_measurement_initialises_then_predict_and_correct() -> None:
    f = PlanarEkf(sensor_timeout=0.02)
    f.process(1_000_000_000, {3: 1.0}, {(3, 3): 0.01})
    assert f.initialized and f.x[3] == 1.0 and f.P[3][3] == 0.01
    f.process(2_000_000_000, {3: 1.0}, {(3, 3): 0.01})
    assert abs(f.x[0] - 1.0) < 1e-9  # predicted one second at 1 m/s
    before = f.last_ns
    f.process(1_500_000_000, {3: 1.0}, {(3, 3): 0.01})  # older: corrected, time not moved back
    assert f.last_ns == before
    assert not f.process(3_000_000_000, {3: 50.0}, {(3, 3): 0.01}, threshold=3.0)


def _plain_gain_update(p: list[list[float]], pht: list[list[float]], s: list[list[float]],
                       s_inv: list[list[float]], y: list[float], x: list[float]) -> list[list[float]]:
    """The gain and Joseph update as plain loops, each sum added left to right from 0.0 (the
    reference :func:`ddes.sim.ekf._gain_update` must equal bit for bit)."""
    n, m = len(p), len(y)

    def dot(a: list[float], b: list[float]) -> float:
        total = 0.0
        for u, v in zip(a, b):
            total += u * v
        return total

    k = [[dot(pht[i], [s_inv[c][b] for c in range(m)]) for b in range(m)] for i in range(n)]
    for i in range(n):
        x[i] += dot(k[i], y)
    ks = [[dot(k[i], [s[c][b] for c in range(m)]) for b in range(m)] for i in range(n)]
    new = []
    for i in range(n):
        row = list(p[i])
        for b in range(m):
            a, u = k[i][b], pht[i][b] - ks[i][b]
            row = [r - a * pht[j][b] - u * k[j][b] for j, r in enumerate(row)]
        new.append(row)
    return new


@given(st.integers(1, 8), st.randoms(use_true_random=False))
def test_generated_gain_update_equals_the_plain_loops_bit_for_bit(m: int, rnd: Any) -> None:
    from ddes.sim.ekf import N, _gain_update

    def num() -> float:
        return rnd.choice([0.0, -0.0, 1e-9, -1.5]) if rnd.random() < 0.1 else rnd.uniform(-3, 3)

    p = [[num() for _ in range(N)] for _ in range(N)]
    pht = [[num() for _ in range(m)] for _ in range(N)]
    s = [[num() for _ in range(m)] for _ in range(m)]
    s_inv = [[num() for _ in range(m)] for _ in range(m)]
    y = [num() for _ in range(m)]
    x1 = [num() for _ in range(N)]
    x2 = list(x1)
    got = _gain_update(m)(p, pht, s, s_inv, y, x1)
    want = _plain_gain_update(p, pht, s, s_inv, y, x2)
    assert [[v.hex() for v in row] for row in got] == [[v.hex() for v in row] for row in want]
    assert [v.hex() for v in x1] == [v.hex() for v in x2]
