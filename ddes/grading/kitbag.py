"""The localisation exercise's kit bag (``ddes course make-bag``): ``smb_navigation.bag`` recorded
from the simulator, reproducibly.

The course's bag (ETH Zurich, Programming for Robotics, exercise 4) holds ``/imu/data``
(sensor_msgs/Imu), ``/joint_states`` (sensor_msgs/JointState), ``/rslidar_points``
(sensor_msgs/PointCloud2) and ``/smb_velocity_controller/odom`` (nav_msgs/Odometry), about 38 s
of the SMB driving.  :func:`make_bag` drives the ddes SMB in the single-pillar world along a
scripted drive drawn from ``seed`` (:func:`drive_script`; the kit's is seed 2021), with the
simulator's point cloud and wheel joints on and its odometry on ``smb_velocity_controller/odom``,
and records those four topics plus ``/scan`` with every header stamp and record time moved by
:data:`STAMP_OFFSET` (1612345678 s, February 2021): played without ``use_sim_time`` and
``--clock`` the stamps lie 51 years in the future of a ddes node's ROS time.

Rates (the course bag's counts are 578, 280, 381 and 306 messages): ``/imu/data`` 20 Hz
(``imu_rate``), ``/smb_velocity_controller/odom`` and ``/joint_states`` 10 Hz (every fifth of the
simulator's 50 Hz), ``/rslidar_points`` and ``/scan`` 10 Hz.  There is no ``/tf`` or
``/tf_static`` in the bag: the robot's frames come from ``ddes_sim/robot_frames`` and
odom → base_link from the EKF.

Same seed, same bytes: the bag is written by one recorder node in kernel order, with no wall
clock.  :class:`KitBag` also returns the simulator's ground truth (10 Hz, odom frame = world frame
since the drive starts at the origin facing +x) for the documentation's plot.
"""

from __future__ import annotations

import random
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from ddes.errors import DdesValueError

__all__ = ["DURATION", "KIT_CONFIG", "KIT_SEED", "STAMP_OFFSET", "TOPICS", "KitBag", "TrackErrors",
           "drive_script", "ekf_track", "make_bag", "plot_localization"]

KIT_SEED = 2021
#: Seconds added to every stamp: 2021-02-03 09:41:18 UTC.
STAMP_OFFSET = 1612345678
#: Seconds of driving recorded.
DURATION = 38.0
#: The recorded topics and their types.
TOPICS = {
    "/imu/data": "sensor_msgs/Imu",
    "/joint_states": "sensor_msgs/JointState",
    "/rslidar_points": "sensor_msgs/PointCloud2",
    "/scan": "sensor_msgs/LaserScan",
    "/smb_velocity_controller/odom": "nav_msgs/Odometry",
}
#: Keep every n-th message of these topics (50 Hz → 10 Hz).
_EVERY = {"/smb_velocity_controller/odom": 5, "/joint_states": 5}


def drive_script(seed: int) -> list[tuple[float, float, float]]:
    """The drive as ``(seconds, v, w)`` segments: 1 s at rest, then straight runs and turns
    drawn from ``random.Random(f"kitbag/{seed}")`` until :data:`DURATION`.  A segment whose
    nominal path (no slip) would come within 3 m of the single-pillar world's pillar is drawn
    again (a turn the other way, up to 20 times; then the robot stops), so no seed crashes."""
    from ddes.sim._trig import sincos

    rng = random.Random(f"kitbag/{seed}")
    segments: list[tuple[float, float, float]] = [(1.0, 0.0, 0.0)]
    total = 1.0
    straight = True
    pose = (0.0, 0.0, 0.0)

    def follow(p: tuple[float, float, float], seg: tuple[float, float, float]
               ) -> tuple[float, float, float] | None:
        x, y, yaw = p
        seconds, v, w = seg
        for _ in range(round(seconds * 10)):
            s, c = sincos(yaw)
            x, y, yaw = x + v * c * 0.1, y + v * s * 0.1, yaw + w * 0.1
            if (x - _PILLAR[0]) ** 2 + (y - _PILLAR[1]) ** 2 < _CLEARANCE ** 2:
                return None
        return x, y, yaw

    while total < DURATION:
        for _attempt in range(20):
            if straight:
                seg = (round(rng.uniform(4.0, 7.0), 1), round(rng.uniform(0.4, 0.7), 2), 0.0)
            else:
                w = round(rng.uniform(0.3, 0.6), 2) * rng.choice((-1.0, 1.0))
                seg = (round(rng.uniform(3.0, 5.0), 1), round(rng.uniform(0.3, 0.5), 2), w)
            seg = (min(seg[0], round(DURATION - total, 1)), seg[1], seg[2])
            after = follow(pose, seg)
            if after is not None:
                pose = after
                break
        else:
            seg = (round(DURATION - total, 1), 0.0, 0.0)
        segments.append(seg)
        total = round(total + seg[0], 1)
        straight = not straight
    return segments


#: The single-pillar world's pillar (x, y) and the clearance the drive keeps from its centre.
_PILLAR = (20.0, 5.0)
_CLEARANCE = 3.0


@dataclass
class KitBag:
    """What :func:`make_bag` wrote: the path, message counts, and the true track."""

    path: Path
    seed: int
    counts: dict[str, int] = field(default_factory=dict)
    #: (t in bag time [ns], x, y, yaw) of the simulator's truth at 10 Hz.
    truth: list[tuple[int, float, float, float]] = field(default_factory=list)


def make_bag(path: str | Path, seed: int = KIT_SEED) -> KitBag:
    """Drive the simulator along :func:`drive_script` (``seed``) and record the kit bag."""
    import ddes
    from ddes.msg import get_message_class
    from ddes.rosbag import Bag
    from ddes.sim import Simulator, WorldSpec
    from ddes.time import Duration

    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    world = ddes.World(seed=seed)
    world.log_output = False
    world.use_sim_time = True
    sim = Simulator(world, WorldSpec.load("single_pillar"), imu_rate=20.0, pointcloud=True,
                    joint_states=True, publish_odom_tf=False,
                    odom_topic="smb_velocity_controller/odom")
    script = drive_script(seed)
    driver = world.create_node("kit_driver")
    twist = get_message_class("geometry_msgs/Twist")
    vec = get_message_class("geometry_msgs/Vector3")
    pub = driver.advertise("/cmd_vel", twist, queue_size=1)
    ends: list[tuple[float, float, float]] = []
    t_end = 0.0
    for seconds, v, w in script:
        t_end = round(t_end + seconds, 1)
        ends.append((t_end, v, w))

    def command(_event: object) -> None:
        now = driver.get_time()
        for end, v, w in ends:
            if now < end:
                pub.publish(twist(linear=vec(x=v), angular=vec(z=w)))
                return
        pub.publish(twist())

    driver.create_timer(0.1, command)
    offset = Duration(STAMP_OFFSET)
    result = KitBag(path, seed, {topic: 0 for topic in TOPICS})
    seen = {topic: 0 for topic in TOPICS}
    bag = Bag(str(path), "w")
    recorder = world.create_node("kit_recorder")
    limit_ns = round(DURATION * 1e9)

    def record(msg: Any, topic: str) -> None:
        n = seen[topic]
        seen[topic] = n + 1
        if n % _EVERY.get(topic, 1):
            return
        stamp_ns = msg.header.stamp.to_nsec()
        if stamp_ns <= 0 or stamp_ns > limit_ns:
            return
        msg.header.stamp = msg.header.stamp + offset
        bag.write(topic, msg, t=msg.header.stamp)
        result.counts[topic] += 1

    try:
        for topic, type_name in TOPICS.items():
            recorder.subscribe(topic, get_message_class(type_name), record, callback_args=topic,
                               queue_size=100)
        world.run(until=DURATION + 0.05)
    finally:
        bag.close()
    if sim.collisions:
        raise DdesValueError(f"the kit drive of seed {seed} hit {sim.collisions[0]}; "
                             "choose another seed")
    hist = sim.history()
    result.truth = [(t, x, y, yaw) for t, x, y, yaw in zip(hist.t_ns, hist.x, hist.y, hist.yaw)
                    if 0 < t <= limit_ns]
    return result


def ekf_track(path: str | Path, config: dict[str, Any] | None = None
              ) -> list[tuple[int, float, float, float]]:
    """``(stamp ns, x, y, yaw)`` of robot_localization's EKF on the bag at ``path``, after each
    of its ``frequency`` updates: the bundled filter node driven directly with the bag's
    messages, its updates at the bag times a ``rosbag play --clock`` run gives them, the robot's
    fixed frames (``ddes_sim/robot_frames``) in its buffer.  ``config``: the node's private
    parameters (default: the kit's ``localization.yaml``)."""
    from ddes.graph.world import World
    from ddes.graph.yamlsafe import load_yaml
    from ddes.rosbag import Bag
    from ddes.sim.frames import FRAMES
    from ddes.sim.localization import EkfLocalizationNode

    if config is None:
        config = load_yaml(KIT_CONFIG.read_text(encoding="utf-8"))
    world = World(0, wall_budget=None)
    world.log_output = False
    world.use_sim_time = True
    for key, value in config.items():
        world.params.set_param(f"/ekf_localization/{key}", value)
    ekf = EkfLocalizationNode(world.create_node("/ekf_localization", disable_rosout=True))
    ts = world.messages.get_message_class("geometry_msgs/TransformStamped")
    for child, (fx, fy, fz) in FRAMES.items():
        t = ts()
        t.header.frame_id, t.child_frame_id = "base_link", child
        t.transform.translation.x, t.transform.translation.y = fx, fy
        t.transform.translation.z = fz
        t.transform.rotation.w = 1.0
        ekf.buffer.set_transform_static(t, "/robot_state_publisher")
    route = {"/" + s.topic.lstrip("/"): s for s in ekf.sensors}
    period = round(1e9 / ekf.frequency)
    track: list[tuple[int, float, float, float]] = []
    f = ekf.filter

    def update(now: int) -> None:
        ekf.integrate(now)
        if f.initialized:
            track.append((f.last_ns, f.x[0], f.x[1], f.x[2]))

    tick: int | None = None
    with Bag(str(path)) as bag:
        for topic, msg, when in bag.read_messages(topics=sorted(route)):
            now = when.to_nsec()
            if tick is None:
                tick = now + period
            while tick <= now:
                update(tick)
                tick += period
            sensor = route[topic]
            if sensor.key.startswith("imu"):
                ekf._on_imu(msg, sensor)
            else:
                ekf._on_odom(msg, sensor)
    if tick is not None:
        update(tick)
    return track


#: The kit's EKF configuration (SMB's localization.yaml, as ``ddes_sim`` ships it).
KIT_CONFIG = Path(__file__).resolve().parents[1] / "packages" / "ddes_sim" / "config" \
    / "localization.yaml"


@dataclass
class TrackErrors:
    """Position errors (m) against the truth, at the truth's 10 Hz samples."""

    ekf_final: float
    ekf_max: float
    odom_final: float
    odom_max: float


def plot_localization(kit: KitBag, png: str | Path) -> TrackErrors:
    """Plot the EKF's x/y on the kit bag against the simulator's truth and the wheel odometry
    (``png``), and return the position errors."""
    import math

    from ddes.display.figure import new_figure
    from ddes.rosbag import Bag

    track = ekf_track(kit.path)
    odom: list[tuple[int, float, float]] = []
    with Bag(str(kit.path)) as bag:
        for _topic, msg, when in bag.read_messages(topics=["/smb_velocity_controller/odom"]):
            p = msg.pose.pose.position  # type: ignore[union-attr]
            odom.append((when.to_nsec(), p.x, p.y))
    offset = STAMP_OFFSET * 1_000_000_000

    def at(series: list[Any], t_ns: int) -> Any:
        """The last sample at or before ``t_ns`` (series sorted by time)."""
        lo, hi = 0, len(series)
        while lo < hi:
            mid = (lo + hi) // 2
            if series[mid][0] <= t_ns:
                lo = mid + 1
            else:
                hi = mid
        return series[max(lo - 1, 0)]

    ekf_err, odom_err = [], []
    for t, x, y, _yaw in kit.truth:
        e = at(track, t + offset)
        o = at(odom, t + offset)
        ekf_err.append(math.hypot(e[1] - x, e[2] - y))
        odom_err.append(math.hypot(o[1] - x, o[2] - y))
    errors = TrackErrors(ekf_err[-1], max(ekf_err), odom_err[-1], max(odom_err))
    fig = new_figure(figsize=(7.0, 6.0))
    ax = fig.add_subplot(1, 1, 1)
    ax.plot([x for _t, x, _y, _w in kit.truth], [y for _t, _x, y, _w in kit.truth], "k-",
            lw=2.5, label="simulator ground truth")
    ax.plot([x for _t, x, _y in odom], [y for _t, _x, y in odom], "C1--", lw=1.2,
            label=f"wheel odometry (final error {errors.odom_final:.2f} m)")
    ax.plot([x for _t, x, _y, _w in track], [y for _t, _x, y, _w in track], "C0-", lw=1.2,
            label=f"EKF /odometry/filtered (final error {errors.ekf_final:.2f} m)")
    ax.set_aspect("equal")
    ax.set_xlabel("x [m] (odom)")
    ax.set_ylabel("y [m] (odom)")
    ax.set_title(f"robot_localization EKF on the kit bag (seed {kit.seed})")
    ax.grid(True, alpha=0.3)
    ax.legend(loc="best", fontsize=8)
    fig.savefig(str(png), dpi=90, metadata={"Software": None})
    return errors
