"""The simulator node: a Super Mega Bot (SMB) on the kernel clock, with laser, odometry, IMU, TF.

One kernel process steps the physics every 10 ms of simulated time (``dt``); within a step the
order is fixed: physics, ``/clock``, odometry and ``/tf`` (every 2nd step, 50 Hz), the IMU
(100 Hz), the laser (every 10th step, 10 Hz) and the trace's ``sim.pose`` (10 Hz).  Simulated
time is ``step * dt`` from the simulator's start (Gazebo's clock starts at zero too); the
kernel period of a step is ``dt / real_time_factor``.

Kinematics (SMB values from ``smb_control/config/control.yaml`` and the URDF): a unicycle at
base_link; the ``/cmd_vel`` command (zero once older than ``cmd_vel_timeout`` = 0.25 s) is
clamped to |v| <= 1.1 m/s, |w| <= 1.1 rad/s; v and w slew toward it within |a| <= 2 m/s^2,
|alpha| <= 3 rad/s^2; midpoint integration; the footprint (0.605 x 0.410 m) is tested against
every obstacle at the new pose.  On contact the robot goes as far along the step as is free
(bisection), v = 0 (the turn is kept when turning alone is free), a :class:`Collision` is
recorded (once per contact: pressing on or sliding along records nothing more until the robot is
5 cm clear of the obstacle) and the IMU shows a crash pulse.

Noise (off with ``noise=False``): each sensor draws from its own stream of the world's seed,
``world.rng_for("sim/<node>/<sensor>")`` (``odom``, ``imu``, ``scan``), so adding a sensor
never shifts another's draws; a Gaussian is the Irwin-Hall sum of 12 ``random()`` calls, which
uses only exact operations (:mod:`ddes.sim.noise`).

The collision warning's file, function and line (``_collide``'s ``logwarn``) go to ``/rosout``
and so into the trace digest: an edit above it that moves it by a line changes the golden
digest of ``tests/sim/test_determinism.py`` (keep the line count above it, or re-record).
"""

from __future__ import annotations

import math
import struct
from collections.abc import Callable
from typing import TYPE_CHECKING, Any, NamedTuple

from ddes.errors import DdesValueError
from ddes.msg import get_message_class, get_service_class
from ddes.services import Service
from ddes.sim._trig import sincos
from ddes.sim.geometry import (
    Footprint,
    LaserGeometry,
    Prepared,
    collides,
    contact_normal,
    prepare,
    wrap_angle,
)
from ddes.sim.noise import gauss as _gauss
from ddes.sim.noise import scan_ranges
from ddes.sim.worlds import Obstacle, WorldSpec
from ddes.time import Time

if TYPE_CHECKING:
    import random

    from simpy.events import ProcessGenerator

    from ddes.graph.node import Node
    from ddes.graph.world import World
    from ddes.msg.message import Message

__all__ = ["Collision", "History", "Pose2D", "RobotLimits", "Simulator", "Truth"]


def _f32(x: float) -> float:
    return float(struct.unpack("<f", struct.pack("<f", x))[0])


_PI = 3.141592653589793
#: The laser's angles as the float32 fields of the message carry them; beam i lies at exactly
#: ``ANGLE_MIN + i * ANGLE_INCREMENT`` (computed in double from these values).
ANGLE_MIN = _f32(-_PI / 2)
ANGLE_INCREMENT = _f32(_PI / 360)
N_BEAMS = 361
ANGLE_MAX = _f32(ANGLE_MIN + (N_BEAMS - 1) * ANGLE_INCREMENT)
RANGE_MIN = 0.45
RANGE_MAX = 50.0

DT_NS = 10_000_000
_DT = 0.01
_G = 9.80665
#: base_link -> base_laser and base_link -> imu_link (x, y, z).
LASER_OFFSET = (0.20, 0.0, 0.33)
IMU_OFFSET = (0.2554, -0.02397, 0.1795)
#: The SMB's wheel joints (sensor_msgs/JointState order), wheel radius and separation (m).
WHEEL_JOINTS = ("LF_WHEEL_JOINT", "RF_WHEEL_JOINT", "LH_WHEEL_JOINT", "RH_WHEEL_JOINT")
WHEEL_RADIUS = 0.19
WHEEL_SEPARATION = 0.57
_ODOM_POSE_COV = (0.1, 0.001, 0.001, 0.001, 0.001, 0.3)
_ODOM_TWIST_COV = (0.001, 0.001, 0.001, 0.001, 0.001, 0.03)
_CRASH_TAU = 0.1
_RING_DECAY = 0.8187307530779818  # exp(-0.01 / 0.05): the ringing's decay per 10 ms step
_CRASH_MIN_SPEED = 0.05


class RobotLimits(NamedTuple):
    """Velocity and acceleration limits (SMB's ``control.yaml``) and the command timeout."""

    v_max: float = 1.1
    a_max: float = 2.0
    w_max: float = 1.1
    alpha_max: float = 3.0
    cmd_vel_timeout: float = 0.25


class Pose2D(NamedTuple):
    x: float
    y: float
    yaw: float


class Truth(NamedTuple):
    """The exact state: pose and the velocities v (m/s) and w (rad/s)."""

    x: float
    y: float
    yaw: float
    v: float
    w: float


class Collision(NamedTuple):
    """A contact of the footprint with an obstacle (recorded when it begins)."""

    t_ns: int               # kernel time
    stamp_ns: int           # simulated time
    obstacle: str
    speed: float            # |v| just before the contact
    normal: tuple[float, float]  # world frame, from the obstacle towards the robot
    pose: Pose2D


class History(NamedTuple):
    """The true state at 10 Hz: simulated times (ns) and values, as lists."""

    t_ns: list[int]
    x: list[float]
    y: list[float]
    yaw: list[float]
    v: list[float]
    w: list[float]


_LIMITS = RobotLimits()
_FOOTPRINT = Footprint()


class Simulator:
    """The deterministic 2D SMB as a node of ``world`` (see the module text).

    ``Simulator(world, WorldSpec.load("single_pillar"), x=0, y=0, yaw=0, noise=True)``.
    Topics: ``cmd_vel`` (in), ``scan``, ``odom``, ``imu/data``, ``/tf``, ``/tf_static``, ``/clock``;
    ``ground_truth/odom``, ``rslidar_points``, ``joint_states`` when asked for; services
    ``~pause_physics``, ``~unpause_physics``, ``~reset_world`` (std_srvs/Empty).
    """

    def __init__(
        self,
        world: World,
        spec: WorldSpec | None = None,
        x: float = 0.0,
        y: float = 0.0,
        yaw: float = 0.0,
        noise: bool = True,
        *,
        name: str = "simulator",
        node: Node | None = None,
        real_time_factor: float = 1.0,
        publish_clock: bool = True,
        laser: bool = True,
        imu_rate: float = 100.0,
        publish_odom_tf: bool = True,
        ground_truth: bool = False,
        odom_topic: str = "odom",
        paused: bool = False,
        pointcloud: bool = False,
        laser_pipeline: str = "direct",
        joint_states: bool = False,
        limits: RobotLimits = _LIMITS,
        footprint: Footprint = _FOOTPRINT,
    ) -> None:
        if not (isinstance(real_time_factor, (int, float)) and 0.0 < real_time_factor <= 1e6):
            raise DdesValueError(f"real_time_factor must be a number > 0, got {real_time_factor!r}"
                                 "; 1.0 runs as fast as the kernel clock")
        if imu_rate not in (100, 100.0, 50, 50.0, 25, 25.0, 20, 20.0, 10, 10.0):
            raise DdesValueError(f"imu_rate must divide the 100 Hz physics rate (100, 50, 25, 20 "
                                 f"or 10), got {imu_rate!r}")
        if laser_pipeline not in ("direct", "smb"):
            raise DdesValueError(f"laser_pipeline must be 'direct' (/scan from the simulator) or "
                                 f"'smb' (only /rslidar_points), got {laser_pipeline!r}")
        self.world = world
        self.node = node if node is not None else world.create_node(name)
        self.spec = spec if spec is not None else WorldSpec((), "empty", "")
        self.noise = bool(noise)
        self.limits = limits
        self.footprint = footprint
        self._fp = footprint.parts()
        hx, hy, _ = self._fp
        self._fp_near = Footprint(2.0 * hx + 0.1, 2.0 * hy + 0.1).parts()  # 5 cm all round
        self.real_time_factor = float(real_time_factor)
        self._period_ns = max(1, round(DT_NS / self.real_time_factor))
        self._imu_every = round(100 / imu_rate)
        self._prepared: list[Prepared] = [prepare(ob) for ob in self.spec.obstacles]
        self._laser = LaserGeometry(ANGLE_MIN, ANGLE_INCREMENT, N_BEAMS, RANGE_MAX)
        self._start = Pose2D(float(x), float(y), wrap_angle(float(yaw)))
        self.collisions: list[Collision] = []
        self._hist = History([], [], [], [], [], [])
        node = self.node
        name_ = node.name
        self._rng_odom: random.Random = world.rng_for(f"sim{name_}/odom")
        self._rng_imu: random.Random = world.rng_for(f"sim{name_}/imu")
        self._rng_scan: random.Random = world.rng_for(f"sim{name_}/scan")
        self._paused = bool(paused)
        self._closed = False
        self._cmd = (0.0, 0.0)
        self._cmd_stamp_ns = -(1 << 62)
        self._step = 0
        self._reset_state(self._start)
        # odometry errors drawn once per run (wheel radius, skid slip) and the gyro's bias
        self._slip_v = _gauss(self._rng_odom, 0.01) if self.noise else 0.0
        self._slip_w = _gauss(self._rng_odom, 0.05) if self.noise else 0.0
        self._gyro_bias = _gauss(self._rng_imu, 0.002) if self.noise else 0.0
        self._make_io(publish_clock, laser and laser_pipeline == "direct", publish_odom_tf,
                      ground_truth, odom_topic)
        self._make_extra_io(laser and (pointcloud or laser_pipeline == "smb"), joint_states)
        node.add_entity(self)
        self._check_free(self._start, "start")
        self._proc = node.process(self._run())

    # -- state --------------------------------------------------------------------------------
    def _reset_state(self, pose: Pose2D) -> None:
        self._x, self._y, self._yaw = pose
        self._v = 0.0
        self._w = 0.0
        self._v_prev = 0.0
        self._ox, self._oy, self._oyaw = 0.0, 0.0, 0.0  # odometry frame starts at the robot
        self._vm = 0.0
        self._wm = 0.0
        self._contact: Prepared | None = None  # the obstacle touched, until 5 cm apart again
        self._pressing = False  # the last step was stopped by an obstacle
        self._pulse: tuple[int, float, float, float, float] | None = None
        self._bump: tuple[int, int, float, float] | None = None  # bump(): from, steps, y, z

    def _check_free(self, pose: Pose2D, what: str) -> None:
        s, c = sincos(pose.yaw)
        for p in self._prepared:
            if collides(self.footprint, pose.x, pose.y, s, c, p):
                raise DdesValueError(
                    f"the robot's {what} pose ({pose.x!r}, {pose.y!r}, yaw {pose.yaw!r}) "
                    f"overlaps obstacle {p.obstacle.name!r} of world {self.spec.name!r}; "
                    "place it elsewhere")

    @property
    def truth(self) -> Truth:
        """The exact pose and velocities now."""
        return Truth(self._x, self._y, self._yaw, self._v, self._w)

    @property
    def pose(self) -> Pose2D:
        return Pose2D(self._x, self._y, self._yaw)

    @property
    def odometry(self) -> Pose2D:
        """The pose the wheel odometry reports (in the odom frame, which starts at the robot)."""
        return Pose2D(self._ox, self._oy, self._oyaw)

    @property
    def sim_time(self) -> Time:
        """The simulator's clock (what ``/clock`` says)."""
        return Time._from_ns(self._step * DT_NS)

    @property
    def paused(self) -> bool:
        return self._paused

    def history(self) -> History:
        """The true state at 10 Hz since the start (copies)."""
        h = self._hist
        return History(list(h.t_ns), list(h.x), list(h.y), list(h.yaw), list(h.v), list(h.w))

    @property
    def obstacles(self) -> tuple[Obstacle, ...]:
        return tuple(p.obstacle for p in self._prepared)

    # -- control ------------------------------------------------------------------------------
    def pause(self) -> None:
        """Stop the physics and the sensors (Gazebo's ``pause_physics``)."""
        if not self._paused:
            self._paused = True
            self.world.record("sim.pause", self.node.name, paused=True)

    def resume(self) -> None:
        """Start them again (``unpause_physics``)."""
        if self._paused:
            self._paused = False
            self.world.record("sim.pause", self.node.name, paused=False)

    unpause = resume

    def reset(self) -> None:
        """Back to the start pose, at rest, odometry zeroed (``reset_world``; time goes on)."""
        self._reset_state(self._start)
        self._cmd = (0.0, 0.0)
        self.world.record("sim.reset", self.node.name, x=self._x.hex(), y=self._y.hex(),
                          yaw=self._yaw.hex())

    def place(self, x: float, y: float, yaw: float = 0.0) -> None:
        """Put the robot at ``(x, y, yaw)`` at rest (odometry keeps counting from where it was)."""
        pose = Pose2D(float(x), float(y), wrap_angle(float(yaw)))
        self._check_free(pose, "new")
        self._x, self._y, self._yaw = pose
        self._v = self._w = 0.0
        self._contact = None
        self._pressing = False
        self.world.record("sim.place", self.node.name, x=pose.x.hex(), y=pose.y.hex(),
                          yaw=pose.yaw.hex())

    def add(self, *obstacles: Obstacle) -> None:
        """Add obstacles to the world while it runs."""
        self.spec = self.spec.with_obstacles(*obstacles)
        self._prepared = [prepare(ob) for ob in self.spec.obstacles]

    def shutdown(self) -> None:
        """Stop stepping (the node's shutdown calls this)."""
        self._closed = True

    # -- optional outputs: the SMB's point cloud and wheel joints -------------------------------
    def _make_extra_io(self, cloud: bool, joints: bool) -> None:
        """``rslidar_points`` (the scan's valid returns as a cloud, the SMB's VLP-16 topic) and
        ``joint_states`` (the four wheel joints, turning at the rates that give the reported
        odometry), each only when asked for: with both off nothing is advertised and nothing
        is drawn, so the trace is that of a simulator without them.
        """
        node = self.node
        self._cloud_pub = self._joints_pub = None
        if cloud:
            pc2 = get_message_class("sensor_msgs/PointCloud2")
            field = get_message_class("sensor_msgs/PointField")
            self._cloud_pub = node.advertise("rslidar_points", pc2, queue_size=10)
            m = self._cloud_m = pc2(height=1, point_step=12, is_bigendian=False, is_dense=True)
            m.header.frame_id = "base_laser"
            m.fields = [field(name=n, offset=4 * i, datatype=7, count=1)  # FLOAT32
                        for i, n in enumerate("xyz")]
        if joints:
            js = get_message_class("sensor_msgs/JointState")
            self._joints_pub = node.advertise("joint_states", js, queue_size=10)
            self._joints_m = js(name=list(WHEEL_JOINTS), effort=[0.0] * 4)
        self._wheel_pos = [0.0, 0.0, 0.0, 0.0]
        self._wheel_vel = [0.0, 0.0, 0.0, 0.0]
        self._lasing = self._scan_pub is not None or self._cloud_pub is not None

    def _publish_joints(self, stamp: Time) -> None:
        m = self._joints_m
        m.header.stamp = stamp
        m.position = list(self._wheel_pos)
        m.velocity = list(self._wheel_vel)
        self._joints_pub.publish(m)  # type: ignore[union-attr]

    def _publish_cloud(self, stamp: Time, ranges: list[float]) -> None:
        """The valid returns of the scan as x, y, z (= 0) float32 points in base_laser."""
        dirs = self._laser.dirs
        xyz: list[float] = []
        for i, r in enumerate(ranges):
            if r != _INF and r != -_INF:
                sa, ca = dirs[i]
                xyz += (r * ca, r * sa, 0.0)
        m = self._cloud_m
        m.header.stamp = stamp
        m.width = n = len(xyz) // 3
        m.row_step = 12 * n
        m.data = struct.pack(f"<{len(xyz)}f", *xyz)
        self._cloud_pub.publish(m)  # type: ignore[union-attr]

    # -- the loop -----------------------------------------------------------------------------
    def _run(self) -> ProcessGenerator:
        timeout = self.world.env.timeout
        self._publish(0)
        while not self._closed:
            yield timeout(self._period_ns)
            if self._closed:
                return
            if self._paused:
                continue
            self._step += 1
            self._physics()
            self._publish(self._step)

    def _physics(self) -> None:
        lim = self.limits
        if (self._step * DT_NS - self._cmd_stamp_ns) <= round(lim.cmd_vel_timeout * 1e9):
            cv, cw = self._cmd
        else:
            cv = cw = 0.0
        # the command clamped to the limits, then the velocities slewed toward it at the
        # acceleration limits; each clamp is `lo if x < lo else (hi if x > hi else x)`,
        # written out rather than called (this runs every 10 ms step): the same comparisons
        # in the same order, so the same bits
        cv = -m if cv < -(m := lim.v_max) else (m if cv > m else cv)
        cw = -m if cw < -(m := lim.w_max) else (m if cw > m else cw)
        dv = lim.a_max * _DT
        dw = lim.alpha_max * _DT
        v0 = self._v
        self._v_prev = v0
        v = v0 + (-dv if (e := cv - v0) < -dv else (dv if e > dv else e))
        w = self._w + (-dw if (e := cw - self._w) < -dw else (dw if e > dw else e))
        x, y, yaw = self._x, self._y, self._yaw
        s, c = sincos(yaw + w * (0.5 * _DT))
        nx = x + v * c * _DT
        ny = y + v * s * _DT
        nyaw = wrap_angle(yaw + w * _DT)
        hit = self._hit(nx, ny, nyaw)
        if hit is None:
            self._x, self._y, self._yaw, self._v, self._w = nx, ny, nyaw, v, w
            self._pressing = False
            if self._contact is not None:
                s, c = sincos(nyaw)
                if not collides(self._fp_near, nx, ny, s, c, self._contact):
                    self._contact = None
        else:
            speed = abs(v)
            if self._hit(x, y, nyaw) is None:
                self._yaw, self._w = nyaw, w
            else:
                self._w = 0.0
            # move as far along the step as is free (bisection to 2**-20 of a step), so the
            # robot rests against the obstacle; while it presses on, it already rests there
            lo, hi = 0.0, 1.0
            dx, dy = nx - x, ny - y
            for _ in range(0 if self._pressing else 20):
                mid = 0.5 * (lo + hi)
                if self._hit(x + mid * dx, y + mid * dy, self._yaw) is None:
                    lo = mid
                else:
                    hi = mid
            self._x, self._y = x + lo * dx, y + lo * dy
            self._v = 0.0
            self._pressing = True
            # one contact until the robot is 5 cm clear of the obstacle again: sliding along
            # it or pressing on records nothing more
            if self._contact is None or self._contact.obstacle.name != hit.obstacle.name:
                self._collide(hit, speed)
            self._contact = hit
        self._odometry()

    def _hit(self, x: float, y: float, yaw: float) -> Prepared | None:
        fp = self._fp
        reach0 = fp[2]
        heading: tuple[float, float] | None = None
        for p in self._prepared:
            fx = p.bx - x
            fy = p.by - y
            reach = reach0 + p.br
            if fx * fx + fy * fy > reach * reach * 1.0001 + 1e-12:
                continue  # the bounding circles are apart: no trig needed
            if heading is None:
                heading = sincos(yaw)
            if collides(fp, x, y, heading[0], heading[1], p):
                return p
        return None

    def _collide(self, p: Prepared, speed: float) -> None:
        heading = sincos(self._yaw)
        n = contact_normal(p, self._x, self._y, heading)
        now = self.world.env.now
        col = Collision(now, self._step * DT_NS, p.obstacle.name, speed, n, self.pose)
        self.collisions.append(col)
        self.world.record("sim.collision", self.node.name, obstacle=p.obstacle.name,
                          speed=speed.hex(), normal_x=n[0].hex(), normal_y=n[1].hex(),
                          stamp=col.stamp_ns)
        self.node.logwarn("collision with %s at %.3f m/s", p.obstacle.name, speed)
        if speed >= _CRASH_MIN_SPEED:
            s, c = heading
            bx = c * n[0] + s * n[1]  # the normal in the body frame
            by = -s * n[0] + c * n[1]
            phase = self._rng_imu.random() * 6.283185307179586 if self.noise else 0.0
            peak = 1.5707963267948966 * speed / _CRASH_TAU
            self._pulse = (self._step, peak, bx, by, phase)

    # -- ROS side -----------------------------------------------------------------------------
    def _make_io(self, publish_clock: bool, laser: bool, odom_tf: bool, ground_truth: bool,
                 odom_topic: str) -> None:
        node = self.node
        twist = get_message_class("geometry_msgs/Twist")
        odometry = get_message_class("nav_msgs/Odometry")
        tfm = get_message_class("tf2_msgs/TFMessage")
        ts = get_message_class("geometry_msgs/TransformStamped")
        self._Clock = get_message_class("rosgraph_msgs/Clock")
        self._Odometry = odometry
        self._Imu = get_message_class("sensor_msgs/Imu")
        self._LaserScan = get_message_class("sensor_msgs/LaserScan")
        self._TFMessage = tfm
        self._TransformStamped = ts
        self._clock_pub = node.advertise("/clock", self._Clock, queue_size=10) \
            if publish_clock else None
        self._odom_pub = node.advertise(odom_topic, odometry, queue_size=10)
        self._tf_pub = node.advertise("/tf", tfm, queue_size=100) if odom_tf else None
        self._imu_pub = node.advertise("imu/data", self._Imu, queue_size=10)
        self._scan_pub = node.advertise("scan", self._LaserScan, queue_size=10) if laser else None
        self._gt_pub = (node.advertise("ground_truth/odom", odometry, queue_size=10)
                        if ground_truth else None)
        self._trace = self.world.trace
        self._env = self.world.env
        self._node_name = node.name
        self._clock_m = self._Clock()
        self._odom_m = self._new_odom("odom")
        self._gt_m = self._new_odom("world")
        self._imu_m = m = self._new_imu()
        # the parts _publish_imu refills (the message is made once, as the others)
        self._imu_parts = (m.header, m.orientation, m.angular_velocity, m.linear_acceleration)
        self._scan_m = self._new_scan()
        moving = ts()
        moving.header.frame_id = "odom"
        moving.child_frame_id = "base_link"
        self._tf_m = tfm(transforms=[moving])
        static = node.advertise("/tf_static", tfm, queue_size=10, latch=True)
        frames = []
        for child, (ox, oy, oz) in (("base_laser", LASER_OFFSET), ("imu_link", IMU_OFFSET)):
            t = ts()
            t.header.frame_id = "base_link"
            t.child_frame_id = child
            t.transform.translation.x, t.transform.translation.y = ox, oy
            t.transform.translation.z = oz
            t.transform.rotation.w = 1.0
            frames.append(t)
        static.publish(tfm(transforms=frames))
        node.subscribe("cmd_vel", twist, self._on_cmd_vel, queue_size=1)
        empty = get_service_class("std_srvs/Empty")

        def handler(action: Callable[[], None]) -> Callable[[Message], Any]:
            def serve(req: Message) -> Any:
                action()
                return empty._response_class()
            return serve

        Service(node, "~pause_physics", empty, handler(self.pause))
        Service(node, "~unpause_physics", empty, handler(self.resume))
        Service(node, "~reset_world", empty, handler(self.reset))

    def _on_cmd_vel(self, msg: Message) -> None:
        self._cmd = (float(msg.linear.x), float(msg.angular.z))
        self._cmd_stamp_ns = self._step * DT_NS

    def _turn_wheels(self) -> None:
        """The wheels' rates that give the reported odometry (left, right side), integrated."""
        half = 0.5 * WHEEL_SEPARATION * self._wm
        left = (self._vm - half) / WHEEL_RADIUS
        right = (self._vm + half) / WHEEL_RADIUS
        self._wheel_vel = [left, right, left, right]
        pos = self._wheel_pos
        for i, rate in enumerate(self._wheel_vel):
            pos[i] += rate * _DT

    def _odometry(self) -> None:
        v, w = self._v, self._w
        if self.noise and (v != 0.0 or w != 0.0):
            r = self._rng_odom.random  # two _gauss(rng, sigma) draws, inlined in the same order
            vm = v * (1.0 + self._slip_v) + 0.01 * abs(v) * (
                (r() + r() + r() + r() + r() + r() + r() + r() + r() + r() + r() + r()) - 6.0)
            wm = w * (1.0 + self._slip_w) + (0.02 * abs(w) + 0.002) * (
                (r() + r() + r() + r() + r() + r() + r() + r() + r() + r() + r() + r()) - 6.0)
        else:
            vm, wm = v, w
        if not self.noise:  # odometry equals the truth, pose included
            self._ox, self._oy, self._oyaw = self._truth_in_odom()
        else:
            s, c = sincos(self._oyaw + wm * (0.5 * _DT))
            self._ox += vm * c * _DT
            self._oy += vm * s * _DT
            self._oyaw = wrap_angle(self._oyaw + wm * _DT)
        self._vm, self._wm = vm, wm
        if self._joints_pub is not None:
            self._turn_wheels()

    def _truth_in_odom(self) -> tuple[float, float, float]:
        x0, y0, yaw0 = self._start
        s, c = sincos(yaw0)
        dx, dy = self._x - x0, self._y - y0
        return c * dx + s * dy, -s * dx + c * dy, wrap_angle(self._yaw - yaw0)

    def _publish(self, step: int) -> None:
        stamp = _new_time(Time)  # Time._from_ns(step * DT_NS), written out (step >= 0)
        stamp.secs, stamp.nsecs = divmod(step * DT_NS, 1_000_000_000)
        if self._clock_pub is not None:
            clock = self._clock_m
            clock.clock = stamp
            self._clock_pub.publish(clock)
        if step % 2 == 0:
            self._publish_odom(stamp)
            if self._joints_pub is not None:
                self._publish_joints(stamp)
        if step % self._imu_every == 0:
            self._publish_imu(stamp, step)
        if step % 10 == 0:
            if self._lasing:
                self._publish_scan(stamp)
            h = self._hist
            h.t_ns.append(step * DT_NS)
            h.x.append(self._x)
            h.y.append(self._y)
            h.yaw.append(self._yaw)
            h.v.append(self._v)
            h.w.append(self._w)
            # world.record("sim.pose", ...), written out: the same row
            self._trace.append_row((self._env.now_ns, "sim.pose", self._node_name, {
                "stamp": step * DT_NS, "x": self._x.hex(), "y": self._y.hex(),
                "yaw": self._yaw.hex(), "v": self._v.hex(), "w": self._w.hex()}))

    # The messages are made once and refilled: a publish serializes its snapshot at once.
    def _new_odom(self, frame: str) -> Message:
        m = self._Odometry()
        m.header.frame_id = frame
        m.child_frame_id = "base_link"
        pc = [0.0] * 36
        tc = [0.0] * 36
        for i in range(6):
            pc[7 * i] = _ODOM_POSE_COV[i]
            tc[7 * i] = _ODOM_TWIST_COV[i]
        m.pose.covariance = pc
        m.twist.covariance = tc
        return m

    @staticmethod
    def _fill_odom(m: Message, stamp: Time, x: float, y: float, yaw: float, v: float,
                   w: float) -> tuple[float, float]:
        m.header.stamp = stamp
        pose = m.pose.pose
        pose.position.x = x
        pose.position.y = y
        s, c = sincos(0.5 * yaw)
        pose.orientation.z = s
        pose.orientation.w = c
        twist = m.twist.twist
        twist.linear.x = v
        twist.angular.z = w
        return s, c

    def _publish_odom(self, stamp: Time) -> None:
        m = self._odom_m
        s, c = self._fill_odom(m, stamp, self._ox, self._oy, self._oyaw, self._vm, self._wm)
        self._odom_pub.publish(m)
        if self._tf_pub is not None:
            tfm = self._tf_m
            t = tfm.transforms[0]
            t.header.stamp = stamp
            tr = t.transform
            tr.translation.x = self._ox
            tr.translation.y = self._oy
            tr.rotation.z = s
            tr.rotation.w = c
            self._tf_pub.publish(tfm)
        if self._gt_pub is not None:
            gm = self._gt_m
            self._fill_odom(gm, stamp, self._x, self._y, self._yaw, self._v, self._w)
            self._gt_pub.publish(gm)

    def _new_imu(self) -> Message:
        m = self._Imu()
        m.header.frame_id = "imu_link"
        m.orientation_covariance = [0.002 ** 2, 0.0, 0.0, 0.0, 0.002 ** 2, 0.0, 0.0, 0.0,
                                    0.002 ** 2]
        m.angular_velocity_covariance = [0.005 ** 2, 0.0, 0.0, 0.0, 0.005 ** 2, 0.0, 0.0, 0.0,
                                         0.005 ** 2]
        m.linear_acceleration_covariance = [0.05 ** 2, 0.0, 0.0, 0.0, 0.05 ** 2, 0.0, 0.0, 0.0,
                                            0.05 ** 2]
        return m

    def _publish_imu(self, stamp: Time, step: int) -> None:
        header, orientation, angular, acc = self._imu_parts
        header.stamp = stamp
        v, w = self._v, self._w
        ax = (v - self._v_prev) / _DT
        ay = v * w
        az = _G
        yaw = self._yaw
        gz = w
        if self.noise:  # five _gauss(rng, sigma) draws, inlined in the same order
            r = self._rng_imu.random
            yaw += 0.002 * ((r() + r() + r() + r() + r() + r() + r() + r() + r() + r() + r()
                             + r()) - 6.0)
            gz += self._gyro_bias + 0.005 * ((r() + r() + r() + r() + r() + r() + r() + r() + r()
                                              + r() + r() + r()) - 6.0)
            ax += 0.05 * ((r() + r() + r() + r() + r() + r() + r() + r() + r() + r() + r() + r())
                          - 6.0)
            ay += 0.05 * ((r() + r() + r() + r() + r() + r() + r() + r() + r() + r() + r() + r())
                          - 6.0)
            az += 0.05 * ((r() + r() + r() + r() + r() + r() + r() + r() + r() + r() + r() + r())
                          - 6.0)
        if self._pulse is not None:
            k0, peak, bx, by, phase = self._pulse
            j = step - k0
            t = (j + 0.5) * _DT
            if t < _CRASH_TAU:
                a = peak * sincos(_PI * t / _CRASH_TAU)[0]
            elif t < _CRASH_TAU + 0.3:
                decay = 1.0
                for _ in range(j - round(_CRASH_TAU / _DT)):
                    decay *= _RING_DECAY
                a = 0.2 * peak * decay * sincos(125.66370614359172 * t + phase)[0]
            else:
                a = 0.0
                self._pulse = None
            ax += a * bx
            ay += a * by
        if self._bump is not None:
            k0, n, by, bz = self._bump
            j = step - k0
            if j >= n:
                self._bump = None
            elif j >= 0:
                a = sincos(_PI * (j + 0.5) / n)[0]
                ay += by * a
                az += bz * a
        s, c = sincos(0.5 * yaw)
        orientation.z = s
        orientation.w = c
        angular.z = gz
        acc.x = ax
        acc.y = ay
        acc.z = az
        self._imu_pub.publish(self._imu_m)

    def bump(self, lateral: float = 6.0, vertical: float = 4.0, duration: float = 0.06) -> None:
        """A wheel rolls over a bump (a cable, a doorsill) from the next step: the IMU's
        lateral and vertical accelerations (m/s^2, body frame) get a half-sine jolt of these
        peaks over ``duration`` seconds; the motion, the forward acceleration and the collision
        list are unchanged: a jolt, not a crash.  Recorded in the trace as ``sim.bump``."""
        for what, value in (("lateral", lateral), ("vertical", vertical)):
            if not (isinstance(value, (int, float)) and math.isfinite(value)
                    and abs(value) <= 100.0):
                raise DdesValueError(f"bump(): {what} must be a number of m/s^2 within "
                                     f"[-100, 100], got {value!r}")
        if not (isinstance(duration, (int, float)) and 0.01 <= duration <= 1.0):
            raise DdesValueError(f"bump(): duration must be within [0.01, 1] s (at least one "
                                 f"10 ms step), got {duration!r}")
        n = max(1, round(duration / _DT))
        self._bump = (self._step + 1, n, float(lateral), float(vertical))
        self.world.record("sim.bump", self.node.name, lateral=float(lateral).hex(),
                          vertical=float(vertical).hex(), steps=n)

    def laser_origin(self) -> tuple[float, float, float]:
        """The laser's position and heading in the world now."""
        s, c = sincos(self._yaw)
        lx = LASER_OFFSET[0]
        return self._x + c * lx, self._y + s * lx, self._yaw

    def ranges(self) -> list[float]:
        """One scan of true ranges now (no noise; REP 117 limits applied), as doubles."""
        ox, oy, yaw = self.laser_origin()
        return [_limit(t) for t in self._laser.cast(self._prepared, ox, oy, yaw)]

    def _new_scan(self) -> Message:
        m = self._LaserScan()
        m.header.frame_id = "base_laser"
        m.angle_min = ANGLE_MIN
        m.angle_max = ANGLE_MAX
        m.angle_increment = ANGLE_INCREMENT
        m.time_increment = 0.0
        m.scan_time = 0.1
        m.range_min = RANGE_MIN
        m.range_max = RANGE_MAX
        return m

    def _publish_scan(self, stamp: Time) -> None:
        ox, oy, yaw = self.laser_origin()
        raw = self._laser.cast(self._prepared, ox, oy, yaw)
        out = scan_ranges(raw, self._rng_scan if self.noise else None)
        if self._scan_pub is not None:
            m = self._scan_m
            m.header.stamp = stamp
            m.ranges = out
            self._scan_pub.publish(m)
        if self._cloud_pub is not None:
            self._publish_cloud(stamp, out)


_INF = float("inf")
_new_time = Time.__new__


def _limit(t: float) -> float:
    """REP 117: below range_min -inf (too close to measure), above range_max +inf (no return)."""
    if t < RANGE_MIN:
        return -_INF
    if t > RANGE_MAX:
        return _INF
    return t
