"""A collision stops the robot, is recorded (list and trace) and shows in the IMU."""

from __future__ import annotations

import math

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import ddes
from ddes.errors import DdesValueError
from ddes.msg import get_message_class
from ddes.sim import Box, Circle, Footprint, Segment, Simulator, WorldSpec
from ddes.sim.geometry import collides, prepare

TWIST = get_message_class("geometry_msgs/Twist")
VEC = get_message_class("geometry_msgs/Vector3")


def drive_into(spec: WorldSpec, x: float, y: float, yaw: float, v: float = 1.0,
               until: float = 6.0) -> tuple[ddes.World, Simulator, list[object]]:
    world = ddes.World(seed=4)
    sim = Simulator(world, spec, x=x, y=y, yaw=yaw, noise=False)
    driver = world.create_node("driver")
    pub = driver.advertise("/cmd_vel", TWIST, queue_size=1)
    driver.create_timer(0.05, lambda e: pub.publish(TWIST(linear=VEC(x=v))))
    imu: list[object] = []
    driver.subscribe("/imu/data", get_message_class("sensor_msgs/Imu"), imu.append)
    world.run(until=until)
    return world, sim, imu


def test_pillar_crash_stops_records_and_pulses() -> None:
    world, sim, imu = drive_into(WorldSpec.load("single_pillar"), 15.0, 5.0, 0.0)
    assert [c.obstacle for c in sim.collisions] == ["pillar"]  # once per contact
    col = sim.collisions[0]
    assert col.speed > 0.9 and col.normal == pytest.approx((-1.0, 0.0))
    # stopped in front of the pillar, not inside it: front edge at or before x = 19
    assert sim.truth.v == 0.0
    assert 19.0 - 1e-7 <= sim.truth.x + 0.3025 <= 19.0
    ev = world.trace.select(kind="sim.collision", source="/simulator")
    assert len(ev) == 1 and ev[0].details["obstacle"] == "pillar"
    assert float.fromhex(ev[0].details["speed"]) == col.speed
    # the crash pulse: a strong backward acceleration along the normal, then it rings out
    ax = [m.linear_acceleration.x for m in imu]
    assert min(ax) < -(math.pi / 2) * 0.9 / 0.1 * 0.9
    stamps = [m.header.stamp.to_nsec() for m in imu]
    assert min(stamps[ax.index(min(ax))] - col.stamp_ns, 10**9) <= 100_000_000
    assert abs(ax[-1]) < 1e-9  # at rest again, no noise


@pytest.mark.parametrize("world_name, pose, obstacle", [
    ("corridor", (0.0, 0.0, math.pi / 2), "wall_north_a"),   # a segment
    ("corridor", (3.0, 0.6, 0.0), "crate_1"),                # a box
    ("robocup_field", (3.0, 2.0, 0.0), "wall_east"),
    ("robocup_field", (3.0, 0.0, 0.0), "goal_east_back"),    # between the posts
])
def test_walls_and_boxes_stop_the_robot(world_name: str, pose: tuple[float, float, float],
                                        obstacle: str) -> None:
    spec = WorldSpec.load(world_name)
    world, sim, _ = drive_into(spec, *pose, until=8.0)
    assert sim.collisions and sim.collisions[0].obstacle == obstacle
    s, c = math.sin(sim.truth.yaw), math.cos(sim.truth.yaw)
    assert len(sim.collisions) == 1  # pressing on is one contact
    # where it stopped it touches nothing; 1e-6 m further it would
    assert not any(collides(Footprint(), sim.truth.x, sim.truth.y, s, c, prepare(ob))
                   for ob in spec.obstacles)
    ahead = (sim.truth.x + 1e-6 * c, sim.truth.y + 1e-6 * s)
    assert any(collides(Footprint(), *ahead, s, c, prepare(ob)) for ob in spec.obstacles)


def test_turning_in_place_against_a_wall_is_kept_when_free() -> None:
    spec = WorldSpec((Segment(0.5, -3.0, 0.5, 3.0, "wall"),), "w")
    world = ddes.World(seed=1)
    sim = Simulator(world, spec, x=0.0, noise=False)
    driver = world.create_node("driver")
    pub = driver.advertise("/cmd_vel", TWIST, queue_size=1)
    driver.create_timer(0.05, lambda e: pub.publish(TWIST(linear=VEC(x=0.5), angular=VEC(z=0.5))))
    world.run(until=3.0)
    assert [c.obstacle for c in sim.collisions] == ["wall"]  # sliding along: one contact
    assert sim.truth.yaw != 0.0  # it kept turning while pressed against the wall


def test_start_inside_an_obstacle_is_refused() -> None:
    world = ddes.World()
    with pytest.raises(DdesValueError, match="overlaps obstacle 'pillar'"):
        Simulator(world, WorldSpec.load("single_pillar"), x=19.5, y=5.0)


def test_footprint_cases() -> None:
    fp = Footprint()
    hx, hy = fp.hx, fp.hy

    def hit(ob: object, x: float = 0.0, y: float = 0.0, yaw: float = 0.0) -> bool:
        return collides(fp, x, y, math.sin(yaw), math.cos(yaw), prepare(ob))  # type: ignore[arg-type]

    assert hit(Circle(hx + 0.1, 0.0, 0.1))                 # touching the front
    assert not hit(Circle(hx + 0.1 + 1e-9, 0.0, 0.1))
    corner = math.hypot(0.1, 0.1)
    assert hit(Circle(hx + 0.1, hy + 0.1, corner))          # touching the corner exactly
    assert not hit(Circle(hx + 0.1, hy + 0.1, corner * (1 - 1e-9)))
    assert hit(Segment(-1.0, 0.0, 1.0, 0.0))                # through it, ends outside
    assert hit(Segment(-0.1, 0.05, 0.1, -0.05))             # wholly inside
    assert not hit(Segment(hx + 0.01, -1.0, hx + 0.01, 1.0))
    assert hit(Segment(-1.0, 1.0 - 1e-3, 1.0, -1.0), yaw=0.0)  # a diagonal across
    assert hit(Box(0.0, 0.0, 0.0, 10.0, 10.0))              # the robot inside a box
    assert not hit(Box(0.0, 1.0, 0.0, 1.0, 1.0))            # beside it (y gap 0.295)
    assert hit(Box(0.0, 0.0, 0.7, 0.1, 0.1))                # a small box inside the robot


@settings(max_examples=200, deadline=None)
@given(st.floats(-1.5, 1.5), st.floats(-1.5, 1.5), st.floats(-3.1, 3.1),
       st.floats(0.05, 0.6))
def test_circle_collision_matches_sampled_footprint(cx: float, cy: float, yaw: float,
                                                    r: float) -> None:
    """Independent check: distance from the circle's centre to the rotated rectangle."""
    fp = Footprint()
    c, s = math.cos(yaw), math.sin(yaw)
    bx, by = c * cx + s * cy, -s * cx + c * cy
    dx = max(abs(bx) - fp.hx, 0.0)
    dy = max(abs(by) - fp.hy, 0.0)
    dist = math.hypot(dx, dy)
    if abs(dist - r) < 1e-9:
        return
    assert collides(fp, 0.0, 0.0, s, c, prepare(Circle(cx, cy, r))) == (dist < r)


def test_bump_jolts_the_imu_sideways_and_up_without_a_crash() -> None:
    world = ddes.World(seed=4)
    sim = Simulator(world, WorldSpec.load("empty"), noise=False)
    driver = world.create_node("driver")
    pub = driver.advertise("/cmd_vel", TWIST, queue_size=1)
    driver.create_timer(0.05, lambda e: pub.publish(TWIST(linear=VEC(x=0.5))))
    imu: list[object] = []
    driver.subscribe("/imu/data", get_message_class("sensor_msgs/Imu"), imu.append)
    world.run(until=2.0)
    before = len(imu)
    sim.bump(-6.0, 4.0, 0.06)
    world.run(until=3.0)
    jolt = imu[before:]
    ay = [m.linear_acceleration.y for m in jolt]
    az = [m.linear_acceleration.z - 9.80665 for m in jolt]
    # a half sine over six 10 ms steps from the next one: peaks just under the given values
    assert min(ay) == pytest.approx(-6.0 * math.sin(math.pi * 2.5 / 6), rel=1e-12)
    assert max(az) == pytest.approx(4.0 * math.sin(math.pi * 2.5 / 6), rel=1e-12)
    assert sum(1 for a in ay if a != 0.0) == 6
    assert all(abs(m.linear_acceleration.x) < 1e-9 for m in jolt)  # cruising: no forward jolt
    assert sim.collisions == [] and sim.truth.v == pytest.approx(0.5)
    ev = world.trace.select(kind="sim.bump", source="/simulator")
    assert len(ev) == 1 and ev[0].details["steps"] == 6


@pytest.mark.parametrize("args, bad", [((float("nan"),), "lateral"), ((1.0, 500.0), "vertical"),
                                       ((1.0, 1.0, 0.001), "duration"), (("6",), "lateral")])
def test_bump_refuses_bad_values_by_name(args: tuple[object, ...], bad: str) -> None:
    sim = Simulator(ddes.World(seed=1), noise=False)
    with pytest.raises(DdesValueError, match=f"bump\\(\\): {bad}"):
        sim.bump(*args)  # type: ignore[arg-type]
