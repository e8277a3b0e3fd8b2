"""ddes.tf2_ros.Buffer: a plain data structure, waits as events at the exact instant, timeouts,
Buffer.transform for the three stamped types (tf2_geometry_msgs's math)."""

from __future__ import annotations

from typing import Any

import pytest

import ddes
from ddes.errors import BlockingOutsideNodeError, DdesValueError
from ddes.msg import get_message_class
from ddes.tf2_ros import (
    Buffer,
    ExtrapolationException,
    LookupException,
    TimeoutException,
    TypeException,
)
from ddes.time.rostime import Duration, Time
from ddes.transformations import quaternion_from_euler, quaternion_matrix

TransformStamped = get_message_class("geometry_msgs/TransformStamped")
PointStamped = get_message_class("geometry_msgs/PointStamped")
PoseStamped = get_message_class("geometry_msgs/PoseStamped")
Vector3Stamped = get_message_class("geometry_msgs/Vector3Stamped")


def stamped(parent: str, child: str, t_ns: int, xyz: tuple[float, float, float],
            rpy: tuple[float, float, float] = (0.0, 0.0, 0.0)) -> Any:
    ts = TransformStamped()
    ts.header.stamp = Time(0, t_ns)
    ts.header.frame_id = parent
    ts.child_frame_id = child
    ts.transform.translation.x, ts.transform.translation.y, ts.transform.translation.z = xyz
    q = quaternion_from_euler(*rpy)
    (ts.transform.rotation.x, ts.transform.rotation.y, ts.transform.rotation.z,
     ts.transform.rotation.w) = q
    return ts


def test_a_buffer_without_a_world_answers_at_once() -> None:
    buf = Buffer()
    buf.set_transform(stamped("odom", "base_link", 1_000_000_000, (1.0, 0.0, 0.0)), "test")
    buf.set_transform(stamped("odom", "base_link", 2_000_000_000, (2.0, 0.0, 0.0)), "test")
    t = buf.lookup_transform("odom", "base_link", Time(1, 500_000_000))
    assert t.transform.translation.x == pytest.approx(1.5)
    assert buf.can_transform("odom", "base_link", Time(1, 500_000_000))
    assert not buf.can_transform("odom", "base_link", Time(3, 0))
    assert buf.can_transform("odom", "base_link", Time(3), timeout=None,
                             return_debug_tuple=True)[0] is False
    with pytest.raises(ExtrapolationException, match="into the future"):
        buf.lookup_transform("odom", "base_link", Time(3), Duration(0))
    with pytest.raises(LookupException):
        buf.lookup_transform("odom", "nowhere", Time())


def test_a_timeout_outside_a_node_says_how_to_wait() -> None:
    buf = Buffer()
    with pytest.raises(DdesValueError, match="has no node"):
        buf.lookup_transform("a", "b", Time(), timeout=1.0)
    world = ddes.World()
    buf = Buffer(node=world.create_node("n"))
    with pytest.raises(BlockingOutsideNodeError):
        buf.lookup_transform("a", "b", Time(), timeout=1.0)


def test_a_wait_ends_in_the_instant_the_transform_is_set() -> None:
    world = ddes.World()
    node = world.create_node("waiter")
    buf = Buffer(node=node)
    seen: list[tuple[int, object]] = []

    def waiter() -> Any:
        ok = yield buf.wait_for_transform("map", "base", Time(), 10.0)
        seen.append((world.now, ok))

    def setter() -> Any:
        yield node.sleep(Duration(1, 234_567_891))
        buf.set_transform(stamped("map", "base", world.now, (1.0, 2.0, 3.0)), "me")

    node.process(waiter())
    node.process(setter())
    world.run(until=20)
    assert seen == [(1_234_567_891, True)]


def test_a_wait_times_out_on_simulated_time_with_tf2s_text() -> None:
    world = ddes.World()
    node = world.create_node("waiter")
    buf = Buffer(node=node)
    buf.set_transform(stamped("map", "base", 1_000_000_000, (0.0, 0.0, 0.0)), "me")
    caught: list[tuple[int, str]] = []

    def waiter() -> Any:
        try:
            yield buf.wait_for_transform("map", "base", Time(5), Duration(2, 500_000_000))
        except TimeoutException as exc:
            caught.append((world.now, str(exc)))

    node.process(waiter())
    world.run(until=10)
    assert caught and caught[0][0] == 2_500_000_000
    assert caught[0][1].startswith("Lookup would require extrapolation")


def test_a_zero_timeout_decides_now() -> None:
    world = ddes.World()
    node = world.create_node("waiter")
    buf = Buffer(node=node)
    ev = buf.wait_for_transform("a", "b", Time(), 0)
    assert ev.triggered and not ev.ok
    ev.defused = True
    assert isinstance(ev.value, TimeoutException)
    buf.set_transform_static(stamped("a", "b", 0, (1.0, 0.0, 0.0)), "me")
    ev2 = buf.wait_for_transform("a", "b", Time(), None)
    assert ev2.triggered and ev2.ok and ev2.value is True


def test_a_static_transform_wakes_a_waiter_too() -> None:
    world = ddes.World()
    node = world.create_node("waiter")
    buf = Buffer(node=node)
    ends: list[int] = []

    def waiter() -> Any:
        yield buf.wait_for_transform("base", "laser", Time(7), 5.0)
        ends.append(world.now)

    def setter() -> Any:
        yield node.sleep(0.25)
        buf.set_transform_static(stamped("base", "laser", 0, (0.2, 0.0, 0.1)), "me")

    node.process(waiter())
    node.process(setter())
    world.run(until=3)
    assert ends == [250_000_000]


def test_a_buffer_serves_one_node() -> None:
    world = ddes.World()
    buf = Buffer(node=world.create_node("a"))
    with pytest.raises(DdesValueError, match="belongs to node /a"):
        buf.attach(world.create_node("b"))


def _rot(rpy: tuple[float, float, float], v: tuple[float, float, float]) -> list[float]:
    m = quaternion_matrix(quaternion_from_euler(*rpy))
    return [sum(m[i][j] * v[j] for j in range(3)) for i in range(3)]


def test_transform_point_pose_and_vector() -> None:
    buf = Buffer()
    rpy = (0.1, -0.2, 0.7)
    buf.set_transform_static(stamped("base", "laser", 0, (0.5, -0.25, 1.0), rpy), "me")
    p = PointStamped()
    p.header.frame_id = "laser"
    p.point.x, p.point.y, p.point.z = 1.0, 2.0, 3.0
    out = buf.transform(p, "base")
    want = [a + b for a, b in zip(_rot(rpy, (1.0, 2.0, 3.0)), (0.5, -0.25, 1.0))]
    assert type(out) is PointStamped and out.header.frame_id == "base"
    assert [out.point.x, out.point.y, out.point.z] == pytest.approx(want, abs=1e-12)

    v = Vector3Stamped()
    v.header.frame_id = "laser"
    v.vector.x, v.vector.y, v.vector.z = 1.0, 2.0, 3.0
    vo = buf.transform(v, "base")
    assert [vo.vector.x, vo.vector.y, vo.vector.z] == pytest.approx(_rot(rpy, (1.0, 2.0, 3.0)),
                                                                    abs=1e-12)

    pose = PoseStamped()
    pose.header.frame_id = "laser"
    pose.pose.position.x = 1.0
    (pose.pose.orientation.x, pose.pose.orientation.y, pose.pose.orientation.z,
     pose.pose.orientation.w) = quaternion_from_euler(0.0, 0.0, 0.3)
    po = buf.transform(pose, "base")
    assert [po.pose.position.x, po.pose.position.y, po.pose.position.z] == pytest.approx(
        [a + b for a, b in zip(_rot(rpy, (1.0, 0.0, 0.0)), (0.5, -0.25, 1.0))], abs=1e-12)
    # the orientation: the rotation of the product, w >= 0 as KDL's GetQuaternion gives it here
    q = [po.pose.orientation.x, po.pose.orientation.y, po.pose.orientation.z,
         po.pose.orientation.w]
    m = quaternion_matrix(q)
    mo = quaternion_matrix(quaternion_from_euler(0.0, 0.0, 0.3))
    mt = quaternion_matrix(quaternion_from_euler(*rpy))
    prod = [[sum(mt[i][k] * mo[k][j] for k in range(3)) for j in range(3)] for i in range(3)]
    assert [m[i][j] for i in range(3) for j in range(3)] == pytest.approx(
        [prod[i][j] for i in range(3) for j in range(3)], abs=1e-12)
    assert q[3] > 0

    with pytest.raises(TypeException, match="if not loaded or supported"):
        buf.transform(TransformStamped(), "base")
    with pytest.raises(TypeException):
        buf.transform(p, "base", new_type=PoseStamped)
