"""ddes.compat.laser_geometry: LaserProjection in a script, its layout, and Noetic's projection."""

from __future__ import annotations

import json
import math
import textwrap
from pathlib import Path
from typing import Any

import pytest

import ddes
from ddes.compat import point_cloud2 as pc2
from ddes.compat.laser_geometry import ChannelOption, LaserProjection
from ddes.compat.scripts import run_script
from ddes.transformations import cos, sin

LaserScan = ddes.msg.get_message_class("sensor_msgs/LaserScan")


def _run(tmp_path: Path, body: str) -> list[str]:
    path = tmp_path / "node.py"
    path.write_text(textwrap.dedent(body))
    out: list[str] = []
    world = ddes.World(seed=7)
    done, _ = run_script(world, path,
                         print_line=lambda text, _err: out.append(text))
    world.run(until=1.0)
    assert done.triggered and done.ok and done.value == 0
    return out


def _scan(**kw: Any) -> Any:
    values: dict[str, Any] = dict(angle_min=-1.0, angle_max=1.0, angle_increment=0.5,
                                  time_increment=0.01, range_min=0.2, range_max=5.0,
                                  ranges=[1.0, 0.1, 2.0, math.inf, 4.0],
                                  intensities=[10.0, 20.0, 30.0, 40.0, 50.0])
    values.update(kw)
    scan = LaserScan(**values)
    scan.header.frame_id = "laser"
    return scan


def test_a_script_projects_a_received_scan(tmp_path: Path) -> None:
    out = _run(tmp_path, """
        import rospy
        from laser_geometry import LaserProjection
        import sensor_msgs.point_cloud2 as pc2
        from sensor_msgs.msg import LaserScan, PointCloud2

        rospy.init_node("projector")
        projector = LaserProjection()
        clouds = rospy.Publisher("cloud", PointCloud2, queue_size=1)
        seen = []

        def on_scan(scan):
            cloud = projector.projectLaser(scan)
            seen.append(cloud)
            clouds.publish(cloud)

        rospy.Subscriber("scan", LaserScan, on_scan)
        pub = rospy.Publisher("scan", LaserScan, queue_size=1, latch=True)
        scan = LaserScan(angle_min=0.0, angle_max=1.5707963, angle_increment=1.5707963,
                         range_min=0.1, range_max=10.0, ranges=[2.0, 3.0])
        scan.header.frame_id = "laser"
        pub.publish(scan)
        rospy.sleep(0.5)
        cloud = seen[0]
        print(type(cloud) is PointCloud2, cloud.header.frame_id,
              [f.name for f in cloud.fields], cloud.point_step)
        for p in pc2.read_points(cloud):
            print("%.5f %.5f %.1f %d" % p)
    """)
    # no intensities in the scan: no "intensity" field though DEFAULT asks for it
    assert out == ["True laser ['x', 'y', 'z', 'index'] 16",
                   "2.00000 0.00000 0.0 0", "0.00000 3.00000 0.0 1"]


def test_fields_follow_the_channel_options() -> None:
    lp = LaserProjection()
    assert LaserProjection.ChannelOption is ChannelOption
    assert ChannelOption.DEFAULT == ChannelOption.INTENSITY | ChannelOption.INDEX == 3
    every = (ChannelOption.INTENSITY | ChannelOption.INDEX | ChannelOption.DISTANCE
             | ChannelOption.TIMESTAMP | ChannelOption.VIEWPOINT)
    cloud = lp.projectLaser(_scan(), channel_options=every)
    assert [(f.name, f.offset, f.datatype, f.count) for f in cloud.fields] == [
        ("x", 0, 7, 1), ("y", 4, 7, 1), ("z", 8, 7, 1), ("intensity", 12, 7, 1),
        ("index", 16, 5, 1), ("distances", 20, 7, 1), ("stamps", 24, 7, 1),
        ("vp_x", 28, 7, 1), ("vp_y", 32, 7, 1), ("vp_z", 36, 7, 1)]
    assert cloud.point_step == 40 and cloud.width == 3 and cloud.header.frame_id == "laser"
    rows = list(pc2.read_points(cloud, field_names=["intensity", "index", "distances", "stamps",
                                                     "vp_x", "vp_y", "vp_z", "z"]))
    f32 = [pc2.read_points(pc2.create_cloud_xyz32(cloud.header, [(v, 0, 0)])) for v in
           (0.02, 0.04)]
    stamp2, stamp4 = (next(p)[0] for p in f32)
    assert rows == [(0.0, 10.0, 0, 1.0, 0.0, 0.0, 0.0, 0.0),
                    (0.0, 30.0, 2, 2.0, stamp2, 0.0, 0.0, 0.0),
                    (0.0, 50.0, 4, 4.0, stamp4, 0.0, 0.0, 0.0)]
    plain = lp.projectLaser(_scan(), channel_options=ChannelOption.NONE)
    assert [f.name for f in plain.fields] == ["x", "y", "z"] and plain.point_step == 12


def test_points_use_the_deterministic_sines_and_the_cutoffs() -> None:
    scan = _scan()
    cloud = LaserProjection().projectLaser(scan, channel_options=ChannelOption.INDEX)
    expected = []
    for i in (0, 2, 4):  # 0.1 < range_min, inf >= range_max
        a = -1.0 + float(i) * 0.5
        r = scan.ranges[i]
        expected.append(next(pc2.read_points(pc2.create_cloud_xyz32(
            scan.header, [(r * cos(a), r * sin(a), 0)]))) + (i,))
    assert list(pc2.read_points(cloud)) == expected
    cut = LaserProjection().projectLaser(scan, range_cutoff=3.0)
    assert [p[0] for p in pc2.read_points(cut, field_names=["index"])] == [0, 2]
    wide = LaserProjection().projectLaser(scan, range_cutoff=100.0)
    assert wide.width == 3  # range_max still applies


def test_the_table_is_kept_until_the_count_or_the_angle_limits_change() -> None:
    lp = LaserProjection()
    first = lp.projectLaser(_scan(), channel_options=0)
    # a new increment alone keeps the old table (as Noetic): the same points
    same = lp.projectLaser(_scan(angle_increment=0.25), channel_options=0)
    assert same.data == first.data
    fresh = LaserProjection().projectLaser(_scan(angle_increment=0.25), channel_options=0)
    assert fresh.data != first.data
    moved = lp.projectLaser(_scan(angle_increment=0.25, angle_max=0.0), channel_options=0)
    assert moved.data == fresh.data


# The same projections under this module (in a script) and Noetic's (numpy's trigonometry).
_REFERENCE = r"""
import json, math
from laser_geometry import LaserProjection
import sensor_msgs.point_cloud2 as pc2
from sensor_msgs.msg import LaserScan

CO = LaserProjection.ChannelOption
n = 181
ranges = [0.5 + 0.037 * i for i in range(n)]
ranges[3] = float("inf"); ranges[7] = float("nan"); ranges[11] = 0.01; ranges[13] = 30.0
ranges[17] = 0.1; ranges[19] = 7.0
scan = LaserScan(angle_min=-math.pi / 2, angle_max=math.pi / 2, angle_increment=math.pi / 180,
                 time_increment=1e-4, range_min=0.1, range_max=7.0, ranges=ranges,
                 intensities=[float(i % 17) for i in range(n)])
scan.header.frame_id = "laser"
scan.header.stamp.secs = 12
out = []
lp = LaserProjection()
for options, cutoff in [(CO.DEFAULT, -1.0), (CO.NONE, 4.0), (0x1F, -1.0), (CO.INDEX, 20.0),
                        (CO.TIMESTAMP | CO.DISTANCE, 5.5)]:
    cloud = lp.projectLaser(scan, cutoff, options)
    out.append({"meta": [cloud.height, cloud.width, cloud.point_step, cloud.row_step,
                         cloud.is_dense, cloud.is_bigendian, cloud.header.frame_id,
                         cloud.header.stamp.secs],
                "fields": [[f.name, f.offset, f.datatype, f.count] for f in cloud.fields],
                "points": [list(p) for p in pc2.read_points(cloud)]})
empty = LaserProjection().projectLaser(LaserScan(range_max=1.0))
out.append({"meta": [empty.width, empty.point_step, len(empty.data)],
            "fields": [f.name for f in empty.fields], "points": []})
print(json.dumps(out))
"""


@pytest.mark.ros
def test_the_projection_matches_noetic(ros_python, tmp_path: Path) -> None:
    expected = ros_python(_REFERENCE, as_json=True)
    out = _run(tmp_path, "import rospy\nrospy.init_node('lp')\n" + _REFERENCE)
    got = json.loads(out[0])
    assert len(got) == len(expected) == 6
    assert sum(len(case["points"]) for case in expected) > 500
    for mine, theirs in zip(got, expected):
        assert mine["meta"] == theirs["meta"]
        assert mine["fields"] == theirs["fields"]
        assert len(mine["points"]) == len(theirs["points"])
        for p, q in zip(mine["points"], theirs["points"]):
            assert len(p) == len(q)
            assert all(math.isclose(a, b, rel_tol=0, abs_tol=1e-12) for a, b in zip(p, q)), (p, q)
