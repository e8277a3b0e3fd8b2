"""ddes.compat.point_cloud2: sensor_msgs.point_cloud2 in scripts, round trips, and Noetic's bytes."""

from __future__ import annotations

import json
import math
import struct
import textwrap
from pathlib import Path
from typing import Any

import pytest
from hypothesis import given
from hypothesis import strategies as st

import ddes
from ddes.compat import point_cloud2 as pc2
from ddes.compat.scripts import run_script

Header = ddes.msg.get_message_class("std_msgs/Header")
PointField = ddes.msg.get_message_class("sensor_msgs/PointField")


def _run(tmp_path: Path, body: str, until: float = 1.0) -> tuple[list[str], list[str]]:
    path = tmp_path / "node.py"
    path.write_text(textwrap.dedent(body))
    out: list[str] = []
    err: list[str] = []
    world = ddes.World(seed=5)
    done, _ = run_script(world, path,
                         print_line=lambda text, stderr: (err if stderr else out).append(text))
    world.run(until=until)
    assert done.triggered and done.ok and done.value == 0
    return out, err


def test_a_script_builds_publishes_and_reads_a_cloud(tmp_path: Path) -> None:
    out, _ = _run(tmp_path, """
        import rospy
        from sensor_msgs import point_cloud2
        import sensor_msgs.point_cloud2 as pc2
        from sensor_msgs.msg import PointCloud2
        from std_msgs.msg import Header

        rospy.init_node("clouds")
        got = []
        rospy.Subscriber("cloud", PointCloud2, got.append)
        pub = rospy.Publisher("cloud", PointCloud2, queue_size=1, latch=True)
        print(pc2 is point_cloud2, point_cloud2.PointCloud2 is PointCloud2)
        header = Header(frame_id="map", stamp=rospy.Time(3))
        cloud = pc2.create_cloud_xyz32(header, [(1.0, 2.0, 3.0), (0.5, -0.25, 8.0)])
        print(type(cloud) is PointCloud2, cloud.width, cloud.height, cloud.point_step,
              cloud.row_step, len(cloud.data))
        pub.publish(cloud)
        rospy.sleep(0.5)
        print(len(got), list(pc2.read_points(got[0])))
        print(pc2.read_points_list(got[0], field_names=("z", "x")))
    """)
    assert out == [
        "True True",
        "True 2 1 12 24 24",
        "1 [(1.0, 2.0, 3.0), (0.5, -0.25, 8.0)]",
        # Noetic's quirk: the names as asked, the values in offset order (x, then z)
        "[Point(z=1.0, x=3.0), Point(z=0.5, x=8.0)]",
    ]


def test_read_points_list_names_fields_in_declared_order_values_in_offset_order() -> None:
    # as Noetic: the names come from cloud.fields, the values from the offset-sorted format
    fields = [PointField("b", 4, PointField.FLOAT32, 1), PointField("a", 0, PointField.FLOAT32, 1)]
    cloud = pc2.create_cloud(Header(), fields, [(1.0, 2.0)])
    assert list(pc2.read_points(cloud)) == [(1.0, 2.0)]
    (point,) = pc2.read_points_list(cloud)
    assert point._fields == ("b", "a") and tuple(point) == (1.0, 2.0)


def test_padding_skip_nans_and_uvs() -> None:
    fields = [PointField("x", 0, PointField.FLOAT32, 1),
              PointField("i", 8, PointField.UINT16, 1),
              PointField("rgb", 12, PointField.UINT8, 3)]
    assert pc2._get_struct_fmt(False, fields) == "<fxxxxHxxBBB"
    assert pc2._get_struct_fmt(True, fields, ["rgb"]) == ">" + "x" * 12 + "BBB"
    points = [(1.0, 7, 1, 2, 3), (math.nan, 8, 4, 5, 6), (3.0, 9, 7, 8, 9)]
    cloud = pc2.create_cloud(Header(), fields, points)
    assert cloud.point_step == 15 and cloud.row_step == 45 and cloud.is_dense is False
    assert cloud.data[4:8] == b"\0\0\0\0"
    assert list(pc2.read_points(cloud, skip_nans=True)) == [points[0], points[2]]
    assert list(pc2.read_points(cloud, field_names=["i"], uvs=[(2, 0), (0, 0)])) == [(9,), (7,)]
    assert list(pc2.read_points(cloud, field_names=["x"], skip_nans=True, uvs=[(1, 0)])) == []
    read = list(pc2.read_points(cloud))
    assert math.isnan(read[1][0]) and read[1][1:] == (8, 4, 5, 6)


def test_read_points_checks_its_argument_lazily_as_noetic() -> None:
    points = pc2.read_points(Header())  # a generator: nothing checked yet
    with pytest.raises(AssertionError, match="cloud is not a sensor_msgs.msg.PointCloud2"):
        next(points)
    with pytest.raises(AssertionError, match="cloud is not a sensor_msgs.msg.PointCloud2"):
        pc2.read_points_list(Header())


def test_an_unknown_datatype_is_skipped_with_a_line_on_the_scripts_stderr(tmp_path: Path
                                                                          ) -> None:
    out, err = _run(tmp_path, """
        import rospy
        from sensor_msgs import point_cloud2 as pc2
        from sensor_msgs.msg import PointField
        rospy.init_node("odd")
        fields = [PointField("x", 0, 9, 1), PointField("y", 4, PointField.FLOAT32, 1)]
        print(pc2._get_struct_fmt(False, fields))
    """)
    assert out == ["<xxxxf"]
    assert err == ["Skipping unknown PointField datatype [9]"]


_TYPES = {
    1: st.integers(-128, 127), 2: st.integers(0, 255), 3: st.integers(-2**15, 2**15 - 1),
    4: st.integers(0, 2**16 - 1), 5: st.integers(-2**31, 2**31 - 1), 6: st.integers(0, 2**32 - 1),
    7: st.floats(width=32, allow_nan=False), 8: st.floats(allow_nan=False),
}


@st.composite
def _clouds(draw: st.DrawFn) -> tuple[list[Any], list[tuple[object, ...]]]:
    kinds = draw(st.lists(st.tuples(st.sampled_from(sorted(_TYPES)), st.integers(1, 3),
                                    st.integers(0, 3)), min_size=1, max_size=5))
    fields: list[Any] = []
    offset = 0
    for n, (datatype, count, gap) in enumerate(kinds):
        offset += gap
        fields.append(PointField(f"f{n}", offset, datatype, count))
        offset += pc2._DATATYPES[datatype][1] * count
    row = st.tuples(*[_TYPES[dt] for dt, count, _ in kinds for _ in range(count)])
    return fields, draw(st.lists(row, max_size=6))


@given(_clouds())
def test_create_then_read_gives_the_points_back(case: tuple[list[Any],
                                                            list[tuple[object, ...]]]) -> None:
    fields, points = case
    cloud = pc2.create_cloud(Header(frame_id="f"), fields, points)
    assert cloud.width == len(points) and cloud.height == 1
    assert len(cloud.data) == cloud.row_step == cloud.point_step * len(points)
    assert list(pc2.read_points(cloud)) == points
    if all(f.count == 1 for f in fields):  # else one name, several values: TypeError, as Noetic
        assert [tuple(p) for p in pc2.read_points_list(cloud)] == points
    again = ddes.msg.deserialize_message(type(cloud), ddes.msg.serialize_message(cloud))
    assert list(pc2.read_points(again)) == points


@given(st.lists(st.tuples(st.floats(allow_nan=False, allow_infinity=False),
                          st.floats(allow_nan=False, allow_infinity=False),
                          st.floats(allow_nan=False, allow_infinity=False)), max_size=5))
def test_xyz32_rounds_each_coordinate_to_float32(points: list[tuple[float, float, float]]
                                                 ) -> None:
    try:
        expected = [struct.unpack("<fff", struct.pack("<fff", *p)) for p in points]
    except OverflowError:
        with pytest.raises(OverflowError):
            pc2.create_cloud_xyz32(Header(), points)
        return
    cloud = pc2.create_cloud_xyz32(Header(), points)
    assert [f.name for f in cloud.fields] == ["x", "y", "z"]
    assert list(pc2.read_points(cloud)) == expected


# The same calls under this module (in a script) and Noetic's: JSON of bytes and points.
_REFERENCE = r"""
import json, math
from sensor_msgs import point_cloud2 as pc2
from sensor_msgs.msg import PointCloud2, PointField
from std_msgs.msg import Header

def clean(points):
    return [[("nan" if isinstance(v, float) and math.isnan(v) else v) for v in p]
            for p in points]

out = {}
fields = [PointField("x", 0, PointField.FLOAT32, 1), PointField("y", 4, PointField.FLOAT32, 1),
          PointField("z", 8, PointField.FLOAT32, 1), PointField("rgb", 16, PointField.UINT32, 1),
          PointField("n", 20, PointField.INT8, 2), PointField("t", 24, PointField.FLOAT64, 1),
          PointField("s", 32, PointField.INT16, 1), PointField("u", 34, PointField.UINT16, 1),
          PointField("i", 36, PointField.INT32, 1), PointField("b", 40, PointField.UINT8, 1)]
points = [(0.1, -2.5, 1e-7, 0xFF00FF, -3, 4, math.pi, -300, 65535, -2**31, 255),
          (float("nan"), 1.0, 2.0, 0, 0, 0, -0.0, 0, 0, 0, 0),
          (1e30, -1e-30, 3.3, 1, 127, -128, 1e300, 32767, 1, 2**31 - 1, 7)]
header = Header(seq=4, frame_id="base")
cloud = pc2.create_cloud(header, fields, points)
out["data"] = cloud.data.hex()
out["meta"] = [cloud.height, cloud.width, cloud.point_step, cloud.row_step, cloud.is_dense,
               cloud.is_bigendian, cloud.header.frame_id]
out["fmt"] = [pc2._get_struct_fmt(False, fields), pc2._get_struct_fmt(True, fields, ["z", "b"])]
out["all"] = clean(pc2.read_points(cloud))
out["named"] = clean(pc2.read_points(cloud, field_names=("t", "x", "b")))
out["nans"] = clean(pc2.read_points(cloud, skip_nans=True))
out["uvs"] = clean(pc2.read_points(cloud, field_names=["i"], uvs=[(2, 0), (0, 0), (1, 0)]))
out["list"] = [[type(p).__name__, list(p._fields)] + clean([p])[0]
               for p in pc2.read_points_list(cloud, field_names=["y", "rgb"])]
xyz = pc2.create_cloud_xyz32(header, [[1.1, 2.2, 3.3], [-0.0, 1e-45, 3.4e38]])
out["xyz"] = [xyz.data.hex(), [[f.name, f.offset, f.datatype, f.count] for f in xyz.fields]]
big = PointCloud2(height=2, width=2, point_step=8, row_step=20, is_bigendian=True,
                  fields=[PointField("a", 0, PointField.INT32, 1),
                          PointField("b", 4, PointField.FLOAT32, 1)],
                  data=bytes(range(40)))
out["big"] = clean(pc2.read_points(big))
out["big_uv"] = clean(pc2.read_points(big, uvs=[(1, 1)]))
out["tables"] = sorted([k, list(v)] for k, v in pc2._DATATYPES.items())
print(json.dumps(out))
"""


@pytest.mark.ros
def test_bytes_and_points_match_noetic(ros_python, tmp_path: Path) -> None:
    expected = ros_python(_REFERENCE, as_json=True)
    out, _ = _run(tmp_path, "import rospy\nrospy.init_node('pc')\n" + _REFERENCE)
    got = json.loads(out[0])
    assert got.keys() == expected.keys()
    for key in expected:
        assert got[key] == expected[key], key
    assert len(bytes.fromhex(got["data"])) == 3 * 41
