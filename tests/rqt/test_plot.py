"""rqt_plot: the curves hold the values and stamps that were published, from a world's trace
and from a bag; rqt_plot's field names; errors that name the fix."""

from __future__ import annotations

from pathlib import Path

import pytest

import ddes
from ddes.errors import DdesTypeError, DdesValueError
from ddes.msg import get_message_class
from ddes.rosbag import Bag
from ddes.rqt.plot import expand_fields, field_series, rqt_plot, split_field

Twist = get_message_class("geometry_msgs/Twist")
Vector3 = get_message_class("geometry_msgs/Vector3")
PoseStamped = get_message_class("geometry_msgs/PoseStamped")


def world_with_data() -> tuple[ddes.World, list[float], list[float]]:
    world = ddes.World(seed=3)
    node = world.create_node("pub")
    cmd = ddes.Publisher(node, "/cmd_vel", Twist, queue_size=10)
    pose = ddes.Publisher(node, "/pose", PoseStamped, queue_size=10)
    sent_v: list[float] = []
    sent_x: list[float] = []

    def tick(_event: object) -> None:
        k = len(sent_v)
        v = 0.25 * k - 1.0
        cmd.publish(Twist(linear=Vector3(x=v)))
        p = PoseStamped()
        p.header.stamp = ddes.Time(100 + k)        # its own stamps: x is the header time
        p.pose.position.x, p.pose.position.y = float(k), float(-k)
        pose.publish(p)
        sent_v.append(v)
        sent_x.append(float(k))

    node.create_timer(0.5, tick)
    world.run(until=3.0)
    return world, sent_v, sent_x


def test_values_equal_the_published_values() -> None:
    world, sent_v, _ = world_with_data()
    s = field_series(world, "/cmd_vel/linear/x")
    assert s.name == "/cmd_vel/linear/x" and s.y == sent_v
    assert s.t == [0.5 * (i + 1) for i in range(len(sent_v))]   # no header: publish time
    p = field_series(world, "pose/pose/position/y")             # relative: as rqt_plot
    assert p.t == [100.0 + i for i in range(len(sent_v))]        # header stamps
    assert p.y == [-float(i) for i in range(len(sent_v))]
    assert field_series(world, "/pose/header/stamp", time="publish").y == p.t


def test_the_figure_has_one_line_per_field(tmp_path: Path) -> None:
    world, sent_v, sent_x = world_with_data()
    fig = rqt_plot(world, "/cmd_vel/linear/x", "/pose/pose/position/x:y", time="publish")
    ax = fig.axes[0]
    lines = {ln.get_gid(): ln for ln in ax.get_lines()}
    assert list(lines) == ["series:/cmd_vel/linear/x", "series:/pose/pose/position/x",
                           "series:/pose/pose/position/y"]
    assert list(lines["series:/cmd_vel/linear/x"].get_ydata()) == sent_v
    assert list(lines["series:/pose/pose/position/x"].get_ydata()) == sent_x
    assert ax.get_xlabel() == "time [s]"
    out = tmp_path / "plot.png"
    fig.savefig(out)
    assert out.read_bytes()[:4] == b"\x89PNG" and out.stat().st_size > 5000


def test_a_bag_gives_the_same_curve(tmp_path: Path) -> None:
    world, sent_v, _ = world_with_data()
    path = tmp_path / "run.bag"
    with Bag(str(path), "w") as bag:
        for ev in world.trace.select(kind="topic.publish", topic="/cmd_vel"):
            bag.write("/cmd_vel", Twist().deserialize(ev.details["data"]), ddes.Time._from_ns(ev.t))
    s = field_series(str(path), "/cmd_vel/linear/x")
    assert s.y == sent_v and s.t == field_series(world, "/cmd_vel/linear/x").t
    with Bag(str(path)) as bag:
        assert field_series(bag, "/cmd_vel/linear/x").y == sent_v


def test_field_names() -> None:
    assert expand_fields("/turtle1/pose/x:y") == ["/turtle1/pose/x", "/turtle1/pose/y"]
    assert split_field("/a/b/c/d", ["/a", "/a/b", "/c"]) == ("/a/b", ["c", "d"])
    assert split_field("/scan/ranges[3]", ["/scan"]) == ("/scan", ["ranges[3]"])


def test_errors_name_the_fix() -> None:
    world, _, _ = world_with_data()
    with pytest.raises(DdesValueError, match=r"did you mean a field of '/pose'"):
        field_series(world, "/poze/pose/position/x")
    with pytest.raises(DdesValueError, match=r"/cmd_vel/linear is not a number.*linear/x"):
        field_series(world, "/cmd_vel/linear")
    with pytest.raises(DdesValueError, match=r"/cmd_vel/linear has no field 'w'"):
        field_series(world, "/cmd_vel/linear/w")
    with pytest.raises(DdesValueError, match="has no header"):
        field_series(world, "/cmd_vel/linear/x", time="header")
    with pytest.raises(DdesValueError, match="name at least one field"):
        rqt_plot(world)
    with pytest.raises(DdesTypeError, match="a Bag or a bag file path"):
        field_series(42, "/x")


def test_a_y_label_and_fields_of_another_unit_on_a_second_y_axis() -> None:
    """Two units, two y-axes (twinx), each named with its unit; one legend for both."""
    world, sent_v, sent_x = world_with_data()
    fig = rqt_plot(world, "/cmd_vel/linear/x", ylabel="speed [m/s]", time="publish",
                   right=["/pose/pose/position/x"], right_ylabel="x [m]")
    left, right = fig.axes
    assert left.get_ylabel() == "speed [m/s]" and right.get_ylabel() == "x [m]"
    assert left.get_xlabel() == "time [s]" and right.get_shared_x_axes().joined(left, right)
    assert [ln.get_gid() for ln in left.get_lines()] == ["series:/cmd_vel/linear/x"]
    assert list(right.get_lines()[0].get_ydata()) == sent_x
    assert right.get_lines()[0].get_color() != left.get_lines()[0].get_color()
    legend = right.get_legend()
    assert [t.get_text() for t in legend.get_texts()] == ["/cmd_vel/linear/x",
                                                          "/pose/pose/position/x"]
    assert rqt_plot(world, "/cmd_vel/linear/x").axes[0].get_ylabel() == ""  # as rqt_plot
